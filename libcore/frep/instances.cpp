#include "frep/instances.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <nanoflann.hpp>

#include "base/library_compat.h"
#include "frep/ops.h"
#include "frep/program.h"

namespace frep {

namespace {

// Above this many candidate copies an interval over a (large) box is not evaluated copy by
// copy; a conservative bound is returned and the caller's subdivision narrows the box.
constexpr std::size_t kMaxIntervalCopies = 64;
// Up to this many copies, a scan beats the k-d tree (radius queries).
constexpr std::size_t kLinearScan = 64;

struct Cloud {
  const std::vector<Vec3>* points;
  std::size_t kdtree_get_point_count() const { return points->size(); }
  double kdtree_get_pt(std::size_t i, std::size_t axis) const { return (*points)[i][axis]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud>, Cloud,
                                                 3, std::uint32_t>;

// A batch is evaluated in parts of at most about this many (point, copy) pairs (and at least one
// point): near a pile of 30,000 copies a chunk of points made 200 MB of pairs, and the
// faulting in of that memory was half the export's time.
constexpr std::size_t kMostPairs = std::size_t(1) << 16;

// Scratch vectors per thread and nesting depth: a copy may itself be an instancer, evaluated
// from within this one's loop on the same thread.
struct Work {
  std::vector<std::uint32_t> ids, chosen;
  std::vector<std::size_t> chosenStart;
  InstanceSet::PairBatch pairs;
  std::vector<double> values;
  std::vector<Dual> duals, dqx, dqy, dqz;
};
class ScopedWork {
 public:
  ScopedWork() {
    if (depth() == pool().size()) pool().emplace_back();  // a deque keeps outer ones in place
    work_ = &pool()[depth()++];
  }
  ~ScopedWork() { --depth(); }
  ScopedWork(const ScopedWork&) = delete;
  ScopedWork& operator=(const ScopedWork&) = delete;
  Work* operator->() { return work_; }

 private:
  static std::deque<Work>& pool() {
    thread_local std::deque<Work> p;
    return p;
  }
  static std::size_t& depth() {
    thread_local std::size_t d = 0;
    return d;
  }
  Work* work_;
};

double valueOf(double v) {
  return v;
}
double valueOf(const Dual& v) {
  return v.v;
}

// The indices of the largest and the next largest of n values (the second is n when n is
// 1), in a fixed scan order, so ties resolve alike in every mode.
template <class T>
std::pair<std::size_t, std::size_t> largestTwo(const T* values, std::size_t n) {
  std::size_t first = 0, second = n;
  for (std::size_t i = 1; i < n; ++i) {
    if (valueOf(values[i]) > valueOf(values[first])) {
      second = first;
      first = i;
    } else if (second == n || valueOf(values[i]) > valueOf(values[second])) {
      second = i;
    }
  }
  return {first, second};
}

}  // namespace

// nanoflann's L2_Simple metric, term for term, so a scan and the tree find the same copies.
static double squaredDistance(const double q[3], const Vec3& p) {
  double d2 = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double diff = q[a] - p[a];
    d2 += diff * diff;
  }
  return d2;
}

// Buckets of a uniform grid for the query every evaluated point makes (the copies within
// `reach`). Each cell keeps, in increasing index order, the copies closer than the reach to
// some point of the cell (tested against the cell's box, slightly enlarged for rounding), so
// a query is one lookup and an exact distance test of those few copies, already in order.
// Cells are half the reach where memory allows (about 2.6 times fewer candidates in 3D than
// cells of the reach and their 26 neighbours), else the reach. The grid covers every point
// within reach of a copy, so a point outside it has no copy in reach. Not built where the
// copies are too sparse or too many for the lists.
class BucketGrid {
 public:
  BucketGrid(const std::vector<Vec3>& points, double reach) : points_(points) {
    if (points.empty() || points.size() > kMaxCopies || !(reach > 0.0) || !std::isfinite(reach))
      return;
    for (int divisions : {2, 1})
      if (build(reach, divisions)) {
        reach_ = reach;
        built_ = true;
        return;
      }
  }

