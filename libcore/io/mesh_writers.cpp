#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <stdexcept>

#include "base/atomic_file.h"
#include "base/errors.h"
#include "base/file_names.h"
#include "base/triangle_adjacency.h"
#include "base/triangle_geometry.h"
#include "io/mesh_3mf.h"
#include "io/mesh_io.h"

namespace frep {

const char* formatName(MeshFormat f) {
  switch (f) {
    case MeshFormat::StlBinary:
      return "stl";
    case MeshFormat::StlAscii:
      return "stl-ascii";
    case MeshFormat::Obj:
      return "obj";
    case MeshFormat::Ply:
      return "ply";
    case MeshFormat::FreecadBms:
      return "bms";
    case MeshFormat::ThreeMf:
      return "3mf";
  }
  return "?";
}

MeshFormat parseFormat(const std::string& name) {
  for (MeshFormat f : {MeshFormat::StlBinary, MeshFormat::StlAscii, MeshFormat::Obj,
                       MeshFormat::Ply, MeshFormat::FreecadBms, MeshFormat::ThreeMf})
    if (name == formatName(f)) return f;
  throw ModelError("unknown format '" + name + "'; allowed: stl, stl-ascii, obj, ply, bms, 3mf");
}

MeshFormat formatFromPath(const std::string& path, const char* allowed) {
  const std::string ext = fileExtension(path);
  if (ext == "stl") return MeshFormat::StlBinary;
  if (ext == "obj") return MeshFormat::Obj;
  if (ext == "ply") return MeshFormat::Ply;
  if (ext == "bms") return MeshFormat::FreecadBms;
  if (ext == "3mf") return MeshFormat::ThreeMf;
  throw FileError(displayName(path) +
                  (ext.empty() ? std::string(": the file name has no extension")
                               : ": unknown mesh file type '." + ext.substr(0, 40) + "'") +
                  "; " + allowed);
}

namespace {

Vec3f facetNormal(const TriangleMesh& m, const Triangle& t) {
  return unitNormal(m.positions[t[0]], m.positions[t[1]], m.positions[t[2]]);
}

// Reports progress every 64k items; throws Cancelled when the callback says so.
class Ticker {
 public:
  Ticker(const WriteProgress& p, std::size_t total) : p_(p), total_(total) {}
  void tick(std::size_t done) {
    if (p_ && (done & 0xFFFF) == 0 && !p_(total_ ? double(done) / double(total_) : 1.0))
      throw Cancelled();
  }

 private:
  const WriteProgress& p_;
  std::size_t total_;
};

void writeStlBinary(const TriangleMesh& m, AtomicFile& f, Ticker& tick) {
  char header[80] = {};
  std::strncpy(header, "FRepCAD binary STL", sizeof(header));
  f.write(header, 80);
  if (m.triangles.size() > 0xFFFFFFFFull) throw FileError("too many triangles for STL");
  const std::uint32_t n = static_cast<std::uint32_t>(m.triangles.size());
  f.write(&n, 4);
  std::vector<char> buffer;
  buffer.reserve(50 * 4096);
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    const Triangle& t = m.triangles[i];
    float rec[12];
    const Vec3f nn = facetNormal(m, t);
    std::memcpy(rec, nn.data(), 12);
    for (int c = 0; c < 3; ++c) std::memcpy(rec + 3 + 3 * c, m.positions[t[c]].data(), 12);
    const char* bytes = reinterpret_cast<const char*>(rec);
    buffer.insert(buffer.end(), bytes, bytes + 48);
    buffer.push_back(0);
    buffer.push_back(0);
    if (buffer.size() >= 50 * 4096) {
      f.write(buffer.data(), buffer.size());
      buffer.clear();
    }
    tick.tick(i);
  }
  f.write(buffer.data(), buffer.size());
}

void writeStlAscii(const TriangleMesh& m, AtomicFile& f, Ticker& tick) {
  f.print("solid frepcad\n");
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    const Triangle& t = m.triangles[i];
    const Vec3f n = facetNormal(m, t);
    f.print("  facet normal %.9g %.9g %.9g\n    outer loop\n", n[0], n[1], n[2]);
    for (int c = 0; c < 3; ++c) {
      const Vec3f& p = m.positions[t[c]];
      f.print("      vertex %.9g %.9g %.9g\n", p[0], p[1], p[2]);
    }
    f.print("    endloop\n  endfacet\n");
    tick.tick(i);
  }
  f.print("endsolid frepcad\n");
}

void writeObj(const TriangleMesh& m, AtomicFile& f, Ticker& tick) {
  const bool normals = m.normals.size() == m.positions.size() && !m.normals.empty();
  f.print("# FRepCAD mesh: %zu vertices, %zu triangles\n", m.positions.size(), m.triangles.size());
  for (const Vec3f& p : m.positions) f.print("v %.9g %.9g %.9g\n", p[0], p[1], p[2]);
  if (normals)
    for (const Vec3f& n : m.normals) f.print("vn %.9g %.9g %.9g\n", n[0], n[1], n[2]);
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    const Triangle& t = m.triangles[i];
    if (normals)
      f.print("f %u//%u %u//%u %u//%u\n", t[0] + 1, t[0] + 1, t[1] + 1, t[1] + 1, t[2] + 1,
              t[2] + 1);
    else
      f.print("f %u %u %u\n", t[0] + 1, t[1] + 1, t[2] + 1);
    tick.tick(i);
  }
}

