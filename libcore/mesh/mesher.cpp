#include "mesh/mesher.h"

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
#include "mesh/sampling_grid.h"

namespace frep {

namespace {

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
Box3 rangeBox(const Grid& g, const CellRange& r) {
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
int provenSign(const Field& field, const Grid& g, const CellRange& r) {
  Interval p[3];
  for (int a = 0; a < 3; ++a) p[a] = {g.coord(a, r.lo[a]), g.coord(a, r.hi[a])};
  const Interval f = field.evalInterval(p[0], p[1], p[2]);
  const Interval v = min(f, g.boxField(p[0], p[1], p[2]));
  if (v.hi < 0.0) return -1;
  if (v.lo >= 0.0 && !v.nan) return 1;
  return 0;
}
bool provenUniform(const Field& field, const Grid& g, const CellRange& r) {
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
Vec3f vertexAt(const Scratch& s, std::size_t e, double t) {
  return {static_cast<float>(s.px[e] + t * s.dx[e]), static_cast<float>(s.py[e] + t * s.dy[e]),
          static_cast<float>(s.pz[e] + t * s.dz[e])};
}

// The local key of the grid edge `e` of the cube whose lowest grid point is `base`: its
// lower grid point x 7 + direction - 1 (the welds' key, in brick-local numbering).
std::uint32_t edgeKey(std::uint32_t base, const std::uint32_t cornerOffset[8], const TetEdge& e) {
  return (base + cornerOffset[e.low]) * 7 + (e.dir - 1);
}

// The cube edges of face `face` (bit 2a + s, as CubeLoopTables::faces) whose corners differ.
int crossedEdgesOnFace(std::uint32_t mask, std::uint8_t face) {
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
                  BrickResult& out) const {
    const std::int64_t n[3] = {r.hi[0] - r.lo[0] + 1, r.hi[1] - r.lo[1] + 1, r.hi[2] - r.lo[2] + 1};
    const std::size_t count = static_cast<std::size_t>(n[0] * n[1] * n[2]);
    auto local = [&](std::int64_t i, std::int64_t j, std::int64_t k) {
      return static_cast<std::uint32_t>(i + n[0] * (j + n[1] * k));
    };

    // 1. Field at the grid points of the brick. Sub-blocks of kSubCells^3 cells that
    // intervals prove uniform need no values: none of their cells is crossed, and every
    // crossed edge lies in a cell of an unproven sub-block, whose corners are all evaluated.
    // Their other points get a stand-in of the proven sign, an infinity, read only by the
    // cell masks and the sieve for thin parts (sieveTentRow), so the mesh is the same as with
    // every point evaluated.
    s.f.resize(count);
    s.need.assign(count, 0);
    s.standIn.assign(count, 0);
    const std::int64_t c[3] = {n[0] - 1, n[1] - 1, n[2] - 1};
    for (std::int64_t k0 = 0; k0 < c[2]; k0 += kSubCells)
      for (std::int64_t j0 = 0; j0 < c[1]; j0 += kSubCells)
        for (std::int64_t i0 = 0; i0 < c[0]; i0 += kSubCells) {
          const std::int64_t i1 = std::min(i0 + kSubCells, c[0]),
                             j1 = std::min(j0 + kSubCells, c[1]),
                             k1 = std::min(k0 + kSubCells, c[2]);
          CellRange sub{{r.lo[0] + i0, r.lo[1] + j0, r.lo[2] + k0},
                        {r.lo[0] + i1, r.lo[1] + j1, r.lo[2] + k1}};
          const bool whole = i1 - i0 == c[0] && j1 - j0 == c[1] && k1 - k0 == c[2];
          const int sign = whole ? 0 : provenSign(field, g_, sub);
          for (std::int64_t k = k0; k <= k1; ++k)
            for (std::int64_t j = j0; j <= j1; ++j)
              for (std::int64_t i = i0; i <= i1; ++i) {
                const std::uint32_t id = local(i, j, k);
                if (sign == 0)
                  s.need[id] = 1;
                else
                  s.standIn[id] = static_cast<std::int8_t>(sign);
              }
        }
    std::vector<double>&qx = s.qx, &qy = s.qy, &qz = s.qz, &qf = s.qf;
    qx.clear();
    qy.clear();
    qz.clear();
    // (a grid point's coordinates are its axes' values: s.x, s.y and s.z hold them per axis)
    std::vector<double>* onAxis[3] = {&s.x, &s.y, &s.z};
    for (int a = 0; a < 3; ++a) {
      onAxis[a]->resize(static_cast<std::size_t>(n[a]));
      for (std::int64_t i = 0; i < n[a]; ++i) (*onAxis[a])[i] = g_.coord(a, r.lo[a] + i);
    }
    const double *cx = s.x.data(), *cy = s.y.data(), *cz = s.z.data();
    for (std::int64_t k = 0; k < n[2]; ++k)
      for (std::int64_t j = 0; j < n[1]; ++j)
        for (std::int64_t i = 0; i < n[0]; ++i)
          if (s.need[local(i, j, k)]) {
            qx.push_back(cx[i]);
            qy.push_back(cy[j]);
            qz.push_back(cz[k]);
          }
    qf.resize(qx.size());
    field.evalBatch(qx.data(), qy.data(), qz.data(), qx.size(), qf.data());
    for (std::int64_t k = 0, id = 0, q = 0; k < n[2]; ++k)
      for (std::int64_t j = 0; j < n[1]; ++j)
        for (std::int64_t i = 0; i < n[0]; ++i, ++id)
          s.f[id] = s.need[id] ? combine(qf[q++], g_.boxField(cx[i], cy[j], cz[k]))
                               : s.standIn[id] * std::numeric_limits<double>::infinity();
    const std::size_t evaluated =
        qx.size() + (opt_.findThinParts ? findThinParts(field, whole, r, n, s, out) : 0);

    // 2. The crossed cubes. With the cube extraction a cube whose surface meets its faces in
    // one loop is capped by a fan over that loop (after the roots are known); any other
    // crossed cube keeps its tetrahedra's polygons, and then the face diagonals it crosses
    // stay on its neighbours' loops too, so both sides of every face draw the same line.
    const KuhnTables& kt = kuhnTables();
    const CubeLoopTables& cl = cubeLoopTables();
    const bool byCubes = opt_.settings.mesher == Extraction::Cubes;
    auto byTetrahedra = [&](int mask, int flips) { return !byCubes || !cl.fanned(mask, flips); };
    s.edgeVertex.assign(count * 7, -1);
    s.polys.clear();
    s.loops.clear();
    std::vector<std::uint32_t>& edgeOf = s.edgeOf;
    edgeOf.clear();
    const std::uint32_t cornerOffset[8] = {0,
                                           local(1, 0, 0),
                                           local(0, 1, 0),
                                           local(1, 1, 0),
                                           local(0, 0, 1),
                                           local(1, 0, 1),
                                           local(0, 1, 1),
                                           local(1, 1, 1)};
    const std::size_t cubes = static_cast<std::size_t>(c[0] * c[1] * c[2]);
    s.cellMask.resize(cubes);
    // (a point's sign and its +x neighbour's as two bits, so a cube's mask is four of them:
    // corners 0-1, 2-3, 4-5 and 6-7 differ by x only)
    s.insidePair.resize(count);
    for (std::size_t id = 0; id + 1 < count; ++id)
      s.insidePair[id] = static_cast<std::uint8_t>(isInside(s.f[id]) | isInside(s.f[id + 1]) << 1);
    for (std::int64_t k = 0, q = 0; k < c[2]; ++k)
      for (std::int64_t j = 0; j < c[1]; ++j)
        for (std::int64_t i = 0; i < c[0]; ++i, ++q) {
          const std::uint8_t* p = &s.insidePair[local(i, j, k)];
          s.cellMask[q] = static_cast<std::uint8_t>(
              p[0] | p[cornerOffset[2]] << 2 | p[cornerOffset[4]] << 4 | p[cornerOffset[6]] << 6);
        }
    s.cellFlips.assign(cubes, 0);
    if (byCubes) {
      resolveAmbiguousFaces(field, r, c, s);
      markKeptDiagonals(whole, r, n, c, cornerOffset, s);
    }
    auto vertexFor = [&](std::uint32_t key) {
      std::int32_t& slot = s.edgeVertex[key];
      if (slot < 0) {
        slot = static_cast<std::int32_t>(edgeOf.size());
        edgeOf.push_back(key);
      }
      return static_cast<std::uint32_t>(slot);
    };
    for (std::int64_t k = 0, q = 0; k < c[2]; ++k)
      for (std::int64_t j = 0; j < c[1]; ++j)
        for (std::int64_t i = 0; i < c[0]; ++i, ++q) {
          const int cellMask = s.cellMask[q];
          if (cellMask == 0 || cellMask == 255) continue;
          const std::uint32_t base = local(i, j, k);
          const int flips = s.cellFlips[q];
          if (!byTetrahedra(cellMask, flips)) {
            // loop entry: cube base, length, then (vertex, cube-local id) pairs
            const CubeLoopCase& lc = cl.caseOf(cellMask, flips);
            const std::size_t head = s.loops.size();
            s.loops.push_back(base);
            s.loops.push_back(static_cast<std::uint32_t>(cellMask) << 8);  // | length
            for (int v = 0; v < lc.length; ++v) {
              const std::uint32_t key = edgeKey(base, cornerOffset, cl.edges[lc.ids[v]]);
              if (lc.ids[v] >= kFirstFaceDiagonal && !s.kept[key]) continue;
              s.loops.push_back(vertexFor(key));
              s.loops.push_back(lc.ids[v]);
              ++s.loops[head + 1];
            }
            continue;
          }
          if (flips != 0) {
            // several loops and a face off Kuhn's split: the twelve tetrahedra round the
            // centre, whose vertices on the centre's edges are this cube's alone
            s.crossings.clear();
            centredCubeCrossings(cellMask, isInside(s.centreValue[q]), flips, s.crossings);
            std::int32_t onCentreEdge[8] = {-1, -1, -1, -1, -1, -1, -1, -1};
            for (const TetCrossing& x : s.crossings) {
              std::uint32_t ids[4] = {0, 0, 0, UINT32_MAX};
              for (int e = 0; e < x.count; ++e) {
                const int u = x.from[e], w = x.to[e];
                if (u == kCubeCentre || w == kCubeCentre) {
                  const int corner = u == kCubeCentre ? w : u;
                  if (onCentreEdge[corner] < 0) {
                    onCentreEdge[corner] = static_cast<std::int32_t>(edgeOf.size());
                    edgeOf.push_back(static_cast<std::uint32_t>(count * 7 + q * 8 + corner));
                  }
                  ids[e] = static_cast<std::uint32_t>(onCentreEdge[corner]);
                } else {
                  ids[e] = vertexFor(edgeKey(base, cornerOffset, edgeBetween(u, w)));
                }
              }
              s.polys.insert(s.polys.end(), ids, ids + 4);
            }
            continue;
          }
          for (int t = 0; t < 6; ++t) {
            const auto& tet = kt.tets[t];
            int mask = 0;
            for (int v = 0; v < 4; ++v) mask |= ((cellMask >> tet[v]) & 1) << v;
            const TetPolygon& poly = kt.polygons[t][mask];
            if (poly.count == 0) continue;
            std::uint32_t ids[4] = {0, 0, 0, UINT32_MAX};
            for (int e = 0; e < poly.count; ++e)
              ids[e] = vertexFor(edgeKey(base, cornerOffset, poly.edges[e]));
            s.polys.insert(s.polys.end(), ids, ids + 4);
          }
        }

    // 3. Vertices: root of the field along each crossed edge.
    out.keys.resize(edgeOf.size());
    out.positions.resize(edgeOf.size());
    const std::size_t rootEvaluations = locateRoots(field, s, edgeOf, n, r, out);
    const std::size_t m = edgeOf.size();
    // Ownership: an edge belongs to the brick whose half-open cell range holds its lower grid
    // point (the last brick on an axis also holds the grid's last points).
    out.owner.resize(m);
    for (std::size_t e = 0; e < m; ++e) {
      if (edgeOf[e] >= count * 7) {  // on a centre's edge: inside one cube of this brick
        out.owner[e] = Ownership::Own;
        continue;
      }
      const std::uint32_t low = edgeOf[e] / 7;
      const std::int64_t l[3] = {low % n[0], (low / n[0]) % n[1], low / (n[0] * n[1])};
      bool mine = true, lowerFace = false;
      for (int a = 0; a < 3; ++a) {
        mine = mine && (r.lo[a] + l[a] < r.hi[a] || r.hi[a] == g_.points[a] - 1);
        lowerFace = lowerFace || l[a] == 0;
      }
      out.owner[e] = !mine ? Ownership::Other : lowerFace ? Ownership::OwnShared : Ownership::Own;
    }
    // Unit normals from the gradient, with the brick's own (specialised) field, in one batch:
    // of every vertex where sharp features place cube vertices from them, else of the vertices
    // this brick owns (a vertex another brick owns takes that brick's normal in the weld).
    const bool sharp = byCubes && opt_.settings.sharpFeatures;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    s.unit.clear();
    if (sharp || opt_.normals) {
      std::vector<std::uint32_t>& owned = s.owned;
      owned.clear();
      for (std::size_t e = 0; e < m; ++e)
        if (sharp || out.owner[e] != Ownership::Other)
          owned.push_back(static_cast<std::uint32_t>(e));
      const std::size_t k = owned.size();
      s.gx.resize(k);
      s.gy.resize(k);
      s.gz.resize(k);
      s.grad.resize(k);
      for (std::size_t i = 0; i < k; ++i) {
        const Vec3f& p = out.positions[owned[i]];
        s.gx[i] = Dual(p[0], 1, 0, 0);
        s.gy[i] = Dual(p[1], 0, 1, 0);
        s.gz[i] = Dual(p[2], 0, 0, 1);
      }
      field.evalGradientBatch(s.gx.data(), s.gy.data(), s.gz.data(), k, s.grad.data());
      s.unit.assign(m, Vec3f{nan, nan, nan});
      for (std::size_t i = 0; i < k; ++i)
        s.unit[owned[i]] = vertexNormal(s.grad[i], g_, out.positions[owned[i]]);
    }
    out.triangles.clear();
    out.flippable.clear();
    out.triangles.reserve(s.polys.size() / 2 + s.loops.size() / 2);
    capLoops(whole, r, n, sharp, s, out);  // adds the cubes' inner vertices, owned here
    out.normals.clear();
    if (opt_.normals) {
      out.normals.assign(s.unit.begin(), s.unit.end());
      for (std::size_t e = 0; e < m; ++e)
        if (out.owner[e] == Ownership::Other) out.normals[e] = Vec3f{nan, nan, nan};
    }

    // 4. The tetrahedra's triangles; a quad is split along the diagonal giving the
    // better-shaped pair.
    for (std::size_t p = 0; p < s.polys.size(); p += 4) {
      const std::uint32_t* q = &s.polys[p];
      if (q[3] == UINT32_MAX) {
        out.triangles.push_back({q[0], q[1], q[2]});
        continue;
      }
      const auto& P = out.positions;
      const double splitA = std::min(triangleQuality(P[q[0]], P[q[1]], P[q[2]]),
                                     triangleQuality(P[q[0]], P[q[2]], P[q[3]]));
      const double splitB = std::min(triangleQuality(P[q[0]], P[q[1]], P[q[3]]),
                                     triangleQuality(P[q[1]], P[q[2]], P[q[3]]));
      if (splitA >= splitB) {
        out.triangles.push_back({q[0], q[1], q[2]});
        out.triangles.push_back({q[0], q[2], q[3]});
      } else {
        out.triangles.push_back({q[0], q[1], q[3]});
        out.triangles.push_back({q[1], q[2], q[3]});
      }
    }
    if (byCubes && opt_.settings.dropFlatVertices) removeFlatVertices(r, n, s, out);
    // Every brick's result is held until the weld: no growth slack kept (the triangles'
    // reserve above is a bound, about twice what a brick makes).
    out.keys.shrink_to_fit();
    out.owner.shrink_to_fit();
    out.positions.shrink_to_fit();
    out.normals.shrink_to_fit();
    out.triangles.shrink_to_fit();
    out.flippable.shrink_to_fit();
    return evaluated + rootEvaluations;
  }

 private:
  // Parts thinner than a cell (mesh/hidden_parts.h): along every grid line, each edge whose
  // two points are evaluated and share a side, where the values at the points beside it make
  // a tent that crosses zero, gets the field evaluated where the tent's lines meet; a point
  // of the other side there proves a hidden part. Edges of a proven sub-block need no test:
  // its intervals hold for every point of its box. Counts the edges this brick owns; returns
  // the evaluations made.
  std::size_t findThinParts(const Field& field, const Field& whole, const CellRange& r,
                            const std::int64_t n[3], Scratch& s, BrickResult& out) const {
    out.thinSolid = out.thinGaps = out.tips = 0;
    out.hiddenEdges.clear();
    out.tipEdges.clear();
    out.exampleUnseen = false;
    out.exampleKey = std::numeric_limits<std::uint64_t>::max();
    siftTents(r, n, s);
    if (s.tentEdge.empty()) return 0;
    std::size_t evaluations = s.lx.size();
    if (!s.lx.empty()) {  // the points beside the candidates that the brick does not hold
      s.lf.resize(s.lx.size());
      whole.evalBatch(s.lx.data(), s.ly.data(), s.lz.data(), s.lx.size(), s.lf.data());
      for (std::size_t i = 0; i < s.lx.size(); ++i) {
        const double v = combine(s.lf[i], g_.boxField(s.lx[i], s.ly[i], s.lz[i]));
        (s.lazyOf[i] % 2 ? s.tentAfter : s.tentBefore)[s.lazyOf[i] / 2] = v;
      }
    }
    // the tents, and the points where their lines meet, evaluated in one batch
    const std::int64_t stride[3] = {1, n[0], n[0] * n[1]};
    const double* f = s.f.data();
    for (auto* v : {&s.lx, &s.ly, &s.lz}) v->clear();
    s.lazyOf.clear();
    for (std::size_t c = 0; c < s.tentEdge.size(); ++c) {
      const std::uint32_t id = s.tentEdge[c] / 3;
      const int a = static_cast<int>(s.tentEdge[c] % 3);
      double t;
      if (!tentCrossesZero(s.tentBefore[c], f[id], f[id + stride[a]], s.tentAfter[c], &t)) continue;
      const std::int64_t l[3] = {id % n[0], (id / n[0]) % n[1], id / (n[0] * n[1])};
      Vec3 p;
      for (int b = 0; b < 3; ++b) p[b] = g_.coord(b, r.lo[b] + l[b]);
      p[a] += t * (g_.coord(a, r.lo[a] + l[a] + 1) - p[a]);
      s.lx.push_back(p[0]);
      s.ly.push_back(p[1]);
      s.lz.push_back(p[2]);
      s.lazyOf.push_back(static_cast<std::uint32_t>(c));
    }
    if (s.lx.empty()) return evaluations;
    evaluations += s.lx.size();
    s.lf.resize(s.lx.size());
    field.evalBatch(s.lx.data(), s.ly.data(), s.lz.data(), s.lx.size(), s.lf.data());
    for (std::size_t i = 0; i < s.lx.size(); ++i) {
      const std::uint32_t edge = s.tentEdge[s.lazyOf[i]], id = edge / 3;
      const int a = static_cast<int>(edge % 3);
      const bool inside = isInside(f[id]);
      if (isInside(combine(s.lf[i], g_.boxField(s.lx[i], s.ly[i], s.lz[i]))) == inside) continue;
      const std::int64_t l[3] = {id % n[0], (id / n[0]) % n[1], id / (n[0] * n[1])};
      bool mine = true;  // (the edge's owner: as for its vertex, the brick of its lower point)
      for (int b = 0; b < 3; ++b)
        mine = mine && (r.lo[b] + l[b] < r.hi[b] || r.hi[b] == g_.points[b] - 1);
      if (!mine) continue;
      const bool unseen = seenNowhereNear(whole, r, n, l, a, inside, s, &evaluations);
      if (unseen)
        ++(inside ? out.thinGaps : out.thinSolid);
      else
        ++out.tips;
      const std::uint64_t key = g_.linear(r.lo[0] + l[0], r.lo[1] + l[1], r.lo[2] + l[2]) * 3 +
                                static_cast<std::uint64_t>(a);
      if (opt_.settings.refining())
        (unseen ? out.hiddenEdges : out.tipEdges).push_back(key);
      // the example: of a part seen nowhere near where there is one
      if (unseen > out.exampleUnseen || (unseen == out.exampleUnseen && key < out.exampleKey)) {
        out.exampleUnseen = unseen;
        out.exampleKey = key;
        out.example = {s.lx[i], s.ly[i], s.lz[i]};
      }
    }
    return evaluations;
  }

  // The candidates for findThinParts (s.tentEdge, with the values beside each edge, NaN where
  // the brick does not hold the point, which is then queued in s.lx/ly/lz for the whole field:
  // beyond the brick's faces, or in a sub-block proven uniform). Every row is sifted in bulk
  // first (sieveTentRow); a neighbour the brick does not hold passes the sieve, and is queued
  // only where the other side's line could make a tent crossing zero within the edge.
  void siftTents(const CellRange& r, const std::int64_t n[3], Scratch& s) const {
    s.tentEdge.clear();
    s.tentBefore.clear();
    s.tentAfter.clear();
    for (auto* v : {&s.lx, &s.ly, &s.lz}) v->clear();
    s.lazyOf.clear();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    const std::int64_t stride[3] = {1, n[0], n[0] * n[1]};
    const double* f = s.f.data();
    const char* need = s.need.data();
    auto queue = [&](const std::int64_t l[3], int a, std::int64_t step, std::uint32_t slot) {
      std::int64_t q[3] = {r.lo[0] + l[0], r.lo[1] + l[1], r.lo[2] + l[2]};
      q[a] += step;
      s.lx.push_back(g_.coord(0, q[0]));
      s.ly.push_back(g_.coord(1, q[1]));
      s.lz.push_back(g_.coord(2, q[2]));
      s.lazyOf.push_back(slot);
    };
    auto consider = [&](const std::int64_t l[3], int a) {
      const std::int64_t d = stride[a];
      const std::int64_t id = l[0] + n[0] * (l[1] + n[1] * l[2]);
      const std::int64_t globalLow = r.lo[a] + l[a];
      if (globalLow < 1 || globalLow + 2 >= g_.points[a]) return;  // the outer layer
      const bool heldBefore = l[a] >= 1 && need[id - d];
      const bool heldAfter = l[a] + 2 < n[a] && need[id + 2 * d];
      const double before = heldBefore ? f[id - d] : nan, after = heldAfter ? f[id + 2 * d] : nan;
      if (heldBefore && !heldAfter && !sideCrossesZero(f[id], before)) return;
      if (heldAfter && !heldBefore && !sideCrossesZero(f[id + d], after)) return;
      const std::uint32_t c = static_cast<std::uint32_t>(s.tentEdge.size());
      s.tentEdge.push_back(static_cast<std::uint32_t>(id) * 3 + static_cast<std::uint32_t>(a));
      s.tentBefore.push_back(before);
      s.tentAfter.push_back(after);
      if (!heldBefore) queue(l, a, -1, c * 2);
      if (!heldAfter) queue(l, a, 2, c * 2 + 1);
    };
    std::vector<double>& flags = s.tentFlags;
    std::vector<double>& passBefore = s.tentPassBefore;
    std::vector<double>& passAfter = s.tentPassAfter;
    flags.resize(static_cast<std::size_t>(n[0]));
    passBefore.resize(static_cast<std::size_t>(n[0]));
    passAfter.resize(static_cast<std::size_t>(n[0]));
    // per row along x: whether it holds an evaluated point (an edge needs two; the rows of a
    // proven sub-block hold none)
    std::vector<std::uint8_t>& rowEvaluated = s.rowEvaluated;
    rowEvaluated.resize(static_cast<std::size_t>(n[1] * n[2]));
    for (std::int64_t q = 0; q < n[1] * n[2]; ++q)
      rowEvaluated[q] = std::memchr(need + q * n[0], 1, static_cast<std::size_t>(n[0])) != nullptr;
    for (int a = 0; a < 3; ++a) {
      const std::int64_t d = stride[a];
      std::int64_t l[3] = {0, 0, 0};
      for (l[2] = 0; l[2] < n[2]; ++l[2])
        for (l[1] = 0; l[1] < n[1]; ++l[1]) {
          if (a > 0 && l[a] + 1 >= n[a]) continue;  // no edge along a from this row
          const std::int64_t rowIndex = l[1] + n[1] * l[2], row = n[0] * rowIndex;
          const double* here = f + row;
          if (!rowEvaluated[rowIndex]) continue;
          if (a == 0) {
            // along the row: its inner edges in bulk, the first and last one by one
            if (sieveTentRow(here, here + 1, here + 2, here + 3, n[0] - 3, flags.data()))
              for (std::int64_t i = 0; i + 3 < n[0]; ++i)
                if (flags[i] != 0.0) {
                  l[0] = i + 1;
                  consider(l, a);
                }
            for (std::int64_t i : {std::int64_t(0), n[0] - 2}) {
              l[0] = i;
              if (need[row + i] && need[row + i + 1] && isInside(here[i]) == isInside(here[i + 1]))
                consider(l, a);
            }
            continue;
          }
          if (!rowEvaluated[rowIndex + (a == 1 ? 1 : n[1])]) continue;
          // across rows: a neighbour layer beyond the brick's face is not held; a value of
          // the ends' side at infinity lets the sieve pass it, to be queued if need be
          const double* before = here - d;
          const double* after = here + 2 * d;
          if (l[a] < 1) {
            for (std::int64_t i = 0; i < n[0]; ++i) passBefore[i] = here[i] < 0.0 ? -inf : inf;
            before = passBefore.data();
          }
          if (l[a] + 2 >= n[a]) {
            for (std::int64_t i = 0; i < n[0]; ++i) passAfter[i] = here[i + d] < 0.0 ? -inf : inf;
            after = passAfter.data();
          }
          if (!sieveTentRow(before, here, here + d, after, n[0], flags.data())) continue;
          for (std::int64_t i = 0; i < n[0]; ++i)
            if (flags[i] != 0.0) {
              l[0] = i;
              consider(l, a);
            }
        }
    }
  }

  // Whether the edge from local point l along axis a (its ends on the side `inside`) has all
  // eighteen points of its four cubes on that side: then no surface the mesh draws comes
  // within a cell of the hidden part it crosses. Points beyond the brick: the whole field.
  bool seenNowhereNear(const Field& whole, const CellRange& r, const std::int64_t n[3],
                       const std::int64_t l[3], int a, bool inside, const Scratch& s,
                       std::size_t* evaluations) const {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    for (int k = 0; k < 18; ++k) {
      std::int64_t q[3] = {l[0], l[1], l[2]};
      q[a] += k % 2;
      q[b] += (k / 2) % 3 - 1;
      q[c] += k / 6 - 1;
      bool held = true;
      for (int e = 0; e < 3; ++e) held = held && q[e] >= 0 && q[e] < n[e];
      double v;
      if (held) {
        v = s.f[static_cast<std::size_t>(q[0] + n[0] * (q[1] + n[1] * q[2]))];
      } else {
        std::int64_t gq[3];
        for (int e = 0; e < 3; ++e) gq[e] = r.lo[e] + q[e];
        if (gq[b] < 0 || gq[c] < 0 || gq[b] >= g_.points[b] || gq[c] >= g_.points[c]) continue;
        const double x = g_.coord(0, gq[0]), y = g_.coord(1, gq[1]), z = g_.coord(2, gq[2]);
        v = combine(whole.eval(x, y, z), g_.boxField(x, y, z));
        ++*evaluations;
      }
      if (isInside(v) != inside) return false;
    }
    return true;
  }

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
                             Scratch& s) const {
    const CubeLoopTables& cl = cubeLoopTables();
    auto evaluate = [&] {
      s.af.resize(s.ax.size());
      field.evalBatch(s.ax.data(), s.ay.data(), s.az.data(), s.ax.size(), s.af.data());
      for (std::size_t i = 0; i < s.ax.size(); ++i)
        s.af[i] = combine(s.af[i], g_.boxField(s.ax[i], s.ay[i], s.az[i]));
    };
    auto lowest = [&](std::uint32_t q, std::int64_t g[3]) {
      g[0] = r.lo[0] + q % c[0];
      g[1] = r.lo[1] + (q / c[0]) % c[1];
      g[2] = r.lo[2] + q / (c[0] * c[1]);
    };
    for (auto* v : {&s.ax, &s.ay, &s.az}) v->clear();
    s.centreOf.clear();
    const std::uint32_t cubes = static_cast<std::uint32_t>(c[0] * c[1] * c[2]);
    for (std::uint32_t q = 0; q < cubes; ++q) {
      const int ambiguous = cl.ambiguous[s.cellMask[q]];
      if (!ambiguous) continue;
      std::int64_t g[3];
      lowest(q, g);
      for (int f = 0; f < 6; ++f) {
        if (!((ambiguous >> f) & 1)) continue;
        const Vec3 p = faceCentre(g, f);
        s.ax.push_back(p[0]);
        s.ay.push_back(p[1]);
        s.az.push_back(p[2]);
        s.centreOf.push_back(q * 6 + static_cast<std::uint32_t>(f));
      }
    }
    if (s.ax.empty()) return;
    evaluate();
    for (std::size_t i = 0; i < s.ax.size(); ++i) {
      const std::uint32_t q = s.centreOf[i] / 6;
      const int f = static_cast<int>(s.centreOf[i] % 6);
      if (flipped(s.cellMask[q], f, s.af[i])) s.cellFlips[q] |= static_cast<std::uint8_t>(1u << f);
    }
    for (auto* v : {&s.ax, &s.ay, &s.az}) v->clear();
    s.centreOf.clear();
    for (std::uint32_t q = 0; q < cubes; ++q) {
      if (!s.cellFlips[q] || cl.fanned(s.cellMask[q], s.cellFlips[q])) continue;
      std::int64_t g[3];
      lowest(q, g);
      s.ax.push_back(g_.mid(0, g[0]));
      s.ay.push_back(g_.mid(1, g[1]));
      s.az.push_back(g_.mid(2, g[2]));
      s.centreOf.push_back(q);
    }
    if (s.ax.empty()) return;
    evaluate();
    s.centreValue.resize(cubes);
    for (std::size_t i = 0; i < s.ax.size(); ++i) s.centreValue[s.centreOf[i]] = s.af[i];
  }

  // The face diagonals that stay on the loops: those a cube meshed by its tetrahedra
  // crosses. Across the brick's own faces that cube is a neighbour brick's: its four outer
  // corners are evaluated here with the whole field, which gives the values the neighbour
  // computes (specialisation keeps values bit-identical), so both bricks decide alike.
  void markKeptDiagonals(const Field& whole, const CellRange& r, const std::int64_t n[3],
                         const std::int64_t c[3], const std::uint32_t cornerOffset[8],
                         Scratch& s) const {
    const CubeLoopTables& cl = cubeLoopTables();
    s.kept.assign(static_cast<std::size_t>(n[0] * n[1] * n[2]) * 7, 0);
    s.hx.clear();
    s.hy.clear();
    s.hz.clear();
    s.haloKey.clear();
    s.haloMask.clear();
    s.haloCube.clear();
    for (std::int64_t k = 0, q = 0; k < c[2]; ++k)
      for (std::int64_t j = 0; j < c[1]; ++j)
        for (std::int64_t i = 0; i < c[0]; ++i, ++q) {
          const int mask = s.cellMask[q];
          if (mask == 0 || mask == 255) continue;
          const std::uint32_t base = static_cast<std::uint32_t>(i + n[0] * (j + n[1] * k));
          const bool byTetrahedra = !cl.fanned(mask, s.cellFlips[q]);
          const std::int64_t at[3] = {i, j, k};
          for (int id = kFirstFaceDiagonal; id < kMainDiagonal; ++id) {
            const TetEdge& e = cl.edges[id];
            if (((mask >> e.low) & 1) == ((mask >> (e.low | e.dir)) & 1)) continue;
            const std::uint32_t key = edgeKey(base, cornerOffset, e);
            if (byTetrahedra) {
              s.kept[key] = 1;
              continue;
            }
            const int a = (~e.dir & 1) ? 0 : (~e.dir & 2) ? 1 : 2;  // the face's normal axis
            const int side = (e.low >> a) & 1;
            if (side ? at[a] != c[a] - 1 : at[a] != 0) continue;  // inside the brick
            const std::int64_t far = r.lo[a] + at[a] + (side ? 2 : -1);
            if (far < 0 || far >= g_.points[a]) continue;  // the grid's edge: never crossed
            std::uint8_t known = 0;  // the neighbour's corners on the shared face, from here
            for (int v = 0; v < 8; ++v)
              if (((v >> a) & 1) != side && ((mask >> (v ^ (1 << a))) & 1)) known |= 1u << v;
            s.haloKey.push_back(key);
            s.haloMask.push_back(known);
            s.haloMask.push_back(static_cast<std::uint8_t>(a * 2 + side));
            for (int b = 0; b < 3; ++b)
              s.haloCube.push_back(r.lo[b] + at[b] + (b == a ? (side ? 1 : -1) : 0));
            for (int v = 0; v < 8; ++v) {
              if (((v >> a) & 1) != side) continue;
              std::int64_t p[3];
              for (int b = 0; b < 3; ++b) p[b] = r.lo[b] + at[b] + ((v >> b) & 1);
              p[a] = far;
              s.hx.push_back(g_.coord(0, p[0]));
              s.hy.push_back(g_.coord(1, p[1]));
              s.hz.push_back(g_.coord(2, p[2]));
            }
          }
        }
    if (s.haloKey.empty()) return;
    s.hf.resize(s.hx.size());
    whole.evalBatch(s.hx.data(), s.hy.data(), s.hz.data(), s.hx.size(), s.hf.data());
    for (std::size_t h = 0; h < s.haloKey.size(); ++h) {
      int mask = s.haloMask[2 * h];
      const int a = s.haloMask[2 * h + 1] / 2, side = s.haloMask[2 * h + 1] % 2;
      for (int v = 0, f = 0; v < 8; ++v) {
        if (((v >> a) & 1) != side) continue;
        const std::size_t at = 4 * h + static_cast<std::size_t>(f++);
        if (isInside(combine(s.hf[at], g_.boxField(s.hx[at], s.hy[at], s.hz[at])))) mask |= 1 << v;
      }
      // the neighbour's own ambiguous faces are split as it splits them (whole field)
      int flips = 0;
      for (int f = 0; f < 6; ++f) {
        if (!((cl.ambiguous[mask] >> f) & 1)) continue;
        const Vec3 p = faceCentre(&s.haloCube[3 * h], f);
        const double v = combine(whole.eval(p[0], p[1], p[2]), g_.boxField(p[0], p[1], p[2]));
        if (flipped(mask, f, v)) flips |= 1 << f;
      }
      if (!cl.fanned(mask, flips)) s.kept[s.haloKey[h]] = 1;
    }
  }

  // Caps every one-loop cube's loop with a fan. From a loop vertex that shares no cube face
  // with any loop vertex but its two neighbours, the fan is embedded: seen from that corner
  // the rest of the loop lies on the other faces, where each ray into the cube leaves it
  // once, so two of its triangles meet only along their shared edge; no triangle lies in a
  // face, and each touches the faces only along the loop, which the neighbour cube draws
  // alike (docs/mesher.md). The best-shaped such fan is taken; a loop with no such vertex
  // (92 of the 3,240 cases) is fanned from a point inside the cube, embedded for the same
  // reason.
  void capLoops(const Field& whole, const CellRange& r, const std::int64_t n[3], bool sharp,
                Scratch& s, BrickResult& out) const {
    const CubeLoopTables& cl = cubeLoopTables();
    const std::vector<Vec3f>& P = out.positions;
    const bool flat = opt_.settings.dropFlatVertices;
    if (flat) {  // (by a cube's lowest grid point, as the loops name their cubes)
      s.fanFirst.assign(static_cast<std::size_t>(n[0] * n[1] * n[2]), 0);
      s.fanCount.assign(s.fanFirst.size(), 0);
    }
    // Flat vertices (removeFlatVertices) are sought only where the cubes have plain fans.
    auto recordFan = [&](std::uint32_t base, std::size_t first) {
      if (!flat) return;
      s.fanFirst[base] = static_cast<std::uint32_t>(first);
      s.fanCount[base] = static_cast<std::uint8_t>(out.triangles.size() - first);
    };
    for (std::size_t p = 0; p < s.loops.size();) {
      const std::uint32_t base = s.loops[p], len = s.loops[p + 1] & 255, mask = s.loops[p + 1] >> 8;
      const std::uint32_t* L = &s.loops[p + 2];
      p += 2 + 2 * static_cast<std::size_t>(len);
      // (i < 2 len: wrapped by a comparison, not a division)
      auto v = [&](std::uint32_t i) { return L[2 * (i < len ? i : i - len)]; };
      auto id = [&](std::uint32_t i) { return L[2 * (i < len ? i : i - len) + 1]; };
      if (sharp && placeFeature(whole, r, n, base, mask, L, len, s, out)) continue;
      const std::size_t first = out.triangles.size();
      if (len == 3) {  // (one triangle, whichever the apex)
        out.triangles.push_back({v(0), v(1), v(2)});
        recordFan(base, first);
        continue;
      }
      int best = -1;
      double bestQuality = -1.0;
      // (a quad's apexes a and a + 2 make the same fan: the first two decide)
      for (std::uint32_t a = 0; a < (len == 4 ? 2u : len); ++a) {
        bool sees = true;
        for (std::uint32_t j = 2; j + 1 < len && sees; ++j)
          sees = (cl.faces[id(a + j)] & cl.faces[id(a)]) == 0;
        if (!sees) continue;
        double q = std::numeric_limits<double>::infinity();
        for (std::uint32_t j = 1; j + 1 < len; ++j)
          q = std::min(q, triangleQuality(P[v(a)], P[v(a + j)], P[v(a + j + 1)]));
        if (q > bestQuality) {
          bestQuality = q;
          best = static_cast<int>(a);
        }
      }
      if (best >= 0) {
        const std::uint32_t a = static_cast<std::uint32_t>(best);
        for (std::uint32_t j = 1; j + 1 < len; ++j)
          out.triangles.push_back({v(a), v(a + j), v(a + j + 1)});
        recordFan(base, first);
        continue;
      }
      const std::uint32_t apex = innerVertex(r, n, base, L, len, s, out);
      for (std::uint32_t j = 0; j < len; ++j) out.triangles.push_back({apex, v(j), v(j + 1)});
      recordFan(base, first);
    }
  }

  // Flat vertices (docs/mesher.md): the grid is cut into blocks of 2 x 2 x 2 cubes, the
  // first at an even cube index (so a block lies in one brick wherever bricks of an even size
  // start, and in one brick job); of the six grid edges from a block's centre, a crossed one
  // whose four cubes all have plain fans may lose its vertex (planFlatVertexRemoval judges,
  // with those four cubes' triangles: all that meet their box). The first that can go, in
  // axis order, goes, and then the one opposite it (its four cubes are the block's other four).
  // Blocks share no cube, so each decision sees its cubes as they came from the fans, and
  // the mesh is the same whatever the bricks.
  void removeFlatVertices(const CellRange& r, const std::int64_t n[3], Scratch& s,
                          BrickResult& out) const {
    const std::int64_t c[3] = {n[0] - 1, n[1] - 1, n[2] - 1};
    auto cube = [&](const std::int64_t i[3]) {  // (its lowest grid point: capLoops' fan index)
      return static_cast<std::size_t>(i[0] + n[0] * (i[1] + n[1] * i[2]));
    };
    // (an edge from a cube's lowest corner: edgeKey needs only that corner's offset, 0)
    static constexpr std::uint32_t kAtLowCorner[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    s.dropped.assign(out.positions.size(), 0);
    std::size_t removed = 0;
    std::int64_t start[3];
    for (int a = 0; a < 3; ++a) start[a] = r.lo[a] % 2 == 0 ? 1 : 2;  // odd global points
    std::int64_t o[3];
    for (o[2] = start[2]; o[2] < c[2]; o[2] += 2)
      for (o[1] = start[1]; o[1] < c[1]; o[1] += 2)
        for (o[0] = start[0]; o[0] < c[0]; o[0] += 2) {
          // Edge d (axis d / 2, from the centre down or up): its lower grid point and (unless
          // null) the brick-local indices of its four cubes ([low, low + 1] along the axis,
          // o - 1 and o across it).
          auto edgeAt = [&](int d, std::int64_t low[3], std::size_t* cubes) {
            const int axis = d / 2;
            for (int b = 0; b < 3; ++b) low[b] = o[b] - (b == axis && d % 2 == 0 ? 1 : 0);
            for (int q = 0; q < 4 && cubes; ++q) {
              std::int64_t at[3];
              for (int b = 0, bit = 0; b < 3; ++b)
                at[b] = b == axis ? low[b] : o[b] - 1 + ((q >> bit++) & 1);
              cubes[q] = cube(at);
            }
          };
          // The block's cubes with plain fans (bit x + 2 y + 4 z): most blocks have none,
          // or too few for an edge, and are passed over before any edge is looked up.
          unsigned fanned = 0;
          for (int q = 0; q < 8; ++q) {
            const std::int64_t at[3] = {o[0] - 1 + (q & 1), o[1] - 1 + ((q >> 1) & 1),
                                        o[2] - 1 + ((q >> 2) & 1)};
            if (s.fanCount[cube(at)] > 0) fanned |= 1u << q;
          }
          // (the four cubes on the low or high side of an axis)
          static constexpr unsigned kSide[6] = {0x55, 0xaa, 0x33, 0xcc, 0x0f, 0xf0};
          // The crossed edges whose four cubes all have plain fans.
          std::int32_t vertexOf[6];
          int order[6], count = 0;
          for (int d = 0; d < 6; ++d) {
            if ((fanned & kSide[d]) != kSide[d]) continue;
            std::int64_t low[3];
            edgeAt(d, low, nullptr);  // (its cubes: known to have fans from the mask)
            const std::uint32_t lowPoint =
                static_cast<std::uint32_t>(low[0] + n[0] * (low[1] + n[1] * low[2]));
            vertexOf[d] = s.edgeVertex[edgeKey(
                lowPoint, kAtLowCorner, TetEdge{0, static_cast<std::uint8_t>(1 << (d / 2))})];
            if (vertexOf[d] >= 0) order[count++] = d;
          }
          // The first that can go, then the one opposite it.
          auto tryRemoval = [&](int d) {
            const int axis = d / 2;
            std::int64_t low[3];
            std::size_t cubes[4];
            edgeAt(d, low, cubes);
            s.region.clear();
            s.regionIndex.clear();
            for (std::size_t id : cubes)
              for (std::uint32_t t = 0; t < s.fanCount[id]; ++t) {
                s.region.push_back(out.triangles[s.fanFirst[id] + t]);
                s.regionIndex.push_back(s.fanFirst[id] + t);
              }
            double boxLo[3], boxHi[3];
            for (int b = 0; b < 3; ++b) {
              const std::int64_t lo = r.lo[b] + (b == axis ? low[b] : o[b] - 1);
              boxLo[b] = g_.coord(b, lo);
              boxHi[b] = g_.coord(b, lo + (b == axis ? 1 : 2));
            }
            FlatVertexRemoval& plan = s.plan;
            if (!planFlatVertexRemoval(static_cast<std::uint32_t>(vertexOf[d]), out.positions,
                                       s.region, boxLo, boxHi, kFlatDeviation * g_.h[axis],
                                       kFlatQuality, &plan) ||
                !flatVertexRemovalIsClear(plan, out.positions, s.region))
              return false;
            for (std::size_t t = 0; t < plan.size; ++t)
              out.triangles[s.regionIndex[plan.star[t]]] =
                  t + 2 < plan.size ? plan.replacement[t]
                                    : Triangle{UINT32_MAX, UINT32_MAX, UINT32_MAX};
            s.dropped[static_cast<std::size_t>(vertexOf[d])] = 1;
            ++removed;
            return true;
          };
          for (int i = 0; i < count; ++i) {
            const int d = order[i];
            if (!tryRemoval(d)) continue;
            for (int j = i + 1; j < count; ++j)
              if (order[j] == (d ^ 1)) tryRemoval(d ^ 1);
            break;
          }
        }
    if (removed == 0) return;
    // Compact: the dead triangles out (the crease flips' list renumbered), the vertices gone.
    std::vector<std::uint32_t> newTriangle(out.triangles.size());
    std::size_t kept = 0;
    for (std::size_t t = 0; t < out.triangles.size(); ++t) {
      newTriangle[t] = static_cast<std::uint32_t>(kept);
      if (out.triangles[t][0] != UINT32_MAX) out.triangles[kept++] = out.triangles[t];
    }
    out.triangles.resize(kept);
    for (std::uint32_t& t : out.flippable) t = newTriangle[t];
    std::vector<std::uint32_t> newVertex(out.positions.size());
    kept = 0;
    for (std::size_t v = 0; v < out.positions.size(); ++v) {
      newVertex[v] = static_cast<std::uint32_t>(kept);
      if (s.dropped[v]) continue;
      out.keys[kept] = out.keys[v];
      out.owner[kept] = out.owner[v];
      out.positions[kept] = out.positions[v];
      if (!out.normals.empty()) out.normals[kept] = out.normals[v];
      ++kept;
    }
    out.keys.resize(kept);
    out.owner.resize(kept);
    out.positions.resize(kept);
    if (!out.normals.empty()) out.normals.resize(kept);
    for (Triangle& t : out.triangles)
      for (std::uint32_t& v : t) v = newVertex[v];
  }

  // Sharp features (as Kobbelt et al.'s extended marching cubes): where the normals at a
  // loop's vertices spread by more than kFeatureCos, the loop is fanned from the point its
  // tangent planes meet at (a crease line's point nearest their mean, or a corner), kept
  // inside the cube, so the fan stays embedded (capLoops), or inside the pyramid it may reach
  // into a uniform neighbour (reachIntoUniformNeighbour). Refused, leaving the plain fan,
  // where that point lies over a cell outside the cube (the feature is not this cube's) or
  // a triangle of the fan would face against its vertices' normals (a fold).
  bool placeFeature(const Field& whole, const CellRange& r, const std::int64_t n[3],
                    std::uint32_t base, std::uint32_t mask, const std::uint32_t* L,
                    std::uint32_t len, Scratch& s, BrickResult& out) const {
    const std::vector<Vec3f>& P = out.positions;
    double leastCos;
    std::size_t spreadA, spreadB;  // the two most different normals
    if (!mostDifferentNormals(
            len, [&](std::size_t i) { return s.unit[L[2 * i]]; }, &leastCos, &spreadA, &spreadB) ||
        leastCos > kFeatureCos)
      return false;
    Quadric q;
    Vec3 normalSum{0, 0, 0};
    for (std::uint32_t i = 0; i < len; ++i) {
      const Vec3f& p = P[L[2 * i]];
      const Vec3f& u = s.unit[L[2 * i]];
      q.addPlane(Vec3{p[0], p[1], p[2]}, Vec3{u[0], u[1], u[2]});
      for (int a = 0; a < 3; ++a) normalSum[a] += u[a];
    }
    int rank = 0;
    Vec3 x = q.minimiser(kFeatureCutoff, &rank);
    if (rank < 2) return false;
    double lo[3], hi[3];
    innerBox(r, n, base, lo, hi);
    // A crease whose point nearest the planes' mean lies outside the cube may still cross
    // it: then the vertex goes where the crease line does, inside (the two most different
    // normals give its direction); else to the cube's point nearest the minimiser.
    if (rank == 2)
      moveAlongCreaseIntoBox(x, s.unit[L[2 * spreadA]], s.unit[L[2 * spreadB]], lo, hi);
    Vec3f at;
    int beyond = 0, outAxis = -1;  // the axes on which the point lies off the inner box
    for (int a = 0; a < 3; ++a) {
      const double h = (hi[a] - lo[a]) / (1.0 - 2.0 * kInnerMargin);
      if (!(x[a] > lo[a] - h && x[a] < hi[a] + h)) return false;
      at[a] = static_cast<float>(std::clamp(x[a], lo[a], hi[a]));
      if (x[a] < lo[a] || x[a] > hi[a]) {
        ++beyond;
        outAxis = a;
      }
    }
    // A crease or corner whose tip pokes through one face into a cube no surface crosses
    // goes there, within the pyramid over that face with its apex at that cube's centre.
    const bool extended =
        rank >= 2 && beyond == 1 &&
        reachIntoUniformNeighbour(whole, r, n, base, outAxis, x[outAxis] > hi[outAxis], x, s, at);
    for (std::uint32_t j = 0; j < len; ++j) {
      const std::uint32_t u = L[2 * j], w = L[2 * (j + 1 == len ? 0 : j + 1)];
      const Vec3d nt = triangleCross(at, P[u], P[w]);
      double dot = 0.0;
      for (int a = 0; a < 3; ++a) dot += nt[a] * (double(s.unit[u][a]) + s.unit[w][a]);
      if (!(dot > 0.0)) return false;
    }
    const std::uint32_t apex = addInnerVertex(r, n, base, at, normalSum, s, out);
    const CubeLoopTables& cl = cubeLoopTables();
    for (std::uint32_t j = 0; j < len; ++j) {
      // A fan triangle over the only line the loop draws on a face (two of the face's edges
      // crossed, no diagonal vertex) may be flipped with its neighbour cube's across that
      // line to join the two feature vertices (mesh/crease_flips.h).
      const std::uint32_t a = L[2 * j + 1], b = L[2 * (j + 1 == len ? 0 : j + 1) + 1];
      if (!extended && a < kFirstFaceDiagonal && b < kFirstFaceDiagonal &&
          crossedEdgesOnFace(mask, cl.faces[a] & cl.faces[b]) == 2)
        out.flippable.push_back(static_cast<std::uint32_t>(out.triangles.size()));
      out.triangles.push_back({apex, L[2 * j], L[2 * (j + 1 == len ? 0 : j + 1)]});
    }
    return true;
  }

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
                                 const Scratch& s, Vec3f& at) const {
    const std::int64_t l[3] = {base % n[0], (base / n[0]) % n[1], base / (n[0] * n[1])};
    const std::int64_t side = upper ? 1 : 0;
    const std::int64_t far = l[axis] + (upper ? 2 : -1);  // the neighbour's far grid layer
    const std::int64_t farGlobal = r.lo[axis] + far;
    if (farGlobal < 0 || farGlobal >= g_.points[axis]) return false;
    int sign = -1;  // all eight corners alike: 0 outside, 1 inside
    for (int v = 0; v < 8; ++v) {
      std::int64_t p[3];
      for (int b = 0; b < 3; ++b) p[b] = l[b] + ((v >> b) & 1);
      p[axis] = (v >> axis) & 1 ? far : l[axis] + side;
      double value;
      if (p[axis] >= 0 && p[axis] < n[axis]) {
        value = s.f[static_cast<std::size_t>(p[0] + n[0] * (p[1] + n[1] * p[2]))];
      } else {
        double c[3];
        for (int b = 0; b < 3; ++b) c[b] = g_.coord(b, r.lo[b] + p[b]);
        value = combine(whole.eval(c[0], c[1], c[2]), g_.boxField(c[0], c[1], c[2]));
      }
      const int in = isInside(value);
      if (sign >= 0 && in != sign) return false;
      sign = in;
    }
    const double face = g_.coord(axis, r.lo[axis] + l[axis] + side);
    const double h = g_.h[axis];
    double lateral = 0.0;  // off the neighbour's centre line across the face, in cells
    for (int b = 0; b < 3; ++b) {
      if (b == axis) continue;
      lateral = std::max(lateral, std::abs(double(at[b]) - g_.mid(b, r.lo[b] + l[b])) / g_.h[b]);
    }
    const double limit = (0.5 - lateral - kInnerMargin) * h;
    const double depth = std::min(std::abs(x[axis] - face), limit);
    if (!(depth > kReachAtLeast * h) || std::abs(x[axis] - face) < kReachBeyond * h) return false;
    at[axis] = static_cast<float>(upper ? face + depth : face - depth);
    return true;
  }

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
                          const std::int64_t n[3], const CellRange& r, BrickResult& out) const {
    const std::size_t m = edgeOf.size();
    for (auto* v : {&s.px, &s.py, &s.pz, &s.dx, &s.dy, &s.dz, &s.ta, &s.tb, &s.fa, &s.fb})
      v->resize(m);
    s.lastSide.assign(m, 0);
    const std::uint64_t edgeKeys = static_cast<std::uint64_t>(n[0] * n[1] * n[2]) * 7;
    const std::int64_t c[3] = {n[0] - 1, n[1] - 1, n[2] - 1};
    for (std::size_t e = 0; e < m; ++e) {
      const std::uint32_t key = edgeOf[e];
      if (key >= edgeKeys) {
        // from the centre of cube q to its corner: keyed after every grid edge of the grid
        const std::uint32_t q = static_cast<std::uint32_t>((key - edgeKeys) / 8),
                            corner = (key - edgeKeys) % 8;
        const std::int64_t l[3] = {q % c[0], (q / c[0]) % c[1], q / (c[0] * c[1])};
        double at[3], to[3];
        for (int a = 0; a < 3; ++a) {
          at[a] = g_.mid(a, r.lo[a] + l[a]);
          to[a] = g_.coord(a, r.lo[a] + l[a] + ((corner >> a) & 1));
        }
        out.keys[e] = g_.centreEdgeKey(r.lo[0] + l[0], r.lo[1] + l[1], r.lo[2] + l[2], corner);
        s.px[e] = at[0];
        s.py[e] = at[1];
        s.pz[e] = at[2];
        s.dx[e] = to[0] - at[0];
        s.dy[e] = to[1] - at[1];
        s.dz[e] = to[2] - at[2];
        s.ta[e] = 0.0;
        s.tb[e] = 1.0;
        s.fa[e] = s.centreValue[q];
        s.fb[e] = s.f[static_cast<std::uint32_t>(
            (l[0] + (corner & 1)) +
            n[0] * ((l[1] + ((corner >> 1) & 1)) + n[1] * (l[2] + ((corner >> 2) & 1))))];
        continue;
      }
      const std::uint32_t low = key / 7, dir = key % 7 + 1;
      const std::int64_t li = low % n[0], lj = (low / n[0]) % n[1], lk = low / (n[0] * n[1]);
      const std::int64_t gi = r.lo[0] + li, gj = r.lo[1] + lj, gk = r.lo[2] + lk;
      const std::int64_t hi = gi + (dir & 1), hj = gj + ((dir >> 1) & 1),
                         hk = gk + ((dir >> 2) & 1);
      out.keys[e] = g_.linear(gi, gj, gk) * 7 + (dir - 1);
      s.px[e] = g_.coord(0, gi);
      s.py[e] = g_.coord(1, gj);
      s.pz[e] = g_.coord(2, gk);
      s.dx[e] = g_.coord(0, hi) - s.px[e];
      s.dy[e] = g_.coord(1, hj) - s.py[e];
      s.dz[e] = g_.coord(2, hk) - s.pz[e];
      const std::uint32_t highLocal = static_cast<std::uint32_t>(
          (li + (dir & 1)) + n[0] * ((lj + ((dir >> 1) & 1)) + n[1] * (lk + ((dir >> 2) & 1))));
      s.ta[e] = 0.0;
      s.tb[e] = 1.0;
      s.fa[e] = s.f[low];
      s.fb[e] = s.f[highLocal];
    }
    std::vector<double>& t = s.x;  // reuse the grid buffers: the grid values are consumed
    std::vector<double>& ft = s.y;
    std::vector<double> qx(m), qy(m), qz(m);
    t.resize(m);
    ft.resize(m);
    auto interpolate = [&](std::size_t e) {
      return illinoisEstimate(s.ta[e], s.tb[e], s.fa[e], s.fb[e]);
    };
    // An edge leaves the iteration once its bracket is narrower than kRootBracket of the edge,
    // or the next estimate (the one the vertex gets) moves less than kRootStep or gives the
    // same float32 vertex; each edge's steps depend on its own values only, so an edge two
    // bricks share still ends the same in both.
    std::vector<std::uint32_t>& active = s.active;
    active.resize(m);
    for (std::size_t e = 0; e < m; ++e) active[e] = static_cast<std::uint32_t>(e);
    std::size_t evaluations = 0;
    for (int it = 0; it < opt_.rootIterations && !active.empty(); ++it) {
      const std::size_t na = active.size();
      for (std::size_t q = 0; q < na; ++q) {
        const std::uint32_t e = active[q];
        t[e] = interpolate(e);
        qx[q] = s.px[e] + t[e] * s.dx[e];
        qy[q] = s.py[e] + t[e] * s.dy[e];
        qz[q] = s.pz[e] + t[e] * s.dz[e];
      }
      field.evalBatch(qx.data(), qy.data(), qz.data(), na, ft.data());
      evaluations += na;
      std::size_t kept = 0;
      for (std::size_t q = 0; q < na; ++q) {
        const std::uint32_t e = active[q];
        const double v = combine(ft[q], g_.boxField(qx[q], qy[q], qz[q]));
        illinoisUpdate(s.ta[e], s.tb[e], s.fa[e], s.fb[e], s.lastSide[e], t[e], v);
        if (v == 0.0) {  // the root exactly: the final interpolation returns it
          s.ta[e] = s.tb[e] = t[e];
          continue;
        }
        const double tn = interpolate(e);
        const bool settled =
            std::abs(tn - t[e]) < kRootStep || vertexAt(s, e, t[e]) == vertexAt(s, e, tn);
        if (s.tb[e] - s.ta[e] > kRootBracket && !settled) active[kept++] = e;
      }
      active.resize(kept);
    }
    for (std::size_t e = 0; e < m; ++e) {
      out.positions[e] = vertexAt(s, e, std::clamp(interpolate(e), kEdgeMargin, 1.0 - kEdgeMargin));
    }
    return evaluations;
  }

