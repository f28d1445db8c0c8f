// lattice/: the three deformations, each beside what it replaces or costs.
//   BM_DeformLevelSet/m  a sphere level set 256 voxels across in a twisted 3 x 3 x 3 lattice:
//                        backward resampling through the inverse with the rebuild (m = 0), the
//                        same without the rebuild (1), seed 002's forward splat (2; gaps)
//   BM_DeformMesh        a 1.3 M-triangle icosphere's vertices through a 4 x 4 x 4 lattice
//   BM_GyroidEval/f      points per second of the gyroid model (f = 0) and of the same model
//                        in a twisted 3 x 3 x 3 lattice (f = 1), near the surface
//   BM_GyroidMesh/f      meshing both at 256 cells
#include <benchmark/benchmark.h>

#include <random>

#include "../tests/lattice_samples.h"
#include "../tests/volume_samples.h"
#include "frep/model_json.h"
#include "frep/structural_bounds.h"
#include "lattice/ffd_lattice.h"
#include "mesh/mesh_ffd.h"
#include "mesh/mesher.h"
#include "volume/grid_ffd.h"
#include "volume/level_sets.h"

namespace frep {
namespace {

const Box3 kUnit{{-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2}};

FfdLattice twisted(int n, const Box3& rest = kUnit) {
  return testing::twistedLattice(n, n, n, 1.2, 0.1, 7, rest);
}

const GridSet& sphereLevelSet() {
  static const GridSet g = [] {
    LevelSetOptions o;
    o.voxel = 2.4 / 256;
    return sampleLevelSet(compile(testing::sphereNode(1.0)), kUnit, o);
  }();
  return g;
}

void BM_DeformLevelSet(benchmark::State& state) {
  const FfdLattice lattice = twisted(3);
  GridFfdOptions o;
  o.rebuildLevelSets = state.range(0) == 0;
  if (state.range(0) == 2) o.method = GridFfdOptions::Method::ForwardSplat;
  std::uint64_t voxels = 0;
  for (auto _ : state) {
    const GridSet out = deformGrids(sphereLevelSet(), lattice, o);
    voxels = out.info(0).activeVoxels;
  }
  state.counters["source_voxels"] = double(sphereLevelSet().info(0).activeVoxels);
  state.counters["voxels"] = double(voxels);
}

void BM_DeformMesh(benchmark::State& state) {
  static const TriangleMesh mesh = testing::icosphere(1.0, 8);  // 1,310,720 triangles
  const FfdLattice lattice = twisted(4);
  for (auto _ : state) benchmark::DoNotOptimize(deformMesh(mesh, lattice));
  state.counters["triangles"] = double(mesh.triangles.size());
}

// The gyroid reference model, alone (0) or in a twisted lattice around its box (1).
const NodePtr& gyroid(int deformed) {
  static const NodePtr plain =
      loadModel(std::string(FREP_SOURCE_DIR) + "/examples/gyroid.json").root;
  static const NodePtr bent = makeNode("ffd", testing::ffdParams(twisted(3)), {plain}, "bench");
  return deformed ? bent : plain;
}

void BM_GyroidEval(benchmark::State& state) {
  const Program p = compile(gyroid(int(state.range(0))));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const std::size_t n = 100000;
  std::vector<double> x(n), y(n), z(n), out(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = u(rng), y[i] = u(rng), z[i] = u(rng);
  for (auto _ : state) p.evalBatch(x.data(), y.data(), z.data(), n, out.data());
  state.counters["points/s"] =
      benchmark::Counter(double(n), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_GyroidMesh(benchmark::State& state) {
  const NodePtr& root = gyroid(int(state.range(0)));
  const Program p = compile(root);
  MeshingOptions o;
  const Box3 known = structuralBounds(root);
  o.bbox = {{std::max(known.lo[0], -1.2), std::max(known.lo[1], -1.2), std::max(known.lo[2], -1.2)},
            {std::min(known.hi[0], 1.6), std::min(known.hi[1], 1.6), std::min(known.hi[2], 1.6)}};
  o.resolution = 2.4 / 256;
  std::size_t triangles = 0;
  for (auto _ : state) triangles = polygonize(p, o).triangles.size();
  state.counters["triangles"] = double(triangles);
}

BENCHMARK(BM_DeformLevelSet)
    ->Arg(0)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);
BENCHMARK(BM_DeformMesh)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
BENCHMARK(BM_GyroidEval)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_GyroidMesh)
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

}  // namespace
}  // namespace frep
