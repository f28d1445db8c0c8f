// The refiner of local refinement (mesh/local_refinement.h), shared by the files that hold
// its phases (the mesher's internals: nothing outside mesh/ includes this):
//   refiner.cpp            its public steps, evaluation and run() (region, seam, half
//                          cubes, assembly; restarts without the cubes a case fails in)
//   refiner_region.cpp     the cubes to refine found, grown and closed
//   refiner_seams.cpp      the seam on the region's faces
//   refiner_half_cubes.cpp the half cubes' signs, lines, fans and roots
//   refiner_assembly.cpp   the outside triangles split and joined to the half cubes'
//   local_refinement.cpp   refineHiddenParts: the levels, one Refiner each
#pragma once

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <unordered_set>

#include "base/errors.h"
#include "base/progress.h"
#include "base/triangle_geometry.h"
#include "mesh/local_refinement.h"
#include "mesh/refined_cells.h"
#include "mesh/refinement_grid.h"

namespace frep {

// Why no triangle can cross another (docs/mesher.md, "Local refinement"):
// - Region. Every triangle whose box reaches into the open inside of a refined cube is taken
//   out, and every cube its box reaches into joins the region, until none does: what is left
//   lies outside the region's open cubes and meets the region's boundary only along lines of
//   the cube extraction on its faces (a triangle of a cube meets the cube's faces only along
//   its loop's lines; flat-vertex and crease-flip triangles span several cubes, which then
//   all join). Those lines are the open edges the removal leaves (the seam).
// - Half cubes. A refined cube's 27 points give eight half cubes. A point of the half-cell
//   grid is sampled (its own sign) where every cube that holds it is refined, else it takes
//   the sign the seam's lines give it (virtual): the side of the coarse vertex on a grid edge,
//   or of the seam's lines on a face, so the half cubes draw the seam exactly, its lines cut
//   where they cross the face's midlines (points inserted into the outside triangles too).
//   Every other face of a half cube draws straight lines between its crossings, paired by
//   one rule both half cubes sharing it apply alike. A half cube's lines form loops on its
//   boundary; one loop is fanned from a point inside the half cube: every ray from there
//   leaves the convex half cube once, so the fan is embedded and meets the half cube's faces
//   only along the loop, which its neighbours draw alike. So triangles of different half
//   cubes, and of a half cube and the outside, meet only in shared edges and vertices.

namespace refinement {

// A case the refinement does not handle in these cubes: they stay as the cube extraction
// made them, and the refinement starts again without them.
struct CubeFailure {
  std::vector<std::uint64_t> cubes;  // left out
  std::vector<std::uint64_t> extra;  // refined too (the seam moves past a doubtful face)
  // the refined cubes beside the doubtful face, left out instead where an extra cube cannot
  // be refined (left out before, or not admitted by the level above)
  std::vector<std::uint64_t> fallback;
};

// Starts again without the cubes at most this many times.
constexpr int kMaxRestarts = 200;

// A face of the region's boundary: the seam's lines on it (as the outside triangles run
// them), the points where they cross its two midlines, and its centre's sign.
struct SeamFace {
  int axis = 0;                      // the face's normal
  std::int64_t cell[3] = {0, 0, 0};  // its lowest grid point
  std::vector<Seg> lines;
  // per half midline (0, 1: the midline across axis b, lower and upper half along c; 2, 3:
  // across c, halves along b): (coordinate along it, vertex), sorted
  std::vector<std::pair<float, std::uint32_t>> halfMid[4];
  std::vector<Seg> quarter[4];  // pieces per quarter (qb + 2 qc), as the region runs them
  bool centreInside = false;
  bool cut = false;  // cutSeamFace has run: the centre's side is known
};

class Refiner {
 public:
  Refiner(const Field& field, const RefinementGrid& g, TriangleMesh& mesh,
          LocalRefinementStats& stats)
      : field_(field), g_(g), mesh_(mesh), stats_(stats), cells_(field, *g.base, mesh, stats) {
    for (int a = 0; a < 3; ++a) {
      points_[a] = g.points[a];
      finePoints_[a] = 2 * g.points[a] - 1;
    }
  }