  const Grid& g_;
  const MeshingOptions& opt_;
};

struct ActiveBrick {
  CellRange range;
  // specialised to the brick's parent in the octree; null: the whole field. The brick's own
  // specialisation is made when it is meshed and dropped after: kept for every brick at
  // once, the copies were a third of the meshing's peak memory on a blend chain (the
  // helix: 16 of 48 MB), whose programs specialisation cannot shorten.
  std::shared_ptr<const Field> field;
};

// Octree descent over bricks: ranges proven uniform are dropped, and each level specialises
// the field to its box (region specialisation), so deep bricks evaluate short programs.
void collectBricks(const Field& field, const std::shared_ptr<const Field>& holder, const Grid& g,
                   const CellRange& cells, int bc, const std::int64_t b0[3],
                   const std::int64_t b1[3], std::vector<ActiveBrick>& out) {
  CellRange r;
  for (int a = 0; a < 3; ++a) {
    r.lo[a] = b0[a] * bc;
    r.hi[a] = std::min(b1[a] * bc, cells.hi[a]);
  }
  if (provenUniform(field, g, r)) return;
  if (b1[0] - b0[0] == 1 && b1[1] - b0[1] == 1 && b1[2] - b0[2] == 1) {
    out.push_back({r, holder});
    return;
  }
  std::shared_ptr<const Field> own = field.specialise(rangeBox(g, r));
  const std::shared_ptr<const Field>& here = own ? own : holder;
  const Field& f = own ? *own : field;
  std::int64_t mid[3];
  for (int a = 0; a < 3; ++a) mid[a] = b0[a] + std::max<std::int64_t>(1, (b1[a] - b0[a]) / 2);
  for (int child = 0; child < 8; ++child) {
    std::int64_t c0[3], c1[3];
    bool empty = false;
    for (int a = 0; a < 3; ++a) {
      const bool upper = (child >> a) & 1;
      c0[a] = upper ? mid[a] : b0[a];
      c1[a] = upper ? b1[a] : mid[a];
      empty = empty || c0[a] >= c1[a];
    }
    if (!empty) collectBricks(f, here, g, cells, bc, c0, c1, out);
  }
}

// Every brick's vertices numbered in one row (brick by brick: `first` of each brick) and
// sorted by global edge key, with the brick each entry came from.
struct KeyOrder {
  std::vector<std::size_t> first, brickOf;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> order;  // (key, entry)
};
KeyOrder sortByKey(const std::vector<BrickResult>& results) {
  KeyOrder k;
  k.first.assign(results.size() + 1, 0);
  for (std::size_t i = 0; i < results.size(); ++i)
    k.first[i + 1] = k.first[i] + results[i].keys.size();
  k.order.resize(k.first.back());
  k.brickOf.resize(k.first.back());
  tbb::parallel_for(std::size_t(0), results.size(), [&](std::size_t i) {
    for (std::size_t v = 0; v < results[i].keys.size(); ++v) {
      k.order[k.first[i] + v] = {results[i].keys[v], static_cast<std::uint32_t>(k.first[i] + v)};
      k.brickOf[k.first[i] + v] = i;
    }
  });
  tbb::parallel_sort(k.order.begin(), k.order.end());
  return k;
}

// Weld, the reference way: sort every brick's vertices by global edge key and merge equal
// keys. Used where the ownership weld below cannot place a vertex (it never should).
TriangleMesh weldBySorting(std::vector<BrickResult>& results, bool normals,
                           std::vector<std::uint32_t>* flippable) {
  KeyOrder sorted = sortByKey(results);
  const std::vector<std::size_t>& first = sorted.first;
  const std::vector<std::size_t>& brickOf = sorted.brickOf;
  const auto& order = sorted.order;
  std::vector<std::uint32_t> unique(order.size());
  std::vector<std::uint32_t> owner;  // unique vertex -> its first entry
  owner.reserve(order.size());
  auto owned = [&](std::size_t entry) {
    return results[brickOf[entry]].owner[entry - first[brickOf[entry]]] != Ownership::Other;
  };
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (i == 0 || order[i].first != order[i - 1].first) owner.push_back(order[i].second);
    // the owner's copy where there is one (only it has a normal)
    if (!owned(owner.back()) && owned(order[i].second)) owner.back() = order[i].second;
    unique[order[i].second] = static_cast<std::uint32_t>(owner.size() - 1);
  }
  TriangleMesh mesh;
  mesh.positions.resize(owner.size());
  if (normals) mesh.normals.resize(owner.size());
  for (std::size_t u = 0; u < owner.size(); ++u) {
    const std::size_t entry = owner[u];
    const BrickResult& from = results[brickOf[entry]];
    mesh.positions[u] = from.positions[entry - first[brickOf[entry]]];
    if (normals) mesh.normals[u] = from.normals[entry - first[brickOf[entry]]];
  }
  std::size_t triangleCount = 0;
  for (const auto& r : results) triangleCount += r.triangles.size();
  mesh.triangles.reserve(triangleCount);
  for (std::size_t i = 0; i < results.size(); ++i) {
    const std::uint32_t base = static_cast<std::uint32_t>(first[i]);
    const std::uint32_t offset = static_cast<std::uint32_t>(mesh.triangles.size());
    for (std::uint32_t t : results[i].flippable) flippable->push_back(offset + t);
    for (const Triangle& t : results[i].triangles)
      mesh.triangles.push_back({unique[base + t[0]], unique[base + t[1]], unique[base + t[2]]});
  }
  return mesh;
}

