// Speed of the modelling nodes that promise it (make bench): the instancer with 10,000 copies
// (evaluation through the k-d tree, and meshing) and a formula against the built-in node it
// spells out (a formula is compiled, not interpreted).
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "frep/tree.h"
#include "mesh/mesher.h"

namespace {

using frep::NodePtr;

NodePtr sphere(double r) {
  return frep::makeNode("sphere", {{"radius", frep::realValue(r)}}, {});
}

// 10,000 spheres of radius 0.3 on a jittered 100 x 100 plate, 0.5 apart (overlapping).
NodePtr plate() {
  std::mt19937 g(11);
  std::uniform_real_distribution<double> jitter(-0.04, 0.04);
  frep::ParamValue at;
  for (int i = 0; i < 100; ++i)
    for (int j = 0; j < 100; ++j)
      for (double c : {0.5 * i + jitter(g), 0.5 * j + jitter(g), jitter(g)})
        at.numbers.push_back(c);
  return frep::makeNode("instancer", {{"positions", at}}, {sphere(0.3)});
}

// Batch evaluation of a million points in the part's box.
void evaluate(benchmark::State& state, const frep::Program& p, double lo, double hi, double zr) {
  const std::size_t n = 1 << 20;
  std::mt19937 g(3);
  std::uniform_real_distribution<double> u(lo, hi), w(-zr, zr);
  std::vector<double> x(n), y(n), z(n), out(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = u(g);
    y[i] = u(g);
    z[i] = w(g);
  }
  for (auto _ : state) {
    p.evalBatch(x.data(), y.data(), z.data(), n, out.data());
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["points_per_s"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_InstancerEval10k(benchmark::State& state) {
  evaluate(state, frep::compile(plate()), -1, 51, 0.6);
}

void BM_InstancerMesh10k(benchmark::State& state) {
  const frep::Program p = frep::compile(plate());
  frep::MeshingOptions o;
  o.bbox = {{-0.5, -0.5, -0.5}, {50.5, 50.5, 0.5}};
  o.resolution = 1.0 / static_cast<double>(state.range(0));
  std::size_t triangles = 0;
  for (auto _ : state) triangles = frep::polygonize(p, o).triangleCount();
  state.counters["triangles"] = static_cast<double>(triangles);
}

// The gyroid shell of examples/gyroid.json as a formula and as the built-in node.
void BM_FormulaGyroidEval(benchmark::State& state) {
  const NodePtr f =
      frep::makeNode("formula",
                     {{"formula", frep::textValue("t - abs(sin(k*x)*cos(k*y) + sin(k*y)*cos(k*z) + "
                                                  "sin(k*z)*cos(k*x))")},
                      {"parameters", frep::textValue("k = 6*pi, t = 0.3")}},
                     {});
  evaluate(state, frep::compile(f), -1.2, 1.2, 1.2);
}

void BM_SphereNodeEval(benchmark::State& state) {
  evaluate(state, frep::compile(sphere(1)), -1.2, 1.2, 1.2);
}
void BM_SphereFormulaEval(benchmark::State& state) {
  const NodePtr f = frep::makeNode("formula",
                                   {{"formula", frep::textValue("r - sqrt(x^2 + y^2 + z^2)")},
                                    {"parameters", frep::textValue("r = 1")}},
                                   {});
  evaluate(state, frep::compile(f), -1.2, 1.2, 1.2);
}

}  // namespace

BENCHMARK(BM_InstancerEval10k)->Unit(benchmark::kMillisecond)->UseRealTime();
// The same plate at 256 cells across its 51-unit box (cell 0.2).
void BM_InstancerAcross(benchmark::State& state) {
  const frep::Program p = frep::compile(plate());
  frep::MeshingOptions o;
  o.normals = state.range(1) != 0;
  o.bbox = {{-0.5, -0.5, -0.5}, {50.5, 50.5, 0.5}};
  o.resolution = 51.0 / static_cast<double>(state.range(0));
  std::size_t triangles = 0;
  for (auto _ : state) triangles = frep::polygonize(p, o).triangleCount();
  state.counters["triangles"] = static_cast<double>(triangles);
}
BENCHMARK(BM_InstancerAcross)->Args({256, 1})->Args({256, 0})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_InstancerMesh10k)->Arg(10)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SphereNodeEval)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SphereFormulaEval)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_FormulaGyroidEval)->Unit(benchmark::kMillisecond)->UseRealTime();
