// Strut lattices beside the TPMS lattice they join (frep/node_types_struts.cpp):
//   BM_LatticeEval/k/g  points per second of a lattice node filling a box of 50 x 50 x 50
//                       cells, values (g = 0) or values and gradients (g = 1): k = 0 the
//                       gyroid sheet (the baseline), 1.. the strut lattices' unit cells in
//                       the node's order (simple cubic, BCC, FCC, octet, Kelvin, diamond),
//                       7 the Voronoi foam (seeds in cells of 1, the default period of 5).
//                       Counter `bytes`: the field's program (instructions and constants)
//                       and, for the foam, its network's bins: the field's whole memory, the
//                       same for any number of cells.
//   BM_BentLatticeEval/s/g  the same for octet cells of 1 in a beam of 20 x 4 x 4 cells bent
//                       along a parabola by an ffd node (4 x 1 x 1 divisions, the middle 5
//                       up), at points of the bent beam: s = 0 the struts curved with their
//                       cells (each point pulled back through the lattice's inverse), 1 kept
//                       straight between their ends' images (the struts binned in the world).
//                       Counter `bytes`: the straight struts' bins.
//   BM_ConformalLatticeEval/s/g  octet cells of 2 round an axis, 28 a turn (struts 0.3), at
//                       points of a pipe of radii 7 and 10, 20 long: s = 0 the struts curved
//                       round the axis, 1 straight (chords, each layer's made on first use:
//                       the first iteration makes them).
#include <benchmark/benchmark.h>

#include <cmath>
#include <functional>
#include <random>

#include "frep/ffd_field.h"
#include "frep/field_sources.h"
#include "frep/node_helpers.h"
#include "frep/periodic_segments.h"
#include "frep/straight_struts.h"
#include "frep/strut_cells.h"
#include "frep/tree.h"
#include "lattice/ffd_lattice.h"
#include "volume/field_sources.h"

namespace frep {
namespace {

NodePtr latticeNode(int k) {
  if (k == 0)
    return makeNode("gyroid",
                    {{"cell", realValue(1.0)},
                     {"level", realValue(0.3)},
                     {"kind", textValue("sheet")},
                     {"origin", vec3Value({0, 0, 0})}},
                    {});
  if (k == 7) {
    registerVolumeSources();
    return makeNode("voronoi_foam", {{"cell", vec3Value({1, 1, 1})}, {"radius", realValue(0.08)}},
                    {});
  }
  return makeNode("strut_lattice",
                  {{"cell_type", textValue(unitCells().at(std::size_t(k - 1)).id)},
                   {"cell", vec3Value({1, 1, 1})},
                   {"radius", realValue(0.1)}},
                  {});
}

// Times the program over 100,000 points from `point`, values or values and gradients in
// one batch per iteration, and reports the points a second.
void timeBatch(benchmark::State& state, const Program& p, const std::function<Vec3()>& point,
               bool gradient) {
  const std::size_t n = 100000;
  std::vector<double> x(n), y(n), z(n), out(n);
  std::vector<Dual> dx(n), dy(n), dz(n), dout(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 q = point();
    x[i] = q[0], y[i] = q[1], z[i] = q[2];
    dx[i] = Dual(x[i], 1, 0, 0), dy[i] = Dual(y[i], 0, 1, 0), dz[i] = Dual(z[i], 0, 0, 1);
  }
  for (auto _ : state) {
    if (gradient)
      p.evalGradientBatch(dx.data(), dy.data(), dz.data(), n, dout.data());
    else
      p.evalBatch(x.data(), y.data(), z.data(), n, out.data());
  }
  state.counters["points/s"] =
      benchmark::Counter(double(n), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_LatticeEval(benchmark::State& state) {
  const int k = int(state.range(0));
  const bool gradient = state.range(1) != 0;
  const NodePtr node = latticeNode(k);
  const Program p = compile(node);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 50.0);  // 50 cells a side
  timeBatch(
      state, p,
      [&] {
        return Vec3{u(rng), u(rng), u(rng)};
      },
      gradient);
  state.SetLabel(k == 0   ? "gyroid"
                 : k == 7 ? "voronoi_foam"
                          : unitCells().at(std::size_t(k - 1)).id);
  double bytes =
      double(p.instructionCount() * sizeof(Instruction) + p.constants().size() * sizeof(double));
  if (k == 7)
    bytes += double(std::dynamic_pointer_cast<const PeriodicSegmentsField>(loadFieldSource(*node))
                        ->memoryBytes());
  state.counters["bytes"] = bytes;
}

BENCHMARK(BM_LatticeEval)
    ->ArgsProduct({{0, 1, 2, 3, 4, 5, 6, 7}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_BentLatticeEval(benchmark::State& state) {
  const bool straight = state.range(0) != 0, gradient = state.range(1) != 0;
  FfdLattice bend({{-10.5, -2.5, -2.5}, {10.5, 2.5, 2.5}}, 4, 1, 1);
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; j <= 1; ++j)
      for (int k = 0; k <= 1; ++k) {
        Vec3 q = bend.point(i, j, k);
        q[2] += 5.0 * (1.0 - std::pow((i - 2) / 2.0, 2));
        bend.setPoint(i, j, k, q);
      }
  const NodePtr octet = makeNode("strut_lattice",
                                 {{"cell_type", textValue("octet")},
                                  {"cell", vec3Value({1, 1, 1})},
                                  {"radius", realValue(0.1)}},
                                 {});
  auto params = ffdParams(bend);
  params["struts"] = textValue(straight ? "straight" : "curved");
  const Program p = compile(makeNode("ffd", params, {octet}));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> along(-10.0, 10.0), across(-2.0, 2.0);
  timeBatch(
      state, p,
      [&] {
        return bend.deform({along(rng), across(rng), across(rng)});
      },
      gradient);
  state.SetLabel(straight ? "straight" : "curved");
  if (straight)
    state.counters["bytes"] = double(straightStrutFields(*octet, bend).struts->memoryBytes());
}

BENCHMARK(BM_BentLatticeEval)
    ->ArgsProduct({{0, 1}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_ConformalLatticeEval(benchmark::State& state) {
  const bool straight = state.range(0) != 0, gradient = state.range(1) != 0;
  const Program p = compile(makeNode("strut_lattice",
                                     {{"cell_type", textValue("octet")},
                                      {"cell", vec3Value({2, 2, 2})},
                                      {"radius", realValue(0.3)},
                                      {"conform", textValue("cylinder")},
                                      {"around", realValue(28)},
                                      {"struts", textValue(straight ? "straight" : "curved")}},
                                     {}));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> radius(7.0, 10.0), angle(0.0, 2.0 * kPi), along(0, 20);
  timeBatch(
      state, p,
      [&] {
        const double r = radius(rng), a = angle(rng);
        return Vec3{r * std::cos(a), r * std::sin(a), along(rng)};
      },
      gradient);
  state.SetLabel(straight ? "straight" : "curved");
}

BENCHMARK(BM_ConformalLatticeEval)
    ->ArgsProduct({{0, 1}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace frep
