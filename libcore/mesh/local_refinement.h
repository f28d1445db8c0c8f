// Local refinement: the cubes where a part thinner than a cell hides between the grid's
// points, meshed again at half a cell after the weld (docs/mesher.md, "Local refinement").
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "base/triangle_mesh.h"
#include "frep/field.h"
#include "mesh/mesher.h"
#include "mesh/sampling_grid.h"

namespace frep {

struct LocalRefinementStats {
  std::size_t cubes = 0;             // cubes meshed at half a cell
  std::size_t trianglesRemoved = 0;  // the cube extraction's triangles taken out
  std::size_t trianglesAdded = 0;    // the half cubes' fans and the seam's split triangles
  std::size_t evaluations = 0;       // points of the field evaluated
  std::size_t cubesLeftOut = 0;      // cubes it would have refined but could not
  std::size_t splitCells = 0;        // cells with several loops split in eight
  std::size_t flips = 0;             // crease flips between half cubes
  std::size_t unflipped = 0;         // crease flips on the region's rim turned back
  std::size_t conedCells = 0;        // ... and at the finest split, meshed by tetrahedra
  std::string skipped;               // why the mesh was left as it was (empty: it was not)
  // Deeper levels (levels > 1): the half cubes meshed again at a quarter cell (and so on),
  // how many it would have refined but could not, and why the deepest asked for was not
  // reached (empty: it was, or nothing there needed it).
  int levels = 0;  // the deepest level meshed
  std::size_t deeperCubes = 0;
  std::size_t deeperCubesLeftOut = 0;
  std::string deeperSkipped;
};

// Refines `mesh` (polygonize's welded mesh of `field` on grid `g`, normals or none) in the
// cubes round `seedEdges` (grid edges, lower grid point x 3 + axis, that a hidden part
// crosses) and in the cubes next to them across every face or edge where a point of the
// half-cell grid shows a part the cube's corners miss, up to `maxCubes`. Each such cube is
// split into eight half cubes, sampled at the 27 points of the half-cell grid and capped
// loop by loop with fans; the cube extraction's lines on the faces the region shares with
// the rest of the mesh stay as they are (the region's side draws them too), so the seam is
// exact and nothing outside the region moves (local_refinement.cpp says why no triangle can
// cross another). Where the region meets a case it does not handle (a half cube with more
// than one loop, a line through a point of the half-cell grid), the mesh is left as it was
// and `stats->skipped` says why. With `levels` > 1 (docs/mesher.md, "Deeper levels") every
// cube holding a vertex is looked at too: those whose quarter cells show what their corners
// miss join the candidates, and those where the mesh lies farther than 0.3 cell from the
// surface (a crease tip cut short) are refined whatever their points show; then the half
// cubes are refined again the same way where their own half cells show what their corners
// miss, down to cells of 2^-levels. A level that fails keeps the level above's mesh.
// progress(fraction of the refinement done, 0..1) is called between its steps and inside
// its long loops, possibly from worker threads (one call at a time); false cancels: throws
// Cancelled (`mesh` is then of no use). Throws ModelError for levels outside 1 to
// kMaxRefinementLevels.
void refineHiddenParts(const Field& field, const Grid& g,
                       const std::vector<std::uint64_t>& seedEdges, std::size_t maxCubes,
                       TriangleMesh& mesh, LocalRefinementStats* stats, int levels = 1,
                       const std::function<bool(double)>& progress = nullptr);

}  // namespace frep