  bool built() const { return built_; }
  double reach() const { return reach_; }

  // A copy in a cell's list: its position kept beside its index, so a query reads one
  // contiguous run.
  struct Entry {
    Vec3 position;
    std::uint32_t id;
  };

  // The candidates of q's cell, in increasing index order: every copy within the reach of q
  // is among them. An empty run where q is outside the grid (no copy reaches it).
  std::pair<const Entry*, const Entry*> candidates(const double q[3]) const {
    std::int64_t at[3];
    for (int a = 0; a < 3; ++a) {
      // q's cell; a product, not a division (rounding may put q a hair outside the cell's
      // box: the lists are built with slack for that)
      const double f = std::floor((q[a] - lo_[a]) * inverseCell_);
      if (!(f >= 0.0 && f < static_cast<double>(dims_[a]))) return {nullptr, nullptr};
      at[a] = static_cast<std::int64_t>(f);
    }
    const std::size_t c = linear(at[0], at[1], at[2]);
    return {entries_.data() + start_[c], entries_.data() + start_[c + 1]};
  }

  // The copies strictly within `radius` (<= the reach) of q, in increasing order.
  void within(const double q[3], double radius, std::vector<std::uint32_t>& out) const {
    const auto [from, to] = candidates(q);
    const double r2 = radius * radius;
    // Without a branch per candidate (about a third are within reach: a branch would
    // mispredict often): every candidate is written, and the count advances for those in reach.
    out.resize(static_cast<std::size_t>(to - from));
    std::size_t found = 0;
    for (const Entry* e = from; e != to; ++e) {
      out[found] = e->id;
      found += squaredDistance(q, e->position) < r2;
    }
    out.resize(found);
  }

 private:
  static constexpr std::size_t kMaxCopies = std::size_t(1) << 22;

  // Cells of reach / divisions; false (nothing kept) where they would take too much memory.
  bool build(double reach, int divisions) {
    const double n = static_cast<double>(points_.size());
    cell_ = reach / divisions;
    inverseCell_ = 1.0 / cell_;
    double lo[3], hi[3];
    for (int a = 0; a < 3; ++a) lo[a] = hi[a] = points_[0][a];
    for (const Vec3& p : points_)
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], p[a]);
        hi[a] = std::max(hi[a], p[a]);
      }
    // The cell count in doubles first: copies far apart (1e30) must not overflow it.
    double cells = 1.0, span[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] -= reach;
      hi[a] += reach;
      span[a] = std::floor((hi[a] - lo[a]) / cell_) + 1.0;
      cells *= span[a];
    }
    if (!(cells <= 32.0 * n + 4096.0)) return false;  // sparse
    for (int a = 0; a < 3; ++a) {
      lo_[a] = lo[a];
      dims_[a] = static_cast<std::int64_t>(span[a]);
    }
    // Rounding of q's cell index can put q a hair outside its cell's box (relative error of
    // the index a few ulps of the largest coordinate).
    const double slack =
        1e-9 * (cell_ + std::max({std::abs(lo[0]), std::abs(lo[1]), std::abs(lo[2]),
                                  std::abs(hi[0]), std::abs(hi[1]), std::abs(hi[2])}));
    const double r2 = sqr(reach + slack);
    const std::size_t cellCount = static_cast<std::size_t>(cells);
    const std::size_t maxEntries = static_cast<std::size_t>(32.0 * n + 4096.0);
    // Every (cell, copy) pair whose box comes within reach, grouped by cell; the copies are
    // visited in index order, so each cell's list comes out sorted.
    std::vector<std::pair<std::size_t, std::uint32_t>> pairs;
    const std::int64_t range = divisions + 1;
    for (std::size_t i = 0; i < points_.size(); ++i) {
      std::int64_t home[3];
      for (int a = 0; a < 3; ++a)
        home[a] = static_cast<std::int64_t>(std::floor((points_[i][a] - lo_[a]) / cell_));
      for (std::int64_t k = std::max<std::int64_t>(home[2] - range, 0);
           k <= std::min(home[2] + range, dims_[2] - 1); ++k)
        for (std::int64_t j = std::max<std::int64_t>(home[1] - range, 0);
             j <= std::min(home[1] + range, dims_[1] - 1); ++j)
          for (std::int64_t l = std::max<std::int64_t>(home[0] - range, 0);
               l <= std::min(home[0] + range, dims_[0] - 1); ++l) {
            const std::int64_t at[3] = {l, j, k};
            double d2 = 0.0;
            for (int a = 0; a < 3; ++a) {
              const double from = lo_[a] + static_cast<double>(at[a]) * cell_ - slack;
              const double to = lo_[a] + static_cast<double>(at[a] + 1) * cell_ + slack;
              const double p = points_[i][a];
              const double d = p < from ? from - p : (p > to ? p - to : 0.0);
              d2 += d * d;
            }
            if (d2 >= r2) continue;
            if (pairs.size() >= maxEntries) return false;
            pairs.emplace_back(linear(l, j, k), static_cast<std::uint32_t>(i));
          }
    }
    std::stable_sort(pairs.begin(), pairs.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    start_.assign(cellCount + 1, 0);
    entries_.resize(pairs.size());
    for (std::size_t e = 0; e < pairs.size(); ++e) {
      ++start_[pairs[e].first + 1];
      entries_[e] = {points_[pairs[e].second], pairs[e].second};
    }
    for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    return true;
  }

  std::size_t linear(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return static_cast<std::size_t>(i + dims_[0] * (j + dims_[1] * k));
  }

  const std::vector<Vec3>& points_;
  double reach_ = 0.0, cell_ = 0.0, inverseCell_ = 0.0, lo_[3] = {0, 0, 0};
  std::int64_t dims_[3] = {1, 1, 1};
  std::vector<std::size_t> start_;  // cell -> first entry of its list
  std::vector<Entry> entries_;      // the cells' lists, one after another
  bool built_ = false;
};

