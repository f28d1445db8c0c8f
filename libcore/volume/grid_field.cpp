// GridField: an OpenVDB float or double grid behind the Field seam (see grid_field.h).
#include "volume/grid_field.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "base/errors.h"
#include "volume/openvdb_grids.h"

namespace frep {

namespace {

struct MinMax {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  void add(double v) {
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  void add(const MinMax& o) {
    lo = std::min(lo, o.lo);
    hi = std::max(hi, o.hi);
  }
};

// An index-space box of voxels, inclusive, in 64 bits (a field's box may reach far beyond
// the 32-bit coordinates of the tree).
struct IndexRange {
  std::int64_t lo[3], hi[3];
  bool contains(const openvdb::CoordBBox& b) const {
    for (int a = 0; a < 3; ++a)
      if (b.min()[a] < lo[a] || b.max()[a] > hi[a]) return false;
    return true;
  }
  bool meets(const openvdb::CoordBBox& b) const {
    for (int a = 0; a < 3; ++a)
      if (b.max()[a] < lo[a] || b.min()[a] > hi[a]) return false;
    return true;
  }
  // Voxels of the range inside b (as a double: ranges can hold more than 2^63 voxels).
  double overlap(const openvdb::CoordBBox& b) const {
    double n = 1;
    for (int a = 0; a < 3; ++a) {
      const std::int64_t l = std::max<std::int64_t>(lo[a], b.min()[a]);
      const std::int64_t h = std::min<std::int64_t>(hi[a], b.max()[a]);
      if (h < l) return 0;
      n *= double(h - l + 1);
    }
    return n;
  }
  double volume() const {
    double n = 1;
    for (int a = 0; a < 3; ++a) n *= double(hi[a] - lo[a] + 1);
    return n;
  }
};

// Interpolation weights along one axis at fraction t of the cell from the floor index, and
// their derivatives: linear over voxels i, i+1; quadratic over i-1, i, i+1 (the parabola
// through the three, as OpenVDB's QuadraticSampler fits it).
template <int N>
void weights(double t, double (&w)[N], double (&dw)[N]) {
  if constexpr (N == 2) {
    w[0] = 1.0 - t;
    w[1] = t;
    dw[0] = -1.0;
    dw[1] = 1.0;
  } else {
    w[0] = 0.5 * t * (t - 1.0);
    w[1] = 1.0 - t * t;
    w[2] = 0.5 * t * (t + 1.0);
    dw[0] = t - 0.5;
    dw[1] = -2.0 * t;
    dw[2] = t + 0.5;
  }
}

template <class GridT>
class GridField final : public Field {
  using TreeT = typename GridT::TreeType;
  using RootT = typename TreeT::RootNodeType;
  using Accessor = openvdb::tree::ValueAccessor<const TreeT, /*IsSafe=*/false>;

 public:
  GridField(typename GridT::ConstPtr grid, bool levelSet, const GridFieldOptions& o)
      : grid_(std::move(grid)),
        sign_(levelSet ? -1.0 : 1.0),
        iso_(o.iso),
        quadratic_(o.interpolation == GridInterpolation::Quadratic) {
    // world -> index, an affine map: OpenVDB's matrices act on row vectors (w = i M).
    const openvdb::math::Mat4d m = grid_->transform().baseMap()->getAffineMap()->getMat4();
    const openvdb::math::Mat4d inv = m.inverse();
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 3; ++i) a_[j][i] = inv(i, j);
      b_[j] = inv(3, j);
    }
    const TreeT& tree = grid_->tree();
    background_ = double(tree.background());
    precompute(tree.root());
    computeBounds();
  }

  double eval(double x, double y, double z) const override {
    Accessor acc(grid_->tree());
    return quadratic_ ? sample<3>(acc, x, y, z, nullptr) : sample<2>(acc, x, y, z, nullptr);
  }

  void evalBatch(const double* x, const double* y, const double* z, std::size_t n,
                 double* out) const override {
    Accessor acc(grid_->tree());
    if (quadratic_)
      for (std::size_t i = 0; i < n; ++i) out[i] = sample<3>(acc, x[i], y[i], z[i], nullptr);
    else
      for (std::size_t i = 0; i < n; ++i) out[i] = sample<2>(acc, x[i], y[i], z[i], nullptr);
  }

