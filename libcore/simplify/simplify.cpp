#include "simplify/simplify.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>

#include "base/errors.h"
#include "base/qef.h"
#include "base/triangle_geometry.h"
#include "check/face_pair_test.h"

namespace frep {

namespace {
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
// A new face may be no thinner than this (4 sqrt(3) area / sum of squared sides: 1 for an
// equilateral triangle) unless the faces it replaces were thinner already; a vertex placed on
// a crease or corner may make faces down to kFeatureQuality (faces along a sharp edge are
// long and thin by nature).
constexpr double kQuality = 0.1;
constexpr double kFeatureQuality = 0.01;
// The quadric's directions weaker than this fraction of its strongest are left at the mean:
// low enough that a corner met by one plane among ten on its faces still counts.
constexpr double kPlaneCutoff = 0.02;
// With collapses onto creases only: a crease is where planes differ by over 30 degrees
// (the eigenvalue ratio of two planes at angle a is tan^2(a / 2)). Curved parts whose
// neighbouring planes differ by 16 to 30 degrees (the gyroid's sheets at 256 cells) are no
// creases to straighten: merged there they cost 60,000 collapses and 8 s for nothing sharper.
constexpr double kCreasePlaneCutoff = 0.0718;
// and the faces near one: a face whose normal is over 12 degrees from the surface's at one of
// its vertices (a chamfer's faces turn by half the crease's angle, 15 degrees and more, from
// either side). Only regions holding such faces are worked on, and only edges and snaps at
// their vertices tried: a sphere is left alone at the cost of one pass over its faces.
constexpr double kNearCreaseCos = 0.978;  // cos 12 degrees
// and the point a vertex goes to must lie on the surface, within this fraction of a cell: on a
// crease the tangent planes of its two sides meet on it, where on a curved part two planes 30
// degrees apart meet outside it (a sphere of radius R: R (1 / cos 15 degrees - 1) = 0.035 R),
// so a curve is not taken for a crease. Without it the twist at 24 and 32 cells (its faces
// turn by 20 degrees within 2.5 cells there) came out dented: crease length 22.5 and 21.7
// (the mesher's 20.1 and 20.7), with it 21.2 and 20.4; 0.05 cell refused merges the twist's
// slightly curved faces need at 64 cells (20.06 -> 20.26).
constexpr double kOnCreaseCells = 0.08;
// A changed face's normal may turn by less than this cosine's angle (about 72 degrees).
constexpr double kTurn = 0.3;
// Edges whose two faces turn by more than this angle (its cosine: 20 degrees) are where edge
// flips look for a crease the collapses left zig-zagging (flipTowardsCreases). (At 10 degrees
// the gyroid's curved sheets, simplified, turn by that at many edges, and its simplification
// took 13 % more time, for flips that rarely pay there.)
constexpr double kFlipTurnCos = 0.94;  // (cos 20 degrees)
// A flip is taken only where it lowers the quad's turning (sum of edge length x angle) by
// more than this fraction: no flip back and forth on rounding.
constexpr double kFlipGain = 1e-3;

Vec3 toVec3(const Vec3f& p) {
  return {p[0], p[1], p[2]};
}
Vec3f toVec3f(const Vec3& p) {
  return {static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])};
}
Vec3 sub(const Vec3& a, const Vec3& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
double dot(const Vec3& a, const Vec3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// The surface the mesher meshed: min(F, distance to the box), its value and unit gradient.
class Surface {
 public:
  Surface(const Field& f, const Box3& box) : f_(f), box_(box) {}

  // An estimate of the distance from p to the surface: |G| / |grad G|.
  double distance(const Vec3& p) const {
    Vec3 n;
    double v;
    if (!plane(p, &v, &n)) return std::numeric_limits<double>::infinity();
    return std::abs(v);
  }
  // G(p) / |grad G| in *value and the unit gradient in *normal; false where the gradient
  // vanishes or is not finite.
  bool plane(const Vec3& p, double* value, Vec3* normal) const {
    return planeFrom(p, f_.evalGradient(p[0], p[1], p[2]), value, normal);
  }
  // plane() at n points in one gradient batch (the field's vector kernels).
  void planes(const Vec3* p, std::size_t n, double* value, Vec3* normal, std::uint8_t* ok) {
    x_.resize(n);
    y_.resize(n);
    z_.resize(n);
    g_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      x_[i] = Dual(p[i][0], 1, 0, 0);
      y_[i] = Dual(p[i][1], 0, 1, 0);
      z_[i] = Dual(p[i][2], 0, 0, 1);
    }
    f_.evalGradientBatch(x_.data(), y_.data(), z_.data(), n, g_.data());
    for (std::size_t i = 0; i < n; ++i) ok[i] = planeFrom(p[i], g_[i], &value[i], &normal[i]);
  }

 private:
  bool planeFrom(const Vec3& p, const Dual& f, double* value, Vec3* normal) const {
    const Dual g = cappedByBox(f, box_, p);
    const double len = std::sqrt(g.d[0] * g.d[0] + g.d[1] * g.d[1] + g.d[2] * g.d[2]);
    if (!(len > 0.0) || !std::isfinite(len) || !std::isfinite(g.v)) return false;
    *value = g.v / len;
    *normal = {g.d[0] / len, g.d[1] / len, g.d[2] / len};
    return true;
  }

  const Field& f_;
  Box3 box_;
  std::vector<Dual> x_, y_, z_, g_;  // scratch of planes()
};

// Regions: cubes of `side` from `origin`; a region's key packs its three indices.
struct Regions {
  Vec3 origin;
  double side;
  std::int64_t index(double v, int a) const {
    return static_cast<std::int64_t>(std::floor((v - origin[a]) / side));
  }
  static std::uint64_t key(std::int64_t i, std::int64_t j, std::int64_t k) {
    const std::uint64_t bias = 1u << 20;
    return ((static_cast<std::uint64_t>(k) + bias) << 42) |
           ((static_cast<std::uint64_t>(j) + bias) << 21) | (static_cast<std::uint64_t>(i) + bias);
  }
  std::uint64_t of(const Vec3f& p) const {
    return key(index(p[0], 0), index(p[1], 1), index(p[2], 2));
  }
};

double quality(const Vec3f& a, const Vec3f& b, const Vec3f& c) {
  const Vec3 pa = toVec3(a), pb = toVec3(b), pc = toVec3(c);
  const double s = dot(sub(pb, pa), sub(pb, pa)) + dot(sub(pc, pb), sub(pc, pb)) +
                   dot(sub(pa, pc), sub(pa, pc));
  return s > 0.0 ? 2.0 * std::sqrt(3.0) * norm(triangleCross(a, b, c)) / s : 0.0;
}
Vec3 faceNormal(const std::vector<Vec3f>& pos, const Triangle& t) {
  return triangleCross(pos[t[0]], pos[t[1]], pos[t[2]]);
}

// The shared state of one simplification: positions (float, as written), quadrics, and which
// vertices are gone or moved. A region's thread writes only its own free vertices.
struct State {
  std::vector<Vec3f> pos;
  std::vector<Quadric> quadric;
  std::vector<std::uint8_t> removed, moved;
  // With collapses onto creases only: the surface's outward unit normal at each vertex as
  // meshed (zero where the gradient vanishes), and, per pass, the vertices of faces near a crease.
  std::vector<Vec3f> normal;
  std::vector<std::uint8_t> nearCrease;
  // The mesher's vertices (points on the surface) a vertex stands for: its own, and those of
  // the vertices merged into it. The mesh must stay within the tolerance of each, so the
  // surface cannot recede from the mesh either (the other side of the Hausdorff distance).
  std::vector<std::vector<Vec3f>> samples;
};

// (collapses onto creases only) whether a vertex of t is near a crease
bool touchesCrease(const State& s, const Triangle& t) {
  return s.nearCrease[t[0]] || s.nearCrease[t[1]] || s.nearCrease[t[2]];
}

struct RegionInput {
  std::uint64_t key;
  const std::uint32_t* inner;  // faces (indices into the pass's face list) inside the region
  std::size_t innerCount;
  const std::uint32_t* frozen;  // faces crossing regions whose box meets this region
  std::size_t frozenCount;
  // Crease flips are made in the last two passes only: made in all three (and from 10
  // degrees), they left the gyroid 1.6 % more triangles and took 10 to 13 % longer (its
  // sheets turn everywhere), for a little straighter creases (the twist at 128 cells: 22.8
  // against 23.1).
  bool flipPass;
};

struct RegionOutput {
  std::vector<Triangle> faces;
  std::size_t collapses = 0, flips = 0;
  double largestDistance = 0.0;
};

// One region's collapses. Faces are kept with global vertex ids (the pair test reads the
// shared positions); the region's vertices and faces have local numbers for the bookkeeping.
class RegionSimplifier {
 public:
  RegionSimplifier(State& s, const Field& field, const SimplifyOptions& o,
                   const Regions& regions, const std::vector<Triangle>& faces)
      : s_(s), field_(field), o_(o), regions_(regions), all_(faces) {}

  void run(const RegionInput& in, RegionOutput& out) {
    key_ = in.key;
    setUp(in);
    // Edges, shortest first (the grid's slivers go first); each is tried in both directions,
    // where v goes found when it is tried. An entry is stale once either end has changed.
    heap_.clear();
    auto push = [&](std::uint32_t a, std::uint32_t b) {
      if (a == kNone || b == kNone || (fixed_[a] && fixed_[b])) return;
      if (o_.creaseCollapsesOnly && !s_.nearCrease[gid_[a]] && !s_.nearCrease[gid_[b]]) return;
      const Vec3 d = sub(toVec3(s_.pos[gid_[a]]), toVec3(s_.pos[gid_[b]]));
      heap_.push_back({dot(d, d), a, b, stamp_[a], stamp_[b]});
      std::push_heap(heap_.begin(), heap_.end(), std::greater<EdgeEntry>());
    };
    for (std::uint32_t f = 0; f < faces_.size(); ++f) {
      if (frozenFace_[f]) continue;
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t a = local(faces_[f][k]), b = local(faces_[f][(k + 1) % 3]);
        if (a < b) push(a, b);  // each edge once: (a, b) in one face, (b, a) in the other
      }
    }
    while (!heap_.empty()) {
      std::pop_heap(heap_.begin(), heap_.end(), std::greater<EdgeEntry>());
      const EdgeEntry e = heap_.back();
      heap_.pop_back();
      if (removedLocal_[e.a] || removedLocal_[e.b] || stamp_[e.a] != e.stampA ||
          stamp_[e.b] != e.stampB)
        continue;
      std::uint32_t v = kNone;
      for (int direction = 0; direction < 2 && v == kNone; ++direction) {
        Candidate c{direction ? e.b : e.a, direction ? e.a : e.b, Vec3{0, 0, 0}};
        if (fixed_[c.u]) continue;
        // Where v goes: it stays when fixed or without sharp features; else the merged
        // quadric's minimiser. A merged vertex that cannot go there may still stay where v
        // is, with sharp features only where that keeps it near every plane it carries:
        // within tolerance^2 of the quadric's least (else a corner or crease would be
        // rounded off).
        const Vec3 here = toVec3(s_.pos[gid_[c.v]]);
        Quadric q;
        Vec3 best = here;
        double least = 0.0;
        int rank = 0;
        if (o_.sharpFeatures) {
          q = merged(c.u, c.v);
          // (onto creases only: a merge whose planes cannot make a crease is not one)
          if (o_.creaseCollapsesOnly && !q.mayBeSharp(planeCutoff())) continue;
          if (q.count > 0.0) {
            best = q.minimiser(planeCutoff(), &rank);
            least = q.error(best);
          }
        }
        auto admissible = [&](const Vec3& p) {
          return !o_.sharpFeatures || q.count <= 0.0 ||
                 q.error(p) <= least + o_.tolerance * o_.tolerance;
        };
        c.at = fixed_[c.v] ? here : best;
        featureMove_ = !fixed_[c.v] && rank >= 2;
        if (o_.creaseCollapsesOnly && !(featureMove_ && onCrease(c.at))) continue;
        bool done = admissible(c.at) && collapse(c, out);
        if (!done && !o_.creaseCollapsesOnly && toVec3f(c.at) != s_.pos[gid_[c.v]]) {
          c.at = here;
          featureMove_ = false;
          done = admissible(here) && collapse(c, out);
        }
        if (done) v = c.v;
      }
      if (v == kNone) continue;
      ++out.collapses;
      if (2 * liveFaces_ < liveAtBuild_) buildGrid();
      ring(v, gid_[v], neighboursU_);
      for (std::uint32_t w : neighboursU_) push(v, local(w));
    }
    // a vertex on a crease lets its neighbours find the crease too: sweep until none moves
    if (o_.sharpFeatures) {
      for (int sweep = 0; sweep < 4 && snapToFeatures(out) > 0; ++sweep) {
      }
      for (int sweep = 0; o_.creaseFlips && in.flipPass && sweep < 4 && flipTowardsCreases(out) > 0;
           ++sweep) {
      }
    }
    for (std::uint32_t f = 0; f < faces_.size(); ++f)
      if (!frozenFace_[f] && deadFace_[f] == kLive) out.faces.push_back(faces_[f]);
  }

 private:
  // (collapses onto creases only) whether p lies on the surface (kOnCreaseCells)
  bool onCrease(const Vec3& p) const {
    double value;
    Vec3 n;
    return region_->plane(p, &value, &n) && std::abs(value) <= kOnCreaseCells * o_.cell;
  }
  double planeCutoff() const { return o_.creaseCollapsesOnly ? kCreasePlaneCutoff : kPlaneCutoff; }

  struct FaceBox {
    float lo[3], hi[3];
    void grow(const FaceBox& b) {
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], b.lo[a]);
        hi[a] = std::max(hi[a], b.hi[a]);
      }
    }
    bool meets(const FaceBox& b) const {  // closed boxes
      for (int a = 0; a < 3; ++a)
        if (hi[a] < b.lo[a] || b.hi[a] < lo[a]) return false;
      return true;
    }
  };
  struct Candidate {
    std::uint32_t u, v;  // u goes, v stays (at `at`)
    Vec3 at;
  };
  struct EdgeEntry {
    double cost;
    std::uint32_t a, b, stampA, stampB;
    bool operator>(const EdgeEntry& e) const { return cost > e.cost; }
  };

  void setUp(const RegionInput& in) {
    // the global -> local map is kept per thread, all kNone between regions
    if (localOf_.size() != s_.pos.size()) localOf_.assign(s_.pos.size(), kNone);
    for (std::uint32_t g : gid_) localOf_[g] = kNone;
    gid_.clear();
    faces_.clear();
    frozenFace_.clear();
    for (std::size_t i = 0; i < in.innerCount; ++i) {
      faces_.push_back(all_[in.inner[i]]);
      frozenFace_.push_back(0);
    }
    for (std::size_t i = 0; i < in.frozenCount; ++i) {
      faces_.push_back(all_[in.frozen[i]]);
      frozenFace_.push_back(1);
    }
    deadFace_.assign(faces_.size(), kLive);
    deviation_.assign(faces_.size(), std::numeric_limits<float>::quiet_NaN());
    // the region's vertices: those of its faces that lie in it
    for (const Triangle& t : faces_)
      for (std::uint32_t v : t)
        if (regions_.of(s_.pos[v]) == key_) gid_.push_back(v);
    std::sort(gid_.begin(), gid_.end());
    gid_.erase(std::unique(gid_.begin(), gid_.end()), gid_.end());
    const std::size_t n = gid_.size();
    for (std::uint32_t l = 0; l < n; ++l) localOf_[gid_[l]] = l;
    // (the lists are cleared, not freed: the next region reuses them)
    if (around_.size() < n) around_.resize(n);
    for (std::size_t l = 0; l < n; ++l) around_[l].clear();
    fixed_.assign(n, 0);
    removedLocal_.assign(n, 0);
    stamp_.assign(n, 0);
    for (std::uint32_t f = 0; f < faces_.size(); ++f)
      for (std::uint32_t v : faces_[f]) {
        const std::uint32_t l = local(v);
        if (l == kNone) continue;
        around_[l].push_back(f);
        if (frozenFace_[f]) fixed_[l] = 1;
      }
    for (int a = 0; a < 3; ++a) {
      const std::int64_t i = static_cast<std::int64_t>((key_ >> (21 * a)) & ((1u << 21) - 1)) -
                             (std::int64_t(1) << 20);
      regionLo_[a] = regions_.origin[a] + static_cast<double>(i) * regions_.side;
    }
    Box3 box;
    for (int a = 0; a < 3; ++a) {
      box.lo[a] = regionLo_[a];
      box.hi[a] = regionLo_[a] + regions_.side;
    }
    region_.emplace(specialiseInto(field_, box, regionField_), o_.bbox);
    visit_.assign(faces_.size(), 0);
    inCell_.assign(faces_.size(), 0);
    visitStamp_ = cellStamp_ = 0;
    faceBox_.resize(faces_.size());
    for (std::uint32_t f = 0; f < faces_.size(); ++f) faceBox_[f] = boxOf(faces_[f]);
    liveFaces_ = faces_.size();
    buildGrid();
  }

  // The search grid over the region and a mesher cell round it, its cells about the size of
  // the live faces (a face then covers a couple of cells per axis it spans). Rebuilt as the
  // faces grow: a grid of the first, small faces would list a grown face in dozens of cells.
  void buildGrid() {
    double sum = 0.0;
    std::size_t live = 0;
    for (std::uint32_t f = 0; f < faces_.size(); ++f) {
      if (deadFace_[f] != kLive) continue;
      const FaceBox& b = faceBox_[f];
      sum += std::max({b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]});
      ++live;
    }
    gridCell_ = std::max(o_.cell, live ? sum / static_cast<double>(live) : o_.cell);
    for (int a = 0; a < 3; ++a) gridLo_[a] = regionLo_[a] - o_.cell;
    gridDim_ = std::max(
        1, std::min(o_.regionCells + 2,
                    static_cast<int>(std::ceil((regions_.side + 2 * o_.cell) / gridCell_))));
    grid_.resize(static_cast<std::size_t>(gridDim_) * gridDim_ * gridDim_);
    for (std::vector<std::uint32_t>& cell : grid_) cell.clear();
    for (std::uint32_t f = 0; f < faces_.size(); ++f)
      if (deadFace_[f] == kLive) insert(f);
    liveAtBuild_ = live;
  }

  std::uint32_t local(std::uint32_t global) const { return localOf_[global]; }

  Quadric merged(std::uint32_t u, std::uint32_t v) const {
    Quadric q = s_.quadric[gid_[u]];
    q += s_.quadric[gid_[v]];
    return q;
  }
  void cellRange(const FaceBox& b, int lo[3], int hi[3]) const {
    for (int a = 0; a < 3; ++a) {
      auto clamp = [&](double v) {
        const double i = std::floor((v - gridLo_[a]) / gridCell_);
        return static_cast<int>(std::max(0.0, std::min(i, static_cast<double>(gridDim_ - 1))));
      };
      lo[a] = clamp(b.lo[a]);
      hi[a] = clamp(b.hi[a]);
    }
  }
  void insert(std::uint32_t f) {
    int lo[3], hi[3];
    cellRange(faceBox_[f], lo, hi);
    for (int k = lo[2]; k <= hi[2]; ++k)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int i = lo[0]; i <= hi[0]; ++i)
          grid_[(static_cast<std::size_t>(k) * gridDim_ + j) * gridDim_ + i].push_back(f);
  }
  // The live faces whose cells meet face f's (stale entries of moved faces included: the
  // pair test decides). Each cell scanned drops its dead and repeated entries on the way.
  void near(const FaceBox& box, std::vector<std::uint32_t>& out) {
    out.clear();
    ++visitStamp_;
    int lo[3], hi[3];
    cellRange(box, lo, hi);
    for (int k = lo[2]; k <= hi[2]; ++k)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int i = lo[0]; i <= hi[0]; ++i) {
          std::vector<std::uint32_t>& cell =
              grid_[(static_cast<std::size_t>(k) * gridDim_ + j) * gridDim_ + i];
          ++cellStamp_;
          std::size_t kept = 0;
          for (std::uint32_t g : cell) {
            // gone for good: dropped; gone only for the collapse under test: kept listed
            if (deadFace_[g] == kGone || inCell_[g] == cellStamp_) continue;
            inCell_[g] = cellStamp_;
            cell[kept++] = g;
            if (deadFace_[g] != kLive) continue;
            if (visit_[g] != visitStamp_) {
              visit_[g] = visitStamp_;
              out.push_back(g);
            }
          }
          cell.resize(kept);
        }
  }

  FaceBox boxOf(const Triangle& t) const {
    FaceBox b;
    for (int a = 0; a < 3; ++a) {
      b.lo[a] = std::min({s_.pos[t[0]][a], s_.pos[t[1]][a], s_.pos[t[2]][a]});
      b.hi[a] = std::max({s_.pos[t[0]][a], s_.pos[t[1]][a], s_.pos[t[2]][a]});
    }
    return b;
  }

  // How far face f's centre is from F = 0 (|F| / |grad F|), cached per face until it changes.
  double deviation(std::uint32_t f) {
    if (std::isnan(deviation_[f])) {
      const Triangle& t = faces_[f];
      Vec3 centre{0, 0, 0};
      for (std::uint32_t w : t)
        for (int a = 0; a < 3; ++a) centre[a] += s_.pos[w][a] / 3.0;
      deviation_[f] = static_cast<float>(region_->distance(centre));
    }
    return deviation_[f];
  }
  // The distance a change of these faces (and of `also`) may leave: the tolerance, or their
  // worst where that is worse already.
  // (At most a cell: the grid's faces are never farther, so a larger estimate is one where
  // the gradient nearly vanishes and |F| / |grad F| overstates the distance.)
  double allowedFor(const std::vector<std::uint32_t>& changed, const std::uint32_t* also, int n) {
    double worst = 0.0;
    for (std::uint32_t f : changed) worst = std::max(worst, deviation(f));
    for (int i = 0; i < n; ++i) worst = std::max(worst, deviation(also[i]));
    return std::max(o_.tolerance, std::min(worst, o_.cell));
  }
  void keepDeviations(const std::vector<std::uint32_t>& changed) {
    for (std::size_t i = 0; i < changed.size(); ++i) deviation_[changed[i]] = newDeviation_[i];
  }

  // The ring of local vertex l (global g): the vertex after it in each of its faces.
  void ring(std::uint32_t l, std::uint32_t g, std::vector<std::uint32_t>& out) const {
    out.clear();
    for (std::uint32_t f : around_[l]) {
      const Triangle& t = faces_[f];
      out.push_back(t[0] == g ? t[1] : (t[1] == g ? t[2] : t[0]));
    }
  }

  bool holds(const Triangle& t, std::uint32_t v) const {
    return t[0] == v || t[1] == v || t[2] == v;
  }

  // Each free vertex moved to the minimiser of its own and its ring's planes where that is a
  // crease or a corner the collapses left cut off (a vertex that carries only planes of one
  // face cannot find the third plane of a corner by itself), under the collapse's tests.
  std::size_t snapToFeatures(RegionOutput& out) {
    std::size_t moved = 0;
    for (std::uint32_t l = 0; l < gid_.size(); ++l) {
      if (fixed_[l] || removedLocal_[l]) continue;
      const std::uint32_t g = gid_[l];
      if (o_.creaseCollapsesOnly && !s_.nearCrease[g]) continue;
      Quadric q = s_.quadric[g];
      ring(l, g, neighboursU_);
      for (std::uint32_t w : neighboursU_) q += s_.quadric[w];
      if (q.count <= 0.0) continue;
      if (o_.creaseCollapsesOnly && !q.mayBeSharp(planeCutoff())) continue;  // (a plane)
      int rank = 0;
      const Vec3 p = q.minimiser(planeCutoff(), &rank), here = toVec3(s_.pos[g]);
      if (rank < 2) continue;  // a plane: nothing sharp to put back
      const Vec3 d = sub(p, here);
      // only a move the own planes allow, by less than two cells (a corner the grid cut off
      // lies up to about a cell from the nearest vertex)
      if (dot(d, d) > 4.0 * o_.cell * o_.cell) continue;
      const Quadric& own = s_.quadric[g];
      if (own.count > 0.0 && own.error(p) > own.error(here) + o_.tolerance * o_.tolerance)
        continue;
      if (q.error(p) + o_.tolerance * o_.tolerance >= q.error(here)) continue;  // no gain
      if (o_.creaseCollapsesOnly && !onCrease(p)) continue;
      moved += relocate(l, p, out);
    }
    return moved;
  }

  // Edge flips that let the mesh's edges follow a crease (data-dependent triangulation, Dyn,
  // Levin and Rippa's least total turning): where an edge turns by over 20 degrees, the two
  // faces on it, (u, v, a) and (v, u, b), become (v, a, b) and (u, b, a) when that lowers
  // the sum over the quad's five edges of length x the angle their faces turn by. Collapses
  // leave the long faces of a simplified crease cutting across it, zig-zagging (the twist at
  // 128 cells and a tenth of a cell: crease length 25.0 against the exact 19.956); a flip
  // puts the edge along it instead. Each flip passes the collapse's tests (shape, distance
  // from F = 0, facing out, every sample still covered, no intersection). Returns the flips.
  std::size_t flipTowardsCreases(RegionOutput& out) {
    std::size_t flips = 0;
    for (std::uint32_t f = 0; f < faces_.size(); ++f) {
      if (frozenFace_[f] || deadFace_[f] != kLive) continue;
      if (o_.creaseCollapsesOnly && !touchesCrease(s_, faces_[f])) continue;
      for (int k = 0; k < 3; ++k) {
        const Triangle& t = faces_[f];
        const std::uint32_t u = t[k], v = t[(k + 1) % 3];
        const std::uint32_t g = across(f, u, v);
        // each edge once (from the face with the lower index), both faces free to change
        if (g == kNone || g < f || frozenFace_[g]) continue;
        if (!turnsMoreThan(f, g, kFlipTurnCos)) continue;
        if (tryFlip(f, g, u, v, out)) {
          ++flips;
          break;  // (f changed: its edges are the new ones)
        }
      }
    }
    out.flips += flips;
    return flips;
  }

  // The live face other than f on the edge u -> v of f (the one with v -> u), or kNone.
  std::uint32_t across(std::uint32_t f, std::uint32_t u, std::uint32_t v) const {
    const std::uint32_t l = local(u);
    if (l == kNone) return kNone;
    for (std::uint32_t g : around_[l]) {
      if (g == f || deadFace_[g] != kLive) continue;
      const Triangle& t = faces_[g];
      for (int k = 0; k < 3; ++k)
        if (t[k] == v && t[(k + 1) % 3] == u) return g;
    }
    return kNone;
  }

  // Whether faces f and g turn across their common edge by more than the angle whose cosine
  // is `cosine` (no arc cosine: most edges are tested and few pass).
  bool turnsMoreThan(std::uint32_t f, std::uint32_t g, double cosine) const {
    const Vec3 a = faceNormal(s_.pos, faces_[f]), b = faceNormal(s_.pos, faces_[g]);
    return !(dot(a, b) > cosine * std::sqrt(dot(a, a) * dot(b, b)));
  }

  // Flips edge u -> v of face f (f = (u, v, a), g = (v, u, b)) when that lowers the quad's
  // turning and every test passes; unchanged otherwise.
  bool tryFlip(std::uint32_t f, std::uint32_t g, std::uint32_t u, std::uint32_t v,
               RegionOutput& out) {
    auto third = [&](std::uint32_t face) {
      const Triangle& t = faces_[face];
      return t[0] != u && t[0] != v ? t[0] : (t[1] != u && t[1] != v ? t[1] : t[2]);
    };
    const std::uint32_t a = third(f), b = third(g);
    const std::uint32_t lu = local(u), lv = local(v), la = local(a), lb = local(b);
    if (a == b || lu == kNone || lv == kNone || la == kNone || lb == kNone) return false;
    // u and v keep three faces each
    if (around_[lu].size() <= 3 || around_[lv].size() <= 3) return false;
    // The quad's turning before and after (its four outer edges keep their outer faces).
    const std::uint32_t outer[4] = {across(f, v, a), across(f, a, u), across(g, u, b),
                                    across(g, b, v)};
    for (std::uint32_t h : outer)
      if (h == kNone) return false;
    const Vec3f &pu = s_.pos[u], &pv = s_.pos[v], &pa = s_.pos[a], &pb = s_.pos[b];
    const Vec3 nf = triangleCross(pu, pv, pa), ng = triangleCross(pv, pu, pb);    // old pair
    const Vec3 nf2 = triangleCross(pv, pa, pb), ng2 = triangleCross(pu, pb, pa);  // new pair
    auto angle = [](const Vec3& x, const Vec3& y) {
      const double l = std::sqrt(dot(x, x) * dot(y, y));
      return l > 0.0 ? std::acos(std::clamp(dot(x, y) / l, -1.0, 1.0)) : 3.141592653589793;
    };
    auto length = [](const Vec3f& x, const Vec3f& y) { return norm(sub(toVec3(x), toVec3(y))); };
    Vec3 nh[4];
    for (int i = 0; i < 4; ++i) nh[i] = faceNormal(s_.pos, faces_[outer[i]]);
    const double sides[4] = {length(pv, pa), length(pa, pu), length(pu, pb),
                             length(pb, pv)};  // (v a), (a u), (u b), (b v)
    const double before = length(pu, pv) * angle(nf, ng) + sides[0] * angle(nf, nh[0]) +
                          sides[1] * angle(nf, nh[1]) + sides[2] * angle(ng, nh[2]) +
                          sides[3] * angle(ng, nh[3]);
    const double after = length(pa, pb) * angle(nf2, ng2) + sides[0] * angle(nf2, nh[0]) +
                         sides[1] * angle(ng2, nh[1]) + sides[2] * angle(ng2, nh[2]) +
                         sides[3] * angle(nf2, nh[3]);
    if (!(after < before * (1.0 - kFlipGain))) return false;
    // a and b are not joined already (the edge would double)
    ring(la, a, neighboursU_);
    if (std::find(neighboursU_.begin(), neighboursU_.end(), b) != neighboursU_.end()) return false;
    ring(lb, b, neighboursU_);
    if (std::find(neighboursU_.begin(), neighboursU_.end(), a) != neighboursU_.end()) return false;
    changed_.assign({f, g});
    const double worstBefore = recordBefore(changed_);
    const double allowed = allowedFor(changed_, nullptr, 0);
    const Triangle oldF = faces_[f], oldG = faces_[g];
    faces_[f] = {v, a, b};
    faces_[g] = {u, b, a};
    auto restore = [&] {
      faces_[f] = oldF;
      faces_[g] = oldG;
    };
    // The surface moves most along the two diagonals (centres alone miss a crease or corner
    // cut off): the new one's midpoint stays within reach of F = 0, and the surface point
    // nearest the old one's midpoint stays within reach of the new faces.
    {
      auto midpoint = [&](std::uint32_t x, std::uint32_t y) {
        const Vec3 p = toVec3(s_.pos[x]), q = toVec3(s_.pos[y]);
        return Vec3{0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]), 0.5 * (p[2] + q[2])};
      };
      double value;
      Vec3 n;
      const Vec3 across = midpoint(a, b), along = midpoint(u, v);
      bool near = region_->plane(across, &value, &n) && std::abs(value) <= allowed &&
                  region_->plane(along, &value, &n);
      if (near) {
        const Vec3 foot{along[0] - value * n[0], along[1] - value * n[1],
                        along[2] - value * n[2]};
        double closest = HUGE_VAL;
        for (std::uint32_t face : {f, g}) {
          const Triangle& t = faces_[face];
          closest = std::min(closest, pointTriangleDistance(foot, toVec3(s_.pos[t[0]]),
                                                            toVec3(s_.pos[t[1]]),
                                                            toVec3(s_.pos[t[2]])));
        }
        near = closest <= allowed;
      }
      if (!near) {
        restore();
        return false;
      }
    }
    auto drop = [](std::vector<std::uint32_t>& list, std::uint32_t face) {
      list.erase(std::find(list.begin(), list.end(), face));
    };
    // the stars as they will be: u loses f, v loses g, b gains f, a gains g
    drop(around_[lu], f);
    drop(around_[lv], g);
    around_[lb].push_back(f);
    around_[la].push_back(g);
    vMoves_ = false;
    featureMove_ = true;  // (the faces turn by design: the outward test guards against folds)
    flipCorners_ = {u, v, a, b};
    const bool ok = acceptable(changed_, worstBefore, kNone, kNone, allowed, out);
    if (!ok) {
      around_[lu].push_back(f);
      around_[lv].push_back(g);
      drop(around_[lb], f);
      drop(around_[la], g);
      restore();
      return false;
    }
    keepDeviations(changed_);
    for (std::uint32_t face : changed_) {
      faceBox_[face] = boxOf(faces_[face]);
      insert(face);
    }
    for (std::uint32_t l : {lu, lv, la, lb}) ++stamp_[l];
    // samples handed to another corner: copied there, then dropped here (from the back)
    for (const SampleMove& m : sampleMoves_)
      s_.samples[flipCorners_[m.to]].push_back(s_.samples[flipCorners_[m.from]][m.index]);
    for (auto m = sampleMoves_.rbegin(); m != sampleMoves_.rend(); ++m) {
      std::vector<Vec3f>& from = s_.samples[flipCorners_[m->from]];
      from.erase(from.begin() + m->index);
    }
    return true;
  }

  // Whether sample q lies within the tolerance of face f as it stands. Most faces of a star
  // are far from a given sample: their box, grown by the tolerance (and a millionth of it,
  // so that no rounding can turn away a face the exact distance would take), rules them out
  // before the distance is computed.
  bool sampleNear(const Vec3f& q, std::uint32_t f) const {
    const Triangle& t = faces_[f];
    const Vec3f &a = s_.pos[t[0]], &b = s_.pos[t[1]], &c = s_.pos[t[2]];
    const double limit = o_.tolerance * (1 + 1e-9), reach = o_.tolerance * (1 + 1e-6);
    for (int k = 0; k < 3; ++k)
      if (double(q[k]) < double(std::min({a[k], b[k], c[k]})) - reach ||
          double(q[k]) > double(std::max({a[k], b[k], c[k]})) + reach)
        return false;
    return pointTriangleDistance(Vec3d{q[0], q[1], q[2]}, toVec3(a), toVec3(b), toVec3(c)) <= limit;
  }

  // Whether each sample of v (and, in a collapse, of u: gu, else kNone) is within the
  // tolerance of v's star as it stands (the collapse applied: u's faces are v's).
  bool samplesCovered(std::uint32_t gv, std::uint32_t gu) {
    const std::uint32_t lv = local(gv);
    star_.clear();
    for (std::uint32_t f : around_[lv])
      if (deadFace_[f] == kLive) star_.push_back(f);
    if (gu != kNone)
      for (std::uint32_t f : around_[local(gu)])
        if (deadFace_[f] == kLive) star_.push_back(f);
    auto covered = [&](const Vec3f& q) {
      for (std::uint32_t f : star_)
        if (sampleNear(q, f)) return true;
      return false;
    };
    for (const Vec3f& q : s_.samples[gv])
      if (!covered(q)) return false;
    if (gu != kNone)
      for (const Vec3f& q : s_.samples[gu])
        if (!covered(q)) return false;
    return true;
  }

  // A flip's samples: each sample of the quad's four corners within the tolerance of a face
  // of one of their stars, and if not of its own corner's, handed (sampleMoves_, made when
  // the flip is) to a corner whose star has such a face, so that every sample stays covered
  // by the star of the vertex that holds it.
  bool quadSamplesCovered() {
    star_.clear();
    for (std::uint32_t w : flipCorners_)
      for (std::uint32_t f : around_[local(w)])
        if (deadFace_[f] == kLive) star_.push_back(f);
    std::sort(star_.begin(), star_.end());
    star_.erase(std::unique(star_.begin(), star_.end()), star_.end());
    sampleMoves_.clear();
    for (int c = 0; c < 4; ++c) {
      const std::uint32_t w = flipCorners_[c];
      const std::vector<Vec3f>& samples = s_.samples[w];
      for (std::uint32_t i = 0; i < samples.size(); ++i) {
        bool own = false;
        for (std::uint32_t f : around_[local(w)])
          if (deadFace_[f] == kLive && sampleNear(samples[i], f)) {
            own = true;
            break;
          }
        if (own) continue;
        int to = -1;
        for (std::uint32_t f : star_) {
          if (!sampleNear(samples[i], f)) continue;
          for (int k = 0; k < 4 && to < 0; ++k)
            if (holds(faces_[f], flipCorners_[k])) to = k;
          break;
        }
        if (to < 0) return false;
        sampleMoves_.push_back({c, i, to});
      }
    }
    return true;
  }

  // The faces about to change, as they are: their normals (for the turn test) and the worst
  // shape among them.
  double recordBefore(const std::vector<std::uint32_t>& changed) {
    double worst = 1.0;
    normalsBefore_.clear();
    for (std::uint32_t f : changed) {
      const Triangle& t = faces_[f];
      worst = std::min(worst, quality(s_.pos[t[0]], s_.pos[t[1]], s_.pos[t[2]]));
      normalsBefore_.push_back(faceNormal(s_.pos, t));
    }
    return worst;
  }

  // Moves local vertex l to p when every test passes; unchanged otherwise.
  bool relocate(std::uint32_t l, const Vec3& p, RegionOutput& out) {
    const std::uint32_t g = gid_[l];
    const Vec3f at = toVec3f(p);
    if (!std::isfinite(at[0]) || !std::isfinite(at[1]) || !std::isfinite(at[2]) ||
        regions_.of(at) != key_ || at == s_.pos[g])
      return false;
    changed_ = around_[l];
    const double worstBefore = recordBefore(changed_);
    const double allowed = allowedFor(changed_, nullptr, 0);
    const Vec3f old = s_.pos[g];
    s_.pos[g] = at;
    vMoves_ = true;
    featureMove_ = true;
    if (!acceptable(changed_, worstBefore, g, kNone, allowed, out)) {
      s_.pos[g] = old;
      return false;
    }
    keepDeviations(changed_);
    s_.moved[g] = 1;
    for (std::uint32_t f : changed_) {
      faceBox_[f] = boxOf(faces_[f]);
      insert(f);
    }
    return true;
  }

  // Merges u into v at c.at when every test passes; the region's state is unchanged otherwise.
  bool collapse(const Candidate& c, RegionOutput& out) {
    const std::uint32_t u = c.u, v = c.v, gu = gid_[u], gv = gid_[v];
    // the two faces on the edge, and their third vertices
    std::uint32_t edgeFaces[2], third[2], m = 0;
    for (std::uint32_t f : around_[u])
      if (holds(faces_[f], gv)) {
        if (m == 2) return false;
        edgeFaces[m] = f;
        for (std::uint32_t w : faces_[f])
          if (w != gu && w != gv) third[m] = w;
        ++m;
      }
    if (m != 2 || third[0] == third[1]) return false;
    // link condition: u's and v's neighbours in common are the two third vertices only
    // (closed manifold fans: each face (w, a, b) gives w's ring the vertex after w)
    ring(u, gu, neighboursU_);
    ring(v, gv, neighboursV_);
    std::size_t common = 0;
    for (std::uint32_t w : neighboursU_)
      if (std::find(neighboursV_.begin(), neighboursV_.end(), w) != neighboursV_.end()) {
        if (w != third[0] && w != third[1]) return false;
        ++common;
      }
    if (common != 2) return false;
    // no pillow: the third vertices and v keep at least three faces each
    for (std::uint32_t w : third) {
      const std::uint32_t l = local(w);
      if (l == kNone || around_[l].size() <= 3) return false;
    }
    if (around_[u].size() + around_[v].size() < 7) return false;

    // where v goes: inside this region, as a float
    const Vec3f at = toVec3f(c.at);
    if (!std::isfinite(at[0]) || !std::isfinite(at[1]) || !std::isfinite(at[2]) ||
        regions_.of(at) != key_)
      return false;
    const Vec3f oldV = s_.pos[gv];
    const bool moves = at != oldV;
    if (moves && fixed_[v]) return false;
    vMoves_ = moves;

    // the changed faces: u's (u becomes v) and, when v moves, v's; the edge's two go
    changed_.clear();
    for (std::uint32_t f : around_[u])
      if (f != edgeFaces[0] && f != edgeFaces[1]) changed_.push_back(f);
    if (moves)
      for (std::uint32_t f : around_[v])
        if (f != edgeFaces[0] && f != edgeFaces[1]) changed_.push_back(f);
    double worstBefore = recordBefore(changed_);
    for (int e = 0; e < 2; ++e) {
      const Triangle& t = faces_[edgeFaces[e]];
      worstBefore = std::min(worstBefore, quality(s_.pos[t[0]], s_.pos[t[1]], s_.pos[t[2]]));
    }

    const double allowed = allowedFor(changed_, edgeFaces, 2);
    // apply, test, and undo on failure
    saved_.clear();
    for (std::uint32_t f : changed_) saved_.push_back(faces_[f]);
    for (std::uint32_t f : changed_)
      for (std::uint32_t& w : faces_[f])
        if (w == gu) w = gv;
    s_.pos[gv] = at;
    deadFace_[edgeFaces[0]] = deadFace_[edgeFaces[1]] = kGoingUnderTest;
    const bool ok = acceptable(changed_, worstBefore, gv, gu, allowed, out);
    if (!ok) {
      for (std::size_t i = 0; i < changed_.size(); ++i) faces_[changed_[i]] = saved_[i];
      s_.pos[gv] = oldV;
      deadFace_[edgeFaces[0]] = deadFace_[edgeFaces[1]] = kLive;
      return false;
    }
    deadFace_[edgeFaces[0]] = deadFace_[edgeFaces[1]] = kGone;
    keepDeviations(changed_);
    liveFaces_ -= 2;

    // commit: u is gone, its faces are v's; the edge's faces leave every list
    removedLocal_[u] = 1;
    s_.removed[gu] = 1;
    if (moves) s_.moved[gv] = 1;
    // (a merged vertex sits on the crease now: its new neighbours are near it)
    if (!s_.nearCrease.empty()) s_.nearCrease[gv] = 1;
    s_.quadric[gv] += s_.quadric[gu];
    s_.samples[gv].insert(s_.samples[gv].end(), s_.samples[gu].begin(), s_.samples[gu].end());
    std::vector<Vec3f>().swap(s_.samples[gu]);
    auto drop = [&](std::uint32_t l) {
      std::vector<std::uint32_t>& a = around_[l];
      a.erase(std::remove_if(a.begin(), a.end(),
                             [&](std::uint32_t f) { return f == edgeFaces[0] || f == edgeFaces[1]; }),
              a.end());
    };
    drop(v);
    for (std::uint32_t w : third) drop(local(w));
    for (std::uint32_t f : around_[u])
      if (f != edgeFaces[0] && f != edgeFaces[1]) around_[v].push_back(f);
    around_[u].clear();
    for (std::uint32_t f : changed_) {
      faceBox_[f] = boxOf(faces_[f]);
      insert(f);
    }
    ++stamp_[v];
    for (std::uint32_t w : neighboursU_) {
      const std::uint32_t l = local(w);
      if (l != kNone) ++stamp_[l];
    }
    for (std::uint32_t w : neighboursV_) {
      const std::uint32_t l = local(w);
      if (l != kNone) ++stamp_[l];
    }
    return true;
  }

  // Whether faces f and g share a vertex other than `skip` whose fan, as it stands, is proved
  // embedded (check/face_pair_test.h): then the two are faces of one embedded fan and cannot
  // intersect. A changed face meets most of its candidates in such a vertex (the link of the
  // collapse, whose fans hold the changed faces and the faces round them), so one proof per
  // link vertex stands for most pair tests. Proofs are made when first asked, once per test.
  bool inProvedFan(const Triangle& f, const Triangle& g, std::uint32_t skip) {
    for (std::uint32_t w : f) {
      if (w == skip || !holds(g, w)) continue;
      if (linkProved(w)) return true;
    }
    return false;
  }

  bool linkProved(std::uint32_t w) {
    for (const auto& [vertex, proved] : linkProofs_)
      if (vertex == w) return proved;
    const std::uint32_t l = local(w);
    bool proved = false;
    if (l != kNone) {  // (a vertex outside the region: not all its faces are listed here)
      sectors_.clear();
      for (std::uint32_t f : around_[l]) {
        if (deadFace_[f] != kLive) continue;
        const Triangle& t = faces_[f];
        const int k = t[0] == w ? 0 : (t[1] == w ? 1 : 2);
        sectors_.emplace_back(t[(k + 1) % 3], t[(k + 2) % 3]);
      }
      proved = fanProvedEmbedded(s_.pos, w, sectors_.data(), sectors_.size());
    }
    linkProofs_.emplace_back(w, proved);
    return proved;
  }

  // The tests on the applied collapse: shape, turn, distance, and no intersection.
  // `allowed`: how far from F = 0 the changed faces may be (the tolerance, or the worst of
  // the faces they replace where that was worse already: a crease the grid cut off is put
  // back one vertex at a time, each step no worse than before).
  // gv: the vertex that stays (or moves); gu: the one merged into it, kNone for a move.
  bool acceptable(const std::vector<std::uint32_t>& changed, double worstBefore, std::uint32_t gv,
                  std::uint32_t gu, double allowed, RegionOutput& out) {
    const double floorQuality = std::min(featureMove_ ? kFeatureQuality : kQuality, worstBefore);
    for (std::size_t i = 0; i < changed.size(); ++i) {
      const Triangle& t = faces_[changed[i]];
      if (quality(s_.pos[t[0]], s_.pos[t[1]], s_.pos[t[2]]) < floorQuality) return false;
      // (a vertex put on a corner may turn its faces further: the outward test below, against
      // the field's gradient, is their guard against folding)
      const Vec3 n = faceNormal(s_.pos, t), before = normalsBefore_[i];
      if (!featureMove_ && dot(n, before) < kTurn * std::sqrt(dot(n, n) * dot(before, before)))
        return false;
      if (o_.maxEdge > 0.0)
        for (int k = 0; k < 3; ++k) {
          const Vec3 d = sub(toVec3(s_.pos[t[k]]), toVec3(s_.pos[t[(k + 1) % 3]]));
          if (dot(d, d) > o_.maxEdge * o_.maxEdge) return false;
        }
      if (collinear(s_.pos[t[0]], s_.pos[t[1]], s_.pos[t[2]])) return false;
    }
    // the surface stays near F = 0: at v and at each changed face's centre
    double largest = 0.0;
    if (vMoves_) {
      largest = region_->distance(toVec3(s_.pos[gv]));
      if (!(largest <= allowed)) return false;
    }
    newDeviation_.clear();
    // and each changed face faces out: against the gradient at its centre (a small part
    // collapsed into itself, turned inside out, fails here); the centres in one batch
    const std::size_t m = changed.size();
    centres_.resize(m);
    values_.resize(m);
    gradients_.resize(m);
    planeOk_.resize(m);
    for (std::size_t i = 0; i < m; ++i) {
      const Triangle& t = faces_[changed[i]];
      centres_[i] = {0, 0, 0};
      for (std::uint32_t w : t)
        for (int a = 0; a < 3; ++a) centres_[i][a] += s_.pos[w][a] / 3.0;
    }
    region_->planes(centres_.data(), m, values_.data(), gradients_.data(), planeOk_.data());
    for (std::size_t i = 0; i < m; ++i) {
      if (!planeOk_[i]) return false;
      const double d = std::abs(values_[i]);
      if (!(d <= allowed)) return false;
      if (!(dot(faceNormal(s_.pos, faces_[changed[i]]), gradients_[i]) < 0.0)) return false;
      largest = std::max(largest, d);
      newDeviation_.push_back(static_cast<float>(d));
    }
    // every surface point v now stands for (u's and v's) stays within the tolerance of v's
    // faces as they will be
    if (gv == kNone ? !quadSamplesCovered() : !samplesCovered(gv, gu)) return false;
    // no changed face meets another face (the changed ones among themselves too: the grid
    // still lists them where they were)
    // (only pairs whose boxes meet can intersect: the check tests no others either)
    // One search for the whole fan (its faces share most of their cells), then each
    // candidate against each changed face whose box it meets.
    // Two faces of v's fan cannot meet where the fan is proved embedded (the check's own proof,
    // check/face_pair_test.h): every changed face is one of them, so then only the faces off
    // the fan are tested. (A flip has no such vertex: its faces are tested pair by pair.)
    bool fanProved = false;
    if (gv != kNone) {
      sectors_.clear();
      for (std::uint32_t l : {local(gv), gu == kNone ? kNone : local(gu)}) {
        if (l == kNone) continue;
        for (std::uint32_t f : around_[l]) {  // (u's faces hold v now)
          if (deadFace_[f] != kLive) continue;
          const Triangle& t = faces_[f];
          const int k = t[0] == gv ? 0 : (t[1] == gv ? 1 : 2);
          sectors_.emplace_back(t[(k + 1) % 3], t[(k + 2) % 3]);
        }
      }
      fanProved = fanProvedEmbedded(s_.pos, gv, sectors_.data(), sectors_.size());
    }
    boxes_.resize(changed.size());
    FaceBox all = boxOf(faces_[changed[0]]);
    for (std::size_t i = 0; i < changed.size(); ++i) {
      boxes_[i] = boxOf(faces_[changed[i]]);
      all.grow(boxes_[i]);
    }
    near(all, nearby_);  // (sets visit_ of every face found to visitStamp_)
    ++visitStamp_;
    for (std::uint32_t f : changed) visit_[f] = visitStamp_;  // the changed ones: below
    linkProofs_.clear();
    for (std::uint32_t g : nearby_) {
      if (visit_[g] == visitStamp_) continue;
      const FaceBox& bg = faceBox_[g];
      if (!all.meets(bg) || (fanProved && holds(faces_[g], gv))) continue;
      for (std::size_t i = 0; i < changed.size(); ++i)
        if (boxes_[i].meets(bg) && !inProvedFan(faces_[changed[i]], faces_[g], gv) &&
            facesIntersect(s_.pos, faces_[changed[i]], faces_[g]))
          return false;
    }
    for (std::size_t i = 0; i < changed.size() && !fanProved; ++i)
      for (std::size_t j = i + 1; j < changed.size(); ++j)
        if (boxes_[i].meets(boxes_[j]) &&
            !inProvedFan(faces_[changed[i]], faces_[changed[j]], gv) &&
            facesIntersect(s_.pos, faces_[changed[i]], faces_[changed[j]]))
          return false;
    out.largestDistance = std::max(out.largestDistance, largest);
    return true;
  }

  State& s_;
  const Field& field_;
  // The region's surface: the field specialised to the region's box (every point a region
  // evaluates lies in it), as the mesher specialises it to a brick.
  std::shared_ptr<const Field> regionField_;
  std::optional<Surface> region_;  // (its batch scratch is this thread's)
  const SimplifyOptions& o_;
  const Regions& regions_;
  const std::vector<Triangle>& all_;
  std::uint64_t key_ = 0;
  std::vector<std::uint32_t> gid_;  // local vertex -> global
  std::vector<std::uint32_t> localOf_;  // global vertex -> local, kNone outside the region
  std::vector<std::vector<std::uint32_t>> around_;  // local vertex -> its faces
  std::vector<std::uint8_t> fixed_, removedLocal_;
  std::vector<std::uint32_t> stamp_;
  std::vector<Triangle> faces_;
  // a face's state: live, removed for good, or removed only by the collapse under test (it
  // must stay in the search grid, which drops removed faces as it meets them)
  static constexpr std::uint8_t kLive = 0, kGone = 1, kGoingUnderTest = 2;
  std::vector<std::uint8_t> frozenFace_, deadFace_;
  double regionLo_[3] = {0, 0, 0}, gridLo_[3] = {0, 0, 0}, gridCell_ = 0.0;
  int gridDim_ = 0;
  std::size_t liveFaces_ = 0, liveAtBuild_ = 0;
  std::vector<std::vector<std::uint32_t>> grid_;
  std::vector<std::uint32_t> visit_;
  std::vector<std::uint32_t> inCell_;
  std::uint32_t visitStamp_ = 0, cellStamp_ = 0;
  // scratch
  std::vector<std::uint32_t> neighboursU_, neighboursV_, changed_, nearby_;
  std::vector<Triangle> saved_;
  std::vector<Vec3> normalsBefore_;
  std::vector<EdgeEntry> heap_;
  std::vector<FaceBox> boxes_;    // the changed faces' boxes, during a test
  std::vector<float> deviation_;     // per face: its centre's distance from F = 0 (NaN: unknown)
  std::vector<float> newDeviation_;  // the changed faces', during a test
  std::vector<Vec3> centres_, gradients_;  // the changed faces' centres and the field there
  std::vector<double> values_;
  std::vector<std::uint8_t> planeOk_;
  std::vector<FaceBox> faceBox_;  // every face's box as it stands
  bool vMoves_ = false;           // the collapse under test moves v
  std::vector<std::uint32_t> star_;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> sectors_;  // a fan, for its proof
  std::vector<std::pair<std::uint32_t, bool>> linkProofs_;        // the test's fan proofs so far
  bool featureMove_ = false;      // ... onto a crease or a corner
  std::array<std::uint32_t, 4> flipCorners_{};  // the flip under test's quad
  struct SampleMove {
    int from;
    std::uint32_t index;
    int to;
  };
  std::vector<SampleMove> sampleMoves_;  // ... and the samples it hands between its corners
};

