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
  const std::int64_t blocks = nb[0] * nb[1] * nb[2];
  const float background = static_cast<float>(o.halfWidthVoxels * h);

  std::vector<LeafT*> leaves;
  std::mutex leavesMutex;
  std::atomic<std::int64_t> done{0};
  std::atomic<bool> cancelled{false};
  tbb::parallel_for(tbb::blocked_range<std::int64_t>(0, blocks, 64), [&](const auto& range) {
    std::vector<Dual> x(512), y(512), z(512), g(512);
    std::vector<LeafT*> mine;
    for (std::int64_t b = range.begin(); b != range.end() && !cancelled; ++b) {
      const std::int64_t bi = b / (nb[1] * nb[2]), bj = (b / nb[2]) % nb[1], bk = b % nb[2];
      const openvdb::Coord origin(int(lo[0] + 8 * bi), int(lo[1] + 8 * bj), int(lo[2] + 8 * bk));
      // The block's voxel centres widened by the band (and a voxel): a voxel within the band
      // of the surface lies in a block whose widened box holds a surface point.
      const double reach = o.halfWidthVoxels + 1.0;
      Interval iv[3];
      for (int a = 0; a < 3; ++a)
        iv[a] = Interval((origin[a] - reach) * h, (origin[a] + 7 + reach) * h);
      const Interval f = field.evalInterval(iv[0], iv[1], iv[2]);
      if (!f.nan && (f.lo > 0.0 || f.hi < 0.0)) continue;
      int n = 0;
      for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j)
          for (int k = 0; k < 8; ++k, ++n) {
            x[n] = Dual((origin[0] + i) * h, 1, 0, 0);
            y[n] = Dual((origin[1] + j) * h, 0, 1, 0);
            z[n] = Dual((origin[2] + k) * h, 0, 0, 1);
          }
      field.evalGradientBatch(x.data(), y.data(), z.data(), 512, g.data());
      auto* leaf = new LeafT(origin, background, false);
      // OpenVDB's leaf order is x-major like the loop above.
      for (openvdb::Index i = 0; i < 512; ++i) {
        // The first-order distance F / |grad F|: a level set's values are distances, an FRep
        // field's only near most primitives (a gyroid's gradient is far from unit length).
        const double len = std::sqrt(g[i].d[0] * g[i].d[0] + g[i].d[1] * g[i].d[1] + g[i].d[2] * g[i].d[2]);
        const double v = len > 1e-12 ? g[i].v / len : g[i].v;
        const double s = v == v ? -v : double(background);
        const float c = static_cast<float>(std::clamp(s, -double(background), double(background)));
        leaf->setValueOnly(i, c);
        if (std::abs(c) < background) leaf->setValueOn(i);
      }
      mine.push_back(leaf);
    }
    const std::int64_t d = done += std::int64_t(range.size());
    std::lock_guard<std::mutex> lock(leavesMutex);
    leaves.insert(leaves.end(), mine.begin(), mine.end());
    // Sampling is the first 60 % of the work; the callback is called one call at a time (as
    // the mesher's), from whichever thread finished a piece.
    if (o.progress && !cancelled && !o.progress(0.6 * double(d) / double(blocks))) cancelled = true;
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
  if (o.progress && !o.progress(1.0)) throw Cancelled();
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
  const float inside = std::isfinite(o.interiorWidthVoxels)
                           ? float(o.interiorWidthVoxels)
                           : std::numeric_limits<float>::max();
  openvdb::FloatGrid::Ptr grid = openvdb::tools::meshToSignedDistanceField<openvdb::FloatGrid>(
      *xform, points, triangles, {}, float(o.halfWidthVoxels), inside);
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  grid->setName(o.name);
  return gridSetOf({grid});
}

TriangleMesh levelSetToMesh(const GridSet& grids, std::size_t index, double iso, double adaptivity) {
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
    for (int k = 0; k < 3; ++k) s += double(points[a][k] - points[b][k]) * (points[a][k] - points[b][k]);
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
