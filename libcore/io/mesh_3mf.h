// 3MF files (the 3D Manufacturing Format's core specification) through lib3mf: one or more
// named mesh objects, each a build item, with the length unit and metadata. lib3mf itself is
// only in mesh_3mf.cpp (its headers define Windows types that must not leak).
#pragma once

#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "base/atomic_file.h"
#include "base/triangle_mesh.h"
#include "io/mesh_io.h"

namespace frep {

enum class LengthUnit { Micrometer, Millimeter, Centimeter, Inch, Foot, Meter };

// "micron", "mm", "cm", "inch", "ft", "m": the 3MF unit names; parseLengthUnit throws
// ModelError naming the allowed values.
const char* lengthUnitName(LengthUnit u);
LengthUnit parseLengthUnit(const std::string& name);

struct NamedMesh {
  std::string name;
  TriangleMesh mesh;
};

struct ThreeMfOptions {
  LengthUnit unit = LengthUnit::Millimeter;
  // (name, value) pairs, names from the core specification's list (Title, Designer,
  // Description, Copyright, LicenseTerms, Rating, CreationDate, ModificationDate, Application).
  std::vector<std::pair<std::string, std::string>> metadata;
  // Refuse an object that is not manifold and consistently oriented, as the core
  // specification requires, judged by lib3mf itself before anything is written. Off where the
  // check judges (the export) and for a write the user forced after it refused the mesh.
  bool validate = true;
  // The package uses the beam lattice extension (its namespace, required): objects may hold
  // beams (ThreeMfStreamWriter::beams).
  bool beamLattice = false;
};

// The 3MF writer is io/three_mf_stream.h's (lib3mf 1.8 rounds coordinates to six decimals and
// holds the whole model in memory; that writer does neither): a package holds every float
// exactly, so a check of the mesh is a check of the file.
//
// Refuses (FileError naming the object) an object without triangles, with too many, with an
// index out of range or, as lib3mf judges it, not manifold and consistently oriented.
void validate3mfObjects(const std::vector<NamedMesh>& objects);
// An object and a build item per mesh, left under the AtomicFile's temporary name (the export
// writes while its check runs). Validates first (with options.validate). Throws FileError,
// Cancelled.
std::unique_ptr<AtomicFile> write3mfUncommitted(const std::vector<NamedMesh>& objects,
                                                const std::string& path,
                                                const ThreeMfOptions& options = {},
                                                const WriteProgress& progress = {});
// The same, committed.
void write3mf(const std::vector<NamedMesh>& objects, const std::string& path,
              const ThreeMfOptions& options = {}, const WriteProgress& progress = {});

struct ThreeMfContents {
  std::vector<NamedMesh> objects;  // one per build item, its transforms applied
  LengthUnit unit = LengthUnit::Millimeter;
  std::vector<std::pair<std::string, std::string>> metadata;
};

// Packages larger than this once unpacked are refused before lib3mf reads them: a zip bomb
// costs nothing but the look at the archive's directory.
constexpr unsigned long long kMax3mfUnpackedBytes = 4ull << 30;
// Component references nested deeper than this are refused (a hostile file can nest them to
// blow the stack or multiply the triangles).
constexpr int kMax3mfComponentDepth = 16;
// Triangles all build items may add up to (components instancing one mesh many times).
constexpr std::size_t kMax3mfTriangles = std::size_t(1) << 26;
// Objects all build items may place, counting every component reference expanded (a fan of
// empty objects adds no triangles but costs lib3mf a visit each).
constexpr std::size_t kMax3mfPlacements = 1000000;

// The beams of every mesh object of a 3MF as lib3mf reads them (the beam lattice extension),
// and how many of those objects clip their beams by another object's mesh. Throws FileError.
struct ThreeMfBeams {
  std::size_t beams = 0, clipped = 0;
  std::vector<std::array<Vec3f, 2>> ends;    // every beam's two vertices, in the object's frame
  std::vector<std::array<double, 2>> radii;  // and its radius at each
};
ThreeMfBeams read3mfBeams(const std::string& path);

// Reads every build item of a 3MF (mesh objects, and components objects flattened with their
// transforms). Throws FileError naming the file and the problem.
ThreeMfContents read3mf(const std::string& path);

// The sum of the declared unpacked sizes of a zip archive's entries, read from its central
// directory alone (exposed for the tests). Throws FileError for a file that is no zip archive.
unsigned long long zipUnpackedBytes(const std::string& path);

}  // namespace frep