// A nanoflann result set: the indices strictly within a squared radius (the test
// RadiusResultSet makes), the search stopped once there are more than `most`.
struct CappedResults {
  using DistanceType = double;  // (what newer nanoflann asks of a result set)
  using IndexType = std::uint32_t;
  double radius2;
  std::size_t most;
  std::vector<std::uint32_t>* out;
  void init() {}
  std::size_t size() const { return out->size(); }
  bool full() const { return true; }
  double worstDist() const { return radius2; }
  void sort() {}  // (the caller sorts the indices)
  template <class Distance, class Index>
  bool addPoint(Distance d2, Index i) {
    if (d2 < radius2) out->push_back(static_cast<std::uint32_t>(i));
    return out->size() <= most;
  }
};

struct InstanceSet::Index {
  Index(const std::vector<Vec3>& points, double reach)
      : cloud{&points},
        tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(8)),
        buckets(points, reach) {}

  // Indices of the copies within `radius` of q, in increasing order. Few copies (a set
  // specialised to a brick) are scanned directly, with nanoflann's own metric and test
  // (sum of squared differences in x, y, z order, strictly below radius^2), so both ways
  // find the same copies.
  // Whether queries of `radius` go to the bucket grid.
  bool bucketed(double radius) const {
    return buckets.built() && radius <= buckets.reach() && cloud.points->size() > kLinearScan;
  }
  void within(const double q[3], double radius, std::vector<std::uint32_t>& out) const {
    if (bucketed(radius)) {
      buckets.within(q, radius, out);
      return;
    }
    if (cloud.points->size() <= kLinearScan) {
      out.clear();
      const double r2 = radius * radius;
      for (std::uint32_t i = 0; i < cloud.points->size(); ++i) {
        const double d2 = squaredDistance(q, (*cloud.points)[i]);
        if (d2 < r2) out.push_back(i);
      }
      return;
    }
    thread_local std::vector<KdRadiusMatch> found;
    found.clear();
    tree.radiusSearch(q, radius * radius, found, kdUnsortedSearch());
    out.clear();
    for (const auto& f : found) out.push_back(f.first);
    std::sort(out.begin(), out.end());
  }
  // As within() where at most `most` copies are within `radius`; false (out incomplete) where
  // more are, found without visiting them all: an interval over a box near a pile of 30,000
  // copies needs only to know that it is a pile (collecting and sorting them all took 85 % of
  // such an export).
  bool withinAtMost(const double q[3], double radius, std::size_t most,
                    std::vector<std::uint32_t>& out) const {
    if (bucketed(radius) || cloud.points->size() <= kLinearScan) {
      within(q, radius, out);
      return out.size() <= most;
    }
    out.clear();
    CappedResults results{radius * radius, most, &out};
    tree.findNeighbors(results, q, kdUnsortedSearch());
    if (out.size() > most) return false;
    std::sort(out.begin(), out.end());
    return true;
  }
  std::uint32_t nearest(const double q[3], double* distance) const {
    std::uint32_t index = 0;
    double d2 = 0;
    tree.knnSearch(q, 1, &index, &d2);
    *distance = std::sqrt(d2);
    return index;
  }

  Cloud cloud;
  Tree tree;
  BucketGrid buckets;
};

