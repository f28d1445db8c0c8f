// The mesher's work on one brick, shared by the files that hold its phases (the mesher's
// internals: nothing outside mesh/ includes this). Which file holds what:
//   brick_mesher.cpp        run(): the field at the grid points, crossed cubes, vertices
//                           (locateRoots), triangles
//   brick_thin_parts.cpp    parts thinner than a cell found and proved
//   brick_cubes.cpp         ambiguous faces, kept diagonals, loops capped by fans
//   brick_flat_vertices.cpp flat vertices dropped
//   brick_features.cpp      feature points on creases and corners
//   mesher.cpp              the driver: bricks collected and meshed in parallel, welded
#pragma once

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <future>
#include <limits>
#include <mutex>
#include <sstream>

#include "base/errors.h"
#include "base/mesh_invariants.h"
#include "base/progress.h"
#include "base/qef.h"
#include "base/triangle_geometry.h"
#include "mesh/centred_cube.h"
#include "mesh/crease_flips.h"
#include "mesh/cube_loops.h"
#include "mesh/edge_roots.h"
#include "mesh/feature_point.h"
#include "mesh/flat_vertex_removal.h"
#include "mesh/hidden_parts.h"
#include "mesh/kuhn_tetrahedra.h"
#include "mesh/local_refinement.h"
#include "mesh/mesher.h"
#include "mesh/sampling_grid.h"

