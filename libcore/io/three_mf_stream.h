// A 3MF package written as its mesh comes (a brick merge never holds the whole
// mesh): the zip through minizip and zlib, the model's XML made here. lib3mf 1.8 builds the
// whole model in memory before it writes a byte, and writes coordinates through a lossy
// float-to-text conversion; this writer gives every coordinate as the shortest decimal that
// reads back as the same float, so the file holds the mesh exactly and a check of the mesh is
// a check of the file. lib3mf stays the reader (io/mesh_3mf.h), and the tests read every
// package this writer makes through it.
//
// The model's XML wants an object's vertices before its triangles. A merge numbers vertices
// and finishes triangles interleaved, so triangles given before closeVertices() wait in a
// binary spill file beside the target (12 bytes each, removed in every case) and follow the
// vertices at endObject().
#pragma once

#include <cstdint>
#include <cstdio>
#include <exception>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "base/atomic_file.h"
#include "base/triangle_mesh.h"
#include "io/mesh_3mf.h"

namespace frep {

// The 3MF unit attribute ("millimeter", ...) of a length unit.
const char* lengthUnitXmlName(LengthUnit unit);

// A beam of a beam lattice (the 3MF beam lattice extension): two vertices of its object and
// the radius at each (<= 0: the lattice's radius).
struct Beam3mf {
  std::uint32_t v1 = 0, v2 = 0;
  double r1 = 0.0, r2 = 0.0;
};
struct BeamLattice3mf {
  double radius = 0.0;               // the beams' radius where a beam gives none (> 0)
  double minLength = 0.0;            // beams shorter than this are dropped by a reader (> 0)
  std::uint32_t clippingObject = 0;  // an earlier object whose mesh clips the beams (0: none)
  std::vector<Beam3mf> beams;
};

class ThreeMfStreamWriter {
 public:
  // `expectedBytes`: about how much XML the objects will make (see expectedXmlBytes); a
  // package that may reach 4 GiB unpacked gets the zip64 headers, a smaller one stays
  // readable by every zip reader. Throws FileError.
  ThreeMfStreamWriter(const std::string& path, const ThreeMfOptions& options,
                      std::uint64_t expectedBytes);
  ~ThreeMfStreamWriter();
  ThreeMfStreamWriter(const ThreeMfStreamWriter&) = delete;
  ThreeMfStreamWriter& operator=(const ThreeMfStreamWriter&) = delete;

  // An object (a mesh and a build item). Throws FileError for a finite-coordinate or index
  // rule of the specification broken, naming the object.
  // `buildItem` false: a resource only (a clipping mesh), not printed by itself.
  void beginObject(const std::string& name, bool buildItem = true);
  // The id of the object begun last (what a beam lattice's clippingObject names).
  std::uint32_t objectId() const { return objects_; }
  void vertex(const Vec3f& position);
  // Vertices are numbered from 0 within the object, in the order given.
  void triangle(const Triangle& vertices);
  // No more vertices in this object: triangles from here go straight into the XML.
  void closeVertices();
  // The object's beams, after its vertices and triangles (an object may have beams and no
  // triangles; the options must have asked for the beam lattice extension).
  void beams(const BeamLattice3mf& lattice);
  void endObject();
  // A whole mesh as one object; `written(n)`, when given, hears of every n vertices or
  // triangles written (a few dozen calls for a large mesh: progress, and a cancel by throwing).
  void addObject(const std::string& name, const TriangleMesh& mesh,
                 const std::function<void(std::size_t)>& written = {});

  // The build, the package's other parts, the zip's directory; the file stays uncommitted.
  std::unique_ptr<AtomicFile> finish();

  std::size_t triangles() const { return trianglesTotal_; }

 private:
  void text(const char* data, std::size_t size);
  void text(const std::string& s) { text(s.data(), s.size()); }
  void flush();
  void writeTriangle(const Triangle& t);

  // Deflating runs on a thread of its own while the caller makes the next XML (about half
  // the time of a brick merge's 3MF was deflate's).
  struct Deflater;
  std::unique_ptr<Deflater> deflater_;
  std::unique_ptr<AtomicFile> file_;
  void* zip_ = nullptr;  // minizip's zipFile (its header stays in the .cpp)
  std::string spillPath_;
  std::FILE* spill_ = nullptr;
  std::string buffer_;
  std::string objectName_;
  bool inObject_ = false, verticesClosed_ = false, zip64_ = false;
  bool trianglesOpen_ = false, objectBeams_ = false, beamLattice_ = false;
  std::vector<bool> buildItems_;  // per object: a build item
  std::uint64_t written_ = 0;     // XML bytes given to the zip
  std::uint32_t objects_ = 0;
  std::uint64_t vertices_ = 0, spilled_ = 0, objectTriangles_ = 0;
  std::size_t trianglesTotal_ = 0;
};

// About how many bytes of XML a mesh of these counts makes (an upper estimate).
std::uint64_t expectedXmlBytes(std::uint64_t vertices, std::uint64_t triangles);

}  // namespace frep