// Weld by ownership: every grid edge belongs to the one brick whose half-open cell range
// holds its lower grid point (the last brick on an axis also holds the grid's last points).
// A vertex on an edge a brick owns gets the next number of that brick's block; a vertex on
// an edge another brick owns takes that brick's number for it, found by key in the owner's
// sorted list. The owner always made that vertex: its edge lies on the face the two bricks
// share, a brick proven uniform has no crossed edge on its closed box, and both bricks
// compute the edge identically. Every step is per brick, in parallel; no global sort.
TriangleMesh weld(const Grid& g, int bc, const std::int64_t bricksPerAxis[3],
                  const std::vector<ActiveBrick>& bricks, std::vector<BrickResult>& results,
                  bool normals, bool* bySorting, std::vector<std::uint32_t>* flippable) {
  const std::size_t count = bricks.size();
  auto brickLinear = [&](const std::int64_t b[3]) {
    return static_cast<std::uint64_t>(b[0] + bricksPerAxis[0] * (b[1] + bricksPerAxis[1] * b[2]));
  };
  // The owner of an edge key, as a brick linear index.
  auto ownerOf = [&](std::uint64_t key) {
    std::uint64_t p = key / 7;
    std::int64_t b[3];
    for (int a = 0; a < 3; ++a) {
      const std::int64_t at =
          static_cast<std::int64_t>(p % static_cast<std::uint64_t>(g.points[a]));
      p /= static_cast<std::uint64_t>(g.points[a]);
      b[a] = std::min(at / bc, bricksPerAxis[a] - 1);
    }
    return brickLinear(b);
  };
  // The output's arrays are zeroed by one thread, and most of that is the first touch of
  // fresh pages (0.1 s on the gyroid at 256 cells): done on a thread of their own while the
  // numbering below runs on the others. (Declared after `mesh`: joined before it goes.)
  TriangleMesh mesh;
  std::vector<std::size_t> firstTriangle(count + 1, 0);
  for (std::size_t i = 0; i < count; ++i)
    firstTriangle[i + 1] = firstTriangle[i] + results[i].triangles.size();
  std::future<void> zeroed = std::async(std::launch::async, [&mesh, &firstTriangle, count] {
    mesh.triangles.resize(firstTriangle[count]);
  });
  std::vector<std::pair<std::uint64_t, std::uint32_t>> brickIndex(count);
  for (std::size_t i = 0; i < count; ++i) {
    const std::int64_t b[3] = {bricks[i].range.lo[0] / bc, bricks[i].range.lo[1] / bc,
                               bricks[i].range.lo[2] / bc};
    brickIndex[i] = {brickLinear(b), static_cast<std::uint32_t>(i)};
  }
  std::sort(brickIndex.begin(), brickIndex.end());

  // 1. Per brick: its own vertices, numbered in local order; the keys others may ask for
  // (those on its lower faces: a neighbour's upper face), sorted.
  std::vector<std::vector<std::int32_t>> ownedRank(count);  // local vertex -> rank, or -1
  std::vector<std::vector<std::pair<std::uint64_t, std::uint32_t>>> ownedKeys(count);
  std::vector<std::size_t> base(count + 1, 0);
  tbb::parallel_for(std::size_t(0), count, [&](std::size_t i) {
    const BrickResult& r = results[i];
    std::vector<std::int32_t>& rank = ownedRank[i];
    rank.assign(r.keys.size(), -1);
    std::int32_t next = 0;
    for (std::size_t v = 0; v < r.keys.size(); ++v) {
      if (r.owner[v] == Ownership::Other) continue;
      if (r.owner[v] == Ownership::OwnShared)
        ownedKeys[i].emplace_back(r.keys[v], static_cast<std::uint32_t>(next));
      rank[v] = next++;
    }
    std::sort(ownedKeys[i].begin(), ownedKeys[i].end());
    base[i + 1] = static_cast<std::size_t>(next);
  });
  for (std::size_t i = 0; i < count; ++i) base[i + 1] += base[i];
  std::future<void> zeroedPositions =
      std::async(std::launch::async, [&mesh, &base, count, normals] {
        mesh.positions.resize(base[count]);
        if (normals) mesh.normals.resize(base[count]);
      });

  // 2. Per brick: the global number of every local vertex.
  std::vector<std::vector<std::uint32_t>> global(count);
  std::atomic<bool> lost{false};
  tbb::parallel_for(std::size_t(0), count, [&](std::size_t i) {
    const std::vector<std::uint64_t>& keys = results[i].keys;
    std::vector<std::uint32_t>& out = global[i];
    out.resize(keys.size());
    for (std::size_t v = 0; v < keys.size(); ++v) {
      if (ownedRank[i][v] >= 0) {
        out[v] = static_cast<std::uint32_t>(base[i] + static_cast<std::size_t>(ownedRank[i][v]));
        continue;
      }
      const std::uint64_t owner = ownerOf(keys[v]);
      const auto at = std::lower_bound(brickIndex.begin(), brickIndex.end(),
                                       std::make_pair(owner, std::uint32_t(0)));
      bool found = false;
      if (at != brickIndex.end() && at->first == owner) {
        const auto& list = ownedKeys[at->second];
        const auto k =
            std::lower_bound(list.begin(), list.end(), std::make_pair(keys[v], std::uint32_t(0)));
        if (k != list.end() && k->first == keys[v]) {
          out[v] = static_cast<std::uint32_t>(base[at->second] + k->second);
          found = true;
        }
      }
      if (!found) lost = true;
    }
  });
  if (lost) {
    *bySorting = true;
    return weldBySorting(results, normals, flippable);
  }

  // 3. Positions, normals and triangles, written in place per brick.
  zeroed.get();
  zeroedPositions.get();
  for (std::size_t i = 0; i < count; ++i)
    for (std::uint32_t t : results[i].flippable)
      flippable->push_back(static_cast<std::uint32_t>(firstTriangle[i]) + t);
  tbb::parallel_for(std::size_t(0), count, [&](std::size_t i) {
    BrickResult& r = results[i];
    for (std::size_t v = 0; v < r.keys.size(); ++v)
      if (ownedRank[i][v] >= 0) {
        mesh.positions[global[i][v]] = r.positions[v];
        if (normals) mesh.normals[global[i][v]] = r.normals[v];
      }
    Triangle* out = mesh.triangles.data() + firstTriangle[i];
    for (const Triangle& t : r.triangles)
      *out++ = {global[i][t[0]], global[i][t[1]], global[i][t[2]]};
    r = BrickResult();  // free as we go
  });
  return mesh;
}

}  // namespace