namespace frep {
namespace meshing {

// (A vertex is kept kEdgeMargin of its edge away from both grid points: mesh/edge_roots.h.)
// The least number of float32 steps a cell must span (so kEdgeMargin is a few steps).
constexpr double kMinCellFloatSteps = 256.0;
// Triangles per cell of a brick's face, for the memory estimate: marching tetrahedra's (5 to
// 7 on the reference models) and the cubes' (a third of that, the gyroid's 2.8 times fewer:
// 2.5 errs on the side of a mesh that fits).
constexpr double kTrianglesPerFaceCell = 6.0;
constexpr double kCubeTrianglesPerFaceCell = 2.5;
// Cells per edge of the sub-blocks of a brick that are proven uniform before its points are
// evaluated: the octants of a 16-cell brick. An interval evaluation costs about as much as
// a few dozen point evaluations (branches and outward rounding against straight vector
// kernels), so 4-cell sub-blocks evaluated fewer points but took longer (the helix at 256
// cells: 2.7 million points in 0.53 s against 4.0 million in 0.38 s with octants).
constexpr std::int64_t kSubCells = 8;
// Root finding stops on an edge once its bracket is kRootBracket narrow (mesh/edge_roots.h),
// or once the next estimate would move the vertex by less than this fraction of the edge.
// Illinois converges superlinearly, so the vertex is then far closer than this to the root
// (the reference models at 256 cells: mean distance 1e-4 of a cell, as with full
// convergence), at about half the evaluations (2.1 instead of 5.2 per vertex on the helix).
constexpr double kRootStep = 1e-3;
// A cube's loop is a sharp feature when two of its vertices' normals differ by more than
// this angle (its cosine; 37 degrees): extended marching cubes' test.
constexpr double kFeatureCos = 0.8;
// Quadric directions weaker than this fraction of the strongest are not solved (the vertex
// stays at the planes' mean along them), as dual contouring truncates its QEF.
constexpr double kFeatureCutoff = 0.02;
// A vertex placed inside a cube keeps this fraction of the cell off its faces.
constexpr double kInnerMargin = 0.05;
// A feature point this many cells beyond a face of its cube, into a cube no surface crosses,
// is followed there (reachIntoUniformNeighbour): clamped into its own cube it would be over
// 0.45 cell from the tip. Shallower tips stay clamped, where the fan keeps its crease flip:
// following every tip (twist, 512 cells) took the Hausdorff distance from 0.52 to 0.46 cell
// but the crease length from 24.9 to 45.7, this threshold to 0.44 and 24.9.
constexpr double kReachBeyond = 0.4;
// ... and only where the pyramid lets it go more than this many cells past the face: near the
// face's rim the pyramid is shallow, and a vertex that gains a few hundredths of a cell is
// not worth the crease flip its fan loses (the twist at 151 cells: a rim along a grid line,
// crease length 28.7 with any depth, 22.3 with this).
constexpr double kReachAtLeast = 0.1;
// A flat vertex goes only where the surface moves by at most this many cells, and no new
// triangle is thinner than this triangleQuality (an equilateral one has 0.29).
constexpr double kFlatDeviation = 0.02;
constexpr double kFlatQuality = 0.02;

struct CellRange {
  std::int64_t lo[3], hi[3];  // cells [lo, hi) per axis
};

// The box of a range's grid points, widened by a hundredth of a cell: the points root finding
// evaluates along an edge (p + t d) may round a little past the edge's end.
inline Box3 rangeBox(const Grid& g, const CellRange& r) {
  Box3 b;
  for (int a = 0; a < 3; ++a) {
    b.lo[a] = g.coord(a, r.lo[a]) - 0.01 * g.h[a];
    b.hi[a] = g.coord(a, r.hi[a]) + 0.01 * g.h[a];
  }
  return b;
}

// Interval proof that every grid point of the range has the same side. Intervals enclose the
// computed point values rigorously (frep/interval.h), so no margin is needed; a point that may
// be NaN counts as outside, so it spoils an "inside" proof only.
// +1: every grid point of the range proven inside, -1: outside, 0: not proven.
inline int provenSign(const Field& field, const Grid& g, const CellRange& r) {
  Interval p[3];
  for (int a = 0; a < 3; ++a) p[a] = {g.coord(a, r.lo[a]), g.coord(a, r.hi[a])};
  const Interval f = field.evalInterval(p[0], p[1], p[2]);
  const Interval v = min(f, g.boxField(p[0], p[1], p[2]));
  if (v.hi < 0.0) return -1;
  if (v.lo >= 0.0 && !v.nan) return 1;
  return 0;
}
inline bool provenUniform(const Field& field, const Grid& g, const CellRange& r) {
  return provenSign(field, g, r) != 0;
}

// Who owns a brick's vertex (see weld()): another brick, this one, or this one with the
// vertex on one of its lower faces (where a neighbour may hold it too and ask for it).
enum class Ownership : std::uint8_t { Other, Own, OwnShared };

struct BrickResult {
  std::vector<std::uint64_t> keys;  // global edge key per local vertex
  std::vector<Ownership> owner;     // per local vertex
  std::vector<Vec3f> positions;
  std::vector<Vec3f> normals;            // when asked for; NaN for the vertices other bricks own
  std::vector<Triangle> triangles;       // local vertex ids
  std::vector<std::uint32_t> flippable;  // triangles crease flips may pair (local indices)
  // Grid edges this brick owns that a part thinner than a cell crosses between two grid points
  // of the other side (hidden_parts.h): seen nowhere near (solid, gaps), or beside the surface
  // the mesh draws (tips); and an example, the first (by key: grid point x 3 + axis) of the
  // first kind where there is one, so that it is the same whatever the bricks.
  std::size_t thinSolid = 0, thinGaps = 0, tips = 0;
  bool exampleUnseen = false;
  std::uint64_t exampleKey = std::numeric_limits<std::uint64_t>::max();
  Vec3 example = {0, 0, 0};
  std::vector<std::uint64_t> hiddenEdges, tipEdges;  // by kind and key (for refinement)
};

struct Scratch {
  std::vector<double> x, y, z, f;        // the grid's coordinates per axis; values per point
  std::vector<double> qx, qy, qz, qf;    // the points evaluated, packed
  std::vector<char> need;                // grid point needs its value
  std::vector<std::int8_t> standIn;      // proven sign of a point that needs none
  std::vector<std::int32_t> edgeVertex;  // local edge key -> local vertex id
  std::vector<std::uint32_t> edgeOf;     // new local vertex -> local edge key
  std::vector<std::uint32_t> polys;      // 4 ids per polygon, last = UINT32_MAX for triangles
  std::vector<std::uint8_t> cellMask;    // per cube: bit v set when corner v is inside
  std::vector<std::uint8_t> insidePair;  // per point: bit 0 inside, bit 1 its +x neighbour
  std::vector<std::uint8_t> kept;        // per local edge key: a face diagonal that stays
  std::vector<std::uint8_t> cellFlips;   // per cube: its faces split off Kuhn's diagonal
  std::vector<double> centreValue;       // per cube split around its centre: the value there
  std::vector<double> ax, ay, az, af;    // face and cube centres evaluated, packed
  std::vector<std::uint32_t> centreOf;   // the cube (or cube * 6 + face) of each
  std::vector<TetCrossing> crossings;    // one centred cube's polygons
  std::vector<std::uint32_t> loops;      // per cube: base, length, (vertex, cube-local id)...
  // corners of the neighbour bricks' cubes next to this brick's faces
  std::vector<double> hx, hy, hz, hf;
  std::vector<std::uint32_t> haloKey;
  std::vector<std::uint8_t> haloMask;  // the neighbour's corners known here, and the axis
  std::vector<std::int64_t> haloCube;  // the neighbour's lowest grid point, 3 per entry
  // root finding, one entry per new vertex
  std::vector<double> px, py, pz, dx, dy, dz, ta, tb, fa, fb;
  std::vector<std::int8_t> lastSide;
  std::vector<std::uint32_t> active;   // edges still being refined
  std::vector<Dual> gx, gy, gz, grad;  // normals: the vertices and the field's gradient there
  std::vector<std::uint32_t> owned;    // normals: the vertices the brick owns
  std::vector<Vec3f> unit;             // unit normal per vertex (NaN where not computed)
  // flat vertices: per cube, its fan's first triangle and count (count 0: no plain fan)
  std::vector<std::uint32_t> fanFirst;
  std::vector<std::uint8_t> fanCount;
  std::vector<Triangle> region;  // the four cubes round an edge: their triangles
  std::vector<std::uint32_t> regionIndex;
  FlatVertexRemoval plan;
  std::vector<std::uint8_t> dropped;
  // parts thinner than a cell: tent candidates (point id x 3 + axis) and where on the edge,
  // the points beside them this brick does not hold (evaluated with the whole field), and
  // the points on the edges evaluated to prove them
  std::vector<std::uint32_t> tentEdge;
  std::vector<double> tentBefore, tentAfter;
  std::vector<double> lx, ly, lz, lf;
  std::vector<std::uint32_t> lazyOf;  // per such point: candidate index x 2 + (0 before, 1 after)
  std::vector<double> tentFlags, tentPassBefore, tentPassAfter;  // one row's sieve
  std::vector<std::uint8_t> rowEvaluated;
};

// The float32 vertex at parameter t along root-finding edge e.
inline Vec3f vertexAt(const Scratch& s, std::size_t e, double t) {
  return {static_cast<float>(s.px[e] + t * s.dx[e]), static_cast<float>(s.py[e] + t * s.dy[e]),
          static_cast<float>(s.pz[e] + t * s.dz[e])};
}

// The local key of the grid edge `e` of the cube whose lowest grid point is `base`: its
// lower grid point x 7 + direction - 1 (the welds' key, in brick-local numbering).
inline std::uint32_t edgeKey(std::uint32_t base, const std::uint32_t cornerOffset[8],
                             const TetEdge& e) {
  return (base + cornerOffset[e.low]) * 7 + (e.dir - 1);
}

// The cube edges of face `face` (bit 2a + s, as CubeLoopTables::faces) whose corners differ.
inline int crossedEdgesOnFace(std::uint32_t mask, std::uint8_t face) {
  const CubeLoopTables& cl = cubeLoopTables();
  int crossed = 0;
  for (int id = 0; id < kFirstFaceDiagonal; ++id) {
    const TetEdge& e = cl.edges[id];
    if ((cl.faces[id] & face) && ((mask >> e.low) & 1) != ((mask >> (e.low | e.dir)) & 1))
      ++crossed;
  }
  return crossed;
}

class BrickMesher {
 public:
  BrickMesher(const Grid& grid, const MeshingOptions& opt) : g_(grid), opt_(opt) {}
  // `field` is the brick's own (specialised) field: equal to the whole one inside the brick;
  // `whole` is the whole one, for the few points just outside the brick.
  std::size_t run(const Field& field, const Field& whole, const CellRange& r, Scratch& s,
                  BrickResult& out) const;

