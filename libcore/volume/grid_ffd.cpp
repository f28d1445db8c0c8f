// deformGrids: backward resampling through the lattice's inverse (grid_ffd.h), leaf by leaf
// in parallel; seed 002's forward splatting for comparison.
#include "volume/grid_ffd.h"

#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/LevelSetRebuild.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>

#include "base/errors.h"
#include "base/progress.h"
#include "lattice/ffd_map.h"
#include "volume/openvdb_grids.h"

namespace frep {

namespace {

using openvdb::Coord;
using openvdb::CoordBBox;
using openvdb::Vec3d;

Vec3 toVec(const Vec3d& v) {
  return {v[0], v[1], v[2]};
}
Vec3d toVdb(const Vec3& v) {
  return {v[0], v[1], v[2]};
}

// The world box of a box of voxels (their centres, grown by half a voxel).
Box3 worldBox(const openvdb::math::Transform& xf, const CoordBBox& b) {
  Box3 out{{1e300, 1e300, 1e300}, {-1e300, -1e300, -1e300}};
  for (int c = 0; c < 8; ++c) {
    const Vec3d ijk(c & 1 ? b.max().x() + 0.5 : b.min().x() - 0.5,
                    c & 2 ? b.max().y() + 0.5 : b.min().y() - 0.5,
                    c & 4 ? b.max().z() + 0.5 : b.min().z() - 0.5);
    const Vec3d w = xf.indexToWorld(ijk);
    for (int k = 0; k < 3; ++k)
      out.lo[k] = std::min(out.lo[k], w[k]), out.hi[k] = std::max(out.hi[k], w[k]);
  }
  return out;
}

// The voxels whose centres a world box can hold.
CoordBBox indexBox(const openvdb::math::Transform& xf, const Box3& b) {
  Coord lo(std::numeric_limits<int>::max()), hi(std::numeric_limits<int>::min());
  for (int c = 0; c < 8; ++c) {
    const Vec3d w(c & 1 ? b.hi[0] : b.lo[0], c & 2 ? b.hi[1] : b.lo[1], c & 4 ? b.hi[2] : b.lo[2]);
    const Vec3d i = xf.worldToIndex(w);
    for (int k = 0; k < 3; ++k) {
      // clamp before converting: a runaway lattice must not overflow the coordinates
      const double l = std::clamp(std::floor(i[k]) - 1, -1e9, 1e9),
                   h = std::clamp(std::ceil(i[k]) + 1, -1e9, 1e9);
      lo[k] = std::min(lo[k], int(l));
      hi[k] = std::max(hi[k], int(h));
    }
  }
  return {lo, hi};
}

// Leaf origins covering the destinations of a grid's active values: where the lattice takes
// each source leaf (the restricted control hull of its box, so the bound is rigorous) and,
// for the parts outside the rest box, where they are.
template <class GridT>
std::vector<Coord> destinationLeaves(const GridT& src, const FfdLattice& lattice,
                                     const GridFfdOptions& o) {
  using LeafT = typename GridT::TreeType::LeafNodeType;
  const openvdb::math::Transform& xf = src.transform();
  const Box3& rest = lattice.rest();
  const std::uint64_t maxLeaves = o.maxVoxels / LeafT::SIZE + 1;
  std::vector<Coord> out;
  std::size_t unique = 0;
  auto addBox = [&](const CoordBBox& b) {
    const std::uint64_t count =
        std::uint64_t((b.max().x() >> LeafT::TOTAL) - (b.min().x() >> LeafT::TOTAL) + 1) *
        std::uint64_t((b.max().y() >> LeafT::TOTAL) - (b.min().y() >> LeafT::TOTAL) + 1) *
        std::uint64_t((b.max().z() >> LeafT::TOTAL) - (b.min().z() >> LeafT::TOTAL) + 1);
    if (count > maxLeaves)
      throw ModelError("deform: the deformed grid '" + src.getName() + "' would need more than " +
                       std::to_string(o.maxVoxels) +
                       " voxels; the lattice stretches it too far for its voxel size");
    for (int x = b.min().x() & ~int(LeafT::DIM - 1); x <= b.max().x(); x += LeafT::DIM)
      for (int y = b.min().y() & ~int(LeafT::DIM - 1); y <= b.max().y(); y += LeafT::DIM)
        for (int z = b.min().z() & ~int(LeafT::DIM - 1); z <= b.max().z(); z += LeafT::DIM)
          out.emplace_back(x, y, z);
    if (out.size() > 4 * unique + 4096) {
      std::sort(out.begin(), out.end());
      out.erase(std::unique(out.begin(), out.end()), out.end());
      unique = out.size();
      if (unique > maxLeaves)
        throw ModelError("deform: the deformed grid '" + src.getName() + "' would need more than " +
                         std::to_string(o.maxVoxels) +
                         " voxels; the lattice stretches it too far for its voxel size");
    }
  };
  auto addSource = [&](const CoordBBox& b) {
    const Box3 w = worldBox(xf, b);
    bool meetsRest = true, withinRest = true;
    for (int k = 0; k < 3; ++k) {
      if (w.hi[k] < rest.lo[k] || w.lo[k] > rest.hi[k]) meetsRest = false;
      if (w.lo[k] < rest.lo[k] || w.hi[k] > rest.hi[k]) withinRest = false;
    }
    if (!withinRest) addBox(b);  // its part outside the rest box stays
    if (!meetsRest) return;
    Box3 stu{lattice.local(w.lo), lattice.local(w.hi)};
    addBox(indexBox(xf, lattice.imageBounds(stu)));
  };
  for (auto leaf = src.tree().cbeginLeaf(); leaf; ++leaf)
    if (leaf->onVoxelCount() > 0) {
      CoordBBox b;
      leaf->evalActiveBoundingBox(b, false);
      addSource(b);
    }
  for (auto it = src.tree().cbeginValueOn(); it; ++it)
    if (it.isTileValue()) addSource(it.getBoundingBox());
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

// How a vector value transforms under the world map with Jacobian `a` = dy/dx at the point.
enum class VectorRule { Keep, Jacobian, InverseTranspose, InverseTransposeNormalized, Position };

VectorRule vectorRule(const openvdb::GridBase& g, const GridFfdOptions& o) {
  if (o.keepVectors) return VectorRule::Keep;
  switch (g.getVectorType()) {
    case openvdb::VEC_COVARIANT:
      return VectorRule::InverseTranspose;
    case openvdb::VEC_COVARIANT_NORMALIZE:
      return VectorRule::InverseTransposeNormalized;
    case openvdb::VEC_CONTRAVARIANT_ABSOLUTE:
      return VectorRule::Position;
    default:
      return VectorRule::Jacobian;  // relative, or invariant: OpenVDB's "never said"
  }
}

template <class T>
T transformed(const T& v, const Mat3&, VectorRule, const FfdLattice&) {
  return v;
}

template <class V>
V transformVector(const V& v, const Mat3& a, VectorRule rule, const FfdLattice& lattice) {
  using S = typename V::ValueType;
  const Vec3 x{double(v[0]), double(v[1]), double(v[2])};
  Vec3 y = x;
  switch (rule) {
    case VectorRule::Keep:
      return v;
    case VectorRule::Position:
      y = lattice.deform(x);
      break;
    case VectorRule::Jacobian:
      for (int r = 0; r < 3; ++r) y[r] = a[r][0] * x[0] + a[r][1] * x[1] + a[r][2] * x[2];
      break;
    case VectorRule::InverseTranspose:
    case VectorRule::InverseTransposeNormalized: {
      Mat3 inv;
      if (!invert(a, &inv)) return v;
      for (int r = 0; r < 3; ++r) y[r] = inv[0][r] * x[0] + inv[1][r] * x[1] + inv[2][r] * x[2];
      if (rule == VectorRule::InverseTransposeNormalized) {
        const double len = std::sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
        if (len > 0) y = {y[0] / len, y[1] / len, y[2] / len};
      }
      break;
    }
  }
  return V(S(y[0]), S(y[1]), S(y[2]));
}
template <>
openvdb::Vec3s transformed(const openvdb::Vec3s& v, const Mat3& a, VectorRule rule,
                           const FfdLattice& l) {
  return transformVector(v, a, rule, l);
}
template <>
openvdb::Vec3d transformed(const openvdb::Vec3d& v, const Mat3& a, VectorRule rule,
                           const FfdLattice& l) {
  return transformVector(v, a, rule, l);
}

template <class T>
constexpr bool kIsVector = false;
template <>
constexpr bool kIsVector<openvdb::Vec3s> = true;
template <>
constexpr bool kIsVector<openvdb::Vec3d> = true;
template <class T>
constexpr bool kInterpolates = std::is_floating_point<T>::value || kIsVector<T>;

// The source's value and active state at a world point: the voxel's own where the point is
// (to 1e-6 voxel) a voxel centre, else interpolated; active where the nearest voxel is.
template <class AccT, class T>
bool sampleAt(const AccT& acc, const openvdb::math::Transform& xf, const Vec3& q, int order,
              T* value) {
  const Vec3d i = xf.worldToIndex(toVdb(q));
  const Coord c(int(std::lround(i[0])), int(std::lround(i[1])), int(std::lround(i[2])));
  const bool active = acc.isValueOn(c);
  if (!active) return false;
  const bool centre =
      std::abs(i[0] - c[0]) < 1e-6 && std::abs(i[1] - c[1]) < 1e-6 && std::abs(i[2] - c[2]) < 1e-6;
  if (centre || order == 0 || !kInterpolates<T>) {
    *value = acc.getValue(c);
  } else if constexpr (std::is_floating_point<T>::value) {
    if (order == 2)
      openvdb::tools::QuadraticSampler::sample(acc, i, *value);
    else
      openvdb::tools::BoxSampler::sample(acc, i, *value);
  } else if constexpr (kIsVector<T>) {
    openvdb::tools::BoxSampler::sample(acc, i, *value);
  }
  return true;
}

template <class GridT>
typename GridT::Ptr backward(const GridT& src, const FfdMap& map, const GridFfdOptions& o,
                             const Progress& share) {
  using TreeT = typename GridT::TreeType;
  using LeafT = typename TreeT::LeafNodeType;
  using ValueT = typename GridT::ValueType;
  const FfdLattice& lattice = map.lattice();
  const openvdb::math::Transform& xf = src.transform();
  const std::vector<Coord> origins = destinationLeaves(src, lattice, o);
  const VectorRule rule = vectorRule(src, o);
  const Box3& rest = lattice.rest();
  // The undeformed map's Jacobian is the identity but for rounding: vectors are left alone.
  const bool transforms = !lattice.isUndeformed();
  typename GridT::Ptr out = src.copyWithNewTree();
  std::vector<LeafT*> leaves(origins.size(), nullptr);
  constexpr std::size_t kChunk = 1024;
  for (std::size_t start = 0; start < origins.size(); start += kChunk) {
    const std::size_t end = std::min(origins.size(), start + kChunk);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(start, end, 8), [&](const auto& range) {
      auto acc = src.getConstAccessor();
      for (std::size_t l = range.begin(); l != range.end(); ++l) {
        auto leaf = std::make_unique<LeafT>(origins[l], src.background(), false);
        const std::vector<int> near = map.leavesMeeting(
            worldBox(xf, CoordBBox(origins[l], origins[l].offsetBy(LeafT::DIM - 1))));
        std::optional<Vec3> last;
        for (auto v = leaf->beginValueAll(); v; ++v) {
          const Vec3 p = toVec(xf.indexToWorld(v.getCoord()));
          Vec3 q = p;
          bool moved = false;
          // Neighbouring voxels come from neighbouring points: Newton from the last
          // voxel's solution converges in a step or two; the full search only where it
          // does not (a solution just outside the cube means outside, as FfdMap says).
          std::optional<Vec3> s;
          bool outside = false;
          if (last) {
            if (auto t = lattice.newton(p, *last)) {
              if (insideUnitCube(*t)) {
                s = Vec3{std::clamp((*t)[0], 0.0, 1.0), std::clamp((*t)[1], 0.0, 1.0),
                         std::clamp((*t)[2], 0.0, 1.0)};
              } else {
                outside = nearUnitCube(*t);
              }
            }
          }
          if (!s && !outside) s = map.inverse(p, &near);
          if (s) {
            last = s;
            q = lattice.restPoint(*s);
            moved = true;
          } else if (boxHolds(rest, p)) {
            continue;  // space the lattice moved away from: nothing there now
          }
          ValueT value;
          if (!sampleAt(acc, xf, q, o.interpolation, &value)) continue;
          if constexpr (kIsVector<ValueT>) {
            if (moved && transforms) {
              Mat3 j, a;  // dy/dx = J diag(1 / rest size)
              lattice.forward(*s, &j);
              for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c) a[r][c] = j[r][c] / (rest.hi[c] - rest.lo[c]);
              value = transformed(value, a, rule, lattice);
            }
          }
          v.setValue(value);
          v.setValueOn(true);
        }
        if (leaf->onVoxelCount() > 0) leaves[l] = leaf.release();
      }
    });
    share.step(0.9 * double(end) / double(origins.size()));
  }
  for (LeafT* leaf : leaves)
    if (leaf) out->tree().addLeaf(leaf);
  return out;
}

// Seed 002's forward map: each active voxel written at the voxel nearest its image (the last
// one written wins). Stretched, some destinations receive no voxel: the gaps.
template <class GridT>
typename GridT::Ptr forwardSplat(const GridT& src, const FfdLattice& lattice,
                                 const Progress& share) {
  typename GridT::Ptr out = src.copyWithNewTree();
  auto acc = out->getAccessor();
  const openvdb::math::Transform& xf = src.transform();
  for (auto v = src.tree().cbeginValueOn(); v; ++v) {
    if (!v.isVoxelValue()) continue;
    const Vec3 y = lattice.deform(toVec(xf.indexToWorld(v.getCoord())));
    const Vec3d i = xf.worldToIndex(toVdb(y));
    acc.setValueOn(Coord(int(std::lround(i[0])), int(std::lround(i[1])), int(std::lround(i[2]))),
                   *v);
  }
  share.step(0.9);
  return out;
}

template <class GridT>
openvdb::GridBase::Ptr deformTyped(const GridT& src, const FfdMap& map, const GridFfdOptions& o,
                                   const Progress& share) {
  typename GridT::Ptr out = o.method == GridFfdOptions::Method::Backward
                                ? backward(src, map, o, share)
                                : forwardSplat(src, map.lattice(), share);
  if constexpr (std::is_floating_point<typename GridT::ValueType>::value) {
    if (src.getGridClass() == openvdb::GRID_LEVEL_SET) {
      openvdb::tools::signedFloodFill(out->tree());
      if (o.rebuildLevelSets && o.method == GridFfdOptions::Method::Backward &&
          !map.lattice().isUndeformed()) {
        const double voxel = src.voxelSize()[0];
        const float halfWidth = float(std::max(1.0, double(src.background()) / voxel));
        typename GridT::Ptr rebuilt = openvdb::tools::levelSetRebuild(*out, 0.0f, halfWidth);
        typename GridT::Ptr kept = src.copyWithNewTree();
        kept->setTree(rebuilt->treePtr());
        out = kept;
      }
    }
  }
  share.step(1.0);
  return out;
}

}  // namespace

