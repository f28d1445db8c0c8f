#include "base/mesh_invariants.h"

#include <stdexcept>

#include "base/triangle_adjacency.h"

namespace frep {

std::string meshInvariantBroken(const TriangleMesh& mesh) {
  const auto& t = mesh.triangles;
  for (std::size_t f = 0; f < t.size(); ++f)
    if (t[f][0] == t[f][1] || t[f][1] == t[f][2] || t[f][2] == t[f][0])
      return "triangle " + std::to_string(f) + " repeats a vertex";
  const std::vector<std::array<std::uint32_t, 3>> next = facetNeighbours(mesh);
  for (std::size_t f = 0; f < t.size(); ++f)
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t a = t[f][i], b = t[f][(i + 1) % 3], g = next[f][i];
      const std::string edge = "edge " + std::to_string(a) + "-" + std::to_string(b) +
                               " of triangle " + std::to_string(f);
      if (g == kNoNeighbour) return edge + " is a border or shared by more than two triangles";
      bool opposite = false;
      for (int j = 0; j < 3; ++j) opposite |= t[g][j] == b && t[g][(j + 1) % 3] == a;
      if (!opposite) return edge + " runs the same way in triangle " + std::to_string(g);
    }
  return {};
}

void assertMeshInvariant(const TriangleMesh& mesh, const char* stage) {
  const std::string broken = meshInvariantBroken(mesh);
  if (!broken.empty())
    throw std::logic_error(std::string(stage) + " broke the mesh's promise: " + broken);
}

}  // namespace frep