 private:
  // Parts thinner than a cell (mesh/hidden_parts.h): along every grid line, each edge whose
  // two points are evaluated and share a side, where the values at the points beside it make
  // a tent that crosses zero, gets the field evaluated where the tent's lines meet; a point
  // of the other side there proves a hidden part. Edges of a proven sub-block need no test:
  // its intervals hold for every point of its box. Counts the edges this brick owns; returns
  // the evaluations made.
  std::size_t findThinParts(const Field& field, const Field& whole, const CellRange& r,
                            const std::int64_t n[3], Scratch& s, BrickResult& out) const;
  // The candidates for findThinParts (s.tentEdge, with the values beside each edge, NaN where
  // the brick does not hold the point, which is then queued in s.lx/ly/lz for the whole field:
  // beyond the brick's faces, or in a sub-block proven uniform). Every row is sifted in bulk
  // first (sieveTentRow); a neighbour the brick does not hold passes the sieve, and is queued
  // only where the other side's line could make a tent crossing zero within the edge.
  void siftTents(const CellRange& r, const std::int64_t n[3], Scratch& s) const;
  // Whether the edge from local point l along axis a (its ends on the side `inside`) has all
  // eighteen points of its four cubes on that side: then no surface the mesh draws comes
  // within a cell of the hidden part it crosses. Points beyond the brick: the whole field.
  bool seenNowhereNear(const Field& whole, const CellRange& r, const std::int64_t n[3],
                       const std::int64_t l[3], int a, bool inside, const Scratch& s,
                       std::size_t* evaluations) const;
  // The centre of face f (2a + s) of the cube whose lowest grid point is g: computed from the
  // face's own grid lines, so the two cubes sharing it compute the same point.
  Vec3 faceCentre(const std::int64_t g[3], int f) const {
    Vec3 p;
    for (int b = 0; b < 3; ++b) p[b] = b == f / 2 ? g_.coord(b, g[b] + f % 2) : g_.mid(b, g[b]);
    return p;
  }
  // Whether face f of a cube with corners `mask` is split off Kuhn's diagonal, given the
  // field's value at its centre: an ambiguous face goes along the diagonal whose corners
  // share the centre's sign (mesh/cube_loops.h).
  static bool flipped(int mask, int f, double centre) {
    const bool kuhnInside = (mask >> cubeLoopTables().faceCorners[f][0]) & 1;
    return isInside(centre) != kuhnInside;
  }
  // Splits the ambiguous faces of the brick's crossed cubes (cellFlips), evaluating their
  // centres with the brick's field (equal to the whole one there, so a face on the brick's
  // boundary is split alike from both sides); then evaluates the centre of every cube that
  // has a flipped face and several loops (centreValue): those are split round it.
  void resolveAmbiguousFaces(const Field& field, const CellRange& r, const std::int64_t c[3],
                             Scratch& s) const;
  // The face diagonals that stay on the loops: those a cube meshed by its tetrahedra
  // crosses. Across the brick's own faces that cube is a neighbour brick's: its four outer
  // corners are evaluated here with the whole field, which gives the values the neighbour
  // computes (specialisation keeps values bit-identical), so both bricks decide alike.
  void markKeptDiagonals(const Field& whole, const CellRange& r, const std::int64_t n[3],
                         const std::int64_t c[3], const std::uint32_t cornerOffset[8],
                         Scratch& s) const;
  // Caps every one-loop cube's loop with a fan. From a loop vertex that shares no cube face
  // with any loop vertex but its two neighbours, the fan is embedded: seen from that corner
  // the rest of the loop lies on the other faces, where each ray into the cube leaves it
  // once, so two of its triangles meet only along their shared edge; no triangle lies in a
  // face, and each touches the faces only along the loop, which the neighbour cube draws
  // alike (docs/mesher.md). The best-shaped such fan is taken; a loop with no such vertex
  // (92 of the 3,240 cases) is fanned from a point inside the cube, embedded for the same
  // reason.
  void capLoops(const Field& whole, const CellRange& r, const std::int64_t n[3], bool sharp,
                Scratch& s, BrickResult& out) const;
  // Flat vertices (docs/mesher.md): the grid is cut into blocks of 2 x 2 x 2 cubes, the
  // first at an even cube index (so a block lies in one brick wherever bricks of an even size
  // start, and in one brick job); of the six grid edges from a block's centre, a crossed one
  // whose four cubes all have plain fans may lose its vertex (planFlatVertexRemoval judges,
  // with those four cubes' triangles: all that meet their box). The first that can go, in
  // axis order, goes, and then the one opposite it (its four cubes are the block's other four).
  // Blocks share no cube, so each decision sees its cubes as they came from the fans, and
  // the mesh is the same whatever the bricks.
  void removeFlatVertices(const CellRange& r, const std::int64_t n[3], Scratch& s,
                          BrickResult& out) const;
  // Sharp features (as Kobbelt et al.'s extended marching cubes): where the normals at a
  // loop's vertices spread by more than kFeatureCos, the loop is fanned from the point its
  // tangent planes meet at (a crease line's point nearest their mean, or a corner), kept
  // inside the cube, so the fan stays embedded (capLoops), or inside the pyramid it may reach
  // into a uniform neighbour (reachIntoUniformNeighbour). Refused, leaving the plain fan,
  // where that point lies over a cell outside the cube (the feature is not this cube's) or
  // a triangle of the fan would face against its vertices' normals (a fold).
  bool placeFeature(const Field& whole, const CellRange& r, const std::int64_t n[3],
                    std::uint32_t base, std::uint32_t mask, const std::uint32_t* L,
                    std::uint32_t len, Scratch& s, BrickResult& out) const;
  // Moves `at` (a point of the cube at `base`, clamped from x) through the cube's face on
  // `axis` (the upper one where `upper`) towards x, into the neighbour cube there, where all
  // eight of that cube's corners have one sign (no surface crosses it): as deep as x lies,
  // and no deeper than the pyramid over the shared face with its apex at the neighbour's
  // centre allows, kInnerMargin of the cell inside it. The six such pyramids of a cube are
  // disjoint, so the fans of different neighbours reaching into one cube never meet; and
  // the cube together with the pyramid is convex, with the loop (which cannot touch the
  // shared face: its corners are the uniform neighbour's) on its boundary, so the fan from a
  // point inside stays embedded (docs/mesher.md, "Sharp features"). Returns whether it
  // moved `at`.
  bool reachIntoUniformNeighbour(const Field& whole, const CellRange& r, const std::int64_t n[3],
                                 std::uint32_t base, int axis, bool upper, const Vec3& x,
                                 const Scratch& s, Vec3f& at) const;
  // The cube at `base` (its lowest grid point, brick-local) shrunk by kInnerMargin of the
  // cell on every side: where a vertex inside it may go.
  void innerBox(const CellRange& r, const std::int64_t n[3], std::uint32_t base, double lo[3],
                double hi[3]) const {
    const std::int64_t l[3] = {base % n[0], (base / n[0]) % n[1], base / (n[0] * n[1])};
    for (int a = 0; a < 3; ++a) {
      const double c0 = g_.coord(a, r.lo[a] + l[a]), c1 = g_.coord(a, r.lo[a] + l[a] + 1);
      lo[a] = c0 + kInnerMargin * (c1 - c0);
      hi[a] = c1 - kInnerMargin * (c1 - c0);
    }
  }
  // The mean of a loop's vertices, kept kInnerMargin of the cell off every face.
  std::uint32_t innerVertex(const CellRange& r, const std::int64_t n[3], std::uint32_t base,
                            const std::uint32_t* L, std::uint32_t count, Scratch& s,
                            BrickResult& out) const {
    double mean[3] = {0, 0, 0};
    Vec3 normalSum{0, 0, 0};
    for (std::uint32_t i = 0; i < count; ++i)
      for (int a = 0; a < 3; ++a) {
        mean[a] += out.positions[L[2 * i]][a];
        if (!s.unit.empty() && std::isfinite(s.unit[L[2 * i]][a]))
          normalSum[a] += s.unit[L[2 * i]][a];
      }
    double lo[3], hi[3];
    innerBox(r, n, base, lo, hi);
    Vec3f at;
    for (int a = 0; a < 3; ++a)
      at[a] = static_cast<float>(std::clamp(mean[a] / count, lo[a], hi[a]));
    return addInnerVertex(r, n, base, at, normalSum, s, out);
  }
  // A vertex inside the cube at `base`, keyed as the cube's main diagonal (a cube capped by
  // a fan has no vertex there), owned by this brick; its normal the loop's mean.
  std::uint32_t addInnerVertex(const CellRange& r, const std::int64_t n[3], std::uint32_t base,
                               const Vec3f& at, const Vec3& normalSum, Scratch& s,
                               BrickResult& out) const {
    const std::int64_t l[3] = {base % n[0], (base / n[0]) % n[1], base / (n[0] * n[1])};
    const std::uint32_t key = base * 7 + 6;
    s.edgeVertex[key] = static_cast<std::int32_t>(s.edgeOf.size());
    s.edgeOf.push_back(key);
    out.positions.push_back(at);
    out.keys.push_back(g_.linear(r.lo[0] + l[0], r.lo[1] + l[1], r.lo[2] + l[2]) * 7 + 6);
    out.owner.push_back(Ownership::Own);
    if (!s.unit.empty()) {
      const double len = std::sqrt(normalSum[0] * normalSum[0] + normalSum[1] * normalSum[1] +
                                   normalSum[2] * normalSum[2]);
      s.unit.push_back(len > 0 ? Vec3f{float(normalSum[0] / len), float(normalSum[1] / len),
                                       float(normalSum[2] / len)}
                               : Vec3f{0.f, 0.f, 0.f});
    }
    return static_cast<std::uint32_t>(s.edgeOf.size() - 1);
  }
  // Illinois (modified regula falsi), all edges of the brick at once so each iteration is one
  // batch evaluation. The edge is parametrised from its lower grid point, so a vertex on a
  // face shared by two bricks is computed identically from both sides.
  // Returns the points evaluated.
  std::size_t locateRoots(const Field& field, Scratch& s, const std::vector<std::uint32_t>& edgeOf,
                          const std::int64_t n[3], const CellRange& r, BrickResult& out) const;

 private:
  const Grid& g_;
  const MeshingOptions& opt_;
};

}  // namespace meshing
}  // namespace frep
