// The marching-tetrahedra surface of one grid cube (Kuhn decomposition) seen from the cube's
// faces: for every sign pattern, the closed loops its boundary draws on the cube's surface.
// The cube extraction (docs/mesher.md, "Cubes") caps each loop of a one-loop cube with a
// fan of straight triangles, so a cube makes the triangles marching cubes would.
//
// Loop vertices are cube-local edge ids: 0..11 the cube's edges, 12..17 its face diagonals
// (the Kuhn split of each face), 18 the main diagonal (never on a loop: it is inside).
#pragma once

#include <array>
#include <cstdint>

#include "mesh/kuhn_tetrahedra.h"

namespace frep {

constexpr int kCubeEdgeIds = 19;
constexpr int kFirstFaceDiagonal = 12;
constexpr int kMainDiagonal = 18;

struct CubeLoopCase {
  std::uint8_t loops = 0;   // closed loops on the cube's surface (0 when uniform)
  std::uint8_t length = 0;  // vertices of the loop when there is exactly one
  // The loop, oriented as the boundary of the outward-facing surface; face diagonals are on
  // it where the diagonal is crossed: the straight loop skips those not kept.
  std::uint8_t ids[18] = {};
};

struct CubeLoopTables {
  std::array<CubeLoopCase, 256> cases;           // by cell mask (bit c: corner c inside)
  std::array<TetEdge, kCubeEdgeIds> edges;       // id -> (low corner, direction)
  std::array<std::uint8_t, kCubeEdgeIds> faces;  // id -> the cube faces it lies on, bit 2a+s
  std::uint8_t idOf[8][8];  // (low corner, direction) -> id, 255 where no such edge

  // A cube of this sign pattern is capped by a fan over its one loop; any other crossed cube
  // keeps its tetrahedra's triangles.
  bool fanned(int mask) const { return cases[mask].loops == 1; }
};

const CubeLoopTables& cubeLoopTables();

}  // namespace frep
