#include "mesh/cube_loops.h"

#include <map>
#include <vector>

namespace frep {

namespace {

// Face 2a + s is the cube's face at offset s along axis a. An edge from `low` along `dir`
// lies on it when the edge keeps coordinate a fixed at s.
std::uint8_t facesOf(const TetEdge& e) {
  std::uint8_t bits = 0;
  for (int a = 0; a < 3; ++a)
    if (!((e.dir >> a) & 1)) bits |= 1u << (2 * a + ((e.low >> a) & 1));
  return bits;
}

CubeLoopTables build() {
  CubeLoopTables t{};
  for (auto& row : t.idOf)
    for (auto& v : row) v = 255;
  int next = 0;
  // cube edges first, then face diagonals, then the main diagonal: the ids the header names
  for (int dirs : {0, 1}) {
    for (int dir = 1; dir < 8; ++dir) {
      const int bits = (dir & 1) + ((dir >> 1) & 1) + ((dir >> 2) & 1);
      if ((dirs == 0) != (bits == 1)) continue;
      for (int low = 0; low < 8; ++low) {
        if (low & dir) continue;
        if (bits == 2 && low != 0 && (low | dir) != 7) continue;  // Kuhn: diagonals via 0 or 7
        if (bits == 3) continue;
        t.edges[next] = {static_cast<std::uint8_t>(low), static_cast<std::uint8_t>(dir)};
        t.idOf[low][dir] = static_cast<std::uint8_t>(next++);
      }
    }
  }
  t.edges[next] = {0, 7};
  t.idOf[0][7] = static_cast<std::uint8_t>(next++);
  for (int id = 0; id < kCubeEdgeIds; ++id) t.faces[id] = facesOf(t.edges[id]);

  const KuhnTables& kt = kuhnTables();
  for (int mask = 1; mask < 255; ++mask) {
    // Boundary edges of the tetrahedra's surface: polygon edges lying in a cube face, kept
    // in their polygon's direction (the outward surface's boundary orientation).
    std::map<int, int> nextOf;
    for (int tet = 0; tet < 6; ++tet) {
      int m = 0;
      for (int v = 0; v < 4; ++v) m |= ((mask >> kt.tets[tet][v]) & 1) << v;
      const TetPolygon& p = kt.polygons[tet][m];
      for (int i = 0; i < p.count; ++i) {
        const int a = t.idOf[p.edges[i].low][p.edges[i].dir];
        const int b = t.idOf[p.edges[(i + 1) % p.count].low][p.edges[(i + 1) % p.count].dir];
        if (t.faces[a] & t.faces[b]) nextOf[a] = b;
      }
    }
    CubeLoopCase& c = t.cases[mask];
    std::map<int, bool> seen;
    for (const auto& [start, unused] : nextOf) {
      (void)unused;
      if (seen[start]) continue;
      ++c.loops;
      std::vector<int> loop;
      for (int v = start; !seen[v]; v = nextOf.at(v)) {
        seen[v] = true;
        loop.push_back(v);
      }
      if (c.loops == 1) {
        c.length = static_cast<std::uint8_t>(loop.size());
        for (std::size_t i = 0; i < loop.size(); ++i) c.ids[i] = static_cast<std::uint8_t>(loop[i]);
      }
    }
    if (c.loops != 1) c.length = 0;
  }
  return t;
}

}  // namespace

const CubeLoopTables& cubeLoopTables() {
  static const CubeLoopTables tables = build();
  return tables;
}

}  // namespace frep
