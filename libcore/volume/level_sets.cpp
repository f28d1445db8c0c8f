// Field -> level set, mesh -> level set, level set -> mesh, through OpenVDB's tools/.
#include "volume/level_sets.h"

#include <openvdb/tools/LevelSetRebuild.h>
#include <openvdb/tools/LevelSetTracker.h>
#include <openvdb/tools/LevelSetUtil.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>

#include "base/errors.h"
#include "base/progress.h"
#include "base/triangle_geometry.h"
#include "check/mesh_check.h"
#include "volume/openvdb_grids.h"

namespace frep {

namespace {

using LeafT = openvdb::FloatTree::LeafNodeType;

void requireVoxel(double voxel) {
  if (!(voxel > 0.0) || !std::isfinite(voxel))
    throw ModelError("level set: voxel size " + std::to_string(voxel) +
                     " is not allowed; allowed: a finite length > 0");
}

// Index coordinates must stay well inside OpenVDB's 32-bit range.
constexpr double kMaxIndex = 1 << 29;

// |grad F| at voxel i of a block's 8^3 values (x-major), by central differences inside the
// block and one-sided ones on its faces.
double differenceSlope(const std::vector<double>& v, int i, double h) {
  const int c[3] = {i >> 6, (i >> 3) & 7, i & 7};
  const int stride[3] = {64, 8, 1};
  double g2 = 0;
  for (int a = 0; a < 3; ++a) {
    const int lo = c[a] > 0 ? i - stride[a] : i, hi = c[a] < 7 ? i + stride[a] : i;
    const double d = (v[hi] - v[lo]) / (double(hi - lo) / stride[a] * h);
    g2 += d * d;
  }
  return std::sqrt(g2);
}

}  // namespace

GridSet sampleLevelSet(const Field& field, const Box3& box, const LevelSetOptions& o) {
  initializeOpenVdb();
  requireVoxel(o.voxel);
  const double h = o.voxel;
  std::int64_t lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(box.lo[a]) || !std::isfinite(box.hi[a]) || box.hi[a] < box.lo[a])
      throw ModelError("level set: the box must be finite and not empty");
    const double l = std::floor(box.lo[a] / h) - 1, u = std::ceil(box.hi[a] / h) + 1;
    if (std::abs(l) > kMaxIndex || std::abs(u) > kMaxIndex)
      throw ModelError("level set: the box holds too many voxels of size " + std::to_string(h) +
                       " (at most 2^29 from the origin along an axis); use larger voxels");
    // Whole leaves of 8 voxels.
    lo[a] = static_cast<std::int64_t>(std::floor(l / 8.0)) * 8;
    hi[a] = static_cast<std::int64_t>(std::floor(u / 8.0)) * 8 + 7;
  }
  const std::int64_t nb[3] = {(hi[0] - lo[0] + 1) / 8, (hi[1] - lo[1] + 1) / 8,
                              (hi[2] - lo[2] + 1) / 8};
  // Regions of kRegion^3 blocks: one interval test and one specialisation of the field per
  // region (region specialisation, as the mesher's bricks), then one test per block inside.
  constexpr std::int64_t kRegion = 4;
  const std::int64_t nr[3] = {(nb[0] + kRegion - 1) / kRegion, (nb[1] + kRegion - 1) / kRegion,
                              (nb[2] + kRegion - 1) / kRegion};
  const std::int64_t regions = nr[0] * nr[1] * nr[2];
  const float background = static_cast<float>(o.halfWidthVoxels * h);
  // A voxel within the band of the surface lies in a block whose box, widened by the band
  // (and a voxel), holds a surface point: the test on the widened box keeps every such block.
  const double reach = o.halfWidthVoxels + 1.0;
  auto widened = [&](const std::int64_t from[3], std::int64_t voxels, Interval iv[3]) {
    for (int a = 0; a < 3; ++a)
      iv[a] = Interval((double(from[a]) - reach) * h, (double(from[a] + voxels - 1) + reach) * h);
  };
  auto mayCross = [](const Interval& f) { return f.nan || (f.lo <= 0.0 && f.hi >= 0.0); };

  std::vector<LeafT*> leaves;
  std::mutex leavesMutex;
  std::atomic<std::int64_t> done{0};
  std::atomic<bool> cancelled{false};
  // Sampling is the first 60 % of the bar; the callback is called one call at a time (as
  // the mesher's), from whichever thread finished a piece.
  const Progress bar(o.progress);
  const Progress sampling = bar.sub(0.0, 0.6);
  tbb::parallel_for(tbb::blocked_range<std::int64_t>(0, regions, 1), [&](const auto& range) {
    std::vector<Dual> x(512), y(512), z(512), g(512);
    std::vector<double> vx(512), vy(512), vz(512), v(512);
    std::vector<int> near(512);
    std::vector<LeafT*> mine;
    for (std::int64_t r = range.begin(); r != range.end() && !cancelled; ++r) {
      const std::int64_t ri = r / (nr[1] * nr[2]), rj = (r / nr[2]) % nr[1], rk = r % nr[2];
      const std::int64_t rorigin[3] = {lo[0] + 8 * kRegion * ri, lo[1] + 8 * kRegion * rj,
                                       lo[2] + 8 * kRegion * rk};
      Interval riv[3];
      widened(rorigin, 8 * kRegion, riv);
      if (!mayCross(field.evalInterval(riv[0], riv[1], riv[2]))) continue;
      std::shared_ptr<const Field> holder;
      const Field& f = specialiseInto(
          field, Box3{{riv[0].lo, riv[1].lo, riv[2].lo}, {riv[0].hi, riv[1].hi, riv[2].hi}},
          holder);
      for (std::int64_t bi = kRegion * ri; bi < std::min(nb[0], kRegion * (ri + 1)); ++bi)
        for (std::int64_t bj = kRegion * rj; bj < std::min(nb[1], kRegion * (rj + 1)); ++bj)
          for (std::int64_t bk = kRegion * rk; bk < std::min(nb[2], kRegion * (rk + 1)); ++bk) {
            const std::int64_t borigin[3] = {lo[0] + 8 * bi, lo[1] + 8 * bj, lo[2] + 8 * bk};
            Interval iv[3];
            widened(borigin, 8, iv);
            if (!mayCross(f.evalInterval(iv[0], iv[1], iv[2]))) continue;
            const openvdb::Coord origin{static_cast<int>(borigin[0]), static_cast<int>(borigin[1]),
                                        static_cast<int>(borigin[2])};
            int n = 0;
            for (int i = 0; i < 8; ++i)
              for (int j = 0; j < 8; ++j)
                for (int k = 0; k < 8; ++k, ++n) {
                  vx[n] = (origin[0] + i) * h;
                  vy[n] = (origin[1] + j) * h;
                  vz[n] = (origin[2] + k) * h;
                }
            f.evalBatch(vx.data(), vy.data(), vz.data(), 512, v.data());
            if (o.firstOrder) {
              // The first-order distance F / |grad F| where |F| is within the band (a level
              // set's values are distances, an FRep field's only near most primitives: a
              // gyroid's gradient is far from unit length); beyond it the value clamps anyway,
              // and its gradient is not computed.
              // Which voxels: those whose distance, estimated with the finite-difference
              // gradient of the block's own values, may lie within twice the band (a steep
              // field's values exceed the band's width right next to its surface).
              int m = 0;
              for (int i = 0; i < 512; ++i)
                if (std::abs(v[i]) < background ||
                    std::abs(v[i]) < 2.0 * background * differenceSlope(v, i, h)) {
                  near[m] = i;
                  x[m] = Dual(vx[i], 1, 0, 0);
                  y[m] = Dual(vy[i], 0, 1, 0);
                  z[m] = Dual(vz[i], 0, 0, 1);
                  ++m;
                }
              f.evalGradientBatch(x.data(), y.data(), z.data(), std::size_t(m), g.data());
              for (int q = 0; q < m; ++q) {
                const double len = std::sqrt(g[q].d[0] * g[q].d[0] + g[q].d[1] * g[q].d[1] +
                                             g[q].d[2] * g[q].d[2]);
                if (len > 1e-12) v[near[q]] = g[q].v / len;
              }
            }
            auto* leaf = new LeafT(origin, background, false);
            // OpenVDB's leaf order is x-major like the loop above.
            for (openvdb::Index i = 0; i < 512; ++i) {
              const double sv = v[i] == v[i] ? -v[i] : double(background);
              const float c =
                  static_cast<float>(std::clamp(sv, -double(background), double(background)));
              leaf->setValueOnly(i, c);
              if (std::abs(c) < background) leaf->setValueOn(i);
            }
            mine.push_back(leaf);
          }
    }
    const std::int64_t d = done += std::int64_t(range.size());
    std::lock_guard<std::mutex> lock(leavesMutex);
    leaves.insert(leaves.end(), mine.begin(), mine.end());
    mine.clear();
    if (!cancelled && !sampling.count(std::size_t(d), std::size_t(regions))) cancelled = true;
  });
  if (cancelled) {
    for (LeafT* l : leaves) delete l;
    throw Cancelled();
  }

  openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(background);
  grid->setTransform(openvdb::math::Transform::createLinearTransform(h));
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  grid->setName(o.name);
  for (LeafT* l : leaves) grid->tree().addLeaf(l);  // the tree owns them now
  // Inside and outside of the blocks that were not sampled, from the signs of those that were.
  openvdb::tools::signedFloodFill(grid->tree());
  if (!grid->tree().empty()) {
    if (o.redistance == Redistance::Rebuild) {
      grid = openvdb::tools::levelSetRebuild(*grid, 0.0f, float(o.halfWidthVoxels));
    } else if (o.redistance == Redistance::Normalize) {
      openvdb::tools::LevelSetTracker<openvdb::FloatGrid> tracker(*grid);
      tracker.normalize();
    }
  }
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  grid->setName(o.name);
  if (o.fog) openvdb::tools::sdfToFogVolume(*grid);
  bar.step(1.0);
  return gridSetOf({grid});
}

