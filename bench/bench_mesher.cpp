// Meshing speed and memory of the reference models (make bench). Peak memory is the process's
// resident high-water mark over each benchmark (reset before it through /proc/self/clear_refs).
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <fstream>
#include <string>

#include "base/process_memory.h"
#include "check/mesh_check.h"
#include "frep/model_json.h"
#include "mesh/mesher.h"
#include "simplify/simplify.h"
#include "simplify/straighten_creases.h"

namespace {

long residentPeakKiB() {
  std::ifstream in("/proc/self/status");
  std::string key;
  long value = 0;
  while (in >> key) {
    if (key == "VmHWM:") {
      in >> value;
      return value;
    }
    in.ignore(1 << 16, '\n');
  }
  return 0;
}

void resetResidentPeak() {
  std::ofstream("/proc/self/clear_refs") << "5";
}

void meshModel(benchmark::State& state, const std::string& name) {
  const frep::Model model =
      frep::loadModel(std::string(FREP_SOURCE_DIR) + "/examples/" + name + ".json");
  const frep::Program program = frep::compile(model.root);
  frep::MeshingOptions options;
  options.bbox = *model.bbox;
  options.resolution = 1.0 / static_cast<double>(state.range(0));
  resetResidentPeak();
  const long before = residentPeakKiB();
  std::size_t triangles = 0;
  for (auto _ : state) {
    const frep::TriangleMesh mesh = frep::polygonize(program, options);
    triangles = mesh.triangleCount();
    benchmark::DoNotOptimize(mesh.triangles.data());
  }
  const long peak = residentPeakKiB();
  state.counters["triangles"] = static_cast<double>(triangles);
  state.counters["peak_MiB"] = static_cast<double>(peak) / 1024.0;
  state.counters["added_MiB"] = static_cast<double>(peak - before) / 1024.0;
  state.counters["bytes_per_tri"] = triangles ? (peak - before) * 1024.0 / triangles : 0.0;
}

void BM_MeshSphere(benchmark::State& s) {
  meshModel(s, "sphere");
}
void BM_MeshCsg(benchmark::State& s) {
  meshModel(s, "csg");
}
// The reference models of the modelling set: the 20-sphere blend chain libfive did not finish
// in fifteen minutes, a lattice and a twist.
void BM_MeshHelix(benchmark::State& s) {
  meshModel(s, "helix");
}
void BM_MeshGyroid(benchmark::State& s) {
  meshModel(s, "gyroid");
}
void BM_MeshTwist(benchmark::State& s) {
  meshModel(s, "twist");
}

// The reference models at N cells across the longest side of their box (the figure the issues
// quote: "256 cells"), so models of different sizes are compared at the same grid.
// The model's program and its box at `cells` across the longest side.
std::pair<frep::Program, frep::MeshingOptions> across(const std::string& name, long cells,
                                                      bool normals) {
  const frep::Model model =
      frep::loadModel(std::string(FREP_SOURCE_DIR) + "/examples/" + name + ".json");
  frep::MeshingOptions options;
  options.bbox = *model.bbox;
  double longest = 0;
  for (int a = 0; a < 3; ++a) longest = std::max(longest, options.bbox.hi[a] - options.bbox.lo[a]);
  options.resolution = longest / static_cast<double>(cells);
  options.normals = normals;
  return {frep::compile(model.root), options};
}

// Meshes `program` once per iteration; the triangles made as a counter.
void meshRepeatedly(benchmark::State& state, const frep::Program& program,
                    const frep::MeshingOptions& options) {
  std::size_t triangles = 0;
  for (auto _ : state) {
    const frep::TriangleMesh mesh = frep::polygonize(program, options);
    triangles = mesh.triangleCount();
    benchmark::DoNotOptimize(mesh.triangles.data());
  }
  state.counters["triangles"] = static_cast<double>(triangles);
}

void meshAcross(benchmark::State& state, const std::string& name, bool normals = true) {
  const auto [program, options] = across(name, state.range(0), normals);
  meshRepeatedly(state, program, options);
}
// The simplifier on the mesher's mesh at N cells, tolerance a tenth of a cell, sharp features
// on: the seconds are the simplification's alone (the mesh is made once, outside the loop).
void simplifyAcross(benchmark::State& state, const std::string& name) {
  const auto [program, options] = across(name, state.range(0), false);
  const frep::TriangleMesh mesh = frep::polygonize(program, options);
  frep::SimplifyOptions so;
  so.bbox = options.bbox;
  so.cell = options.resolution;
  so.tolerance = 0.1 * options.resolution;
  std::size_t triangles = 0;
  for (auto _ : state) {
    const frep::TriangleMesh s = frep::simplifyMesh(mesh, program, so);
    triangles = s.triangleCount();
    benchmark::DoNotOptimize(s.triangles.data());
  }
  state.counters["triangles_in"] = static_cast<double>(mesh.triangleCount());
  state.counters["triangles"] = static_cast<double>(triangles);
  state.counters["collapses_per_s"] = benchmark::Counter(
      static_cast<double>(mesh.vertexCount()) -
          static_cast<double>(mesh.vertexCount()) * triangles / mesh.triangleCount(),
      benchmark::Counter::kIsIterationInvariantRate);
}
void BM_SimplifySphere(benchmark::State& s) {
  simplifyAcross(s, "sphere");
}
void BM_SimplifyCsg(benchmark::State& s) {
  simplifyAcross(s, "csg");
}
void BM_SimplifyHelix(benchmark::State& s) {
  simplifyAcross(s, "helix");
}

// Straightened creases (simplify/straighten_creases.h) on the mesher's mesh at N cells, the
// straightening's seconds alone (the mesh is made once): beside BM_Across* for the meshing.
void straightenAcross(benchmark::State& state, const std::string& name) {
  const auto [program, options] = across(name, state.range(0), false);
  const frep::TriangleMesh mesh = frep::polygonize(program, options);
  const frep::StraightenOptions so{options.bbox, options.resolution, {}};
  frep::SimplifyStats stats;
  for (auto _ : state) {
    const frep::TriangleMesh s = frep::straightenCreases(mesh, program, so, &stats);
    benchmark::DoNotOptimize(s.triangles.data());
  }
  state.counters["triangles_in"] = static_cast<double>(mesh.triangleCount());
  state.counters["triangles"] = static_cast<double>(stats.trianglesAfter);
  state.counters["merged"] = static_cast<double>(stats.collapses);
}
void BM_StraightenSphere(benchmark::State& s) {
  straightenAcross(s, "sphere");
}
void BM_StraightenTwist(benchmark::State& s) {
  straightenAcross(s, "twist");
}
void BM_StraightenCsg(benchmark::State& s) {
  straightenAcross(s, "csg");
}
BENCHMARK(BM_StraightenSphere)->Arg(256)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_StraightenTwist)->Arg(128)->Arg(256)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_StraightenCsg)->Arg(256)->Unit(benchmark::kMillisecond)->UseRealTime();

