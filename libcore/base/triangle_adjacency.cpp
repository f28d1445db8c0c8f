#include "base/triangle_adjacency.h"

namespace frep {

std::vector<std::array<std::uint32_t, 3>> facetNeighbours(const TriangleMesh& mesh) {
  const std::size_t nv = mesh.positions.size(), nf = mesh.triangles.size();
  // Facets around each vertex, as a compressed table (counting sort by vertex).
  std::vector<std::uint32_t> start(nv + 1, 0);
  for (const Triangle& t : mesh.triangles)
    for (std::uint32_t v : t) ++start[v + 1];
  for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<std::uint32_t> around(start.back()), fill(start.begin(), start.end() - 1);
  for (std::uint32_t f = 0; f < nf; ++f)
    for (std::uint32_t v : mesh.triangles[f]) around[fill[v]++] = f;

  std::vector<std::array<std::uint32_t, 3>> neighbours(nf);
  for (std::uint32_t f = 0; f < nf; ++f) {
    const Triangle& t = mesh.triangles[f];
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t a = t[i], b = t[(i + 1) % 3];
      std::uint32_t found = kNoNeighbour;
      int sharing = 0;
      for (std::uint32_t k = start[a]; k < start[a + 1]; ++k) {
        const std::uint32_t g = around[k];
        if (g == f) continue;
        const Triangle& u = mesh.triangles[g];
        if (u[0] == b || u[1] == b || u[2] == b) {
          found = g;
          ++sharing;
        }
      }
      neighbours[f][i] = sharing == 1 ? found : kNoNeighbour;
    }
  }
  return neighbours;
}

}  // namespace frep