// The vertices of the faces near a crease (kNearCreaseCos), and those moved before: a face
// whose normal turns from the surface's at a vertex (or that has no normal there).
void markNearCreases(State& s, const std::vector<Triangle>& faces) {
  std::vector<std::uint8_t> near(faces.size());
  tbb::parallel_for(std::size_t(0), faces.size(), [&](std::size_t f) {
    const Triangle& t = faces[f];
    const Vec3 n = faceNormal(s.pos, t);
    const double length = norm(n);
    bool turns = !(length > 0.0);
    for (int k = 0; k < 3 && !turns; ++k) {
      const Vec3 m = toVec3(s.normal[t[k]]);
      turns = s.moved[t[k]] || !(dot(n, m) > kNearCreaseCos * length);
    }
    near[f] = turns;
  });
  std::fill(s.nearCrease.begin(), s.nearCrease.end(), 0);
  for (std::size_t f = 0; f < faces.size(); ++f)
    if (near[f])
      for (std::uint32_t v : faces[f]) s.nearCrease[v] = 1;
}

void validate(const SimplifyOptions& o) {
  auto bad = [](const std::string& what) { throw ModelError("simplify: " + what); };
  if (!(o.cell > 0.0) || !std::isfinite(o.cell)) bad("cell must be a positive number");
  if (!(o.tolerance > 0.0) || !std::isfinite(o.tolerance))
    bad("tolerance must be a positive distance");
  if (!(o.maxEdge >= 0.0)) bad("maxEdge must be 0 (no bound) or a positive length");
  if (o.regionCells < 4 || o.regionCells > 256) bad("regionCells must be 4 to 256");
  if (o.passes < 1 || o.passes > 16) bad("passes must be 1 to 16");
  if (o.creaseCollapsesOnly && !o.sharpFeatures)
    bad("collapses onto creases only need sharp features (the creases are found by them)");
}

}  // namespace