GridSet deformGrids(const GridSet& grids, const FfdLattice& lattice, const GridFfdOptions& o) {
  initializeOpenVdb();
  if (auto fold = lattice.findFold()) throw ModelError("deform: " + fold->text());
  if (o.interpolation < 0 || o.interpolation > 2)
    throw ModelError("deform: interpolation " + std::to_string(o.interpolation) +
                     " is not one of 0 (nearest), 1 (trilinear), 2 (triquadratic)");
  const FfdMap map(lattice);
  openvdb::GridPtrVec out;
  const std::size_t n = grids.impl->grids.size();
  for (std::size_t g = 0; g < n; ++g) {
    const openvdb::GridBase& base = *grids.impl->grids[g];
    // grid g of n: [g / n, (g + 1) / n) of the bar
    const Progress share = Progress(o.progress).sub(double(g) / double(n), 1.0 / double(n));
    openvdb::GridBase::Ptr d;
    if (auto f = dynamic_cast<const openvdb::FloatGrid*>(&base))
      d = deformTyped(*f, map, o, share);
    else if (auto dd = dynamic_cast<const openvdb::DoubleGrid*>(&base))
      d = deformTyped(*dd, map, o, share);
    else if (auto i = dynamic_cast<const openvdb::Int32Grid*>(&base))
      d = deformTyped(*i, map, o, share);
    else if (auto b = dynamic_cast<const openvdb::BoolGrid*>(&base))
      d = deformTyped(*b, map, o, share);
    else if (auto vs = dynamic_cast<const openvdb::Vec3SGrid*>(&base))
      d = deformTyped(*vs, map, o, share);
    else if (auto vd = dynamic_cast<const openvdb::Vec3DGrid*>(&base))
      d = deformTyped(*vd, map, o, share);
    else
      throw ModelError("deform: grid '" + base.getName() + "' holds " + base.valueType() +
                       " values; allowed: float, double, int32, bool, vec3s, vec3d");
    out.push_back(d);
  }
  GridSet set = gridSetOf(std::move(out));
  set.impl->fileMetadata = grids.impl->fileMetadata;
  return set;
}

}  // namespace frep