  const RefinementGrid& grid() const { return g_; }
  // The work from here moves along `range` as it goes (the look at the surface's cubes chunk
  // by chunk, run() step by step).
  void reportAt(const Progress& range) {
    range_ = range;
    at_ = 0.0;
    checkCancel();
  }
  // The id, on the next level's grid, of half cube h (corner at + (h & 1, h & 2, h & 4)) of
  // cube c.
  std::uint64_t halfCubeId(const std::int64_t c[3], int h) const {
    const std::int64_t f[3] = {2 * c[0] + (h & 1), 2 * c[1] + ((h >> 1) & 1),
                               2 * c[2] + ((h >> 2) & 1)};
    return static_cast<std::uint64_t>(f[0] + finePoints_[0] * (f[1] + finePoints_[1] * f[2]));
  }
  // The cube index along axis a holding coordinate x (clamped to the grid).
  std::int64_t cubeIndexOf(int a, double x) const {
    const std::int64_t c = static_cast<std::int64_t>(std::floor((x - g_.coord(a, 0)) / g_.h[a]));
    return std::clamp<std::int64_t>(c, 0, points_[a] - 2);
  }
  // The 125 points of the quarter-cell grid of each of `count` cubes (point d of cube i at
  // 125 i + d, d = qx + 5 qy + 25 qz) and the box-capped field's values there.
  struct QuarterSamples {
    std::vector<double> x, y, z, v;
  };
  void sampleQuarterPoints(const std::uint64_t* cubes, std::size_t count,
                           QuarterSamples* out) const;
  // The four cubes round each grid edge (lower grid point x 3 + axis).
  std::vector<std::uint64_t> cubesRound(const std::vector<std::uint64_t>& edges) const;

  // ---- a deeper level (docs/mesher.md, "Deeper levels"): the next level refines this
  // level's half cubes as this one refines cubes, those of the region's cubes. Its grid
  // points take the sides this level meshed them with: the field's, or on the seam the
  // side the seam gives them (there the value is the field's where the sides agree, else the
  // smallest number of the seam's side, so a root on an edge from there lies at that end).
  std::vector<std::uint64_t> finerCandidates() const;
  bool admitsFinerCube(const std::int64_t f0[3]) const {
    for (int a = 0; a < 3; ++a)
      if (f0[a] < 0 || f0[a] > finePoints_[a] - 2) return false;
    const std::int64_t parent[3] = {f0[0] / 2, f0[1] / 2, f0[2] / 2};
    return inOmega(parent);
  }
  // The next level needs the sides this level meshes its points with (asked before the
  // mesh is assembled: the seam's vertices are numbered anew there).
  void keepSidesForNextLevel() { keepSides_ = lookDeeper_ = true; }
  void refineWhateverTheyShow(const std::vector<std::uint64_t>& cubes) {
    mustRefine_.insert(cubes.begin(), cubes.end());
  }
  // The half cubes of the cubes refined for lying far from the surface (in the region): the
  // next level looks at them again, on this level's mesh.
  std::vector<std::uint64_t> halvesOfFarCubes() const;
  // Takes the sides this level meshed the region's points with as the next level's grid
  // values, and its region as where the next level may refine.
  void handDown(Refiner& next) const;
  void recordSides();

  void run(const std::vector<std::uint64_t>& seedCubes, std::size_t maxCubes);

 private:
  void reset(const TriangleMesh& original);

  // ---- indices
  std::uint64_t cubeId(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return static_cast<std::uint64_t>(i + points_[0] * (j + points_[1] * k));
  }
  void cubeOf(std::uint64_t id, std::int64_t c[3]) const {
    c[0] = static_cast<std::int64_t>(id % points_[0]);
    c[1] = static_cast<std::int64_t>((id / points_[0]) % points_[1]);
    c[2] = static_cast<std::int64_t>(id / (points_[0] * points_[1]));
  }
  bool validCube(const std::int64_t c[3]) const {
    for (int a = 0; a < 3; ++a)
      if (c[a] < 0 || c[a] > points_[a] - 2) return false;
    return true;
  }
  bool inOmega(const std::int64_t c[3]) const {
    return validCube(c) && region_.count(cubeId(c[0], c[1], c[2])) != 0;
  }
  std::uint64_t fineKey(const std::int64_t f[3]) const {
    return static_cast<std::uint64_t>(f[0] + finePoints_[0] * (f[1] + finePoints_[1] * f[2]));
  }
  double fineCoord(int a, std::int64_t f) const {
    return (f % 2 == 0) ? g_.coord(a, f / 2) : g_.mid(a, f / 2);
  }
  float fineF(int a, std::int64_t f) const { return static_cast<float>(fineCoord(a, f)); }
  float planeF(int a, std::int64_t j) const { return static_cast<float>(g_.coord(a, j)); }