namespace {

// The grid for the options: validated (box, resolution, brick size, float32 steps), with its
// cells (the outer layer included) and bricks per axis.
Grid makeGrid(const MeshingOptions& opt, CellRange* cells, std::int64_t bricks[3]) {
  const Box3& box = opt.bbox;
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(box.lo[a]) || !std::isfinite(box.hi[a]) || !(box.lo[a] < box.hi[a]))
      throw ModelError("mesher: the bounding box must be finite with min < max on every axis");
  if (!(opt.resolution > 0.0) || !std::isfinite(opt.resolution))
    throw ModelError("mesher: resolution (cell size) must be a number > 0");
  if (opt.brickCells < 2 || opt.brickCells > 64)
    throw ModelError("mesher: brick size must be between 2 and 64 cells");
  if (opt.settings.dropFlatVertices && opt.brickCells % 2 != 0)
    throw ModelError("mesher: flat vertices need an even brick size (blocks of 2 x 2 x 2 cubes)");
  opt.settings.validate();

  Grid g;
  g.lo = box.lo;
  g.hi = box.hi;
  for (int a = 0; a < 3; ++a) {
    const double extent = box.hi[a] - box.lo[a];
    const double want = std::ceil(extent / opt.resolution - 1e-9);
    if (want > static_cast<double>(kMaxCellsPerAxis)) {
      std::ostringstream os;
      os << "mesher: resolution " << opt.resolution << " needs " << want
         << " cells along an axis of the bounding box; at most " << kMaxCellsPerAxis
         << " are allowed: use a larger cell size";
      throw ModelError(os.str());
    }
    const std::int64_t n = std::max<std::int64_t>(1, static_cast<std::int64_t>(want));
    g.h[a] = extent / static_cast<double>(n);
    g.points[a] = n + 2;
    cells->lo[a] = 0;
    cells->hi[a] = n + 1;
    bricks[a] = (cells->hi[a] + opt.brickCells - 1) / opt.brickCells;
  }

