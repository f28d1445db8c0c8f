// Parts of the solid the grid cannot see: a sliver of solid that passes between two outside
// grid points without touching either (a wall thinner than a cell, the tip of a crease, a
// grazing contact), or a gap that passes between two inside ones. The mesh, made from the
// grid points' signs, leaves the first out and closes the second; the mesher counts both so
// that the user hears of it (docs/mesher.md, "Parts thinner than a cell").
//
// Found along the grid's lines: where the values at four points in a row, p-1, p, p+1 and
// p+2, rise towards the edge p-p+1 from both sides while p and p+1 are both outside, the two
// lines through (p-1, p) and (p+2, p+1) meet above zero between p and p+1 (a tent: the field
// of a wedge or a thin wall is a min of nearly linear parts), and the field evaluated where
// they meet is inside, then that point is a point of the solid on the edge. The same with
// the signs swapped for gaps. Each such edge is proved by a point of the field itself; edges
// whose values do not look like a tent are not found (about 85 % of such edges are on the
// gyroid at 256 cells, measured by sampling each edge at sixteen points).
#pragma once

#include <cstdint>

namespace frep {

// Where on the edge from p (t = 0) to p + 1 (t = 1) the lines through the values at p - 1, p
// and at p + 2, p + 1 meet beyond zero, the four values (`before` = f(p - 1), `a` = f(p),
// `b` = f(p + 1), `after` = f(p + 2)) seen from the side of `a` and `b`, which share it
// (both inside, >= 0, or both outside, < 0). Returns false where they do not: no tent, or
// one that stays on a and b's side of zero (NaN anywhere: false).
bool tentCrossesZero(double before, double a, double b, double after, double* t);

// One line's side of such a tent, seen from the edge: the value v at the edge's end rises
// from `beyond` towards the edge (seen from outside; falls seen from inside) steeply enough
// that the line through them crosses zero within the edge. Both sides must, for the tent to.
inline bool sideCrossesZero(double v, double beyond) {
  return v < 0.0 ? (v > beyond) & (2.0 * v - beyond >= 0.0)
                 : (v < beyond) & (2.0 * v - beyond < 0.0);
}

// The sieve over a row of edges a[i] - b[i] (i < count) with neighbours before[i] (beside a)
// and after[i] (beside b): flags[i] is 1 where a and b lie on one side and both neighbours
// pass sideCrossesZero, else 0; returns whether any is 1. An infinite value of the ends' side passes as a neighbour
// (the mesher's stand-in for a point proven uniform or not held, whose value it evaluates
// later) and fails as an end. Comparisons only, no branches: vector code (this file is
// compiled without trapping maths, which lets the compiler evaluate both sides of a
// comparison).
bool sieveTentRow(const double* before, const double* a, const double* b, const double* after,
                  std::int64_t count, double* flags);

}  // namespace frep