  // ---- values of the half-cell grid
  void evaluate(const std::vector<std::array<std::int64_t, 3>>& points);
  void evaluateCubes(const std::vector<std::uint64_t>& cubes);
  double value(const std::int64_t f[3]) const {
    const auto it = values_.find(fineKey(f));
    if (it == values_.end()) throw Abort("a point of the half-cell grid was not evaluated");
    return it->second;
  }

  // Left out after a failure, or (a deeper level) a cube the level above does not admit.
  bool isBanned(std::uint64_t id) const {
    if (banned_.count(id)) return true;
    if (!above_) return false;
    std::int64_t c[3];
    cubeOf(id, c);
    return !above_->admitsFinerCube(c);
  }

  // ---- 1. the region: cubes where the half-cell grid shows what the corners miss
  void grow(const std::vector<std::uint64_t>& seedCubes, std::size_t maxCubes);

 public:
  // With a deeper level to follow, every cube holding a vertex of the mesh is looked at too
  // (its 125 points of the quarter-cell grid, in parallel), not only those round the
  // detector's edges: the detector sees a tent on about one hidden edge in seven, and the
  // parts narrower than half a cell (the gyroid's sheet tips where they graze the sphere)
  // are often far from any it saw. `*candidates` gets the cubes whose half or quarter cells
  // show a side their corners miss (grow() looks at them), `*far` those where the surface
  // crosses a quarter-cell edge farther than kFarCells from the mesh's triangles in the
  // cube and round it: a crease tip cut short, which every sign the grid sees agrees with
  // (refined whatever they show).
  static constexpr double kFarCells = 0.3;
  void surfaceCubesToLookAt(std::vector<std::uint64_t>* candidates, std::vector<std::uint64_t>* far,
                            const std::vector<std::uint64_t>* only = nullptr);

