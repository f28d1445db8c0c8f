// A mesh's triangles as sorted coordinate rows (each rotated to start at its least corner):
// two meshes with the same triangles compare equal whatever their vertex and triangle order.
#pragma once

#include <algorithm>
#include <array>
#include <vector>

#include "base/triangle_mesh.h"

namespace frep::testing {

inline std::vector<std::array<float, 9>> sortedTriangles(const TriangleMesh& mesh) {
  std::vector<std::array<float, 9>> t;
  for (const auto& tri : mesh.triangles) {
    std::array<Vec3f, 3> c = {mesh.positions[tri[0]], mesh.positions[tri[1]],
                              mesh.positions[tri[2]]};
    std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
    t.push_back({c[0][0], c[0][1], c[0][2], c[1][0], c[1][1], c[1][2], c[2][0], c[2][1], c[2][2]});
  }
  std::sort(t.begin(), t.end());
  return t;
}

}  // namespace frep::testing
