// Fewer triangles from a mesher mesh, keeping every guarantee the mesher gives (closed,
// manifold, oriented, no self-intersection, no degenerate face), by edge collapses that
// are each proved safe before they are made:
// - the link condition (the surface keeps its topology, no face or edge doubles);
// - every face the collapse changes is tested against every face near it with CGAL's exact
//   predicates and rules (check/face_pair_test.h), on the float coordinates that are written;
// - no face folds over (its normal turns less than a right angle) or becomes a sliver worse
//   than those it replaces;
// - the surface stays within `tolerance` of F = 0 (at the moved vertex and at the centres of
//   the changed faces, distance estimated as |F| / |grad F|), or, where the mesher's faces
//   were farther already (creases the grid cut off), gets no farther.
// Merged vertices are placed by the quadric of the field's tangent planes at the vertices
// they replace (dual contouring's Hermite data), so creases and corners the grid cut off
// come back; without sharp features a vertex stays where one of the two already was. With
// them, edge flips under the same tests then let the edges of a crease follow it
// (creaseFlips).
// Collapses run in parallel in cubic regions: a region changes only the faces whose three
// vertices lie in it, and keeps moved vertices in it, so regions never meet; the faces
// crossing regions are frozen in one pass and inner in the next (regions shift between
// passes). docs/mesher.md says why this and not a dual method.
#pragma once

#include <cstddef>
#include <functional>

#include "base/triangle_mesh.h"
#include "base/vec.h"
#include "frep/field.h"

namespace frep {

struct SimplifyOptions {
  Box3 bbox;             // the meshing box: the mesher meshed min(F, box distance)
  double cell = 0.0;     // the mesher's cell size (> 0): the unit of regions and of the search
  double tolerance = 0.0;  // how far the surface may move from F = 0 (absolute, > 0)
  double maxEdge = 0.0;    // the longest edge a collapse may make (0: no bound)
  bool sharpFeatures = true;
  // With sharp features: after the collapses, edges that turn by over 20 degrees are flipped
  // where that lowers the turning (length x angle) of the faces round them, so that the long
  // faces of a simplified crease follow it instead of zig-zagging across (each flip under the
  // collapses' tests). Off: the collapses alone.
  bool creaseFlips = true;
  // Only the collapses whose merged vertex goes onto a crease or a corner (its planes' rank
  // is 2 or 3; needs sharpFeatures): the vertices either side of a chamfered or zig-zagging
  // crease are merged onto it and flat parts are left alone (straightenCreases). Off: any
  // collapse the tests allow.
  bool creaseCollapsesOnly = false;
  int regionCells = 16;  // region edge, in cells
  int passes = 3;
  // fraction done (0..1), from the calling thread; false cancels (throws Cancelled)
  std::function<bool(double)> progress;
};

struct SimplifyStats {
  std::size_t trianglesBefore = 0, trianglesAfter = 0, collapses = 0;
  std::size_t flips = 0;  // edges flipped to follow a crease
  // The largest distance from F = 0 of a face the simplifier made (estimated at its centre):
  // at most the tolerance, except where the mesher's faces were farther already (a crease
  // the grid cut off), which are only ever made better.
  double largestDistance = 0.0;
  double seconds = 0.0;
};

// Throws ModelError for options out of range, Cancelled.
TriangleMesh simplifyMesh(const TriangleMesh& mesh, const Field& field,
                          const SimplifyOptions& options, SimplifyStats* stats = nullptr);

}  // namespace frep
