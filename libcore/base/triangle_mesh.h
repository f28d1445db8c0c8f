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

}  // namespace frep