TriangleMesh simplifyMesh(const TriangleMesh& mesh, const Field& field,
                          const SimplifyOptions& o, SimplifyStats* stats) {
  const auto start = std::chrono::steady_clock::now();
  validate(o);
  const Surface surface(field, o.bbox);
  const std::size_t nv = mesh.positions.size();
  State s;
  s.pos = mesh.positions;
  s.quadric.assign(nv, Quadric());
  s.removed.assign(nv, 0);
  s.moved.assign(nv, 0);
  s.samples.resize(nv);
  for (std::size_t v = 0; v < nv; ++v) s.samples[v].assign(1, s.pos[v]);
  if (o.creaseCollapsesOnly) {
    s.normal.assign(nv, Vec3f{0, 0, 0});
    s.nearCrease.assign(nv, 0);
  }
  // Hermite data: each vertex's tangent plane of the meshed surface
  tbb::parallel_for(std::size_t(0), nv, [&](std::size_t v) {
    const Vec3 p = toVec3(s.pos[v]);
    double value;
    Vec3 n;
    if (surface.plane(p, &value, &n)) {
      // the plane through the surface point nearest p along n
      const Vec3 foot{p[0] - value * n[0], p[1] - value * n[1], p[2] - value * n[2]};
      s.quadric[v].addPlane(foot, n);
      if (!s.normal.empty()) s.normal[v] = toVec3f({-n[0], -n[1], -n[2]});  // (F grows inwards)
    }
  });

  std::vector<Triangle> faces = mesh.triangles;
  std::size_t collapses = 0, flips = 0;
  double largest = 0.0;
  const double side = o.cell * o.regionCells;
  const double shifts[4] = {0.0, 0.5, 0.25, 0.75};
  for (int pass = 0; pass < o.passes; ++pass) {
    if (o.progress && !o.progress(static_cast<double>(pass) / o.passes)) throw Cancelled();
    Regions regions;
    for (int a = 0; a < 3; ++a)
      regions.origin[a] = o.bbox.lo[a] - shifts[pass % 4] * side - o.cell * (pass / 4) * 0.37;
    regions.side = side;
    // faces inside one region, grouped by it; faces crossing regions, frozen
    std::vector<std::pair<std::uint64_t, std::uint32_t>> inner, frozen;
    std::vector<std::uint32_t> crossing;
    // With collapses onto creases only, the regions holding a face near a crease (the others'
    // faces stay as they are and are not sorted in: most of the mesh)
    std::vector<std::uint64_t> active;
    auto isActive = [&](std::uint64_t r) {
      return !o.creaseCollapsesOnly || std::binary_search(active.begin(), active.end(), r);
    };
    if (o.creaseCollapsesOnly) {
      markNearCreases(s, faces);
      for (const Triangle& t : faces) {
        if (!touchesCrease(s, t)) continue;
        const std::uint64_t r = regions.of(s.pos[t[0]]);
        if (regions.of(s.pos[t[1]]) == r && regions.of(s.pos[t[2]]) == r) active.push_back(r);
      }
      std::sort(active.begin(), active.end());
      active.erase(std::unique(active.begin(), active.end()), active.end());
    }
    for (std::uint32_t f = 0; f < faces.size(); ++f) {
      const Triangle& t = faces[f];
      const std::uint64_t r = regions.of(s.pos[t[0]]);
      if (regions.of(s.pos[t[1]]) == r && regions.of(s.pos[t[2]]) == r) {
        if (isActive(r))
          inner.emplace_back(r, f);
        else
          crossing.push_back(f);  // (left as it is)
        continue;
      }
      crossing.push_back(f);
      std::int64_t lo[3], hi[3];
      for (int a = 0; a < 3; ++a) {
        // every region whose closed cube the face's box meets
        const double mn = std::min({s.pos[t[0]][a], s.pos[t[1]][a], s.pos[t[2]][a]});
        const double mx = std::max({s.pos[t[0]][a], s.pos[t[1]][a], s.pos[t[2]][a]});
        lo[a] = static_cast<std::int64_t>(std::floor((mn - regions.origin[a]) / side - 1e-9)) ;
        hi[a] = static_cast<std::int64_t>(std::floor((mx - regions.origin[a]) / side + 1e-9));
      }
      for (std::int64_t k = lo[2]; k <= hi[2]; ++k)
        for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
          for (std::int64_t i = lo[0]; i <= hi[0]; ++i)
            if (isActive(Regions::key(i, j, k))) frozen.emplace_back(Regions::key(i, j, k), f);
    }
    tbb::parallel_sort(inner.begin(), inner.end());
    tbb::parallel_sort(frozen.begin(), frozen.end());
    std::vector<std::uint32_t> innerFaces(inner.size()), frozenFaces(frozen.size());
    for (std::size_t i = 0; i < inner.size(); ++i) innerFaces[i] = inner[i].second;
    for (std::size_t i = 0; i < frozen.size(); ++i) frozenFaces[i] = frozen[i].second;
    std::vector<RegionInput> work;
    for (std::size_t i = 0; i < inner.size();) {
      std::size_t j = i;
      while (j < inner.size() && inner[j].first == inner[i].first) ++j;
      const auto range = std::equal_range(
          frozen.begin(), frozen.end(), std::make_pair(inner[i].first, std::uint32_t(0)),
          [](const auto& a, const auto& b) { return a.first < b.first; });
      work.push_back({inner[i].first, innerFaces.data() + i, j - i,
                      frozenFaces.data() + (range.first - frozen.begin()),
                      static_cast<std::size_t>(range.second - range.first), pass + 2 >= o.passes});
      i = j;
    }
    std::vector<RegionOutput> results(work.size());
    tbb::enumerable_thread_specific<std::unique_ptr<RegionSimplifier>> simplifiers;
    tbb::parallel_for(std::size_t(0), work.size(), [&](std::size_t r) {
      std::unique_ptr<RegionSimplifier>& rs = simplifiers.local();
      if (!rs) rs = std::make_unique<RegionSimplifier>(s, field, o, regions, faces);
      rs->run(work[r], results[r]);
    });
    std::vector<Triangle> next;
    next.reserve(faces.size());
    for (std::uint32_t f : crossing) next.push_back(faces[f]);
    for (RegionOutput& r : results) {
      next.insert(next.end(), r.faces.begin(), r.faces.end());
      collapses += r.collapses;
      flips += r.flips;
      largest = std::max(largest, r.largestDistance);
    }
    faces.swap(next);
  }

  // the surviving vertices, renumbered in their order
  TriangleMesh result;
  std::vector<std::uint32_t> number(nv, kNone);
  for (std::size_t v = 0; v < nv; ++v)
    if (!s.removed[v]) {
      number[v] = static_cast<std::uint32_t>(result.positions.size());
      result.positions.push_back(s.pos[v]);
    }
  if (!mesh.normals.empty()) {
    result.normals.resize(result.positions.size());
    tbb::parallel_for(std::size_t(0), nv, [&](std::size_t v) {
      if (number[v] == kNone) return;
      Vec3f& n = result.normals[number[v]];
      n = mesh.normals[v];
      if (!s.moved[v]) return;
      double value;
      Vec3 g;
      if (surface.plane(toVec3(s.pos[v]), &value, &g)) n = toVec3f({-g[0], -g[1], -g[2]});
    });
  }
  result.triangles.reserve(faces.size());
  for (const Triangle& t : faces) result.triangles.push_back({number[t[0]], number[t[1]], number[t[2]]});
  if (o.progress) o.progress(1.0);
  if (stats) {
    stats->trianglesBefore = mesh.triangles.size();
    stats->trianglesAfter = result.triangles.size();
    stats->collapses = collapses;
    stats->flips = flips;
    stats->largestDistance = largest;
    stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return result;
}

}  // namespace frep