InstanceSet::InstanceSet(std::vector<Vec3> positions, std::vector<std::array<double, 9>> rotations,
                         std::shared_ptr<const Program> copy, double reach, Combine combine,
                         Blend blend)
    : positions_(std::move(positions)),
      rotations_(std::move(rotations)),
      copy_(std::move(copy)),
      reach_(reach),
      combine_(combine),
      blend_(blend),
      index_(std::make_unique<Index>(positions_, reach_)) {}

InstanceSet::~InstanceSet() = default;

void InstanceSet::near(double x, double y, double z, std::vector<std::uint32_t>& out) const {
  const double q[3] = {x, y, z};
  index_->within(q, reach_, out);
  if (out.empty() && !positions_.empty() && !whole_ && combine_ != Combine::Sum) {
    double d = 0;
    out.push_back(index_->nearest(q, &d));
  }
}

template <class T>
void InstanceSet::local(std::uint32_t i, const T& x, const T& y, const T& z, T q[3]) const {
  const Vec3& c = positions_[i];
  const T d[3] = {x - c[0], y - c[1], z - c[2]};
  if (rotations_.empty()) {
    q[0] = d[0];
    q[1] = d[1];
    q[2] = d[2];
    return;
  }
  const std::array<double, 9>& r = rotations_[i];
  for (int k = 0; k < 3; ++k) q[k] = d[0] * r[k] + d[1] * r[3 + k] + d[2] * r[6 + k];  // R^T d
}

template <class T>
T InstanceSet::combine(const T* values, std::size_t n) const {
  if (combine_ == Combine::Sum) {
    if (n == 0) return T(0.0);
    T r = values[0];
    for (std::size_t i = 1; i < n; ++i) r = r + values[i];
    return r;
  }
  if (combine_ == Combine::Union) {
    T r = values[0];
    for (std::size_t i = 1; i < n; ++i) r = max(r, values[i]);
    return r;
  }
  const auto [first, second] = largestTwo(values, n);
  if (second == n) return values[first];
  const double k[3] = {blend_.a0, blend_.a1, blend_.a1};
  return values[first] + blendBump(values[first], values[second], k);
}

double InstanceSet::eval(double x, double y, double z) const {
  ScopedWork work;
  std::vector<std::uint32_t>& ids = work->ids;
  std::vector<double>& values = work->values;
  near(x, y, z, ids);
  if (ids.empty() && whole_) return whole_->eval(x, y, z);
  values.resize(ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i) {
    double q[3];
    local(ids[i], x, y, z, q);
    values[i] = copy_->eval(q[0], q[1], q[2]);
  }
  return combine(values.data(), values.size());
}

