// Polygonisation of a field (a compiled FRep tree or any other Field) inside a bounding box at a
// given cell size.
//
// Guarantees, for any function: the mesh is closed, 2-manifold, consistently oriented with
// normals pointing out of the solid F >= 0, free of self-intersections, and every triangle
// has three distinct, non-collinear vertices. How (see docs/mesher.md): the topology of
// marching tetrahedra on the Kuhn decomposition of a regular grid (no ambiguous cases), each
// crossed cube capped by a fan over the loop that topology draws on its faces (marching
// cubes' triangle count; embedded by construction), creases and corners given vertices from
// the gradient, the bounding box intersected into the field (so cut solids get caps),
// vertices found by bracketed root finding and kept strictly inside their grid edge.
#pragma once

#include <cstddef>
#include <functional>
#include <string>

#include "base/mesh_piece.h"
#include "base/triangle_mesh.h"
#include "base/vec.h"
#include "frep/field.h"
#include "mesh/mesh_settings.h"

namespace frep {

struct MeshingOptions {
  Box3 bbox;
  // What the user chose (mesh/mesh_settings.h); the mesher reads mesher, sharpFeatures,
  // dropFlatVertices, refine and refineLevels (the rest are meshAndFinish's).
  MeshSettings settings;
  // Look for parts thinner than a cell that pass between the grid's points (MeshingStats's
  // thin parts; docs/mesher.md): the mesh is the same either way, and looking costs 4 to 9 %
  // of the meshing time (docs/performance.md).
  bool findThinParts = true;
  // At most this many cubes are meshed again by settings.refine.
  std::size_t refinementCubes = 200000;
  double resolution = 0.05;  // target cell size; the grid fits the box exactly (cells <= this)
  int brickCells = 16;       // cells per brick edge: the unit of pruning and threading (even)
  int rootIterations = 8;    // Illinois iterations per edge vertex
  bool normals = true;       // per-vertex normals from the gradient
  // Memory the mesh may take (bytes; 0: no limit) at `bytesPerTriangle` (the mesher's own
  // need is up to about 50; a caller that checks the mesh with CGAL adds the check's). The
  // triangles are estimated from the active bricks before any is meshed, and an estimate
  // over the budget is a ModelError with the figures and the smallest cell size that fits.
  std::size_t memoryBudget = 0;
  double bytesPerTriangle = 60.0;
  // Called with the fraction done (0..1), possibly from worker threads (one call at a time).
  // Return false to cancel: polygonize then throws frep::Cancelled.
  std::function<bool(double)> progress;
};

struct MeshingStats {
  MeshSettings settings;             // what the mesh was made with
  std::size_t cells[3] = {0, 0, 0};  // grid cells per axis (including the outside layer)
  std::size_t bricksTotal = 0;
  std::size_t bricksActive = 0;  // bricks interval pruning could not prove empty or full
  std::size_t pointsEvaluated = 0;
  // The bricks' vertices were merged by a global sort because the ownership weld could not
  // place one (never expected: a sign that bricks disagree about a shared face).
  bool weldedBySorting = false;
  // Parts of the solid thinner than a cell, which the grid passes between (docs/mesher.md,
  // "Parts thinner than a cell"), counted as the grid edges they cross between two points of
  // the other side, each proved by a point of the field: seen nowhere near (no surface the
  // mesh draws within a cell): solid the mesh leaves out (walls, struts or slivers thinner
  // than a cell) and gaps it closes; and beside the mesh's surface: the tips of creases and
  // thin edges, cut off short. A point on the first part of the first kind found (of the
  // second where there is none).
  std::size_t thinSolidEdges = 0, thinGapEdges = 0, tipEdges = 0;
  Vec3 thinExample = {0, 0, 0};
  // Local refinement (settings.refine): the cubes meshed at half a cell, or why none were.
  std::size_t refinedCubes = 0;
  std::string refinementSkipped;
  // ... deeper levels (refineLevels > 1): the deepest level meshed, the smaller cubes
  // meshed again below the first level, those left out, and why a level was not reached
  int refinementLevelsReached = 0;
  std::size_t refinedDeeperCubes = 0;
  std::size_t refinedDeeperLeftOut = 0;
  std::string refinementDeeperSkipped;
  double seconds = 0.0;
};

// Throws ModelError on bad options (empty box, resolution <= 0, grid too large), Cancelled.
TriangleMesh polygonize(const Field& field, const MeshingOptions& options,
                        MeshingStats* stats = nullptr);

// Brick jobs: the mesh of a box of the mesher's bricks, made anywhere, welded with
// its neighbours' by key (mesh/piece_merge.h) into exactly the mesh polygonize makes.
//
// The bricks per axis of the grid polygonize makes for these options (validated as
// polygonize does: ModelError).
void brickGrid(const MeshingOptions& options, std::int64_t bricks[3]);
// The bricks [brickLo, brickHi) alone, as a piece: vertices keyed by grid edge, crease flips
// inside the job made, those across its faces left to the merge; no normals. Throws as
// polygonize does, and ModelError for bricks outside the grid.
MeshPiece polygonizePiece(const Field& field, const MeshingOptions& options,
                          const std::int64_t brickLo[3], const std::int64_t brickHi[3],
                          MeshingStats* stats = nullptr);

// Largest grid polygonize accepts, in cells per axis.
constexpr std::size_t kMaxCellsPerAxis = 1u << 16;

}  // namespace frep
