// volume/: each FRepCAD route beside the plain OpenVDB way of doing the same.
//   BM_MeshToField*      a 1.3 M-triangle closed mesh (an icosphere) to a field: the exact
//                        distance (check + CGAL AABB tree) vs OpenVDB's meshToLevelSet at
//                        1/256 of its size
//   BM_FieldToLevelSet*  the csg and helix models to 256^3 level sets: interval-pruned leaves
//                        (and, x/1, OpenVDB's LevelSetTracker::normalize after) vs every voxel
//                        evaluated into a tools::Dense grid and copied to a sparse one (what
//                        OpenVDB offers for a function)
//   BM_*Eval             points per second within a tenth of the radius of a sphere's surface
//                        (where a mesher asks): our grid field vs OpenVDB's GridSampler
//                        (BoxSampler), and the exact mesh distance
#include <benchmark/benchmark.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/LevelSetRebuild.h>
#include <openvdb/tools/MeshToVolume.h>

#include <tbb/parallel_for.h>

#include <random>

#include "frep/model_json.h"
#include "frep/structural_bounds.h"
#include "pipeline/export_pipeline.h"
#include "volume/field_sources.h"
#include "volume/grid_field.h"
#include "volume/level_sets.h"
#include "volume/openvdb_grids.h"
#include "dense_route.h"
#include "../tests/volume_samples.h"

namespace frep {
namespace {

const TriangleMesh& bigMesh() {
  static const TriangleMesh m = testing::icosphere(1.0, 8);  // 1,310,720 triangles
  return m;
}

void BM_MeshToFieldExact(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(meshField(bigMesh(), MeshFieldMethod::Exact, 0, "ico"));
  state.counters["triangles"] = double(bigMesh().triangles.size());
}

void BM_MeshToFieldOpenVdb(benchmark::State& state) {
  initializeOpenVdb();
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> tris;
  for (const auto& p : bigMesh().positions) points.emplace_back(p[0], p[1], p[2]);
  for (const auto& t : bigMesh().triangles) tris.emplace_back(t[0], t[1], t[2]);
  const auto xform = openvdb::math::Transform::createLinearTransform(2.0 / 256);
  for (auto _ : state)
    benchmark::DoNotOptimize(openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*xform, points, tris, 3.0f));
}

// The reference models with their boxes (the helix's automatic, as an export chooses it).
struct ModelCase {
  Program program;
  Box3 box;
};
const ModelCase& model(int which) {
  static const ModelCase cases[2] = {
      [] {
        const Model m = loadModel(std::string(FREP_SOURCE_DIR) + "/examples/csg.json");
        return ModelCase{compile(m.root), *m.bbox};
      }(),
      [] {
        const Model m = loadModel(std::string(FREP_SOURCE_DIR) + "/examples/helix.json");
        Program p = compile(m.root);
        BoxRequest r;
        r.cells = 256;
        const Box3 box = chooseBox(p, structuralBounds(m.root), r).box;
        return ModelCase{std::move(p), box};
      }()};
  return cases[which];
}

double voxelOf(const Box3& b) {
  return std::max({b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]}) / 256;
}

// range(0): the model (0 csg, 1 helix); range(1): 0 first-order distances (the default), 1
// the same normalized after (LevelSetTracker), 2 values only (-F, like the dense route).
void BM_FieldToLevelSetPruned(benchmark::State& state) {
  const ModelCase& m = model(int(state.range(0)));
  LevelSetOptions o;
  o.voxel = voxelOf(m.box);
  o.redistance = state.range(1) == 1 ? Redistance::Normalize : Redistance::None;
  o.firstOrder = state.range(1) != 2;
  for (auto _ : state) benchmark::DoNotOptimize(sampleLevelSet(m.program, m.box, o));
}