// Every (point, copy) pair of the first points of a batch: the point in the copy's coordinates
// (qx, qy, qz), the copy, and where each point's pairs start. `at(j)` gives point j's x, y, z.
// Returns how many points (at least one) were gathered: all n, unless their pairs pass
// kMostPairs first.
template <class At>
std::size_t InstanceSet::gatherPairs(std::size_t n, At at, PairBatch& pairs) const {
  pairs.start.resize(n + 1);
  pairs.start[0] = 0;
  std::size_t used = 0;  // pairs so far; the arrays are kept longer (no zeroing per batch)
  const auto room = [&pairs](std::size_t need) {
    if (need <= pairs.qx.size()) return;
    const std::size_t size = std::max(need, 2 * pairs.qx.size());
    pairs.qx.resize(size);
    pairs.qy.resize(size);
    pairs.qz.resize(size);
    pairs.copies.resize(size);
  };
  const bool bucketed = index_->bucketed(reach_);
  const double r2 = reach_ * reach_;
  for (std::size_t j = 0; j < n; ++j) {
    const std::array<double, 3> p = at(j);
    const std::size_t before = used;
    if (bucketed) {
      // The bucket query and the pairs in one pass, without a branch per candidate: each
      // candidate is written and kept when within reach (the test within() makes, and the
      // difference local() takes).
      const double q[3] = {p[0], p[1], p[2]};
      const auto [from, to] = index_->buckets.candidates(q);
      room(used + static_cast<std::size_t>(to - from));
      for (auto e = from; e != to; ++e) {
        const double d[3] = {q[0] - e->position[0], q[1] - e->position[1], q[2] - e->position[2]};
        pairs.qx[used] = d[0];
        pairs.qy[used] = d[1];
        pairs.qz[used] = d[2];
        pairs.copies[used] = e->id;
        used += ((0.0 + d[0] * d[0]) + d[1] * d[1]) + d[2] * d[2] < r2;
      }
      if (!rotations_.empty())
        for (std::size_t e = before; e < used; ++e) {
          double r[3];
          local(pairs.copies[e], p[0], p[1], p[2], r);
          pairs.qx[e] = r[0];
          pairs.qy[e] = r[1];
          pairs.qz[e] = r[2];
        }
    }
    if (used == before) {  // not bucketed, or no copy within reach (near() decides what then)
      near(p[0], p[1], p[2], pairs.ids);
      room(used + pairs.ids.size());
      for (std::uint32_t id : pairs.ids) {
        double r[3];
        local(id, p[0], p[1], p[2], r);
        pairs.qx[used] = r[0];
        pairs.qy[used] = r[1];
        pairs.qz[used] = r[2];
        pairs.copies[used++] = id;
      }
    }
    pairs.start[j + 1] = used;
    if (used >= kMostPairs) return j + 1;
  }
  return n;
}

void InstanceSet::evalBatch(const double* x, const double* y, const double* z, std::size_t n,
                            double* out) const {
  for (std::size_t done = 0; done < n;)
    done += evalBatchPart(x + done, y + done, z + done, n - done, out + done);
}

std::size_t InstanceSet::evalBatchPart(const double* x, const double* y, const double* z,
                                       std::size_t points, double* out) const {
  // Every (point, copy) pair of the chunk is evaluated in one batch call of the copy, then
  // each point's values are combined in the same order eval() uses.
  ScopedWork work;
  PairBatch& pairs = work->pairs;
  const std::size_t n = gatherPairs(
      points,
      [&](std::size_t j) {
        return std::array<double, 3>{x[j], y[j], z[j]};
      },
      pairs);
  const std::vector<std::size_t>& start = pairs.start;
  std::vector<double>& values = work->values;
  values.resize(pairs.start[n]);
  copy_->evalBatch(pairs.qx.data(), pairs.qy.data(), pairs.qz.data(), values.size(), values.data());
  for (std::size_t j = 0; j < n; ++j)
    out[j] = start[j + 1] == start[j] && whole_
                 ? whole_->eval(x[j], y[j], z[j])  // no copy of the subset reaches it
                 : combine(values.data() + start[j], start[j + 1] - start[j]);
  return n;
}

