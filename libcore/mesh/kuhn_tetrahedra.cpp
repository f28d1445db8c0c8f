#include "mesh/kuhn_tetrahedra.h"

#include <algorithm>

namespace frep {

namespace {

int offset(int corner, int axis) { return (corner >> axis) & 1; }

int orientation(const std::array<std::uint8_t, 4>& t) {
  int d[3][3];
  for (int r = 0; r < 3; ++r)
    for (int a = 0; a < 3; ++a) d[r][a] = offset(t[r + 1], a) - offset(t[0], a);
  const int det = d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1]) -
                  d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0]) +
                  d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0]);
  return det;
}

bool isEven(const int p[4]) {
  int inversions = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) inversions += p[i] > p[j];
  return inversions % 2 == 0;
}

TetPolygon polygonFor(const std::array<std::uint8_t, 4>& t, int mask) {
  const TetCrossing c = tetCrossing(mask);
  TetPolygon poly;
  poly.count = c.count;
  for (int i = 0; i < c.count; ++i) poly.edges[i] = edgeBetween(t[c.from[i]], t[c.to[i]]);
  return poly;
}

KuhnTables build() {
  KuhnTables k{};
  static const int kPerms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int t = 0; t < 6; ++t) {
    const int a = 1 << kPerms[t][0], b = 1 << kPerms[t][1];
    std::array<std::uint8_t, 4> tet = {0, static_cast<std::uint8_t>(a),
                                       static_cast<std::uint8_t>(a | b), 7};
    if (orientation(tet) < 0) std::swap(tet[1], tet[2]);
    k.tets[t] = tet;
    for (int mask = 0; mask < 16; ++mask) k.polygons[t][mask] = polygonFor(tet, mask);
  }
  return k;
}

}  // namespace

TetEdge edgeBetween(int a, int b) {
  const int low = (a & b) == a ? a : b;
  return {static_cast<std::uint8_t>(low), static_cast<std::uint8_t>(a ^ b)};
}

// Derivation (docs/mesher.md): for a positively oriented tetrahedron (v0..v3) with only v0
// inside, the triangle (e01, e02, e03) faces away from v0; with {v0, v1} inside, the quad
// (e02, e03, e13, e12) faces away from them. Even permutations keep the orientation.
TetCrossing tetCrossing(int mask) {
  TetCrossing c;
  int insideCount = 0;
  for (int i = 0; i < 4; ++i) insideCount += (mask >> i) & 1;
  auto edge = [&](int k, int i, int j) {
    c.from[k] = static_cast<std::uint8_t>(i);
    c.to[k] = static_cast<std::uint8_t>(j);
  };
  if (insideCount == 1 || insideCount == 3) {
    const bool loneInside = insideCount == 1;
    int lone = 0;
    for (int i = 0; i < 4; ++i)
      if ((((mask >> i) & 1) == 1) == loneInside) lone = i;
    static const int kEven[4][4] = {{0, 1, 2, 3}, {1, 0, 3, 2}, {2, 3, 0, 1}, {3, 2, 1, 0}};
    const int* p = kEven[lone];
    c.count = 3;
    edge(0, p[0], p[1]);
    edge(1, p[0], loneInside ? p[2] : p[3]);
    edge(2, p[0], loneInside ? p[3] : p[2]);
  } else if (insideCount == 2) {
    int in[2], out[2], ni = 0, no = 0;
    for (int i = 0; i < 4; ++i) ((mask >> i) & 1 ? in[ni++] : out[no++]) = i;
    int p[4] = {in[0], in[1], out[0], out[1]};
    if (!isEven(p)) std::swap(p[2], p[3]);
    c.count = 4;
    edge(0, p[0], p[2]);
    edge(1, p[0], p[3]);
    edge(2, p[1], p[3]);
    edge(3, p[1], p[2]);
  }
  return c;
}

const KuhnTables& kuhnTables() {
  static const KuhnTables tables = build();
  return tables;
}

}  // namespace frep