  // Whether a crossing of the cube's quarter-cell edges (by linear interpolation of the 125
  // values) lies farther than `limit` from every triangle in the cube and the 26 round it.
  template <class TrianglesOf>
  bool farFromMesh(std::uint64_t id, const double* v, const double* x, const double* y,
                   const double* z, double limit, const TrianglesOf& trianglesOf) const {
    std::int64_t c[3];
    cubeOf(id, c);
    const auto& P = mesh_.positions;
    auto toD = [](const Vec3f& p) { return Vec3d{p[0], p[1], p[2]}; };
    auto nearerThan = [&](const Vec3d& q, std::uint64_t cube, double lim2) {
      const auto range = trianglesOf(cube);
      // a vertex that near first: a few multiplications against the closest point's tests
      for (auto it = range.first; it != range.second; ++it)
        for (std::uint32_t v : mesh_.triangles[it->second]) {
          const double dx = P[v][0] - q[0], dy = P[v][1] - q[1], dz = P[v][2] - q[2];
          if (dx * dx + dy * dy + dz * dz <= lim2) return true;
        }
      for (auto it = range.first; it != range.second; ++it) {
        const Triangle& tr = mesh_.triangles[it->second];
        const Vec3d r = closestPointOnTriangle(q, toD(P[tr[0]]), toD(P[tr[1]]), toD(P[tr[2]]));
        const double d2 = (r[0] - q[0]) * (r[0] - q[0]) + (r[1] - q[1]) * (r[1] - q[1]) +
                          (r[2] - q[2]) * (r[2] - q[2]);
        if (d2 <= lim2) return true;
      }
      return false;
    };
    const double lim2 = limit * limit;
    // the mesh's vertices and face centroids in the cube against the surface: |F| / |grad F| from
    // the trilinear interpolation of the quarter cell holding each (a vertex placed off the
    // surface, where a sheet meets another at a grazing angle)
    const double x0 = x[0], y0 = y[0], z0 = z[0];
    const double qx = x[1] - x[0], qy = y[5] - y[0], qz = z[25] - z[0];
    const auto range = trianglesOf(id);
    for (auto it = range.first; it != range.second; ++it)
      for (int corner = 0; corner < 4; ++corner) {  // its vertices, then its centroid
        const Triangle& tr = mesh_.triangles[it->second];
        Vec3d pv;
        for (int a = 0; a < 3; ++a)
          pv[a] = corner < 3 ? double(P[tr[corner]][a])
                             : (double(P[tr[0]][a]) + P[tr[1]][a] + P[tr[2]][a]) / 3.0;
        const double u[3] = {(pv[0] - x0) / qx, (pv[1] - y0) / qy, (pv[2] - z0) / qz};
        int cell[3];
        double f[3];
        bool insideCube = true;
        for (int a = 0; a < 3; ++a) {
          if (!(u[a] >= 0.0 && u[a] < 4.0)) insideCube = false;
          cell[a] = std::clamp(static_cast<int>(std::floor(u[a])), 0, 3);
          f[a] = u[a] - cell[a];
        }
        if (!insideCube) continue;
        double val = 0.0, grad[3] = {0, 0, 0};
        bool finite = true;
        for (int k = 0; k < 8; ++k) {
          const int dx = k & 1, dy = (k >> 1) & 1, dz = k >> 2;
          const double w = v[(cell[0] + dx) + 5 * (cell[1] + dy) + 25 * (cell[2] + dz)];
          if (!std::isfinite(w)) finite = false;
          const double wx = dx ? f[0] : 1 - f[0], wy = dy ? f[1] : 1 - f[1],
                       wz = dz ? f[2] : 1 - f[2];
          val += w * wx * wy * wz;
          grad[0] += w * (dx ? 1 : -1) * wy * wz / qx;
          grad[1] += w * (dy ? 1 : -1) * wx * wz / qy;
          grad[2] += w * (dz ? 1 : -1) * wx * wy / qz;
        }
        const double g2 = grad[0] * grad[0] + grad[1] * grad[1] + grad[2] * grad[2];
        if (finite && g2 > 0.0 && val * val > lim2 * g2) return true;
      }
    for (int axis = 0; axis < 3; ++axis) {
      const int stride = axis == 0 ? 1 : axis == 1 ? 5 : 25;
      for (int d = 0; d < 125; ++d) {
        const int along = axis == 0 ? d % 5 : axis == 1 ? (d / 5) % 5 : d / 25;
        if (along == 4) continue;
        const double a = v[d], b = v[d + stride];
        if (isInside(a) == isInside(b) || !std::isfinite(a) || !std::isfinite(b)) continue;
        const double t = a / (a - b);
        const Vec3d q{x[d] + t * (x[d + stride] - x[d]), y[d] + t * (y[d + stride] - y[d]),
                      z[d] + t * (z[d + stride] - z[d])};
        if (nearerThan(q, id, lim2)) continue;
        bool near = false;
        for (int n = 0; n < 27 && !near; ++n) {
          const std::int64_t o[3] = {c[0] + n % 3 - 1, c[1] + (n / 3) % 3 - 1, c[2] + n / 9 - 1};
          if (n == 13 || !validCube(o)) continue;
          near = nearerThan(q, cubeId(o[0], o[1], o[2]), lim2);
        }
        if (!near) return true;
      }
    }
    return false;
  }

 private:
  // Where a deeper level follows, the cubes whose 27 points show nothing are looked at a
  // level deeper too: the cubes among them where a half cube's own 27 points (the 125
  // points of a quarter-cell grid) show a side their corners miss, so that the next level
  // finds its half cubes in the region (the gyroid's slivers narrower than half a cell).
  // Their neighbours are all queued. Results are kept across restarts.
  std::vector<std::uint64_t> deeperShowsHidden(const std::vector<std::uint64_t>& cubes);

  // Whether the cube's 27 points show a side its corners miss (showsHidden); the cubes across
  // such edges and faces are queued.
  bool hidesSomething(const std::int64_t c[3], std::vector<std::uint64_t>* next) const;

  // ---- 2. closure: every triangle reaching into the region goes, its cubes join
  // The cubes along axis a whose open inside the span [mn, mx] reaches into (both cubes
  // beside a grid plane when the span is that plane).
  void span(int a, float mn, float mx, std::int64_t* lo, std::int64_t* hi) const;