// The world gradient of copy i from its gradient g in its own coordinates: turned back
// (R g), times d(p)/d(world) carried by x, y, z.
Dual InstanceSet::toWorld(std::uint32_t i, const Dual& g, const Dual& x, const Dual& y,
                          const Dual& z) const {
  double w[3] = {g.d[0], g.d[1], g.d[2]};
  if (!rotations_.empty()) {
    const std::array<double, 9>& r = rotations_[i];
    for (int k = 0; k < 3; ++k)
      w[k] = r[3 * k] * g.d[0] + r[3 * k + 1] * g.d[1] + r[3 * k + 2] * g.d[2];
  }
  const Dual* in[3] = {&x, &y, &z};
  Dual v(g.v);
  for (int a = 0; a < 3; ++a) v.d[a] = w[0] * in[0]->d[a] + w[1] * in[1]->d[a] + w[2] * in[2]->d[a];
  return v;
}

Dual InstanceSet::evalGradient(const Dual& x, const Dual& y, const Dual& z) const {
  ScopedWork work;
  std::vector<std::uint32_t>& ids = work->ids;
  near(x.v, y.v, z.v, ids);
  if (ids.empty() && whole_) return whole_->evalGradient(x, y, z);
  std::vector<Dual>& values = work->duals;
  values.resize(ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i) {
    double q[3];
    local(ids[i], x.v, y.v, z.v, q);
    values[i] = toWorld(ids[i], copy_->evalGradient(q[0], q[1], q[2]), x, y, z);
  }
  return combine(values.data(), values.size());
}

void InstanceSet::evalGradientBatch(const Dual* x, const Dual* y, const Dual* z, std::size_t n,
                                    Dual* out) const {
  for (std::size_t done = 0; done < n;)
    done += evalGradientBatchPart(x + done, y + done, z + done, n - done, out + done);
}

std::size_t InstanceSet::evalGradientBatchPart(const Dual* x, const Dual* y, const Dual* z,
                                               std::size_t points, Dual* out) const {
  // As evalBatch: every (point, copy) pair's value in one batch. A union's gradient is its
  // first largest copy's and a blend's comes from its largest two, so only those copies'
  // gradients are evaluated (one gradient batch), then combined as evalGradient combines
  // them: each result is bit-identical to evalGradient's (a copy's gradient value is its
  // point value, so the same copies are picked).
  ScopedWork work;
  PairBatch& pairs = work->pairs;
  const std::size_t n = gatherPairs(
      points,
      [&](std::size_t j) {
        return std::array<double, 3>{x[j].v, y[j].v, z[j].v};
      },
      pairs);
  const std::vector<std::size_t>& start = pairs.start;
  const bool all = combine_ == Combine::Sum;
  std::vector<double>& v = work->values;
  if (!all) {
    v.resize(pairs.start[n]);
    copy_->evalBatch(pairs.qx.data(), pairs.qy.data(), pairs.qz.data(), v.size(), v.data());
  }
  // The pairs whose gradients are needed, per point, in their order.
  std::vector<std::size_t>& chosenStart = work->chosenStart;
  std::vector<std::uint32_t>& chosen = work->chosen;
  chosenStart.assign(1, 0);
  chosen.clear();
  for (std::size_t j = 0; j < n; ++j) {
    const std::size_t from = start[j], to = start[j + 1];
    if (all || to - from <= 1) {
      for (std::size_t e = from; e < to; ++e) chosen.push_back(static_cast<std::uint32_t>(e));
    } else if (combine_ == Combine::Union) {
      std::size_t best = from;  // the first largest: max() keeps the earlier one on ties
      for (std::size_t e = from + 1; e < to; ++e)
        if (v[e] > v[best]) best = e;
      chosen.push_back(static_cast<std::uint32_t>(best));
    } else {  // blend: the largest two, found as combine() finds them, kept in index order
      const auto [first, second] = largestTwo(v.data() + from, to - from);
      chosen.push_back(static_cast<std::uint32_t>(from + std::min(first, second)));
      chosen.push_back(static_cast<std::uint32_t>(from + std::max(first, second)));
    }
    chosenStart.push_back(chosen.size());
  }
  std::vector<Dual>&qx = work->dqx, &qy = work->dqy, &qz = work->dqz, &values = work->duals;
  const std::size_t m = chosen.size();
  qx.resize(m);
  qy.resize(m);
  qz.resize(m);
  for (std::size_t c = 0; c < m; ++c) {
    qx[c] = Dual(pairs.qx[chosen[c]], 1, 0, 0);
    qy[c] = Dual(pairs.qy[chosen[c]], 0, 1, 0);
    qz[c] = Dual(pairs.qz[chosen[c]], 0, 0, 1);
  }
  values.resize(m);
  copy_->evalGradientBatch(qx.data(), qy.data(), qz.data(), m, values.data());
  for (std::size_t j = 0; j < n; ++j) {
    if (start[j + 1] == start[j] && whole_) {  // no copy of the subset reaches it
      out[j] = whole_->evalGradient(x[j], y[j], z[j]);
      continue;
    }
    for (std::size_t c = chosenStart[j]; c < chosenStart[j + 1]; ++c)
      values[c] = toWorld(pairs.copies[chosen[c]], values[c], x[j], y[j], z[j]);
    out[j] = combine(values.data() + chosenStart[j], chosenStart[j + 1] - chosenStart[j]);
  }
  return n;
}

