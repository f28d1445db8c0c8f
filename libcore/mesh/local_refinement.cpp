#include "mesh/local_refinement.h"

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

namespace {

using refinement::Abort;
using refinement::Cell;
using refinement::dirKey;
using refinement::FaceCut;
using refinement::halfCubesShowingHidden;
using refinement::kNoRoot;
using refinement::RefinementGrid;
using refinement::Seg;
using refinement::showsHidden;
using refinement::WalkStep;

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
      P_[a] = g.points[a];
      F_[a] = 2 * g.points[a] - 1;
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
    return static_cast<std::uint64_t>(f[0] + F_[0] * (f[1] + F_[1] * f[2]));
  }
  // The cube index along axis a holding coordinate x (clamped to the grid).
  std::int64_t cubeIndexOf(int a, double x) const {
    const std::int64_t c = static_cast<std::int64_t>(std::floor((x - g_.coord(a, 0)) / g_.h[a]));
    return std::clamp<std::int64_t>(c, 0, P_[a] - 2);
  }
  // The 125 points of the quarter-cell grid of each of `count` cubes (point d of cube i at
  // 125 i + d, d = qx + 5 qy + 25 qz) and the box-capped field's values there.
  struct QuarterSamples {
    std::vector<double> x, y, z, v;
  };
  void sampleQuarterPoints(const std::uint64_t* cubes, std::size_t count,
                           QuarterSamples* out) const {
    const RefinementGrid quarter = g_.finer().finer();
    const std::size_t n = 125 * count;
    out->x.resize(n);
    out->y.resize(n);
    out->z.resize(n);
    out->v.resize(n);
    for (std::size_t i = 0; i < count; ++i) {
      std::int64_t c[3];
      cubeOf(cubes[i], c);
      for (int d = 0; d < 125; ++d) {
        out->x[125 * i + d] = quarter.coord(0, 4 * c[0] + d % 5);
        out->y[125 * i + d] = quarter.coord(1, 4 * c[1] + (d / 5) % 5);
        out->z[125 * i + d] = quarter.coord(2, 4 * c[2] + d / 25);
      }
    }
    field_.evalBatch(out->x.data(), out->y.data(), out->z.data(), n, out->v.data());
    for (std::size_t k = 0; k < n; ++k)
      out->v[k] = combine(out->v[k], g_.boxField(out->x[k], out->y[k], out->z[k]));
  }
  // The four cubes round each grid edge (lower grid point x 3 + axis).
  std::vector<std::uint64_t> cubesRound(const std::vector<std::uint64_t>& edges) const {
    std::vector<std::uint64_t> cubes;
    for (std::uint64_t e : edges) {
      const int a = static_cast<int>(e % 3);
      std::int64_t l[3];
      cubeOf(e / 3, l);
      const int b = (a + 1) % 3, c = (a + 2) % 3;
      for (int d = 0; d < 4; ++d) {
        std::int64_t q[3] = {l[0], l[1], l[2]};
        q[b] -= d & 1;
        q[c] -= d >> 1;
        if (validCube(q)) cubes.push_back(cubeId(q[0], q[1], q[2]));
      }
    }
    return cubes;
  }

  // ---- a deeper level (docs/mesher.md, "Deeper levels"): the next level refines this
  // level's half cubes as this one refines cubes, those of the region's cubes. Its grid
  // points take the sides this level meshed them with: the field's, or on the seam the
  // side the seam gives them (there the value is the field's where the sides agree, else the
  // smallest number of the seam's side, so a root on an edge from there lies at that end).
  std::vector<std::uint64_t> finerCandidates() const {
    std::vector<std::uint64_t> out;
    out.reserve(8 * cubes_.size());
    for (std::uint64_t id : cubes_) {
      std::int64_t c[3];
      cubeOf(id, c);
      // the half cubes a look a level deeper showed something in (all where none was taken)
      const auto seen = deeperHides_.find(id);
      const unsigned mask = seen == deeperHides_.end() ? 0xffu : seen->second;
      for (int h = 0; h < 8; ++h)
        if (mask & (1u << h)) out.push_back(halfCubeId(c, h));
    }
    std::sort(out.begin(), out.end());
    return out;
  }
  bool admitsFinerCube(const std::int64_t f0[3]) const {
    for (int a = 0; a < 3; ++a)
      if (f0[a] < 0 || f0[a] > F_[a] - 2) return false;
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
  std::vector<std::uint64_t> halvesOfFarCubes() const {
    std::vector<std::uint64_t> out;
    for (std::uint64_t id : mustRefine_) {
      if (!omega_.count(id)) continue;
      std::int64_t c[3];
      cubeOf(id, c);
      for (int h = 0; h < 8; ++h) out.push_back(halfCubeId(c, h));
    }
    std::sort(out.begin(), out.end());
    return out;
  }
  // Takes the sides this level meshed the region's points with as the next level's grid
  // values, and its region as where the next level may refine.
  void handDown(Refiner& next) const {
    for (const auto& [key, v] : sides_) {
      std::int64_t f[3];
      f[0] = static_cast<std::int64_t>(key % F_[0]);
      f[1] = static_cast<std::int64_t>((key / F_[0]) % F_[1]);
      f[2] = static_cast<std::int64_t>(key / (F_[0] * F_[1]));
      const std::int64_t there[3] = {2 * f[0], 2 * f[1], 2 * f[2]};
      next.values_[next.fineKey(there)] = v;
    }
    next.above_ = this;
  }
  void recordSides() {
    sides_.clear();
    for (std::uint64_t id : cubes_) {
      std::int64_t c[3];
      cubeOf(id, c);
      for (int d = 0; d < 27; ++d) {
        const std::int64_t f[3] = {2 * c[0] + d % 3, 2 * c[1] + (d / 3) % 3, 2 * c[2] + d / 9};
        const std::uint64_t key = fineKey(f);
        if (sides_.count(key)) continue;
        double v = value(f);
        const bool side = fineSign(f);
        if (isInside(v) != side)
          v = side ? std::numeric_limits<double>::min() : -std::numeric_limits<double>::min();
        sides_[key] = v;
      }
    }
  }

  void run(const std::vector<std::uint64_t>& seedCubes, std::size_t maxCubes) {
    const TriangleMesh original = mesh_;
    for (int attempt = 0;; ++attempt) {
      try {
        grow(seedCubes, maxCubes);  // (a restart reports where it got: the bar never moves back)
        if (omega_.empty()) return;
        at_ = std::max(at_, 0.2);
        close(maxCubes);
        at_ = std::max(at_, 0.5);
        checkCancel();
        findSeam();
        for (auto& [key, face] : seam_) {
          try {
            cutSeamFace(face);
          } catch (const Abort&) {
            std::int64_t below[3] = {face.cell[0], face.cell[1], face.cell[2]};
            below[face.axis] -= 1;
            const std::uint64_t up = cubeId(face.cell[0], face.cell[1], face.cell[2]),
                                down = cubeId(below[0], below[1], below[2]);
            failed_.extra.push_back(inOmega(below) ? up : down);
            failed_.fallback.push_back(inOmega(below) ? down : up);
          }
        }
        throwFailures();
        checkCancel();
        meshHalfCubes();
        splitTriangles();
        if (keepSides_) recordSides();
        assemble();
        return;
      } catch (const CubeFailure& f) {
        if (attempt == kMaxRestarts) throw Abort("too many cubes left out");
        banned_.insert(f.cubes.begin(), f.cubes.end());
        bool blocked = false;
        for (std::uint64_t id : f.extra) {
          if (!isBanned(id))
            forced_.insert(id);
          else
            blocked = true;
        }
        if (blocked) banned_.insert(f.fallback.begin(), f.fallback.end());
        stats_.cubesLeftOut = banned_.size();
        reset(original);
      }
    }
  }

 private:
  void reset(const TriangleMesh& original) {
    mesh_ = original;
    omega_.clear();
    cubes_.clear();
    removed_.clear();
    seam_.clear();
    cells_.clear();
    edgeVertex_.clear();
    rootVertex_.clear();
    roots_.clear();
    stats_.cubes = stats_.trianglesRemoved = stats_.trianglesAdded = 0;
  }

  // ---- indices
  std::uint64_t cubeId(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return static_cast<std::uint64_t>(i + P_[0] * (j + P_[1] * k));
  }
  void cubeOf(std::uint64_t id, std::int64_t c[3]) const {
    c[0] = static_cast<std::int64_t>(id % P_[0]);
    c[1] = static_cast<std::int64_t>((id / P_[0]) % P_[1]);
    c[2] = static_cast<std::int64_t>(id / (P_[0] * P_[1]));
  }
  bool validCube(const std::int64_t c[3]) const {
    for (int a = 0; a < 3; ++a)
      if (c[a] < 0 || c[a] > P_[a] - 2) return false;
    return true;
  }
  bool inOmega(const std::int64_t c[3]) const {
    return validCube(c) && omega_.count(cubeId(c[0], c[1], c[2])) != 0;
  }
  std::uint64_t fineKey(const std::int64_t f[3]) const {
    return static_cast<std::uint64_t>(f[0] + F_[0] * (f[1] + F_[1] * f[2]));
  }
  double fineCoord(int a, std::int64_t f) const {
    return (f % 2 == 0) ? g_.coord(a, f / 2) : g_.mid(a, f / 2);
  }
  float fineF(int a, std::int64_t f) const { return static_cast<float>(fineCoord(a, f)); }
  float planeF(int a, std::int64_t j) const { return static_cast<float>(g_.coord(a, j)); }

  // ---- values of the half-cell grid
  void evaluate(const std::vector<std::array<std::int64_t, 3>>& points) {
    std::vector<double> x, y, z, v;
    std::vector<std::uint64_t> keys;
    for (const auto& p : points) {
      const std::uint64_t k = fineKey(p.data());
      if (values_.count(k)) continue;
      values_[k] = 0.0;  // (reserved: filled below)
      keys.push_back(k);
      x.push_back(fineCoord(0, p[0]));
      y.push_back(fineCoord(1, p[1]));
      z.push_back(fineCoord(2, p[2]));
    }
    if (keys.empty()) return;
    v.resize(keys.size());
    field_.evalBatch(x.data(), y.data(), z.data(), keys.size(), v.data());
    stats_.evaluations += keys.size();
    for (std::size_t i = 0; i < keys.size(); ++i)
      values_[keys[i]] = combine(v[i], g_.boxField(x[i], y[i], z[i]));
  }
  void evaluateCubes(const std::vector<std::uint64_t>& cubes) {
    std::vector<std::array<std::int64_t, 3>> pts;
    for (std::uint64_t id : cubes) {
      std::int64_t c[3];
      cubeOf(id, c);
      for (int d = 0; d < 27; ++d)
        pts.push_back({2 * c[0] + d % 3, 2 * c[1] + (d / 3) % 3, 2 * c[2] + d / 9});
    }
    evaluate(pts);
  }
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
  void grow(const std::vector<std::uint64_t>& seedCubes, std::size_t maxCubes) {
    std::vector<std::uint64_t> candidates = seedCubes;
    std::unordered_set<std::uint64_t> tried;
    while (!candidates.empty() && omega_.size() < maxCubes) {
      checkCancel();
      std::sort(candidates.begin(), candidates.end());
      candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
      std::vector<std::uint64_t> fresh;
      for (std::uint64_t c : candidates)
        if (tried.insert(c).second && !isBanned(c)) fresh.push_back(c);
      evaluateCubes(fresh);
      std::vector<std::uint64_t> next, quiet;
      for (std::uint64_t id : fresh) {
        if (omega_.size() >= maxCubes) break;
        std::int64_t c[3];
        cubeOf(id, c);
        if (hidesSomething(c, &next) || mustRefine_.count(id))
          omega_.insert(id);
        else if (lookDeeper_)
          quiet.push_back(id);
      }
      for (std::uint64_t id : deeperShowsHidden(quiet)) {
        if (omega_.size() >= maxCubes) break;
        omega_.insert(id);
        std::int64_t c[3];
        cubeOf(id, c);
        for (int d = 0; d < 27; ++d) {
          const std::int64_t q[3] = {c[0] + d % 3 - 1, c[1] + (d / 3) % 3 - 1, c[2] + d / 9 - 1};
          if (d != 13 && validCube(q)) next.push_back(cubeId(q[0], q[1], q[2]));
        }
      }
      candidates.swap(next);
    }
    std::vector<std::uint64_t> forced;
    for (std::uint64_t id : forced_)
      if (!isBanned(id) && !omega_.count(id)) forced.push_back(id);
    std::sort(forced.begin(), forced.end());
    evaluateCubes(forced);
    omega_.insert(forced.begin(), forced.end());
  }

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
                            const std::vector<std::uint64_t>* only = nullptr) {
    const auto& P = mesh_.positions;
    // Given `only`, the triangles are needed in those cubes and round them alone (a few
    // thousand cubes against a mesh of millions of triangles: no sort of them all).
    std::vector<std::uint64_t> wanted;
    if (only) {
      for (std::uint64_t id : *only) {
        std::int64_t c[3];
        cubeOf(id, c);
        for (int n = 0; n < 27; ++n) {
          const std::int64_t o[3] = {c[0] + n % 3 - 1, c[1] + (n / 3) % 3 - 1, c[2] + n / 9 - 1};
          if (validCube(o)) wanted.push_back(cubeId(o[0], o[1], o[2]));
        }
      }
      std::sort(wanted.begin(), wanted.end());
      wanted.erase(std::unique(wanted.begin(), wanted.end()), wanted.end());
    }
    // the triangles by the cubes their boxes reach into (in parallel: millions of them)
    using CubeTriangle = std::pair<std::uint64_t, std::uint32_t>;
    tbb::enumerable_thread_specific<std::vector<CubeTriangle>> pairs;
    const std::size_t T = mesh_.triangles.size();
    tbb::parallel_for(std::size_t(0), (T + 4095) / 4096, [&](std::size_t block) {
      std::vector<CubeTriangle>& out = pairs.local();
      for (std::size_t t = 4096 * block; t < std::min(T, 4096 * (block + 1)); ++t) {
        const Triangle& tr = mesh_.triangles[t];
        std::int64_t lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
          lo[a] = cubeIndexOf(a, std::min({P[tr[0]][a], P[tr[1]][a], P[tr[2]][a]}));
          hi[a] = cubeIndexOf(a, std::max({P[tr[0]][a], P[tr[1]][a], P[tr[2]][a]}));
        }
        for (std::int64_t k = lo[2]; k <= hi[2]; ++k)
          for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
            for (std::int64_t i = lo[0]; i <= hi[0]; ++i) {
              const std::uint64_t id = cubeId(i, j, k);
              if (!only || std::binary_search(wanted.begin(), wanted.end(), id))
                out.push_back({id, static_cast<std::uint32_t>(t)});
            }
      }
    });
    std::vector<CubeTriangle> byCube;
    std::size_t count = 0;
    for (const auto& v : pairs) count += v.size();
    byCube.reserve(count);
    for (const auto& v : pairs) byCube.insert(byCube.end(), v.begin(), v.end());
    tbb::parallel_sort(byCube.begin(), byCube.end());
    std::vector<std::uint64_t> cubes;
    if (only) {
      cubes = *only;
    } else {
      for (const auto& [id, t] : byCube)
        if (cubes.empty() || cubes.back() != id) cubes.push_back(id);
    }
    auto trianglesOf = [&](std::uint64_t id) {
      return std::equal_range(byCube.begin(), byCube.end(), std::make_pair(id, std::uint32_t(0)),
                              [](const auto& u, const auto& w) { return u.first < w.first; });
    };
    // (in the mesher's cells at every level: the goal is theirs)
    const double farLimit = kFarCells * std::max({g_.base->h[0], g_.base->h[1], g_.base->h[2]});
    constexpr std::size_t kChunk = 256;
    struct Found {
      std::vector<std::uint64_t> candidates, far;
      std::vector<std::pair<std::uint64_t, std::uint8_t>> masks;
    };
    tbb::enumerable_thread_specific<Found> found;
    const std::size_t chunks = (cubes.size() + kChunk - 1) / kChunk;
    std::mutex progressMutex;  // (the caller's progress: one call at a time)
    std::size_t chunksDone = 0;
    std::atomic<bool> cancelled{false};
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t ch) {
      if (cancelled.load(std::memory_order_relaxed)) return;
      if (range_) {
        std::lock_guard<std::mutex> lock(progressMutex);
        if (!range_.count(chunksDone++, chunks)) cancelled = true;
      }
      const std::size_t from = ch * kChunk, to = std::min(cubes.size(), from + kChunk);
      QuarterSamples q;
      sampleQuarterPoints(cubes.data() + from, to - from, &q);
      const std::vector<double>&x = q.x, &y = q.y, &z = q.z, &v = q.v;
      Found& out = found.local();
      for (std::size_t i = from; i < to; ++i) {
        const std::size_t base = 125 * (i - from);
        auto in = [&](int qx, int qy, int qz) { return isInside(v[base + qx + 5 * qy + 25 * qz]); };
        bool shows = showsHidden([&](int dx, int dy, int dz) { return in(2 * dx, 2 * dy, 2 * dz); },
                                 [](int, int, int) {}, [](int, int) {});
        const std::uint8_t mask = halfCubesShowingHidden(in);
        out.masks.push_back({cubes[i], mask});
        if (shows || mask) out.candidates.push_back(cubes[i]);
        if (farFromMesh(cubes[i], v.data() + base, x.data() + base, y.data() + base,
                        z.data() + base, farLimit, trianglesOf))
          out.far.push_back(cubes[i]);
      }
    });
    if (cancelled) throw Cancelled();
    stats_.evaluations += 125 * cubes.size();
    for (const Found& f : found) {
      for (const auto& [id, mask] : f.masks) deeperHides_[id] = mask;
      candidates->insert(candidates->end(), f.candidates.begin(), f.candidates.end());
      far->insert(far->end(), f.far.begin(), f.far.end());
    }
    std::sort(candidates->begin(), candidates->end());
    std::sort(far->begin(), far->end());
  }

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
  std::vector<std::uint64_t> deeperShowsHidden(const std::vector<std::uint64_t>& cubes) {
    std::vector<std::uint64_t> out, todo;
    for (std::uint64_t id : cubes) {
      const auto it = deeperHides_.find(id);
      if (it == deeperHides_.end())
        todo.push_back(id);
      else if (it->second)
        out.push_back(id);
    }
    if (todo.empty()) return out;
    QuarterSamples q;
    sampleQuarterPoints(todo.data(), todo.size(), &q);
    stats_.evaluations += q.v.size();
    for (std::size_t i = 0; i < todo.size(); ++i) {
      const std::uint8_t mask = halfCubesShowingHidden(
          [&](int qx, int qy, int qz) { return isInside(q.v[125 * i + qx + 5 * qy + 25 * qz]); });
      deeperHides_[todo[i]] = mask;
      if (mask) out.push_back(todo[i]);
    }
    return out;
  }

  // Whether the cube's 27 points show a side its corners miss (showsHidden); the cubes across
  // such edges and faces are queued.
  bool hidesSomething(const std::int64_t c[3], std::vector<std::uint64_t>* next) const {
    auto queue = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
      const std::int64_t q[3] = {x, y, z};
      if (validCube(q)) next->push_back(cubeId(x, y, z));
    };
    return showsHidden(
        [&](int dx, int dy, int dz) {
          const std::int64_t f[3] = {2 * c[0] + dx, 2 * c[1] + dy, 2 * c[2] + dz};
          return isInside(value(f));
        },
        [&](int a, int db, int dc) {  // the four cubes round that edge
          const int b = (a + 1) % 3, cc = (a + 2) % 3;
          for (int d = 0; d < 4; ++d) {
            std::int64_t q[3] = {c[0], c[1], c[2]};
            q[b] += db / 2 - (d & 1);
            q[cc] += dc / 2 - (d >> 1);
            queue(q[0], q[1], q[2]);
          }
        },
        [&](int a, int side) {  // the cube across that face
          std::int64_t q[3] = {c[0], c[1], c[2]};
          q[a] += side == 0 ? -1 : 1;
          queue(q[0], q[1], q[2]);
        });
  }

  // ---- 2. closure: every triangle reaching into the region goes, its cubes join
  // The cubes along axis a whose open inside the span [mn, mx] reaches into (both cubes
  // beside a grid plane when the span is that plane).
  void span(int a, float mn, float mx, std::int64_t* lo, std::int64_t* hi) const {
    std::int64_t j = static_cast<std::int64_t>(std::floor((mn - g_.coord(a, 0)) / g_.h[a]));
    j = std::clamp<std::int64_t>(j, 0, P_[a] - 2);
    while (j > 0 && planeF(a, j) > mn) --j;
    while (j < P_[a] - 2 && planeF(a, j + 1) <= mn) ++j;
    if (mn == mx && mn == planeF(a, j)) {
      *lo = std::max<std::int64_t>(j - 1, 0);
      *hi = j;
      return;
    }
    *lo = j;
    std::int64_t k = j;
    while (k + 1 <= P_[a] - 2 && planeF(a, k + 1) < mx) ++k;
    *hi = k;
  }

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
      hi[a] = std::min<std::int64_t>(c[a] + reach, P_[a] - 2);
    }
    for (std::int64_t k = lo[2]; k <= hi[2]; k += 1)
      for (std::int64_t j = lo[1]; j <= hi[1]; j += 1)
        for (std::int64_t i = lo[0]; i <= hi[0]; i += 1)
          if (!zone_[blockOf(i, j, k)]) return false;
    return true;
  }
  void buildZone() {
    for (int a = 0; a < 3; ++a) nb_[a] = P_[a] / kBlock + 1;
    const std::size_t blocks = static_cast<std::size_t>(nb_[0] * nb_[1] * nb_[2]);
    zone_.assign(blocks, 0);
    zoneGrown_.assign(blocks, 0);
    auto mark = [&](std::vector<std::uint8_t>& bits, const std::int64_t c[3], std::int64_t reach) {
      std::int64_t lo[3], hi[3];
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::max<std::int64_t>(c[a] - reach, 0) / kBlock;
        hi[a] = std::min<std::int64_t>((c[a] + reach) / kBlock, nb_[a] - 1);
      }
      for (std::int64_t k = lo[2]; k <= hi[2]; ++k)
        for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
          for (std::int64_t i = lo[0]; i <= hi[0]; ++i)
            bits[static_cast<std::size_t>(i + nb_[0] * (j + nb_[1] * k))] = 1;
    };
    for (std::uint64_t id : omega_) {
      std::int64_t c[3];
      cubeOf(id, c);
      mark(zone_, c, kZoneReach);
      mark(zoneGrown_, c, kZoneReach + kBlock);
    }
    // the triangles reaching into it, with the cubes their boxes reach into
    const auto& P = mesh_.positions;
    nearby_.clear();
    for (std::size_t t = 0; t < mesh_.triangles.size(); ++t) {
      const Triangle& tr = mesh_.triangles[t];
      // a triangle under a block across whose first vertex's block is not in the grown
      // zone has neither corner of its box in the zone
      bool small = true;
      std::int64_t v0[3];
      for (int a = 0; a < 3; ++a) {
        const float mn = std::min({P[tr[0]][a], P[tr[1]][a], P[tr[2]][a]});
        const float mx = std::max({P[tr[0]][a], P[tr[1]][a], P[tr[2]][a]});
        small = small && (double(mx) - mn) < (kBlock - 2) * g_.h[a];
        v0[a] = cubeIndexOf(a, P[tr[0]][a]);
      }
      if (small && !zoneGrown_[blockOf(v0[0], v0[1], v0[2])]) continue;
      Near n;
      n.t = static_cast<std::uint32_t>(t);
      for (int a = 0; a < 3; ++a) {
        const float mn = std::min({P[tr[0]][a], P[tr[1]][a], P[tr[2]][a]});
        const float mx = std::max({P[tr[0]][a], P[tr[1]][a], P[tr[2]][a]});
        span(a, mn, mx, &n.lo[a], &n.hi[a]);
      }
      if (zone_[blockOf(n.lo[0], n.lo[1], n.lo[2])] || zone_[blockOf(n.hi[0], n.hi[1], n.hi[2])])
        nearby_.push_back(n);
    }
    flipEdge_.clear();
    for (std::size_t ni = 0; ni < nearby_.size(); ++ni) {
      const Near& n = nearby_[ni];
      int axes = 0;
      for (int a = 0; a < 3; ++a) axes += n.hi[a] > n.lo[a];
      if (axes != 1) continue;
      const Triangle& tr = mesh_.triangles[n.t];
      for (int e = 0; e < 3; ++e)
        flipEdge_[dirKey(tr[e], tr[(e + 1) % 3])] = static_cast<std::uint32_t>(ni);
    }
    byCube_.clear();
    for (std::size_t ni = 0; ni < nearby_.size(); ++ni) {
      const Near& n = nearby_[ni];
      for (std::int64_t k = n.lo[2]; k <= n.hi[2]; ++k)
        for (std::int64_t j = n.lo[1]; j <= n.hi[1]; ++j)
          for (std::int64_t i = n.lo[0]; i <= n.hi[0]; ++i)
            byCube_[cubeId(i, j, k)].push_back(static_cast<std::uint32_t>(ni));
    }
  }
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
  void setSpan(Near& n) const {
    const auto& P = mesh_.positions;
    const Triangle& tr = mesh_.triangles[n.t];
    for (int a = 0; a < 3; ++a) {
      const float mn = std::min({P[tr[0]][a], P[tr[1]][a], P[tr[2]][a]});
      const float mx = std::max({P[tr[0]][a], P[tr[1]][a], P[tr[2]][a]});
      span(a, mn, mx, &n.lo[a], &n.hi[a]);
    }
  }
  // A crease flip's pair (mesh/crease_flips.h), (v1, a, v2) and (v1, v2, b) with v1 and v2
  // feature vertices inside two cubes sharing a face and a, b on it, is turned back into the
  // two cubes' own fan triangles (v1, a, b) and (v2, b, a), as the cube extraction made them
  // (embedded by its own argument), so that refining one cube does not pull in the other.
  bool unflip(std::uint32_t ni) {
    Near& n = nearby_[ni];
    int axis = -1;
    for (int a = 0; a < 3; ++a) {
      if (n.hi[a] == n.lo[a]) continue;
      if (axis >= 0 || n.hi[a] != n.lo[a] + 1) return false;
      axis = a;
    }
    if (axis < 0) return false;
    const float plane = planeF(axis, n.hi[axis]);
    const auto& P = mesh_.positions;
    auto inner = [&](std::uint32_t v) {
      for (int a = 0; a < 3; ++a)
        if (planeAt(a, P[v][a]) >= 0) return false;
      return true;
    };
    Triangle t = mesh_.triangles[n.t];
    for (int r = 0; r < 3; ++r) {
      const std::uint32_t v1 = t[r], a = t[(r + 1) % 3], v2 = t[(r + 2) % 3];
      if (P[a][axis] != plane || !inner(v1) || !inner(v2)) continue;
      if ((P[v1][axis] < plane) == (P[v2][axis] < plane)) continue;
      const auto it = flipEdge_.find(dirKey(v1, v2));
      if (it == flipEdge_.end()) return false;
      Near& m = nearby_[it->second];
      if (removed_[m.t]) return false;
      const Triangle u = mesh_.triangles[m.t];
      int s = 0;
      while (s < 3 && !(u[s] == v1 && u[(s + 1) % 3] == v2)) ++s;
      if (s == 3) return false;
      const std::uint32_t b = u[(s + 2) % 3];
      if (P[b][axis] != plane) return false;
      mesh_.triangles[n.t] = {v1, a, b};
      mesh_.triangles[m.t] = {v2, b, a};
      setSpan(n);
      setSpan(m);
      flipEdge_.erase(dirKey(v1, v2));
      flipEdge_.erase(dirKey(v2, v1));
      ++stats_.unflipped;
      return true;
    }
    return false;
  }

  void close(std::size_t maxCubes) {
    const std::size_t T = mesh_.triangles.size();
    removed_.assign(T, 0);
    buildZone();
    std::vector<std::uint64_t> queue(omega_.begin(), omega_.end());
    for (;;) {
      checkCancel();
      // triangles reaching into the cubes queued go; the cubes they reach into join
      std::vector<std::uint64_t> joined;
      for (std::uint64_t id : queue) {
        const auto it = byCube_.find(id);
        if (it == byCube_.end()) continue;
        for (std::uint32_t ni : it->second) {
          if (removed_[nearby_[ni].t]) continue;
          if (unflip(ni) && !inSpan(nearby_[ni], id)) continue;  // now in the other cube alone
          const Near& n = nearby_[ni];
          removed_[n.t] = 1;
          std::vector<std::uint64_t> range;
          for (std::int64_t k = n.lo[2]; k <= n.hi[2]; ++k)
            for (std::int64_t j = n.lo[1]; j <= n.hi[1]; ++j)
              for (std::int64_t i = n.lo[0]; i <= n.hi[0]; ++i) range.push_back(cubeId(i, j, k));
          join(range, &joined);
        }
      }
      throwFailures();
      if (joined.empty()) {
        // A refined cube's crossed grid edge with no vertex: flat-vertex removal took it and
        // fanned its four cubes together, so they are refined together.
        findEdgeVertices();
        for (std::uint64_t id : omega_) {
          std::int64_t c[3];
          cubeOf(id, c);
          for (int a = 0; a < 3; ++a) {
            const int b = (a + 1) % 3, cc = (a + 2) % 3;
            for (int e = 0; e < 4; ++e) {
              std::int64_t l[3] = {c[0], c[1], c[2]};
              l[b] += e & 1;
              l[cc] += e >> 1;
              const std::int64_t f0[3] = {2 * l[0], 2 * l[1], 2 * l[2]};
              std::int64_t f2[3] = {f0[0], f0[1], f0[2]};
              f2[a] += 2;
              if (isInside(value(f0)) == isInside(value(f2))) continue;
              if (edgeVertex_.count(g_.linear(l[0], l[1], l[2]) * 3 +
                                    static_cast<std::uint64_t>(a)))
                continue;
              std::vector<std::uint64_t> round;
              for (int d = 0; d < 4; ++d) {
                std::int64_t q[3] = {l[0], l[1], l[2]};
                q[b] -= d & 1;
                q[cc] -= d >> 1;
                if (validCube(q)) round.push_back(cubeId(q[0], q[1], q[2]));
              }
              join(round, &joined);
            }
          }
        }
        throwFailures();
        if (joined.empty()) break;
      }
      std::sort(joined.begin(), joined.end());
      joined.erase(std::unique(joined.begin(), joined.end()), joined.end());
      if (omega_.size() + joined.size() > 2 * maxCubes)
        throw Abort("the region grew past its limit");
      evaluateCubes(joined);
      omega_.insert(joined.begin(), joined.end());
      queue = joined;
      // a cube joined near the zone's rim: the zone grows (triangles beyond it may reach in)
      bool rim = false;
      for (std::uint64_t id : joined) {
        std::int64_t c[3];
        cubeOf(id, c);
        if (!inZone(c, 2)) rim = true;
      }
      if (rim) {
        buildZone();
        queue.assign(omega_.begin(), omega_.end());
      }
    }
    cubes_.assign(omega_.begin(), omega_.end());
    std::sort(cubes_.begin(), cubes_.end());
  }

  // Cubes that must be refined together with the refined ones among them: queued to join,
  // or, where one of them was left out, the refined ones are left out too.
  void join(const std::vector<std::uint64_t>& cubes, std::vector<std::uint64_t>* joined) {
    bool conflict = false;
    for (std::uint64_t id : cubes) conflict = conflict || isBanned(id);
    if (!conflict) {
      for (std::uint64_t id : cubes)
        if (!omega_.count(id)) joined->push_back(id);
      return;
    }
    for (std::uint64_t id : cubes)
      if (omega_.count(id)) failed_.cubes.push_back(id);
  }

  // The grid-edge vertices of the removed triangles: the coarse crossings virtual edges keep.
  void findEdgeVertices() {
    const auto& P = mesh_.positions;
    edgeVertex_.clear();
    std::vector<std::uint8_t> seen(P.size(), 0);
    for (std::size_t t = 0; t < mesh_.triangles.size(); ++t) {
      if (!removed_[t]) continue;
      for (std::uint32_t v : mesh_.triangles[t]) {
        if (seen[v]) continue;
        seen[v] = 1;
        int on = 0, along = -1;
        std::int64_t l[3];
        for (int a = 0; a < 3; ++a) {
          l[a] = planeAt(a, P[v][a]);
          if (l[a] >= 0)
            ++on;
          else
            along = a;
        }
        if (on != 2) continue;
        l[along] = cellAt(along, P[v][along]);
        if (l[along] < 0) continue;
        edgeVertex_[g_.linear(l[0], l[1], l[2]) * 3 + static_cast<std::uint64_t>(along)] = v;
      }
    }
  }

  // ---- 3. the seam: open edges the removal leaves, each on a face of the region's boundary
  // The grid plane index j with planeF(a, j) == x, or -1.
  std::int64_t planeAt(int a, float x) const {
    const std::int64_t j =
        static_cast<std::int64_t>(std::llround((double(x) - g_.coord(a, 0)) / g_.h[a]));
    return (j >= 0 && j < P_[a] && planeF(a, j) == x) ? j : -1;
  }
  // The cube index u along a with planeF(a, u) < x < planeF(a, u + 1), or -1.
  std::int64_t cellAt(int a, double x) const {
    std::int64_t u = static_cast<std::int64_t>(std::floor((x - g_.coord(a, 0)) / g_.h[a]));
    u = std::clamp<std::int64_t>(u, 0, P_[a] - 2);
    while (u > 0 && planeF(a, u) >= x) --u;
    while (u < P_[a] - 2 && planeF(a, u + 1) <= x) ++u;
    return (planeF(a, u) < x && x < planeF(a, u + 1)) ? static_cast<std::int64_t>(u) : -1;
  }

  void findSeam() {
    const auto& P = mesh_.positions;
    const std::size_t T = mesh_.triangles.size(), V = P.size();
    std::vector<std::uint8_t> touched(V, 0);
    std::unordered_set<std::uint64_t> removedEdges;
    for (std::size_t t = 0; t < T; ++t) {
      if (!removed_[t]) continue;
      const Triangle& tr = mesh_.triangles[t];
      for (int e = 0; e < 3; ++e) {
        touched[tr[e]] = 1;
        removedEdges.insert(dirKey(tr[e], tr[(e + 1) % 3]));
      }
      ++stats_.trianglesRemoved;
    }
    std::size_t open = 0;  // removed edges whose partner stays
    for (std::uint64_t k : removedEdges)
      if (!removedEdges.count((k << 32) | (k >> 32))) ++open;
    std::size_t seamEdges = 0;
    for (std::size_t t = 0; t < T; ++t) {
      if (removed_[t]) continue;
      const Triangle& tr = mesh_.triangles[t];
      for (int e = 0; e < 3; ++e) {
        const std::uint32_t p = tr[e], q = tr[(e + 1) % 3];
        if (!touched[p] || !touched[q] || !removedEdges.count(dirKey(q, p))) continue;
        ++seamEdges;
        addSeamLine(p, q);
      }
    }
    throwFailures();
    if (seamEdges != open) throw Abort("the removed triangles do not close up with the rest");
  }

  void addSeamLine(std::uint32_t p, std::uint32_t q) {
    try {
      addSeamLineOrFail(p, q);
    } catch (const Abort&) {
      // the cubes round both ends join, so the seam moves away from the line
      for (const Vec3f& x : {mesh_.positions[p], mesh_.positions[q]}) {
        std::int64_t lo[3], hi[3];
        for (int a = 0; a < 3; ++a) span(a, x[a], x[a], &lo[a], &hi[a]);
        for (std::int64_t k = lo[2]; k <= hi[2]; ++k)
          for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
            for (std::int64_t i = lo[0]; i <= hi[0]; ++i)
              (omega_.count(cubeId(i, j, k)) ? failed_.fallback : failed_.extra)
                  .push_back(cubeId(i, j, k));
      }
    }
  }
  void throwFailures() {
    if (failed_.cubes.empty() && failed_.extra.empty()) return;
    CubeFailure f;
    std::swap(f, failed_);
    throw f;
  }

  void addSeamLineOrFail(std::uint32_t p, std::uint32_t q) {
    const auto& P = mesh_.positions;
    int axis = -1;
    std::int64_t plane = -1;
    for (int a = 0; a < 3; ++a) {
      if (P[p][a] != P[q][a]) continue;
      const std::int64_t j = planeAt(a, P[p][a]);
      if (j < 0) continue;
      if (axis >= 0) throw Abort("a seam line runs along a grid line");
      axis = a;
      plane = j;
    }
    if (axis < 0) throw Abort("a seam line lies on no face of the grid");
    std::int64_t cell[3];
    cell[axis] = plane;
    for (int b = 0; b < 3; ++b) {
      if (b == axis) continue;
      cell[b] = cellAt(b, 0.5 * (double(P[p][b]) + double(P[q][b])));
      if (cell[b] < 0) throw Abort("a seam line's midpoint lies on a grid line");
    }
    std::int64_t below[3] = {cell[0], cell[1], cell[2]};
    below[axis] -= 1;
    if (inOmega(below) == inOmega(cell))
      throw Abort("a seam line lies on a face inside or outside the region");
    const std::uint64_t key =
        g_.linear(cell[0], cell[1], cell[2]) * 3 + static_cast<std::uint64_t>(axis);
    SeamFace& f = seam_[key];
    f.axis = axis;
    for (int a = 0; a < 3; ++a) f.cell[a] = cell[a];
    f.lines.push_back({p, q});
  }

  // ---- 4. a seam face cut at its midlines; its centre's side from the cuts
  std::uint32_t newVertex(const Vec3f& p) { return cells_.newVertex(p); }

  void cutSeamFace(SeamFace& f) {
    const int a = f.axis, b = (a + 1) % 3, c = (a + 2) % 3;
    float midF[3] = {0.f, 0.f, 0.f};
    midF[b] = static_cast<float>(g_.mid(b, f.cell[b]));
    midF[c] = static_cast<float>(g_.mid(c, f.cell[c]));
    FaceCut cut;
    cells_.cutFace(a, f.lines, midF, &cut);
    for (int q = 0; q < 4; ++q) {
      f.halfMid[q] = std::move(cut.halfMid[q]);
      for (const Seg& piece : cut.quarter[q]) f.quarter[q].push_back({piece.to, piece.from});
    }
    // the centre's side from each half midline: its outer end's side, flipped at each cut
    int centre = -1;
    for (int half = 0; half < 4; ++half) {
      std::int64_t e[3];  // the fine point at the half midline's outer end
      for (int k = 0; k < 3; ++k) e[k] = 2 * f.cell[k];
      const int along = half < 2 ? c : b, across = half < 2 ? b : c;
      e[across] += 1;
      e[along] += (half % 2) ? 2 : 0;
      const bool end = virtualSign(e);
      const int s = (end ? 1 : 0) ^ static_cast<int>(f.halfMid[half].size() % 2);
      if (centre >= 0 && s != centre) throw Abort("a seam face's centre has no one side");
      centre = s;
    }
    f.centreInside = centre == 1;
    f.cut = true;
  }

  // ---- the side of a point of the half-cell grid: its own where every cube holding it is
  // refined, else what the seam gives it
  bool fineSign(const std::int64_t f[3]) const {
    return sampled(f) ? isInside(value(f)) : virtualSign(f);
  }
  // Whether every cube holding this point is refined (always so for a grid point, whose
  // side is the grid's, and a cube's centre).
  bool sampled(const std::int64_t f[3]) const {
    int odd = 0;
    for (int a = 0; a < 3; ++a) odd += static_cast<int>(f[a] & 1);
    if (odd == 0) return true;
    if (odd == 3) return true;
    std::int64_t lo[3];
    for (int a = 0; a < 3; ++a) lo[a] = f[a] / 2;  // odd: the cell; even: the plane
    // cubes round: along an even axis, the cubes below and above the plane
    std::int64_t q[3];
    for (int d = 0; d < 8; ++d) {
      bool skip = false;
      for (int a = 0; a < 3; ++a) {
        const int bit = (d >> a) & 1;
        if (f[a] & 1) {
          if (bit) skip = true;
          q[a] = lo[a];
        } else {
          q[a] = lo[a] - bit;
        }
      }
      if (skip) continue;
      if (!inOmega(q)) return false;
    }
    return true;
  }
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
  bool virtualSign(const std::int64_t f[3]) const {
    int odd = 0, oddAxis = -1, evenAxis = -1;
    for (int a = 0; a < 3; ++a) {
      if (f[a] & 1) {
        ++odd;
        oddAxis = a;
      } else {
        evenAxis = a;
      }
    }
    if (odd == 1) {  // a grid edge's midpoint: the side of the edge's vertex
      std::int64_t e0[3] = {f[0], f[1], f[2]}, e1[3] = {f[0], f[1], f[2]};
      e0[oddAxis] -= 1;
      e1[oddAxis] += 1;
      const bool s0 = isInside(value(e0)), s1 = isInside(value(e1));
      if (s0 == s1) return s0;
      const std::int64_t l[3] = {f[0] / 2, f[1] / 2, f[2] / 2};
      bool lowerHalf;
      coarseVertex(l, oddAxis, &lowerHalf);
      return lowerHalf ? s1 : s0;
    }
    // a face's centre: from the seam face, or the corners' side where no line crosses it
    std::int64_t cell[3] = {f[0] / 2, f[1] / 2, f[2] / 2};
    const std::uint64_t key =
        g_.linear(cell[0], cell[1], cell[2]) * 3 + static_cast<std::uint64_t>(evenAxis);
    const auto it = seam_.find(key);
    if (it != seam_.end() && !it->second.lines.empty()) {
      if (!it->second.cut) throw Abort("a seam face's centre was asked before it was cut");
      return it->second.centreInside;
    }
    const int b = (evenAxis + 1) % 3, c = (evenAxis + 2) % 3;
    std::int64_t k0[3] = {f[0], f[1], f[2]};
    k0[b] -= 1;
    k0[c] -= 1;
    const bool s = isInside(value(k0));
    for (int d = 1; d < 4; ++d) {
      std::int64_t k[3] = {k0[0], k0[1], k0[2]};
      k[b] += 2 * (d & 1);
      k[c] += 2 * (d >> 1);
      if (isInside(value(k)) != s) throw Abort("a crossed face of the seam has no lines");
    }
    return s;
  }

  // ---- 5. the half cubes: lines on their faces, loops, fans
  // The vertices on a fine edge (lower fine point f, along axis d), in order along d.
  std::vector<std::uint32_t> crossings(const std::int64_t f[3], int d) {
    const int b = (d + 1) % 3, c = (d + 2) % 3;
    std::int64_t f1[3] = {f[0], f[1], f[2]};
    f1[d] += 1;
    const bool oddB = f[b] & 1, oddC = f[c] & 1;
    if (!oddB && !oddC) {  // on a grid edge
      if (!sampled(f[d] % 2 ? f : f1)) {
        // virtual: the coarse vertex, where it lies in this half
        std::int64_t e0[3] = {f[0], f[1], f[2]};
        e0[d] = f[d] - (f[d] & 1);
        std::int64_t e2[3] = {e0[0], e0[1], e0[2]};
        e2[d] += 2;
        if (isInside(value(e0)) == isInside(value(e2))) return {};
        const std::int64_t l[3] = {e0[0] / 2, e0[1] / 2, e0[2] / 2};
        bool lowerHalf;
        const std::uint32_t v = coarseVertex(l, d, &lowerHalf);
        if (lowerHalf == ((f[d] & 1) == 0)) return {v};
        return {};
      }
    } else if (oddB != oddC) {                       // on a grid face, along a midline
      const int n = oddB ? c : b, o = oddB ? b : c;  // the face's normal; the odd axis
      std::int64_t cell[3] = {f[0] / 2, f[1] / 2, f[2] / 2};
      std::int64_t below[3] = {cell[0], cell[1], cell[2]};
      below[n] -= 1;
      if (inOmega(below) != inOmega(cell)) {  // a seam face
        const std::uint64_t key =
            g_.linear(cell[0], cell[1], cell[2]) * 3 + static_cast<std::uint64_t>(n);
        const auto it = seam_.find(key);
        if (it == seam_.end()) return {};
        const SeamFace& sf = it->second;
        const int fb = (n + 1) % 3;
        // the midline across o, halves along d
        const int half = (o == fb ? 0 : 2) + static_cast<int>(f[d] & 1);
        std::vector<std::uint32_t> out;
        for (const auto& [x, v] : sf.halfMid[half]) out.push_back(v);
        return out;
      }
    }
    if (fineSign(f) == fineSign(f1)) return {};
    const std::uint64_t key = fineKey(f) * 3 + static_cast<std::uint64_t>(d);
    const auto it = rootVertex_.find(key);
    if (it != rootVertex_.end()) return {it->second};
    const std::uint32_t v = newVertex({0.f, 0.f, 0.f});
    rootVertex_[key] = v;
    roots_.push_back({{f[0], f[1], f[2]}, d, v});
    return {v};
  }

  void meshHalfCubes() {
    // every half cube's lines first (their vertices on the half-cell grid's edges found in
    // one batch), then the cells
    std::vector<Cell> cells;
    std::vector<std::uint64_t> cellCube;
    for (std::uint64_t id : cubes_) {
      std::int64_t c[3];
      cubeOf(id, c);
      try {
        for (int h = 0; h < 8; ++h) {
          const std::int64_t f0[3] = {2 * c[0] + (h & 1), 2 * c[1] + ((h >> 1) & 1),
                                      2 * c[2] + ((h >> 2) & 1)};
          cells.push_back(halfCube(f0));
          cellCube.push_back(id);
        }
      } catch (const Abort&) {
        failed_.cubes.push_back(id);
      }
    }
    throwFailures();
    findRoots();
    std::uint64_t last = UINT64_MAX;
    for (std::size_t i = 0; i < cells.size(); ++i) {
      if (cellCube[i] == last && !failed_.cubes.empty() && failed_.cubes.back() == last) continue;
      try {
        cells_.meshCell(cells[i], 0);
      } catch (const Abort&) {
        failed_.cubes.push_back(cellCube[i]);
      }
      if (cellCube[i] != last) ++stats_.cubes;
      last = cellCube[i];
    }
    throwFailures();
    cells_.flipCreases();
  }

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
  void faceLines(const std::int64_t f0[3], int a, int side, std::vector<Seg>* out) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    std::int64_t fp[3] = {f0[0], f0[1], f0[2]};
    fp[a] += side;
    if ((fp[a] & 1) == 0) {  // on a grid face: a seam face gives its pieces
      std::int64_t cell[3] = {fp[0] / 2, fp[1] / 2, fp[2] / 2};
      std::int64_t below[3] = {cell[0], cell[1], cell[2]};
      below[a] -= 1;
      if (inOmega(below) != inOmega(cell)) {
        const std::uint64_t key =
            g_.linear(cell[0], cell[1], cell[2]) * 3 + static_cast<std::uint64_t>(a);
        const auto it = seam_.find(key);
        if (it == seam_.end()) return;
        const int quarter = static_cast<int>(fp[b] & 1) + 2 * static_cast<int>(fp[c] & 1);
        for (const Seg& s : it->second.quarter[quarter]) out->push_back(s);
        return;
      }
    }
    // the face's corners counterclockwise seen from outside the half cube
    static const int ccw[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    std::int64_t corner[4][3];
    for (int k = 0; k < 4; ++k) {
      const int i = side == 1 ? k : (4 - k) % 4;
      for (int x = 0; x < 3; ++x) corner[k][x] = fp[x];
      corner[k][b] += ccw[i][0];
      corner[k][c] += ccw[i][1];
    }
    // walk: corner k, then the crossings on the edge to corner k + 1
    std::vector<WalkStep> walk;
    for (int k = 0; k < 4; ++k) {
      const std::int64_t* p = corner[k];
      const std::int64_t* q = corner[(k + 1) % 4];
      walk.push_back({true, fineSign(p), 0});
      int d = -1;
      for (int x = 0; x < 3; ++x)
        if (p[x] != q[x]) d = x;
      std::int64_t lower[3] = {p[0], p[1], p[2]};
      lower[d] = std::min(p[d], q[d]);
      std::vector<std::uint32_t> xs = crossings(lower, d);
      if (q[d] < p[d]) std::reverse(xs.begin(), xs.end());
      for (std::uint32_t v : xs) walk.push_back({false, false, v});
    }
    double mid[3];
    for (int x = 0; x < 3; ++x)
      mid[x] = 0.5 * (fineCoord(x, corner[0][x]) + fineCoord(x, corner[2][x]));
    cells_.pairCrossings(walk, mid, out);
  }

  // ---- 6. the vertices on the half-cell grid's edges: Illinois on the field where it
  // changes sign between the ends, else the edge's middle (a virtual end)
  struct Root {
    std::int64_t f[3];
    int d;
    std::uint32_t v;
  };

  void findRoots() {
    const std::size_t n = roots_.size();
    if (n == 0) return;
    std::vector<IllinoisBracket> b(n);
    std::vector<double> t(n, kNoRoot);
    std::vector<char> active(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
      std::int64_t f1[3] = {roots_[i].f[0], roots_[i].f[1], roots_[i].f[2]};
      f1[roots_[i].d] += 1;
      b[i].fa = value(roots_[i].f);
      b[i].fb = value(f1);
      active[i] = isInside(b[i].fa) != isInside(b[i].fb);
    }
    std::vector<double> x, y, z, v;
    std::vector<std::size_t> which;
    for (int it = 0; it < kMaxRootSteps; ++it) {
      x.clear();
      y.clear();
      z.clear();
      which.clear();
      for (std::size_t i = 0; i < n; ++i) {
        if (!active[i]) continue;
        const double u = illinoisEstimate(b[i]);
        t[i] = u;
        const Root& r = roots_[i];
        double p[3];
        for (int k = 0; k < 3; ++k) p[k] = fineCoord(k, r.f[k]);
        p[r.d] += u * (fineCoord(r.d, r.f[r.d] + 1) - p[r.d]);
        x.push_back(p[0]);
        y.push_back(p[1]);
        z.push_back(p[2]);
        which.push_back(i);
      }
      if (which.empty()) break;
      v.resize(which.size());
      field_.evalBatch(x.data(), y.data(), z.data(), which.size(), v.data());
      stats_.evaluations += which.size();
      for (std::size_t w = 0; w < which.size(); ++w) {
        const std::size_t i = which[w];
        const double fv = combine(v[w], g_.boxField(x[w], y[w], z[w]));
        if (fv == 0.0 || std::isnan(fv)) {
          active[i] = 0;
          continue;
        }
        illinoisUpdate(b[i], t[i], fv);
        if (b[i].tb - b[i].ta < kRootBracket) active[i] = 0;
      }
    }
    for (std::size_t i = 0; i < n; ++i) {
      const Root& r = roots_[i];
      const double u = std::clamp(t[i], kEdgeMargin, 1.0 - kEdgeMargin);
      Vec3f p;
      for (int k = 0; k < 3; ++k) p[k] = fineF(k, r.f[k]);
      const double a0 = fineCoord(r.d, r.f[r.d]), a1 = fineCoord(r.d, r.f[r.d] + 1);
      p[r.d] = static_cast<float>(a0 + u * (a1 - a0));
      if (!(p[r.d] > fineF(r.d, r.f[r.d]) && p[r.d] < fineF(r.d, r.f[r.d] + 1)))
        throw Abort("a half cell is too small for float32");
      mesh_.positions[r.v] = p;
    }
  }

  // ---- 7. every triangle with an edge that was cut (on the seam, or between a split cell
  // and its neighbour) takes the cuts as vertices: a fan from its opposite corner over one cut
  // edge, from its centroid (in its plane) over several

  bool splitTriangle(const Triangle& tr, std::vector<Triangle>* out) {
    std::vector<std::uint32_t> on[3];
    int cutEdges = 0, which = 0;
    for (int e = 0; e < 3; ++e) {
      on[e] = cells_.between(tr[e], tr[(e + 1) % 3]);
      if (!on[e].empty()) {
        ++cutEdges;
        which = e;
      }
    }
    if (cutEdges == 0) return false;
    if (cutEdges == 1) {
      std::vector<std::uint32_t> chain = {tr[which]};
      chain.insert(chain.end(), on[which].begin(), on[which].end());
      chain.push_back(tr[(which + 1) % 3]);
      for (std::size_t i = 0; i + 1 < chain.size(); ++i)
        out->push_back({tr[(which + 2) % 3], chain[i], chain[i + 1]});
      return true;
    }
    std::vector<std::uint32_t> poly;
    for (int e = 0; e < 3; ++e) {
      poly.push_back(tr[e]);
      poly.insert(poly.end(), on[e].begin(), on[e].end());
    }
    Vec3f cen;
    for (int k = 0; k < 3; ++k)
      cen[k] = static_cast<float>((double(mesh_.positions[tr[0]][k]) + mesh_.positions[tr[1]][k] +
                                   mesh_.positions[tr[2]][k]) /
                                  3.0);
    const std::uint32_t v = newVertex(cen);
    for (std::size_t i = 0; i < poly.size(); ++i)
      out->push_back({v, poly[i], poly[(i + 1) % poly.size()]});
    return true;
  }

  void splitTriangles() {
    if (cells_.cuts().empty()) return;
    std::vector<std::uint8_t> mark(mesh_.positions.size(), 0);
    for (const auto& [k, list] : cells_.cuts()) {
      mark[k >> 32] = 1;
      mark[k & 0xffffffffu] = 1;
    }
    auto marked = [&](const Triangle& t) {
      int n = 0;
      for (std::uint32_t v : t) n += v < mark.size() && mark[v];
      return n >= 2;
    };
    std::vector<Triangle> outside;
    for (std::size_t t = 0; t < mesh_.triangles.size(); ++t) {
      if (removed_[t] || !marked(mesh_.triangles[t])) continue;
      const Triangle tr = mesh_.triangles[t];
      if (splitTriangle(tr, &outside)) removed_[t] = 1;
    }
    std::vector<Triangle> inside;
    std::vector<Triangle>& added = cells_.added();
    inside.reserve(added.size());
    for (const Triangle& tr : added)
      if (!marked(tr) || !splitTriangle(tr, &inside)) inside.push_back(tr);
    added = std::move(inside);
    added.insert(added.end(), outside.begin(), outside.end());
  }

  // ---- 8. the mesh: the triangles kept, the new ones, unused vertices dropped, normals
  void assemble() {
    std::vector<Triangle> tris;
    const std::vector<Triangle>& added = cells_.added();
    tris.reserve(mesh_.triangles.size() + added.size());
    for (std::size_t t = 0; t < mesh_.triangles.size(); ++t)
      if (!removed_[t]) tris.push_back(mesh_.triangles[t]);
    stats_.trianglesAdded = added.size();
    tris.insert(tris.end(), added.begin(), added.end());
    const std::size_t oldCount = mesh_.normals.size();
    std::vector<std::uint32_t> remap(mesh_.positions.size(), UINT32_MAX);
    for (const Triangle& t : tris)
      for (std::uint32_t v : t) remap[v] = 0;
    std::vector<Vec3f> positions, normals;
    std::vector<std::uint32_t> fresh;  // new vertices (their new index) for normals
    const bool withNormals = oldCount > 0;
    for (std::size_t v = 0; v < remap.size(); ++v) {
      if (remap[v] == UINT32_MAX) continue;
      remap[v] = static_cast<std::uint32_t>(positions.size());
      positions.push_back(mesh_.positions[v]);
      if (withNormals) {
        normals.push_back(v < oldCount ? mesh_.normals[v] : Vec3f{0.f, 0.f, 0.f});
        if (v >= oldCount) fresh.push_back(remap[v]);
      }
    }
    for (Triangle& t : tris)
      for (std::uint32_t& v : t) v = remap[v];
    for (std::uint32_t i : fresh) {
      const Vec3f& p = positions[i];
      normals[i] = vertexNormal(field_.evalGradient(p[0], p[1], p[2]), *g_.base, p);
    }
    mesh_.positions = std::move(positions);
    mesh_.normals = std::move(normals);
    mesh_.triangles = std::move(tris);
  }

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
  std::int64_t P_[3], F_[3];
  std::unordered_map<std::uint64_t, double> values_;
  std::unordered_set<std::uint64_t> omega_;
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

}  // namespace