  // Vertices are float32 (as STL stores them) and are kept kEdgeMargin of an edge away from
  // its grid points: a cell must span enough float steps at the box's coordinates for that
  // margin to survive rounding, or triangles collapse (a fine grid far from the origin).
  double far = 0.0, h = g.h[0];
  for (int a = 0; a < 3; ++a) {
    far = std::max({far, std::abs(box.lo[a]), std::abs(box.hi[a])});
    h = std::min(h, g.h[a]);
  }
  const float f = static_cast<float>(far);
  const double step =
      static_cast<double>(std::nextafter(f, std::numeric_limits<float>::infinity())) - f;
  if (h < kMinCellFloatSteps * step) {
    std::ostringstream os;
    os << "mesher: cells of " << h << " at coordinates up to " << far << " span only "
       << std::floor(h / step) << " float32 steps (meshes store float32 coordinates, as STL "
       << "does); allowed here: cells of at least " << kMinCellFloatSteps * step
       << ": use a larger cell size or move the model nearer the origin";
    throw ModelError(os.str());
  }
  return g;
}

// Memory guard: an ordinary surface makes about 6 triangles per cell of a brick's face by
// tetrahedra, a third by cubes (calibrated on the reference models; a gyroid's dense sheets
// make more, so the estimate never refuses a mesh that would fit).
void refuseOverBudget(const MeshingOptions& opt, const Grid& g, std::size_t activeBricks) {
  if (opt.memoryBudget == 0) return;
  const int bc = opt.brickCells;
  const double triangles =
      static_cast<double>(activeBricks) * bc * bc *
      (opt.settings.mesher == Extraction::Cubes ? kCubeTrianglesPerFaceCell : kTrianglesPerFaceCell);
  const double bytes = triangles * opt.bytesPerTriangle;
  if (bytes <= static_cast<double>(opt.memoryBudget)) return;
  double h = g.h[0];
  for (int a = 1; a < 3; ++a) h = std::max(h, g.h[a]);
  std::ostringstream os;
  os.precision(3);
  // three significant digits, but whole numbers from 1,000 on (no 1.13e+04)
  auto readable = [](double v) {
    std::ostringstream t;
    t.precision(3);
    if (v >= 1000.0)
      t << std::llround(v);
    else
      t << v;
    return t.str();
  };
  os << "mesher: at cell size " << opt.resolution << " the mesh would have about "
     << readable(triangles / 1e6) << " million triangles, needing about "
     << readable(bytes / 1e9) << " GB, and " << static_cast<double>(opt.memoryBudget) / 1e9
     << " GB is available: use a cell size of at least "
     << h * std::sqrt(bytes / static_cast<double>(opt.memoryBudget)) * 1.1
     << " (or a smaller box)";
  throw TooLargeError(os.str());
}

