// The Kuhn (Freudenthal) decomposition of a grid cube into six tetrahedra sharing the main
// diagonal corner 0 -> corner 7, and the marching-tetrahedra polygon for every sign pattern.
// Neighbouring cubes split their common face along the same diagonal, so the tetrahedra of the
// whole grid form one simplicial complex: no ambiguous cases, no cracks.
// Corner c of a cell sits at offset (c & 1, (c >> 1) & 1, (c >> 2) & 1).
#pragma once

#include <array>
#include <cstdint>

namespace frep {

struct TetEdge {
  std::uint8_t low;  // corner with the smaller coordinates (its offset is a subset of the other's)
  std::uint8_t dir;  // offset from low to high as a bit mask, 1..7
};

// The edge between two corners of a cube (0..7), from the one with the smaller coordinates.
TetEdge edgeBetween(int a, int b);

// The surface piece a tetrahedron contributes: nothing, a triangle, or a quad (cyclic order),
// oriented so that its normal points from the inside (F >= 0) to the outside.
struct TetPolygon {
  std::uint8_t count = 0;  // 0, 3 or 4
  TetEdge edges[4];
};

// The crossing of a positively oriented tetrahedron whose vertex i is inside when bit i of
// `mask` is set: its crossed edges as pairs of its vertices (0..3), in the cyclic order of
// a polygon facing from the inside to the outside (docs/mesher.md). Any tetrahedron, not
// only Kuhn's: the cubes split around their centre use it too (mesh/centred_cube.h).
struct TetCrossing {
  std::uint8_t count = 0;  // 0, 3 or 4
  std::uint8_t from[4] = {}, to[4] = {};
};
TetCrossing tetCrossing(int mask);

struct KuhnTables {
  std::array<std::array<std::uint8_t, 4>, 6> tets;  // corner ids, positively oriented
  // polygons[t][mask]: mask bit i set when corner tets[t][i] is inside
  std::array<std::array<TetPolygon, 16>, 6> polygons;
};

const KuhnTables& kuhnTables();

}  // namespace frep
