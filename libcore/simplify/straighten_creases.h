// Creases made straight and sharp without simplifying the rest: the simplifier
// (simplify/simplify.h) run with collapses only where the merged vertex goes onto a crease or
// a corner, then its snaps and crease flips. Where the grid's cubes left a crease chamfered
// (two rows of edges either side of it, each turning by half the crease's angle) or
// zig-zagging across it (a cube whose corners all lie outside the crease's tip places no
// vertex on it), the vertices either side are merged onto the crease line and its edges are
// flipped to run along it. Every change passes the simplifier's tests, so the mesh stays
// printable, within a third of a cell of the surface. docs/mesher.md, "Straightened creases".
#pragma once

#include <functional>

#include "base/triangle_mesh.h"
#include "base/vec.h"
#include "frep/field.h"
#include "simplify/simplify.h"

namespace frep {

// How far a face may move from F = 0 to reach a crease, and the longest edge a merge onto a
// crease may make, in cells. Measured on the twist (docs/performance.md, "Straightened
// creases"): an edge bound of 1.5 cells left chamfers that need a merge across a cube's
// diagonal (crease length 20.75 at 512 cells against the exact 19.956), 2 to 4 cells all met
// 0.5 %, and without a bound the crease vertices swallowed their neighbours along the crease
// (68,000 merges instead of 16,000, twice the time) and a few long faces left chamfers again.
constexpr double kStraightenToleranceCells = 0.3;
constexpr double kStraightenLongestEdgeCells = 2.5;

struct StraightenOptions {
  Box3 bbox;          // the meshing box
  double cell = 0.0;  // the mesher's cell size (> 0)
  // fraction done (0..1), from the calling thread; false cancels (throws Cancelled)
  std::function<bool(double)> progress;
};

// The simplifier's options for it (also for callers that run it their own way).
SimplifyOptions straightenOptions(const StraightenOptions& options);

// Throws ModelError for options out of range, Cancelled.
TriangleMesh straightenCreases(const TriangleMesh& mesh, const Field& field,
                               const StraightenOptions& options, SimplifyStats* stats = nullptr);

}  // namespace frep