  Dual evalGradient(const Dual& x, const Dual& y, const Dual& z) const override {
    Accessor acc(grid_->tree());
    double g[3];
    const double v = quadratic_ ? sample<3>(acc, x.v, y.v, z.v, g) : sample<2>(acc, x.v, y.v, z.v, g);
    return composed(v, g, x, y, z);
  }
  using Field::evalGradient;

  Interval evalInterval(const Interval& x, const Interval& y, const Interval& z) const override {
    const Interval in[3] = {x, y, z};
    bool nan = x.nan || y.nan || z.nan;
    IndexRange r;
    for (int j = 0; j < 3; ++j) {
      // The index box of the world box, through the affine map.
      double lo = b_[j], hi = b_[j];
      for (int i = 0; i < 3; ++i) {
        const double p = a_[j][i] * in[i].lo, q = a_[j][i] * in[i].hi;
        if (a_[j][i] == 0.0) continue;
        lo += std::min(p, q);
        hi += std::max(p, q);
      }
      if (!(lo == lo) || !(hi == hi)) return Interval::entire(true);
      // A margin for the rounding of the map, then the voxels the stencil can read.
      const double pad = 1e-9 * (1.0 + std::abs(lo) + std::abs(hi));
      lo = std::floor(lo - pad) - (quadratic_ ? 1 : 0);
      hi = std::floor(hi + pad) + 1;
      constexpr double kFar = 4.0e18;
      r.lo[j] = static_cast<std::int64_t>(std::clamp(lo, -kFar, kFar));
      r.hi[j] = static_cast<std::int64_t>(std::clamp(hi, -kFar, kFar));
    }
    MinMax v = query(r);
    if (quadratic_) {
      // Each axis' parabola through three values stays within 1/8 of their range beyond them;
      // over three axes in turn that compounds to 61/128 of the range (0.5 taken).
      const double range = v.hi - v.lo;
      v.lo -= 0.5 * range;
      v.hi += 0.5 * range;
    }
    const double pad = 1e-12 * (std::abs(v.lo) + std::abs(v.hi) + std::abs(iso_)) + 1e-300;
    Interval out = sign_ > 0 ? Interval(v.lo - iso_ - pad, v.hi - iso_ + pad, nan)
                             : Interval(iso_ - v.hi - pad, iso_ - v.lo + pad, nan);
    return out;
  }

  Box3 bounds() const override { return bounds_; }

 private:
  // F at a world point; with g, also dF/dworld.
  template <int N>
  double sample(Accessor& acc, double x, double y, double z, double* g) const {
    double idx[3];
    for (int j = 0; j < 3; ++j) idx[j] = a_[j][0] * x + a_[j][1] * y + a_[j][2] * z + b_[j];
    if (!(std::abs(idx[0]) < 2e9 && std::abs(idx[1]) < 2e9 && std::abs(idx[2]) < 2e9)) {
      // Beyond the tree's coordinates (or NaN): the background.
      if (g) g[0] = g[1] = g[2] = 0.0;
      if (idx[0] != idx[0] || idx[1] != idx[1] || idx[2] != idx[2])
        return std::numeric_limits<double>::quiet_NaN();
      return sign_ * background_ - sign_ * iso_;
    }
    int base[3];
    double w[3][N], dw[3][N];
    for (int j = 0; j < 3; ++j) {
      const double f = std::floor(idx[j]);
      base[j] = static_cast<int>(f) - (N == 3 ? 1 : 0);
      weights<N>(idx[j] - f, w[j], dw[j]);
    }
    // The stencil's voxels: straight from the leaf's buffer when they all lie in one leaf (most
    // of the time: 7^3 of 8^3 cells for the linear one), else through the accessor. The same
    // voxels either way, so the same value.
    double s3[N][N][N];
    using LeafT = typename TreeT::LeafNodeType;
    const bool oneLeaf = (base[0] & 7) <= 8 - N && (base[1] & 7) <= 8 - N && (base[2] & 7) <= 8 - N;
    const LeafT* leaf = oneLeaf ? acc.probeConstLeaf(openvdb::Coord(base[0], base[1], base[2])) : nullptr;
    if (leaf) {
      const auto* data = leaf->buffer().data();
      const openvdb::Index o = LeafT::coordToOffset(openvdb::Coord(base[0], base[1], base[2]));
      for (int i = 0; i < N; ++i)
        for (int j = 0; j < N; ++j)
          for (int k = 0; k < N; ++k) s3[i][j][k] = double(data[o + (i << 6) + (j << 3) + k]);
    } else if (oneLeaf) {
      // No leaf there: the leaf-sized region is one tile (or the background), one value.
      const double t = double(acc.getValue(openvdb::Coord(base[0], base[1], base[2])));
      for (int i = 0; i < N; ++i)
        for (int j = 0; j < N; ++j)
          for (int k = 0; k < N; ++k) s3[i][j][k] = t;
    } else {
      for (int i = 0; i < N; ++i)
        for (int j = 0; j < N; ++j)
          for (int k = 0; k < N; ++k)
            s3[i][j][k] = double(acc.getValue(openvdb::Coord(base[0] + i, base[1] + j, base[2] + k)));
    }
    double v = 0.0, gi[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < N; ++i)
      for (int j = 0; j < N; ++j)
        for (int k = 0; k < N; ++k) {
          const double s = s3[i][j][k];
          v += w[0][i] * w[1][j] * w[2][k] * s;
          if (g) {
            gi[0] += dw[0][i] * w[1][j] * w[2][k] * s;
            gi[1] += w[0][i] * dw[1][j] * w[2][k] * s;
            gi[2] += w[0][i] * w[1][j] * dw[2][k] * s;
          }
        }
    if (g)
      for (int i = 0; i < 3; ++i)
        g[i] = sign_ * (gi[0] * a_[0][i] + gi[1] * a_[1][i] + gi[2] * a_[2][i]);
    return sign_ > 0 ? v - iso_ : iso_ - v;
  }