void BM_FieldToLevelSetDense(benchmark::State& state) {
  initializeOpenVdb();
  const ModelCase& m = model(int(state.range(0)));
  const double h = voxelOf(m.box);
  const openvdb::Coord lo(int(std::floor(m.box.lo[0] / h)), int(std::floor(m.box.lo[1] / h)),
                          int(std::floor(m.box.lo[2] / h)));
  const openvdb::Coord hi(int(std::ceil(m.box.hi[0] / h)), int(std::ceil(m.box.hi[1] / h)),
                          int(std::ceil(m.box.hi[2] / h)));
  for (auto _ : state) {
    auto grid = bench::denseLevelSet(m.program, lo, hi, h);
    benchmark::DoNotOptimize(grid);
  }
}

struct Points {
  std::vector<double> x, y, z;
  explicit Points(std::size_t n, double r) : x(n), y(n), z(n) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-r, r);
    for (std::size_t i = 0; i < n; ++i) x[i] = u(rng), y[i] = u(rng), z[i] = u(rng);
  }
};

// Points where a mesher asks: within a tenth of the radius of the surface (deep inside a
// sphere every triangle is nearly as far as the nearest, the AABB tree's worst case).
struct NearSurface : Points {
  NearSurface(std::size_t n) : Points(n, 1.0) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> r(0.9, 1.1);
    for (std::size_t i = 0; i < n; ++i) {
      const double len = std::sqrt(x[i] * x[i] + y[i] * y[i] + z[i] * z[i]), s = r(rng) / len;
      x[i] *= s, y[i] *= s, z[i] *= s;
    }
  }
};

const GridSet& sphereGrid() {
  static const GridSet g = [] {
    LevelSetOptions o;
    o.voxel = 2.4 / 256;
    return sampleLevelSet(compile(testing::sphereNode(1.0)), Box3{{-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2}}, o);
  }();
  return g;
}

void BM_GridFieldEval(benchmark::State& state) {
  const auto f = gridField(sphereGrid(), 0, GridFieldOptions{}, "sphere");
  const NearSurface p(1 << 16);
  std::vector<double> out(p.x.size());
  for (auto _ : state) f->evalBatch(p.x.data(), p.y.data(), p.z.data(), p.x.size(), out.data());
  state.SetItemsProcessed(state.iterations() * std::int64_t(p.x.size()));
}

void BM_OpenVdbSamplerEval(benchmark::State& state) {
  const auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(sphereGrid().impl->grids[0]);
  const NearSurface p(1 << 16);
  std::vector<double> out(p.x.size());
  for (auto _ : state) {
    auto acc = grid->getConstAccessor();
    openvdb::tools::GridSampler<openvdb::FloatGrid::ConstAccessor, openvdb::tools::BoxSampler> s(acc, grid->transform());
    for (std::size_t i = 0; i < p.x.size(); ++i) out[i] = -s.wsSample(openvdb::Vec3d(p.x[i], p.y[i], p.z[i]));
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(state.iterations() * std::int64_t(p.x.size()));
}

void BM_MeshDistanceEval(benchmark::State& state) {
  static const auto f = meshField(testing::icosphere(1.0, int(state.range(0))), MeshFieldMethod::Exact, 0, "ico");
  const NearSurface p(1 << 14);
  f->eval(0.0, 0.0, 1.0);  // CGAL builds its k-d tree on the first query
  std::vector<double> out(p.x.size());
  for (auto _ : state) f->evalBatch(p.x.data(), p.y.data(), p.z.data(), p.x.size(), out.data());
  state.SetItemsProcessed(state.iterations() * std::int64_t(p.x.size()));
  state.counters["triangles"] = 20.0 * std::pow(4.0, double(state.range(0)));
}

BENCHMARK(BM_MeshToFieldExact)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
BENCHMARK(BM_MeshToFieldOpenVdb)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
BENCHMARK(BM_FieldToLevelSetPruned)->Args({0, 0})->Args({0, 1})->Args({0, 2})->Args({1, 0})->Args({1, 2})
    ->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_FieldToLevelSetDense)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
BENCHMARK(BM_GridFieldEval)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_OpenVdbSamplerEval)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_MeshDistanceEval)->Arg(8)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace frep