  // The zone: blocks of kBlock^3 cubes within kZoneReach cubes of the region. Only the
  // triangles whose box reaches into it are looked at again while the region closes.
  static constexpr std::int64_t kBlock = 4, kZoneReach = 4;
  // The zone's blocks as bits (nb_ blocks per axis), and the same grown by a block (to pass
  // over most triangles before their boxes are worked out).
  std::int64_t nb_[3] = {0, 0, 0};
  std::vector<std::uint8_t> zone_, zoneGrown_;
  std::uint64_t blockOf(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return static_cast<std::uint64_t>(i / kBlock + nb_[0] * (j / kBlock + nb_[1] * (k / kBlock)));
  }
  // Whether every cube within `reach` of cube c lies in the zone.
  bool inZone(const std::int64_t c[3], std::int64_t reach) const {
    std::int64_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::max<std::int64_t>(c[a] - reach, 0);
      hi[a] = std::min<std::int64_t>(c[a] + reach, points_[a] - 2);
    }
    for (std::int64_t k = lo[2]; k <= hi[2]; k += 1)
      for (std::int64_t j = lo[1]; j <= hi[1]; j += 1)
        for (std::int64_t i = lo[0]; i <= hi[0]; i += 1)
          if (!zone_[blockOf(i, j, k)]) return false;
    return true;
  }
  void buildZone();
  struct Near {
    std::uint32_t t;
    std::int64_t lo[3], hi[3];
  };
  bool inSpan(const Near& n, std::uint64_t id) const {
    std::int64_t c[3];
    cubeOf(id, c);
    for (int a = 0; a < 3; ++a)
      if (c[a] < n.lo[a] || c[a] > n.hi[a]) return false;
    return true;
  }
  void setSpan(Near& n) const;
  // A crease flip's pair (mesh/crease_flips.h), (v1, a, v2) and (v1, v2, b) with v1 and v2
  // feature vertices inside two cubes sharing a face and a, b on it, is turned back into the
  // two cubes' own fan triangles (v1, a, b) and (v2, b, a), as the cube extraction made them
  // (embedded by its own argument), so that refining one cube does not pull in the other.
  bool unflip(std::uint32_t ni);

  void close(std::size_t maxCubes);

  // Cubes that must be refined together with the refined ones among them: queued to join,
  // or, where one of them was left out, the refined ones are left out too.
  void join(const std::vector<std::uint64_t>& cubes, std::vector<std::uint64_t>* joined);

  // The grid-edge vertices of the removed triangles: the coarse crossings virtual edges keep.
  void findEdgeVertices();

  // ---- 3. the seam: open edges the removal leaves, each on a face of the region's boundary
  // The grid plane index j with planeF(a, j) == x, or -1.
  std::int64_t planeAt(int a, float x) const {
    const std::int64_t j =
        static_cast<std::int64_t>(std::llround((double(x) - g_.coord(a, 0)) / g_.h[a]));
    return (j >= 0 && j < points_[a] && planeF(a, j) == x) ? j : -1;
  }
  // The cube index u along a with planeF(a, u) < x < planeF(a, u + 1), or -1.
  std::int64_t cellAt(int a, double x) const {
    std::int64_t u = static_cast<std::int64_t>(std::floor((x - g_.coord(a, 0)) / g_.h[a]));
    u = std::clamp<std::int64_t>(u, 0, points_[a] - 2);
    while (u > 0 && planeF(a, u) >= x) --u;
    while (u < points_[a] - 2 && planeF(a, u + 1) <= x) ++u;
    return (planeF(a, u) < x && x < planeF(a, u + 1)) ? static_cast<std::int64_t>(u) : -1;
  }

  void findSeam();

  void addSeamLine(std::uint32_t p, std::uint32_t q);
  void throwFailures() {
    if (failed_.cubes.empty() && failed_.extra.empty()) return;
    CubeFailure f;
    std::swap(f, failed_);
    throw f;
  }

  void addSeamLineOrFail(std::uint32_t p, std::uint32_t q);

  // ---- 4. a seam face cut at its midlines; its centre's side from the cuts
  std::uint32_t newVertex(const Vec3f& p) { return cells_.newVertex(p); }

  void cutSeamFace(SeamFace& f);

  // ---- the side of a point of the half-cell grid: its own where every cube holding it is
  // refined, else what the seam gives it
  bool fineSign(const std::int64_t f[3]) const {
    return sampled(f) ? isInside(value(f)) : virtualSign(f);
  }
  // Whether every cube holding this point is refined (always so for a grid point, whose
  // side is the grid's, and a cube's centre).
  bool sampled(const std::int64_t f[3]) const;
  // The cube extraction's vertex on the crossed grid edge from grid point l along `axis` (the
  // seam keeps it), and whether it lies in the edge's lower half.
  std::uint32_t coarseVertex(const std::int64_t l[3], int axis, bool* lowerHalf) const {
    const auto it =
        edgeVertex_.find(g_.linear(l[0], l[1], l[2]) * 3 + static_cast<std::uint64_t>(axis));
    if (it == edgeVertex_.end()) throw Abort("a crossed grid edge of the seam has no vertex");
    const float x = mesh_.positions[it->second][axis];
    const float mid = static_cast<float>(g_.mid(axis, l[axis]));
    if (x == mid) throw Abort("a grid edge's vertex lies at its midpoint");
    *lowerHalf = x < mid;
    return it->second;
  }