Interval InstanceSet::evalInterval(const Interval& x, const Interval& y, const Interval& z) const {
  if (whole_) return whole_->evalInterval(x, y, z);  // identical to the whole set's, as promised
  const Interval box[3] = {x, y, z};
  double c[3], h2 = 0;
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(box[a].lo) || !std::isfinite(box[a].hi)) return Interval::entire();
    c[a] = 0.5 * (box[a].lo + box[a].hi);
    h2 += 0.25 * box[a].width() * box[a].width();
  }
  const double h = std::sqrt(h2);
  if (combine_ == Combine::Sum) return sumInterval(box, c, h);
  const double inf = std::numeric_limits<double>::infinity();
  // Every copy that can matter at a point p of the box: those within reach of p (within
  // reach + h of the centre) and p's nearest copy (within d* + 2h, d* = the centre's).
  double dNearest = 0;
  index_->nearest(c, &dNearest);
  ScopedWork work;
  std::vector<std::uint32_t>& candidates = work->ids;
  const bool few = index_->withinAtMost(c, std::max(reach_ + h, dNearest + 2 * h),
                                        kMaxIntervalCopies, candidates);
  const bool anyInReach = dNearest <= reach_ + h;
  const double bumpMax = combine_ == Combine::Blend ? std::max(blend_.a0, 0.0) : 0.0;
  if (!few) {
    // Beyond its reach a copy's field is negative, so far from every copy F < 0.
    if (!anyInReach) return {-inf, 0.0, true};
    const Interval whole =
        copy_->evalInterval({-reach_, reach_}, {-reach_, reach_}, {-reach_, reach_});
    return outward(-inf, whole.hi + bumpMax, true);
  }
  double lo = inf, hi = -inf, always = -inf;
  bool nan = false;
  for (std::uint32_t id : candidates) {
    const Vec3& p = positions_[id];
    Interval q[3];
    local(id, x, y, z, q);
    const Interval v = copy_->evalInterval(q[0], q[1], q[2]);
    lo = std::min(lo, v.lo);
    hi = std::max(hi, v.hi);
    nan = nan || v.nan;
    const double d = std::sqrt(sqr(c[0] - p[0]) + sqr(c[1] - p[1]) + sqr(c[2] - p[2]));
    if (d + h <= reach_) always = std::max(always, v.lo);  // a copy every point combines
  }
  if (always > -inf) lo = always;
  if (combine_ == Combine::Blend) {
    // F = m1 + bump with 0 <= bump <= a0 / (1 + (m1/a1)^2)
    const Interval m2 = sqr(Interval(lo, hi));
    hi += blend_.a0 / (1.0 + m2.lo / (blend_.a1 * blend_.a1));
    // the sum m1 + bump and the bump itself round: a few ulps more
    return outward(lo, hi, nan, 4);
  }
  return {lo, hi, nan};
}