// Meshes every brick in parallel, with progress (to 95 %) and cancel; returns the points
// evaluated.
std::size_t meshBricks(const Field& field, const Grid& g, const MeshingOptions& opt,
                       const std::vector<ActiveBrick>& bricks, std::vector<BrickResult>& results) {
  results.resize(bricks.size());
  tbb::enumerable_thread_specific<Scratch> scratch;
  BrickMesher mesher(g, opt);
  std::atomic<std::size_t> evaluated{0};
  ThreadedProgress bar(Progress(opt.progress).sub(0.0, 0.95), bricks.size());
  tbb::parallel_for(std::size_t(0), bricks.size(), [&](std::size_t i) {
    if (bar.cancelled()) return;
    const ActiveBrick& b = bricks[i];
    const Field& parent = b.field ? *b.field : field;
    const std::shared_ptr<const Field> own = parent.specialise(rangeBox(g, b.range));
    evaluated += mesher.run(own ? *own : parent, field, b.range, scratch.local(), results[i]);
    bar.itemDone();
  });
  if (bar.cancelled()) throw Cancelled();
  return evaluated;
}

// The bricks' parts thinner than a cell, summed into the stats (before the weld frees them).
void countThinParts(const std::vector<BrickResult>& results, MeshingStats* stats) {
  if (!stats) return;
  bool unseen = false;
  std::uint64_t first = std::numeric_limits<std::uint64_t>::max();
  stats->thinSolidEdges = stats->thinGapEdges = stats->tipEdges = 0;
  for (const BrickResult& b : results) {
    stats->thinSolidEdges += b.thinSolid;
    stats->thinGapEdges += b.thinGaps;
    stats->tipEdges += b.tips;
    if (b.exampleKey != std::numeric_limits<std::uint64_t>::max() &&
        (b.exampleUnseen > unseen || (b.exampleUnseen == unseen && b.exampleKey < first))) {
      unseen = b.exampleUnseen;
      first = b.exampleKey;
      stats->thinExample = b.example;
    }
  }
}

