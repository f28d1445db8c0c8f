// The simplifier's work on one region of the mesh, shared by the files that hold its parts
// (the simplifier's internals: nothing outside simplify/ includes this):
//   region_simplifier.cpp  the region's set-up, its faces' grid and the collapse loop
//   simplify_collapse.cpp  one collapse placed, changed and proved
//   simplify_flips.cpp     vertices snapped onto creases, edges flipped along them
//   simplify_samples.cpp   the surface samples every change must keep covered
//   simplify.cpp           simplifyMesh: the regions, in parallel, pass after pass
#pragma once

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
#include "simplify/simplify.h"
#include "simplify/work_zone.h"

namespace frep {
namespace simplifying {

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

inline Vec3 toVec3(const Vec3f& p) {
  return {p[0], p[1], p[2]};
}
inline Vec3f toVec3f(const Vec3& p) {
  return {static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])};
}
inline Vec3 sub(const Vec3& a, const Vec3& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
inline double dot(const Vec3& a, const Vec3& b) {
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

inline double quality(const Vec3f& a, const Vec3f& b, const Vec3f& c) {
  const Vec3 pa = toVec3(a), pb = toVec3(b), pc = toVec3(c);
  const double s =
      dot(sub(pb, pa), sub(pb, pa)) + dot(sub(pc, pb), sub(pc, pb)) + dot(sub(pa, pc), sub(pa, pc));
  return s > 0.0 ? 2.0 * std::sqrt(3.0) * norm(triangleCross(a, b, c)) / s : 0.0;
}
inline Vec3 faceNormal(const std::vector<Vec3f>& pos, const Triangle& t) {
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
  // With collapses onto creases only, per pass: where the pass works (no change leaves it),
  // and the vertices with a face left out of every region (their stars are not all loaded:
  // they stay, and no collapse or flip reads their stars).
  const WorkZone* zone = nullptr;
  std::vector<std::uint8_t> incomplete;
};

// (collapses onto creases only) whether a vertex of t is near a crease
inline bool touchesCrease(const State& s, const Triangle& t) {
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
  RegionSimplifier(State& s, const Field& field, const SimplifyOptions& o, const Regions& regions,
                   const std::vector<Triangle>& faces)
      : s_(s), field_(field), o_(o), regions_(regions), all_(faces) {}

  void run(const RegionInput& in, RegionOutput& out);

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

  void setUp(const RegionInput& in);

  // The search grid over the region and a mesher cell round it, its cells about the size of
  // the live faces (a face then covers a couple of cells per axis it spans). Rebuilt as the
  // faces grow: a grid of the first, small faces would list a grown face in dozens of cells.
  void buildGrid();

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
  void near(const FaceBox& box, std::vector<std::uint32_t>& out);

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
  std::size_t snapToFeatures(RegionOutput& out);

  // Edge flips that let the mesh's edges follow a crease (data-dependent triangulation, Dyn,
  // Levin and Rippa's least total turning): where an edge turns by over 20 degrees, the two
  // faces on it, (u, v, a) and (v, u, b), become (v, a, b) and (u, b, a) when that lowers
  // the sum over the quad's five edges of length x the angle their faces turn by. Collapses
  // leave the long faces of a simplified crease cutting across it, zig-zagging (the twist at
  // 128 cells and a tenth of a cell: crease length 25.0 against the exact 19.956); a flip
  // puts the edge along it instead. Each flip passes the collapse's tests (shape, distance
  // from F = 0, facing out, every sample still covered, no intersection). Returns the flips.
  std::size_t flipTowardsCreases(RegionOutput& out);

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
               RegionOutput& out);

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
  bool samplesCovered(std::uint32_t gv, std::uint32_t gu);

  // A flip's samples: each sample of the quad's four corners within the tolerance of a face
  // of one of their stars, and if not of its own corner's, handed (sampleMoves_, made when
  // the flip is) to a corner whose star has such a face, so that every sample stays covered
  // by the star of the vertex that holds it.
  bool quadSamplesCovered();

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
  bool relocate(std::uint32_t l, const Vec3& p, RegionOutput& out);

  // Merges u into v at c.at when every test passes; the region's state is unchanged otherwise.
  bool collapse(const Candidate& c, RegionOutput& out);

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

  bool linkProved(std::uint32_t w);

  // The tests on the applied collapse: shape, turn, distance, and no intersection.
  // `allowed`: how far from F = 0 the changed faces may be (the tolerance, or the worst of
  // the faces they replace where that was worse already: a crease the grid cut off is put
  // back one vertex at a time, each step no worse than before).
  // gv: the vertex that stays (or moves); gu: the one merged into it, kNone for a move.
  bool acceptable(const std::vector<std::uint32_t>& changed, double worstBefore, std::uint32_t gv,
                  std::uint32_t gu, double allowed, RegionOutput& out);

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
  std::vector<std::uint32_t> gid_;      // local vertex -> global
  std::vector<std::uint32_t> localOf_;  // global vertex -> local, kNone outside the region
  std::vector<std::uint32_t> outside_;  // (set-up's scratch: vertices of its faces outside it)
  std::vector<std::vector<std::uint32_t>> around_;  // local vertex -> its faces
  std::vector<std::uint8_t> fixed_, removedLocal_;
  std::vector<std::uint8_t> incomplete_;  // local vertex -> a face of its star is not loaded
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
  std::vector<FaceBox> boxes_;       // the changed faces' boxes, during a test
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
  bool featureMove_ = false;                                      // ... onto a crease or a corner
  std::array<std::uint32_t, 4> flipCorners_{};                    // the flip under test's quad
  struct SampleMove {
    int from;
    std::uint32_t index;
    int to;
  };
  std::vector<SampleMove> sampleMoves_;  // ... and the samples it hands between its corners
};

}  // namespace simplifying
}  // namespace frep