  // The side the seam gives a point on a grid edge or face (not sampled).
  bool virtualSign(const std::int64_t f[3]) const;

  // ---- 5. the half cubes: lines on their faces, loops, fans
  // The vertices on a fine edge (lower fine point f, along axis d), in order along d.
  std::vector<std::uint32_t> crossings(const std::int64_t f[3], int d);

  void meshHalfCubes();

  Cell halfCube(const std::int64_t f0[3]) {
    Cell cell;
    for (int a = 0; a < 3; ++a) {
      cell.lo[a] = fineCoord(a, f0[a]);
      cell.hi[a] = fineCoord(a, f0[a] + 1);
      for (int side = 0; side < 2; ++side) faceLines(f0, a, side, &cell.face[2 * a + side]);
    }
    for (int d = 0; d < 8; ++d) {
      const std::int64_t f[3] = {f0[0] + (d & 1), f0[1] + ((d >> 1) & 1), f0[2] + ((d >> 2) & 1)};
      cell.inside[d] = fineSign(f);
    }
    return cell;
  }

  // The lines on face (a, side) of the half cube at f0, as that half cube runs them.
  void faceLines(const std::int64_t f0[3], int a, int side, std::vector<Seg>* out);

  // ---- 6. the vertices on the half-cell grid's edges: Illinois on the field where it
  // changes sign between the ends, else the edge's middle (a virtual end)
  struct Root {
    std::int64_t f[3];
    int d;
    std::uint32_t v;
  };

  void findRoots();

  // ---- 7. every triangle with an edge that was cut (on the seam, or between a split cell
  // and its neighbour) takes the cuts as vertices: a fan from its opposite corner over one cut
  // edge, from its centroid (in its plane) over several

  bool splitTriangle(const Triangle& tr, std::vector<Triangle>* out);

  void splitTriangles();

  // ---- 8. the mesh: the triangles kept, the new ones, unused vertices dropped, normals
  void assemble();

  // ---- progress and cancel: the fraction reported is where the caller put this step
  void checkCancel() const { range_.step(at_); }

  const Field& field_;
  const RefinementGrid g_;
  TriangleMesh& mesh_;
  LocalRefinementStats& stats_;
  const Refiner* above_ = nullptr;  // a deeper level's: the level it refines
  bool keepSides_ = false;
  bool lookDeeper_ = false;  // a deeper level follows: grow() looks at quarter cells too
  std::unordered_set<std::uint64_t> mustRefine_;  // crease tips cut short (kFarCells)
  // cube -> its half cubes whose quarter cells show a side their corners miss (bit h)
  std::unordered_map<std::uint64_t, std::uint8_t> deeperHides_;
  std::unordered_map<std::uint64_t, double> sides_;  // the region's points as meshed
  // grid points per axis of this level's grid, and of the half-cell grid inside it
  std::int64_t points_[3], finePoints_[3];
  std::unordered_map<std::uint64_t, double> values_;
  std::unordered_set<std::uint64_t> region_;  // the cubes refined (their ids)
  std::vector<std::uint64_t> cubes_;
  std::vector<std::uint8_t> removed_;
  std::unordered_map<std::uint64_t, SeamFace> seam_;
  std::unordered_map<std::uint64_t, std::uint32_t> edgeVertex_;
  std::unordered_map<std::uint64_t, std::uint32_t> rootVertex_;
  std::vector<Root> roots_;
  std::unordered_set<std::uint64_t> banned_;
  CubeFailure failed_;
  std::unordered_set<std::uint64_t> forced_;
  std::vector<Near> nearby_;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> byCube_;
  std::unordered_map<std::uint64_t, std::uint32_t> flipEdge_;  // spanning triangles' edges
  refinement::CellMesher cells_;  // the half cubes' meshing, their triangles and cuts
  Progress range_;
  double at_ = 0.0;  // (of range_)
};

}  // namespace refinement
}  // namespace frep