// A brick job's bricks welded by key (each key once, sorted), positions from any brick that
// made the vertex (all make it bit-identically); the fan triangles crease flips may pair.
MeshPiece weldPiece(std::vector<BrickResult>& results, std::vector<std::uint32_t>* flippable) {
  KeyOrder sorted = sortByKey(results);
  const std::vector<std::size_t>& first = sorted.first;
  const std::vector<std::size_t>& brickOf = sorted.brickOf;
  const auto& order = sorted.order;
  std::vector<std::uint32_t> unique(order.size());
  MeshPiece piece;
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (i == 0 || order[i].first != order[i - 1].first) {
      const std::size_t entry = order[i].second;
      piece.keys.push_back(order[i].first);
      piece.positions.push_back(results[brickOf[entry]].positions[entry - first[brickOf[entry]]]);
    }
    unique[order[i].second] = static_cast<std::uint32_t>(piece.keys.size() - 1);
  }
  for (std::size_t i = 0; i < results.size(); ++i) {
    const std::uint32_t base = static_cast<std::uint32_t>(first[i]);
    const std::uint32_t offset = static_cast<std::uint32_t>(piece.triangles.size());
    for (std::uint32_t t : results[i].flippable) flippable->push_back(offset + t);
    for (const Triangle& t : results[i].triangles)
      piece.triangles.push_back({unique[base + t[0]], unique[base + t[1]], unique[base + t[2]]});
    results[i] = BrickResult();
  }
  return piece;
}

}  // namespace

