// Meshes for the repair and manufacturing tests: a sphere meshed from its field, an
// axis-aligned box of grid faces, two meshes side by side.
#pragma once

#include <cstdint>
#include <vector>

#include "base/triangle_mesh.h"
#include "check/mesh_check.h"
#include "frep/program.h"
#include "frep/tree.h"
#include "mesh/mesher.h"

namespace frep {

inline TriangleMesh sphereMesh(double r = 1.0, Vec3 centre = {0, 0, 0}, double cell = 0.1) {
  NodePtr s = makeNode("sphere", {{"radius", realValue(r)}}, {});
  s = makeNode("translate", {{"offset", vec3Value(centre)}}, {s});
  const Program p = compile(s);
  MeshingOptions o;
  o.bbox = {{centre[0] - r - 2 * cell, centre[1] - r - 2 * cell, centre[2] - r - 2 * cell},
            {centre[0] + r + 2 * cell, centre[1] + r + 2 * cell, centre[2] + r + 2 * cell}};
  o.resolution = cell;
  o.normals = false;
  return polygonize(p, o);
}

inline TriangleMesh merged(const TriangleMesh& a, const TriangleMesh& b) {
  TriangleMesh m = a;
  appendMesh(m, b);
  return m;
}

// An axis-aligned box from lo to hi, each face an n x n grid of quads, two triangles each;
// outward, or facing in (a cavity) when `inward`.
inline TriangleMesh gridBox(Vec3 lo, Vec3 hi, int n, bool inward = false) {
  TriangleMesh m;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const auto base = static_cast<std::uint32_t>(m.positions.size());
      for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
          Vec3f p;
          p[axis] = float(side ? hi[axis] : lo[axis]);
          p[u] = float(lo[u] + (hi[u] - lo[u]) * i / n);
          p[v] = float(lo[v] + (hi[v] - lo[v]) * j / n);
          m.positions.push_back(p);
        }
      // (u, v, axis) is right-handed: u x v = +axis, so (i,j),(i+1,j),(i,j+1) faces +axis.
      const bool flip = (side == 0) != inward;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          const std::uint32_t a = base + i * (n + 1) + j, b = a + (n + 1), c = a + 1, d = b + 1;
          if (!flip) {
            m.triangles.push_back({a, b, c});
            m.triangles.push_back({b, d, c});
          } else {
            m.triangles.push_back({a, c, b});
            m.triangles.push_back({b, c, d});
          }
        }
    }
  // The faces' grids share their border vertices: weld them.
  std::vector<Vec3f> welded;
  const auto map = weldIdenticalVertices(m.positions, welded);
  for (auto& t : m.triangles)
    for (auto& v : t) v = map[v];
  m.positions = welded;
  return m;
}

}  // namespace frep
