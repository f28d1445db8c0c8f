// Sample files for the file-backed node types (mesh_sdf, vdb_grid), written once per test
// process into a temporary folder: an icosphere STL and a sphere level set .vdb. Including
// this header also registers the volume loaders, as every program reading models does.
#pragma once

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <string>

#include "base/triangle_mesh.h"
#include "frep/tree.h"
#include "io/mesh_io.h"
#include "volume/field_sources.h"
#include "volume/level_sets.h"

namespace frep::testing {

// A sphere of radius r from an icosahedron with each face split into 4, `levels` times,
// every vertex on the sphere (to float rounding).
inline TriangleMesh icosphere(double r, int levels) {
  TriangleMesh m;
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  const double v[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                           {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<double, 3>> pts;
  auto push = [&](double x, double y, double z) {
    const double n = std::sqrt(x * x + y * y + z * z);
    pts.push_back({x / n, y / n, z / n});
    return static_cast<std::uint32_t>(pts.size() - 1);
  };
  for (const auto& p : v) push(p[0], p[1], p[2]);
  m.triangles = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                 {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto middle = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      const std::uint32_t i = push(pts[a][0] + pts[b][0], pts[a][1] + pts[b][1], pts[a][2] + pts[b][2]);
      mid[key] = i;
      return i;
    };
    std::vector<Triangle> next;
    for (const Triangle& f : m.triangles) {
      const std::uint32_t ab = middle(f[0], f[1]), bc = middle(f[1], f[2]), ca = middle(f[2], f[0]);
      next.insert(next.end(), {{f[0], ab, ca}, {f[1], bc, ab}, {f[2], ca, bc}, {ab, bc, ca}});
    }
    m.triangles = std::move(next);
  }
  for (const auto& p : pts)
    m.positions.push_back({float(r * p[0]), float(r * p[1]), float(r * p[2])});
  return m;
}

// A folder of this process, removed at exit.
inline const std::string& sampleFolder() {
  static const std::string folder = [] {
    std::string pattern = (std::getenv("TMPDIR") ? std::string(std::getenv("TMPDIR")) : "/tmp") +
                          "/frep-volume-samples-XXXXXX";
    if (!mkdtemp(pattern.data())) std::abort();
    static struct Remove {
      std::string path;
      ~Remove() { std::system(("rm -rf '" + path + "'").c_str()); }
    } remove{pattern};
    return pattern;
  }();
  return folder;
}

inline const std::string& sampleMeshPath() {
  static const std::string path = [] {
    const std::string p = sampleFolder() + "/icosphere.stl";
    writeMesh(icosphere(1.0, 2), p, MeshFormat::StlBinary);
    return p;
  }();
  return path;
}

inline NodePtr sphereNode(double r) { return makeNode("sphere", {{"radius", realValue(r)}}, {}); }

inline const std::string& sampleVdbPath() {
  static const std::string path = [] {
    registerVolumeSources();
    const std::string p = sampleFolder() + "/sphere.vdb";
    LevelSetOptions o;
    o.voxel = 0.1;
    o.name = "sphere";
    const Program sphere = compile(sphereNode(1.0));
    writeVdb(sampleLevelSet(sphere, Box3{{-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2}}, o), p);
    return p;
  }();
  return path;
}

// The sample file for a node type's file parameter.
inline std::string sampleFileFor(const std::string& typeId) {
  registerVolumeSources();
  return typeId == "vdb_grid" ? sampleVdbPath() : sampleMeshPath();
}

}  // namespace frep::testing