void refineHiddenParts(const Field& field, const Grid& g,
                       const std::vector<std::uint64_t>& seedEdges, std::size_t maxCubes,
                       TriangleMesh& mesh, LocalRefinementStats* stats, int levels,
                       const std::function<bool(double)>& progress) {
  LocalRefinementStats local;
  LocalRefinementStats& s = stats ? *stats : local;
  s = LocalRefinementStats();
  if (levels < 1 || levels > kMaxRefinementLevels)
    throw ModelError("mesher: refinementLevels must be 1 to " +
                     std::to_string(kMaxRefinementLevels) + "; got " + std::to_string(levels));
  if (seedEdges.empty() && levels == 1) return;
  // The bar: the look at the surface's cubes (deeper levels only) a third, the levels the
  // rest in equal parts (a deeper level refines about as many cubes, each smaller).
  const double lookShare = levels > 1 ? 0.3 : 0.0, levelShare = (1.0 - lookShare) / levels;
  const Progress bar(progress);
  auto aboveMesh = std::make_unique<TriangleMesh>(mesh);
  std::unique_ptr<Refiner> above;
  try {
    above = std::make_unique<Refiner>(field, RefinementGrid::of(g), *aboveMesh, s);
    std::vector<std::uint64_t> seeds = above->cubesRound(seedEdges);
    if (levels > 1) {
      above->keepSidesForNextLevel();
      std::vector<std::uint64_t> more, far;
      above->reportAt(bar.sub(0.0, lookShare));
      above->surfaceCubesToLookAt(&more, &far);
      seeds.insert(seeds.end(), more.begin(), more.end());
      seeds.insert(seeds.end(), far.begin(), far.end());
      above->refineWhateverTheyShow(far);
    }
    above->reportAt(bar.sub(lookShare, levelShare));
    above->run(seeds, maxCubes);
  } catch (const Abort& e) {
    const std::size_t evaluations = s.evaluations;
    s = LocalRefinementStats();
    s.evaluations = evaluations;
    s.skipped = e.what();
    return;
  }
  if (s.cubes == 0) return;
  mesh = *aboveMesh;
  s.levels = 1;
  // Deeper levels: each refines the half cubes of the one above where its own half cells
  // show what their corners miss, on that level's mesh. A level that fails leaves the mesh
  // as the level above made it.
  for (int level = 2; level <= levels; ++level) {
    std::vector<std::uint64_t> seeds = above->finerCandidates();
    auto deeper = std::make_unique<TriangleMesh>(mesh);
    LocalRefinementStats ls;
    auto next = std::make_unique<Refiner>(field, above->grid().finer(), *deeper, ls);
    above->handDown(*next);
    if (level < levels) next->keepSidesForNextLevel();
    const double start = lookShare + (level - 1) * levelShare;
    next->reportAt(bar.sub(start, 0.0));
    try {
      // where the level above was refined for lying far from the surface, its half cubes
      // are looked at again on its mesh (a sliver's tip, narrower than its half cells)
      const std::vector<std::uint64_t> halves = above->halvesOfFarCubes();
      if (!halves.empty()) {
        std::vector<std::uint64_t> more, far;
        next->surfaceCubesToLookAt(&more, &far, &halves);
        seeds.insert(seeds.end(), more.begin(), more.end());
        seeds.insert(seeds.end(), far.begin(), far.end());
        next->refineWhateverTheyShow(far);
      }
      if (seeds.empty()) break;
      next->reportAt(bar.sub(start, levelShare));
      next->run(seeds, maxCubes);
    } catch (const Abort& e) {
      s.evaluations += ls.evaluations;
      s.deeperSkipped = e.what();
      break;
    }
    s.evaluations += ls.evaluations;
    s.deeperCubesLeftOut += ls.cubesLeftOut;
    if (ls.cubes == 0) break;
    s.deeperCubes += ls.cubes;
    s.trianglesAdded += ls.trianglesAdded;
    s.trianglesRemoved += ls.trianglesRemoved;
    s.levels = level;
    mesh = *deeper;
    above = std::move(next);
    aboveMesh = std::move(deeper);  // (the Refiner's mesh, kept while it is asked)
  }
  if (progress && !progress(1.0)) throw Cancelled();
}

}  // namespace frep