Interval InstanceSet::sumInterval(const Interval box[3], const double c[3], double h) const {
  // The copies within reach of some point of the box. Each adds its own interval over the box
  // where it reaches every point, and that interval joined with 0 where it may not reach
  // some; summed in index order with outward rounding, as the points sum them.
  ScopedWork work;
  std::vector<std::uint32_t>& candidates = work->ids;
  const bool few = index_->withinAtMost(c, reach_ + h, kMaxIntervalCopies, candidates);
  if (candidates.empty()) return Interval(0.0);
  if (!few) {
    // (as many as every copy: counting those within reach would cost visiting them all)
    const Interval one =
        copy_->evalInterval({-reach_, reach_}, {-reach_, reach_}, {-reach_, reach_});
    const double n = static_cast<double>(positions_.size());
    return outward(n * std::min(one.lo, 0.0), n * std::max(one.hi, 0.0), one.nan, 4);
  }
  Interval sum;
  bool first = true;
  for (std::uint32_t id : candidates) {
    const Vec3& p = positions_[id];
    Interval q[3];
    local(id, box[0], box[1], box[2], q);
    Interval v = copy_->evalInterval(q[0], q[1], q[2]);
    const double d = std::sqrt(sqr(c[0] - p[0]) + sqr(c[1] - p[1]) + sqr(c[2] - p[2]));
    if (!(d + h < reach_ * (1 - 1e-12))) v = hull(v, Interval(0.0));  // may be left out
    sum = first ? v : sum + v;
    first = false;
  }
  return sum;
}

std::shared_ptr<const Field> InstanceSet::specialise(const Box3& box) const {
  double c[3], h2 = 0;
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(box.lo[a]) || !std::isfinite(box.hi[a])) return nullptr;
    c[a] = 0.5 * (box.lo[a] + box.hi[a]);
    h2 += 0.25 * sqr(box.hi[a] - box.lo[a]);
  }
  const double h = std::sqrt(h2);
  if (positions_.empty()) return nullptr;
  // With the bucket grid a point's query already costs only the copies round it: a subset
  // (its own k-d tree, per brick) would buy nothing.
  if (index_->buckets.built() && positions_.size() > kLinearScan) return nullptr;
  // Every copy within reach of a point of the box (with a little slack); points no copy
  // reaches go to the whole set.
  std::vector<std::uint32_t> keep;
  index_->within(c, (reach_ + h) * (1 + 1e-6) + 1e-12, keep);
  if (keep.size() == positions_.size()) return nullptr;
  std::vector<Vec3> positions;
  std::vector<std::array<double, 9>> rotations;
  positions.reserve(keep.size());
  for (std::uint32_t i : keep) {
    positions.push_back(positions_[i]);
    if (!rotations_.empty()) rotations.push_back(rotations_[i]);
  }
  auto subset = std::make_shared<InstanceSet>(std::move(positions), std::move(rotations), copy_,
                                              reach_, combine_, blend_);
  subset->whole_ = whole_ ? whole_ : shared_from_this();
  return subset;
}

Box3 InstanceSet::bounds() const {
  Box3 b = Field::bounds();
  // A sum is >= 0 everywhere: its solid is whatever the threshold subtracted from it makes.
  if (positions_.empty() || combine_ == Combine::Sum) return b;
  for (int a = 0; a < 3; ++a) {
    b.lo[a] = std::numeric_limits<double>::infinity();
    b.hi[a] = -std::numeric_limits<double>::infinity();
  }
  for (const Vec3& p : positions_)
    for (int a = 0; a < 3; ++a) {
      b.lo[a] = std::min(b.lo[a], p[a] - reach_);
      b.hi[a] = std::max(b.hi[a], p[a] + reach_);
    }
  return b;
}

}  // namespace frep