void writePly(const TriangleMesh& m, AtomicFile& f, Ticker& tick) {
  const bool normals = m.normals.size() == m.positions.size() && !m.normals.empty();
  f.print("ply\nformat binary_little_endian 1.0\ncomment FRepCAD mesh\n");
  f.print("element vertex %zu\nproperty float x\nproperty float y\nproperty float z\n",
          m.positions.size());
  if (normals) f.print("property float nx\nproperty float ny\nproperty float nz\n");
  f.print("element face %zu\nproperty list uchar int vertex_indices\nend_header\n",
          m.triangles.size());
  std::vector<char> buffer;
  for (std::size_t v = 0; v < m.positions.size(); ++v) {
    const char* p = reinterpret_cast<const char*>(m.positions[v].data());
    buffer.insert(buffer.end(), p, p + 12);
    if (normals) {
      const char* n = reinterpret_cast<const char*>(m.normals[v].data());
      buffer.insert(buffer.end(), n, n + 12);
    }
  }
  f.write(buffer.data(), buffer.size());
  buffer.clear();
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    buffer.push_back(3);
    const char* t = reinterpret_cast<const char*>(m.triangles[i].data());
    buffer.insert(buffer.end(), t, t + 12);
    tick.tick(i);
  }
  f.write(buffer.data(), buffer.size());
}

// FreeCAD's MeshKernel binary layout (version 1.0, little endian): magic, version, a 256-byte
// text block, point and facet counts, float xyz per point, per facet three point indices and
// three neighbour indices (neighbour i across edge i -> i+1), then the bounding box as
// min x, max x, min y, max y, min z, max z. FreeCAD adopts the neighbours as they are, so
// reading it skips the topology rebuild a PLY needs (see docs/file-formats.md).
void writeFreecadBms(const TriangleMesh& m, AtomicFile& f, Ticker& tick) {
  if (m.positions.size() >= kNoNeighbour || m.triangles.size() >= kNoNeighbour)
    throw FileError("too many vertices or triangles for a FreeCAD mesh");
  const std::uint32_t head[2] = {0xA0B0C0D0u, 0x00010000u};
  f.write(head, sizeof(head));
  char text[256];
  for (int i = 0; i < 255; ++i) text[i] = "MESH-"[i % 5];
  text[255] = '\n';
  f.write(text, sizeof(text));
  const std::uint32_t counts[2] = {std::uint32_t(m.positions.size()),
                                   std::uint32_t(m.triangles.size())};
  f.write(counts, sizeof(counts));
  float box[6] = {0, 0, 0, 0, 0, 0};  // FreeCAD's empty box is inverted; never written empty
  if (!m.positions.empty())
    for (int a = 0; a < 3; ++a) box[2 * a] = box[2 * a + 1] = m.positions[0][a];
  for (const Vec3f& p : m.positions)
    for (int a = 0; a < 3; ++a) {
      box[2 * a] = std::min(box[2 * a], p[a]);
      box[2 * a + 1] = std::max(box[2 * a + 1], p[a]);
    }
  f.write(m.positions.data(), m.positions.size() * sizeof(Vec3f));
  const auto neighbours = facetNeighbours(m);
  std::vector<std::uint32_t> buffer;
  buffer.reserve(6 * 8192);
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    buffer.insert(buffer.end(), m.triangles[i].begin(), m.triangles[i].end());
    buffer.insert(buffer.end(), neighbours[i].begin(), neighbours[i].end());
    if (buffer.size() >= 6 * 8192) {
      f.write(buffer.data(), buffer.size() * 4);
      buffer.clear();
    }
    tick.tick(i);
  }
  f.write(buffer.data(), buffer.size() * 4);
  f.write(box, sizeof(box));
}

}  // namespace

std::unique_ptr<AtomicFile> writeMeshUncommitted(const TriangleMesh& mesh, const std::string& path,
                                                 MeshFormat format, const WriteProgress& progress) {
  if (format == MeshFormat::ThreeMf) {
    // One object named after the file, written as it is (the caller's check judges it).
    ThreeMfOptions options;
    options.validate = false;
    return write3mfUncommitted({{std::filesystem::path(path).stem().string(), mesh}}, path, options,
                               progress);
  }
  auto file = std::make_unique<AtomicFile>(path);
  Ticker tick(progress, mesh.triangles.size());
  switch (format) {
    case MeshFormat::StlBinary:
      writeStlBinary(mesh, *file, tick);
      break;
    case MeshFormat::StlAscii:
      writeStlAscii(mesh, *file, tick);
      break;
    case MeshFormat::Obj:
      writeObj(mesh, *file, tick);
      break;
    case MeshFormat::Ply:
      writePly(mesh, *file, tick);
      break;
    case MeshFormat::FreecadBms:
      writeFreecadBms(mesh, *file, tick);
      break;
    case MeshFormat::ThreeMf:
      break;
  }
  return file;
}

void writeMesh(const TriangleMesh& mesh, const std::string& path, MeshFormat format,
               const WriteProgress& progress) {
  const std::unique_ptr<AtomicFile> file = writeMeshUncommitted(mesh, path, format, progress);
  if (progress && !progress(1.0)) throw Cancelled();
  file->commit();
}

}  // namespace frep