void brickGrid(const MeshingOptions& opt, std::int64_t bricks[3]) {
  CellRange cells;
  makeGrid(opt, &cells, bricks);
}

TriangleMesh polygonize(const Field& field, const MeshingOptions& opt, MeshingStats* stats) {
  const auto start = std::chrono::steady_clock::now();
  CellRange cells;
  std::int64_t b0[3] = {0, 0, 0}, b1[3];
  const Grid g = makeGrid(opt, &cells, b1);
  const int bc = opt.brickCells;
  std::vector<ActiveBrick> bricks;
  collectBricks(field, nullptr, g, cells, bc, b0, b1, bricks);
  refuseOverBudget(opt, g, bricks.size());

  // The bar: the bricks up to 0.95, or, where the thin parts are refined (several times the
  // meshing's time, ten times and more with deeper levels), up to `bricksEnd` and the
  // refinement from there.
  const bool refining = opt.settings.refining();
  const double bricksEnd = !refining ? 1.0 : opt.settings.refineLevels > 1 ? 0.05 : 0.2;
  const Progress bar(opt.progress);
  MeshingOptions brickOptions = opt;
  brickOptions.progress = bar.sub(0.0, bricksEnd).callback();
  std::vector<BrickResult> results;
  const std::size_t evaluated = meshBricks(field, g, brickOptions, bricks, results);
  std::size_t refinementEvaluations = 0;
  countThinParts(results, stats);
  std::vector<std::uint64_t> hiddenEdges;
  for (const BrickResult& b : results) {
    if (opt.settings.refining())
      hiddenEdges.insert(hiddenEdges.end(), b.hiddenEdges.begin(), b.hiddenEdges.end());
    if (opt.settings.refine == Refinement::Tips)
      hiddenEdges.insert(hiddenEdges.end(), b.tipEdges.begin(), b.tipEdges.end());
  }
  bool bySorting = false;
  std::vector<std::uint32_t> flippable;
  TriangleMesh mesh = weld(g, bc, b1, bricks, results, opt.normals, &bySorting, &flippable);
  flipCreases(mesh, flippable);
  if (!hiddenEdges.empty() || (refining && opt.settings.refineLevels > 1)) {
    std::sort(hiddenEdges.begin(), hiddenEdges.end());
    LocalRefinementStats rs;
    // (the bricks' own bar ends at 0.95 of theirs: the weld takes the rest)
    refineHiddenParts(field, g, hiddenEdges, opt.refinementCubes, mesh, &rs,
                      opt.settings.refineLevels,
                      bar.sub(0.0, 0.95).sub(bricksEnd, 1.0 - bricksEnd).callback());
    refinementEvaluations = rs.evaluations;
    if (stats) {
      stats->refinedCubes = rs.cubes;
      stats->refinementSkipped = rs.skipped;
      stats->refinementLevelsReached = rs.levels;
      stats->refinedDeeperCubes = rs.deeperCubes;
      stats->refinedDeeperLeftOut = rs.deeperCubesLeftOut;
      stats->refinementDeeperSkipped = rs.deeperSkipped;
    }
  }
  FREP_ASSERT_MESH(mesh, "the mesher");
  bar.report(1.0);

  if (stats) {
    stats->settings = opt.settings;
    for (int a = 0; a < 3; ++a) stats->cells[a] = static_cast<std::size_t>(cells.hi[a]);
    stats->bricksTotal = static_cast<std::size_t>(b1[0] * b1[1] * b1[2]);
    stats->bricksActive = bricks.size();
    stats->pointsEvaluated = evaluated + refinementEvaluations;
    stats->weldedBySorting = bySorting;
    stats->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return mesh;
}

MeshPiece polygonizePiece(const Field& field, const MeshingOptions& opt,
                          const std::int64_t brickLo[3], const std::int64_t brickHi[3],
                          MeshingStats* stats) {
  const auto start = std::chrono::steady_clock::now();
  CellRange cells;
  std::int64_t all[3];
  const Grid g = makeGrid(opt, &cells, all);
  for (int a = 0; a < 3; ++a)
    if (brickLo[a] < 0 || brickHi[a] > all[a] || brickLo[a] >= brickHi[a]) {
      std::ostringstream os;
      os << "mesher: a brick job's bricks must lie in [0, " << all[a] << ") on axis " << a
         << " with lo < hi; got [" << brickLo[a] << ", " << brickHi[a] << ")";
      throw ModelError(os.str());
    }
  const int bc = opt.brickCells;
  std::vector<ActiveBrick> bricks;
  collectBricks(field, nullptr, g, cells, bc, brickLo, brickHi, bricks);
  refuseOverBudget(opt, g, bricks.size());

  MeshingOptions withoutNormals = opt;
  withoutNormals.normals = false;  // a piece carries positions only (STL and 3MF need no more)
  std::vector<BrickResult> results;
  const std::size_t evaluated = meshBricks(field, g, withoutNormals, bricks, results);
  countThinParts(results, stats);
  std::vector<std::uint32_t> flippable;
  MeshPiece piece = weldPiece(results, &flippable);
  for (int a = 0; a < 3; ++a) {
    piece.gridCells[a] = cells.hi[a];
    piece.cellLo[a] = brickLo[a] * bc;
    piece.cellHi[a] = std::min(brickHi[a] * bc, cells.hi[a]);
  }
  // Pairs inside the job are decided here; a fan triangle left without its partner may pair
  // with one of a neighbouring job across their shared face (its edge then lies there).
  TriangleMesh mesh;
  mesh.positions = std::move(piece.positions);
  mesh.triangles = std::move(piece.triangles);
  for (std::uint32_t t : flipCreases(mesh, flippable)) {
    const Triangle& tr = mesh.triangles[t];
    if (onJobSeam(piece, piece.keys[tr[1]]) && onJobSeam(piece, piece.keys[tr[2]]))
      piece.pendingFlips.push_back(t);
  }
  piece.positions = std::move(mesh.positions);
  piece.triangles = std::move(mesh.triangles);
  if (opt.progress) opt.progress(1.0);
  if (stats) {
    stats->settings = opt.settings;
    for (int a = 0; a < 3; ++a) stats->cells[a] = static_cast<std::size_t>(cells.hi[a]);
    stats->bricksTotal = static_cast<std::size_t>((brickHi[0] - brickLo[0]) *
                                                  (brickHi[1] - brickLo[1]) *
                                                  (brickHi[2] - brickLo[2]));
    stats->bricksActive = bricks.size();
    stats->pointsEvaluated = evaluated;
    stats->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return piece;
}

}  // namespace frep
