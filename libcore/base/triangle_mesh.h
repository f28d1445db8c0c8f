// The indexed triangle mesh libcore produces and reads: flat arrays, float coordinates (what
// STL and PLY files hold, so a check of this mesh is a check of the file).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace frep {

using Vec3f = std::array<float, 3>;
using Triangle = std::array<std::uint32_t, 3>;

struct TriangleMesh {
  std::vector<Vec3f> positions;
  std::vector<Vec3f> normals;  // one per vertex, or empty
  std::vector<Triangle> triangles;

  std::size_t vertexCount() const { return positions.size(); }
  std::size_t triangleCount() const { return triangles.size(); }
};

// Appends `part`'s vertices and triangles to `mesh` (its indices shifted; normals dropped
// unless both have them): several objects or shells as one mesh.
inline void appendMesh(TriangleMesh& mesh, const TriangleMesh& part) {
  const bool normals = mesh.normals.size() == mesh.positions.size() &&
                       part.normals.size() == part.positions.size();
  const auto base = static_cast<std::uint32_t>(mesh.positions.size());
  mesh.positions.insert(mesh.positions.end(), part.positions.begin(), part.positions.end());
  if (normals) mesh.normals.insert(mesh.normals.end(), part.normals.begin(), part.normals.end());
  else mesh.normals.clear();
  for (const Triangle& t : part.triangles)
    mesh.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

}  // namespace frep