  // ---- per-node extrema ----

  template <class NodeT>
  MinMax precompute(const NodeT& node) {
    MinMax m;
    if constexpr (NodeT::LEVEL == 0) {
      for (openvdb::Index n = 0; n < NodeT::SIZE; ++n) m.add(double(node.getValue(n)));
    } else {
      for (openvdb::Index n = 0; n < NodeT::NUM_VALUES; ++n) {
        if (node.isChildMaskOn(n))
          m.add(precompute(*node.getTable()[n].getChild()));
        else
          m.add(double(node.getTable()[n].getValue()));
      }
    }
    extrema_[&node] = m;
    return m;
  }

  void precompute(const RootT& root) {
    for (auto it = root.cbeginChildOn(); it; ++it) precompute(*it);
  }

  template <class NodeT>
  void query(const NodeT& node, const IndexRange& r, MinMax& m) const {
    const openvdb::CoordBBox box = node.getNodeBoundingBox();
    if (r.contains(box)) {
      m.add(extrema_.at(&node));
      return;
    }
    if constexpr (NodeT::LEVEL == 0) {
      for (openvdb::Index n = 0; n < NodeT::SIZE; ++n) {
        const openvdb::Coord c = node.offsetToGlobalCoord(n);
        if (c[0] >= r.lo[0] && c[0] <= r.hi[0] && c[1] >= r.lo[1] && c[1] <= r.hi[1] &&
            c[2] >= r.lo[2] && c[2] <= r.hi[2])
          m.add(double(node.getValue(n)));
      }
    } else {
      using ChildT = typename NodeT::ChildNodeType;
      const openvdb::Coord o = node.origin();
      // (OpenVDB's DIM constants are unsigned: mixed with a negative origin they would wrap.)
      constexpr std::int64_t dim = NodeT::DIM, childDim = ChildT::DIM;
      std::int64_t from[3], to[3];
      for (int a = 0; a < 3; ++a) {
        const std::int64_t origin = o[a];
        from[a] = (std::max(r.lo[a], origin) - origin) / childDim;
        to[a] = (std::min(r.hi[a], origin + dim - 1) - origin) / childDim;
      }
      for (std::int64_t i = from[0]; i <= to[0]; ++i)
        for (std::int64_t j = from[1]; j <= to[1]; ++j)
          for (std::int64_t k = from[2]; k <= to[2]; ++k) {
            const openvdb::Index n = openvdb::Index((i << (2 * NodeT::LOG2DIM)) + (j << NodeT::LOG2DIM) + k);
            if (node.isChildMaskOn(n))
              query(*node.getTable()[n].getChild(), r, m);
            else
              m.add(double(node.getTable()[n].getValue()));
          }
    }
  }