// The search for parts thinner than a cell (MeshingOptions::findThinParts) off and on, the
// reference models at 256 cells without normals: BM_ThinParts/csg/256/0 against .../1.
void thinParts(benchmark::State& state, const std::string& name) {
  auto [program, options] = across(name, state.range(0), false);
  options.findThinParts = state.range(1) != 0;
  meshRepeatedly(state, program, options);
}
void BM_ThinPartsCsg(benchmark::State& s) {
  thinParts(s, "csg");
}
void BM_ThinPartsHelix(benchmark::State& s) {
  thinParts(s, "helix");
}
void BM_ThinPartsGyroid(benchmark::State& s) {
  thinParts(s, "gyroid");
}
BENCHMARK(BM_ThinPartsCsg)
    ->Args({256, 0})
    ->Args({256, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_ThinPartsHelix)
    ->Args({256, 0})
    ->Args({256, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_ThinPartsGyroid)
    ->Args({256, 0})
    ->Args({256, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Local refinement (MeshSettings::refine) off, thin parts only (1),
// with the tips (2), and with the tips two levels deep (3, refinementLevels), at N cells
// without normals: BM_RefineGyroid/256/0 against .../2.
void refine(benchmark::State& state, const std::string& name) {
  auto [program, options] = across(name, state.range(0), false);
  options.settings.refine = state.range(1) >= 2   ? frep::Refinement::Tips
                            : state.range(1) >= 1 ? frep::Refinement::ThinParts
                                                  : frep::Refinement::Off;
  options.settings.refineLevels = state.range(1) == 3 ? 2 : 1;
  meshRepeatedly(state, program, options);
}
void BM_RefineTwist(benchmark::State& s) {
  refine(s, "twist");
}
void BM_RefineGyroid(benchmark::State& s) {
  refine(s, "gyroid");
}
BENCHMARK(BM_RefineTwist)
    ->Args({256, 0})
    ->Args({256, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_RefineGyroid)
    ->Args({128, 0})
    ->Args({128, 1})
    ->Args({128, 2})
    ->Args({128, 3})
    ->Args({256, 0})
    ->Args({256, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Without vertex normals: what an STL export and a workbench preview mesh.
void BM_AcrossHelixNoNormals(benchmark::State& s) {
  meshAcross(s, "helix", false);
}
void BM_AcrossCsgNoNormals(benchmark::State& s) {
  meshAcross(s, "csg", false);
}
BENCHMARK(BM_AcrossHelixNoNormals)->Arg(256)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_AcrossCsgNoNormals)->Arg(256)->Unit(benchmark::kMillisecond)->UseRealTime();
void BM_AcrossHelix(benchmark::State& s) {
  meshAcross(s, "helix");
}
void BM_AcrossCsg(benchmark::State& s) {
  meshAcross(s, "csg");
}
void BM_AcrossTwist(benchmark::State& s) {
  meshAcross(s, "twist");
}
void BM_AcrossGyroid(benchmark::State& s) {
  meshAcross(s, "gyroid");
}
BENCHMARK(BM_AcrossHelix)->Arg(256)->Unit(benchmark::kMillisecond)->UseRealTime();

// Mesher v2 beside marching tetrahedra: each reference model at 128, 256 and 512
// cells, 1 and 2 threads, without normals (as an STL export meshes): BM_Cubes/csg/256/2 and
// BM_Tetra/csg/256/2 side by side in one run.
void meshBy(benchmark::State& state, const std::string& name, frep::Extraction extraction) {
  auto [program, options] = across(name, state.range(0), false);
  options.settings.mesher = extraction;
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(state.range(1)));
  meshRepeatedly(state, program, options);
}
const bool kExtractionBenchmarks = [] {
  for (const char* model : {"sphere", "csg", "twist", "helix", "gyroid"})
    for (const auto& [label, extraction] :
         {std::pair<const char*, frep::Extraction>{"Cubes", frep::Extraction::Cubes},
          {"Tetra", frep::Extraction::Tetrahedra}})
      benchmark::RegisterBenchmark(
          (std::string("BM_") + label + "/" + model).c_str(),
          [m = std::string(model), e = extraction](benchmark::State& st) { meshBy(st, m, e); })
          ->ArgsProduct({{128, 256, 512}, {1, 2}})
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
  return true;
}();
// The check alone (the fast check) on the mesher's mesh of each reference model at N
// cells, 1 and 2 threads: BM_Check/csg/256/2. The mesh is made once, outside the loop.
void checkBy(benchmark::State& state, const std::string& name) {
  const auto [program, options] = across(name, state.range(0), false);
  const frep::TriangleMesh mesh = frep::polygonize(program, options);
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(state.range(1)));
  bool printable = false;
  for (auto _ : state) printable = frep::checkMesh(mesh).printable();
  state.counters["triangles"] = static_cast<double>(mesh.triangleCount());
  state.counters["printable"] = printable ? 1.0 : 0.0;
}
const bool kCheckBenchmarks = [] {
  for (const char* model : {"sphere", "csg", "twist", "helix", "gyroid"})
    benchmark::RegisterBenchmark((std::string("BM_Check/") + model).c_str(),
                                 [m = std::string(model)](benchmark::State& st) { checkBy(st, m); })
        ->ArgsProduct({{128, 256, 512}, {1, 2}})
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  return true;
}();
BENCHMARK(BM_AcrossCsg)->Arg(256)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_AcrossTwist)->Arg(256)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_AcrossGyroid)->Arg(256)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK(BM_MeshSphere)->Arg(64)->Arg(256)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_MeshCsg)->Arg(64)->Arg(256)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_MeshHelix)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_MeshGyroid)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_MeshTwist)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK(BM_SimplifySphere)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SimplifyCsg)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SimplifyHelix)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();

// The benchmarks take memory as the command-line tool does (base/process_memory.h), so the
// figures are the export's.
int main(int argc, char** argv) {
  frep::useLargePageHeap();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