GridSet meshToLevelSet(const TriangleMesh& mesh, const LevelSetOptions& o,
                       const std::string& where) {
  initializeOpenVdb();
  requireVoxel(o.voxel);
  // Flood fill decides the sign, so the mesh must be closed; everything else (winding,
  // self-intersections) meshToLevelSet resolves.
  const CheckReport r = checkMesh(mesh, nullptr, 1);
  if (r.faces == 0) throw FileError(where + ": the mesh has no triangles");
  if (r.borderEdges)
    throw FileError(where + ": the mesh is open (" + std::to_string(r.borderEdges) +
                    " border edges), so it has no inside; close its holes first (frepcad "
                    "check lists them)");
  std::vector<openvdb::Vec3s> points(mesh.positions.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    points[i] = openvdb::Vec3s(mesh.positions[i][0], mesh.positions[i][1], mesh.positions[i][2]);
  std::vector<openvdb::Vec3I> triangles(mesh.triangles.size());
  for (std::size_t i = 0; i < triangles.size(); ++i)
    triangles[i] = openvdb::Vec3I(mesh.triangles[i][0], mesh.triangles[i][1], mesh.triangles[i][2]);
  const openvdb::math::Transform::Ptr xform =
      openvdb::math::Transform::createLinearTransform(o.voxel);
  const float inside = std::isfinite(o.interiorWidthVoxels) ? float(o.interiorWidthVoxels)
                                                            : std::numeric_limits<float>::max();
  openvdb::FloatGrid::Ptr grid = openvdb::tools::meshToSignedDistanceField<openvdb::FloatGrid>(
      *xform, points, triangles, {}, float(o.halfWidthVoxels), inside);
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  grid->setName(o.name);
  return gridSetOf({grid});
}

TriangleMesh levelSetToMesh(const GridSet& grids, std::size_t index, double iso,
                            double adaptivity) {
  initializeOpenVdb();
  const openvdb::GridBase::Ptr& g = grids.impl->grids.at(index);
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
  std::vector<openvdb::Vec4I> quads;
  if (auto f = openvdb::gridPtrCast<openvdb::FloatGrid>(g))
    openvdb::tools::volumeToMesh(*f, points, triangles, quads, iso, adaptivity);
  else if (auto d = openvdb::gridPtrCast<openvdb::DoubleGrid>(g))
    openvdb::tools::volumeToMesh(*d, points, triangles, quads, iso, adaptivity);
  else
    throw ModelError("grid '" + g->getName() + "' holds " + g->valueType() +
                     " values; only float and double grids have an isosurface");
  TriangleMesh m;
  m.positions.reserve(points.size());
  for (const auto& p : points) m.positions.push_back({p[0], p[1], p[2]});
  for (const auto& t : triangles) m.triangles.push_back({t[0], t[1], t[2]});
  auto d2 = [&](std::uint32_t a, std::uint32_t b) {
    double s = 0;
    for (int k = 0; k < 3; ++k)
      s += double(points[a][k] - points[b][k]) * (points[a][k] - points[b][k]);
    return s;
  };
  for (const auto& q : quads) {
    if (d2(q[0], q[2]) <= d2(q[1], q[3])) {
      m.triangles.push_back({q[0], q[1], q[2]});
      m.triangles.push_back({q[0], q[2], q[3]});
    } else {
      m.triangles.push_back({q[0], q[1], q[3]});
      m.triangles.push_back({q[1], q[2], q[3]});
    }
  }
  // OpenVDB's winding depends on the grid class's sign convention: face outward.
  if (meshVolume(m) < 0)
    for (Triangle& t : m.triangles) std::swap(t[1], t[2]);
  return m;
}

}  // namespace frep