  MinMax query(const IndexRange& r) const {
    MinMax m;
    double covered = 0.0;
    const RootT& root = grid_->tree().root();
    for (auto it = root.cbeginChildOn(); it; ++it) {
      const openvdb::CoordBBox box = it->getNodeBoundingBox();
      if (!r.meets(box)) continue;
      covered += r.overlap(box);
      query(*it, r, m);
    }
    for (auto it = root.cbeginValueAll(); it; ++it) {
      const openvdb::CoordBBox box = openvdb::CoordBBox::createCube(it.getCoord(), RootT::ChildNodeType::DIM);
      if (!r.meets(box)) continue;
      covered += r.overlap(box);
      m.add(double(*it));
    }
    if (covered < r.volume()) m.add(background_);
    return m;
  }

  // Where F >= 0 can be: everywhere when the background is inside, else within the leaves
  // and tiles of the tree whose values reach inside, widened by the stencil.
  bool mayBeInside(const MinMax& m) const {
    // (Triquadratic overshoot needs a spread of values, which a constant never has.)
    const double spread = quadratic_ ? 0.5 * (m.hi - m.lo) : 0.0;
    return sign_ > 0 ? m.hi + spread - iso_ >= 0 : iso_ - (m.lo - spread) >= 0;
  }

  template <class NodeT>
  void insideBox(const NodeT& node, openvdb::CoordBBox& all) const {
    if (!mayBeInside(extrema_.at(&node))) return;
    if constexpr (NodeT::LEVEL == 0) {
      all.expand(node.getNodeBoundingBox());
    } else {
      using ChildT = typename NodeT::ChildNodeType;
      for (openvdb::Index n = 0; n < NodeT::NUM_VALUES; ++n) {
        if (node.isChildMaskOn(n)) {
          insideBox(*node.getTable()[n].getChild(), all);
        } else {
          MinMax m;
          m.add(double(node.getTable()[n].getValue()));
          if (mayBeInside(m))
            all.expand(openvdb::CoordBBox::createCube(node.offsetToGlobalCoord(n), ChildT::DIM));
        }
      }
    }
  }

  void computeBounds() {
    const double inf = std::numeric_limits<double>::infinity();
    MinMax bg;
    bg.add(background_);
    if (mayBeInside(bg)) {
      bounds_ = Box3{{-inf, -inf, -inf}, {inf, inf, inf}};
      return;
    }
    openvdb::CoordBBox all;
    const RootT& root = grid_->tree().root();
    for (auto it = root.cbeginChildOn(); it; ++it) insideBox(*it, all);
    for (auto it = root.cbeginValueAll(); it; ++it) {
      MinMax m;
      m.add(double(*it));
      if (mayBeInside(m)) all.expand(openvdb::CoordBBox::createCube(it.getCoord(), RootT::ChildNodeType::DIM));
    }
    if (all.empty()) {
      bounds_ = Box3{{0, 0, 0}, {0, 0, 0}};
      return;
    }
    const openvdb::BBoxd wb = grid_->transform().indexToWorld(
        openvdb::BBoxd(all.min().asVec3d() - 2.0, all.max().asVec3d() + 2.0));
    bounds_ = Box3{{wb.min()[0], wb.min()[1], wb.min()[2]}, {wb.max()[0], wb.max()[1], wb.max()[2]}};
  }

  typename GridT::ConstPtr grid_;
  double sign_, iso_;
  bool quadratic_;
  double a_[3][3], b_[3];
  double background_ = 0.0;
  std::unordered_map<const void*, MinMax> extrema_;
  Box3 bounds_;
};

}  // namespace

std::shared_ptr<const Field> gridField(const GridSet& grids, std::size_t index,
                                       const GridFieldOptions& options, const std::string& where) {
  initializeOpenVdb();
  const openvdb::GridBase::Ptr& g = grids.impl->grids.at(index);
  if (!g->transform().isLinear())
    throw ModelError(where + ": grid '" + g->getName() +
                     "' has a frustum (non-linear) transform; only linear transforms are read");
  const bool levelSet = g->getGridClass() == openvdb::GRID_LEVEL_SET;
  if (auto f = openvdb::gridPtrCast<openvdb::FloatGrid>(g))
    return std::make_shared<GridField<openvdb::FloatGrid>>(f, levelSet, options);
  if (auto d = openvdb::gridPtrCast<openvdb::DoubleGrid>(g))
    return std::make_shared<GridField<openvdb::DoubleGrid>>(d, levelSet, options);
  throw ModelError(where + ": grid '" + g->getName() + "' holds " + g->valueType() +
                   " values; a solid needs a float or double grid");
}

}  // namespace frep
