// The surface of one grid cube seen from the cube's faces: for every sign pattern, and for
// every way of splitting the cube's ambiguous faces, the closed loops the surface draws on the
// cube's surface. The cube extraction (docs/mesher.md, "Cubes") caps each loop of a one-loop
// cube with a fan of straight triangles, so a cube makes the triangles marching cubes would.
//
// A face is split into two triangles along a diagonal, and the loops follow from the
// triangles' signs. The Kuhn decomposition (mesh/kuhn_tetrahedra.h) splits every face along
// the diagonal through corner 0 or 7. A face whose corners alternate in sign (ambiguous) is
// split along the diagonal the field's value at the face's centre favours: through the two
// inside corners where the centre is inside, else through the two outside ones. `flips` has
// bit f set where that is not Kuhn's diagonal (only ambiguous faces are ever flipped).
//
// Loop vertices are cube-local edge ids: 0..11 the cube's edges, 12..17 its face diagonals
// (the Kuhn split of each face), 18 the main diagonal (never on a loop: it is inside). A
// flipped diagonal joins two corners of one sign, so it is never crossed and needs no id.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <vector>

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
  std::vector<CubeLoopCase> cases;          // by flips * 256 + cell mask (bit c: corner c inside)
  std::array<TetEdge, kCubeEdgeIds> edges;  // id -> (low corner, direction)
  std::array<std::uint8_t, kCubeEdgeIds> faces;  // id -> the cube faces it lies on, bit 2a+s
  std::uint8_t idOf[8][8];  // (low corner, direction) -> id, 255 where no such edge
  // Face f = 2a + s: its corners in cyclic order, from s << a along axis a + 1, then a + 2;
  // Kuhn's diagonal joins the first and the third.
  std::uint8_t faceCorners[6][4];
  // Face f's two triangles: [f][0] split along Kuhn's diagonal, [f][1] along the other. The
  // fans' loops and the cubes split round their centre (mesh/centred_cube.h) both read them,
  // so the two draw the same lines on every face.
  std::uint8_t faceTriangles[6][2][2][3];
  std::array<std::uint8_t, 256> ambiguous;  // by cell mask: the faces whose corners alternate

  const CubeLoopCase& caseOf(int mask, int flips) const { return cases[flips * 256 + mask]; }
  // A cube of this sign pattern and split is capped by a fan over its one loop; any other
  // crossed cube keeps the triangles of its tetrahedra (mesh/centred_cube.h where it has
  // flipped faces).
  bool fanned(int mask, int flips) const { return caseOf(mask, flips).loops == 1; }
};

const CubeLoopTables& cubeLoopTables();

// The loops that directed lines on the cube's faces make (nextOf: from one cube-local edge id
// to the next along the loop): how many, and the first, started at its least id.
CubeLoopCase loopsFromLines(const std::map<int, int>& nextOf);

}  // namespace frep
