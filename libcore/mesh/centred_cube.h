// A cube split around its centre: each face into its two triangles (split as
// mesh/cube_loops.h says: along Kuhn's diagonal, or the other one on a flipped face), and each
// triangle with the centre a tetrahedron, twelve in all. Whatever the split of its faces, they
// draw on every face the lines the neighbour cube draws there, which Kuhn's six tetrahedra do
// only with Kuhn's diagonals: a crossed cube with flipped faces and more than one loop is
// meshed by these (docs/mesher.md, "Ambiguous faces").
#pragma once

#include <vector>

#include "mesh/kuhn_tetrahedra.h"

namespace frep {

// The vertex id of the cube's centre; 0..7 are its corners.
constexpr int kCubeCentre = 8;

// Appends the crossing polygon of every crossed tetrahedron of the cube whose corners are
// inside where `mask` has their bit, its centre where `centreInside`, and whose faces are
// split as `flips` says. Each polygon's `from`/`to` are cube vertex ids (0..8), in the cyclic
// order of a polygon facing from the inside to the outside.
void centredCubeCrossings(int mask, bool centreInside, int flips, std::vector<TetCrossing>& out);

}  // namespace frep
