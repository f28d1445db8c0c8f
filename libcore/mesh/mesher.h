// Polygonisation of a field (a compiled FRep tree or any other Field) inside a bounding box at a given cell size.
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

namespace frep {

// How a crossed cube becomes triangles (docs/mesher.md).
enum class Extraction {
  // Each cube whose surface meets its faces in one loop caps that loop with a fan of
  // straight triangles (as many as marching cubes makes); the rare cube with several loops
  // keeps its tetrahedra's triangles. The default.
  Cubes,
  // Marching tetrahedra in every cube: about three times the triangles (`--mesher tetra`,
  // kept for one release).
  Tetrahedra,
};

// The most levels of local refinement (MeshingOptions::refinementLevels): half, quarter and
// eighth cells.
constexpr int kMaxRefinementLevels = 3;

struct MeshingOptions {
  Box3 bbox;
  Extraction extraction = Extraction::Cubes;
  // Cubes only: a cube a crease or corner crosses gets a vertex on it (from the normals'
  // tangent planes) instead of a chamfer across it.
  bool sharpFeatures = true;
  // Cubes only: where the surface is flat to within a fiftieth of a cell, a vertex on a grid
  // edge goes and its neighbours are fanned again, two triangles fewer each time (docs/mesher.md,
  // "Flat vertices"; off with `--keep-flat-vertices`): 6 to 15 % fewer triangles on the
  // reference models, fewer than marching cubes makes, at a cost in meshing time
  // (docs/performance.md). Needs an even brickCells.
  bool flatVertices = true;
  // Look for parts thinner than a cell that pass between the grid's points (MeshingStats's
  // thin parts; docs/mesher.md): the mesh is the same either way, and looking costs 4 to 9 %
  // of the meshing time (docs/performance.md).
  bool findThinParts = true;
  // Mesh the cubes round the parts findThinParts sees nowhere near (solid left out, gaps
  // closed) again at half a cell (mesh/local_refinement.h), and with refineTips those round
  // the tips too (the gyroid's slivers; crease tips, whose creases then come out less
  // clean), up to refinementCubes cubes.
  bool refineThinParts = false;
  bool refineTips = false;
  std::size_t refinementCubes = 200000;
  // Levels of that refinement (1 to kMaxRefinementLevels): 2 meshes the half cubes inside
  // the refined region again at a quarter cell where their own half cells show what their
  // corners miss (the gyroid's slivers, narrower than half a cell; docs/mesher.md, "Deeper
  // levels"), 3 at an eighth.
  int refinementLevels = 1;
  double resolution = 0.05;  // target cell size; the grid fits the box exactly (cells <= this)
  int brickCells = 16;       // cells per brick edge: the unit of pruning and of threading
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
  // Local refinement (refineThinParts): the cubes meshed at half a cell, or why none were.
  std::size_t refinedCubes = 0;
  std::string refinementSkipped;
  // ... deeper levels (refinementLevels > 1): the deepest level meshed, the smaller cubes
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

// Brick jobs (issue 17): the mesh of a box of the mesher's bricks, made anywhere, welded with
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
