// Strut lattices beside the TPMS lattice they join (frep/node_types_struts.cpp):
//   BM_LatticeEval/k/g  points per second of a lattice node filling a box of 50 x 50 x 50
//                       cells, values (g = 0) or values and gradients (g = 1): k = 0 the
//                       gyroid sheet (the baseline), 1.. the strut lattices' unit cells in
//                       the node's order (simple cubic, BCC, FCC, octet, Kelvin, diamond),
//                       7 the Voronoi foam (seeds in cells of 1, the default period of 5).
//                       Counter `bytes`: the field's program (instructions and constants)
//                       and, for the foam, its network's bins: the field's whole memory, the
//                       same for any number of cells.
#include <benchmark/benchmark.h>

#include <random>

#include "frep/field_sources.h"
#include "frep/periodic_segments.h"
#include "frep/strut_cells.h"
#include "frep/tree.h"
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

void BM_LatticeEval(benchmark::State& state) {
  const int k = int(state.range(0));
  const bool gradient = state.range(1) != 0;
  const NodePtr node = latticeNode(k);
  const Program p = compile(node);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 50.0);  // 50 cells a side
  const std::size_t n = 100000;
  std::vector<double> x(n), y(n), z(n), out(n);
  std::vector<Dual> dx(n), dy(n), dz(n), dout(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = u(rng), y[i] = u(rng), z[i] = u(rng);
    dx[i] = Dual(x[i], 1, 0, 0), dy[i] = Dual(y[i], 0, 1, 0), dz[i] = Dual(z[i], 0, 0, 1);
  }
  for (auto _ : state) {
    if (gradient)
      p.evalGradientBatch(dx.data(), dy.data(), dz.data(), n, dout.data());
    else
      p.evalBatch(x.data(), y.data(), z.data(), n, out.data());
  }
  state.SetLabel(k == 0   ? "gyroid"
                 : k == 7 ? "voronoi_foam"
                          : unitCells().at(std::size_t(k - 1)).id);
  state.counters["points/s"] =
      benchmark::Counter(double(n), benchmark::Counter::kIsIterationInvariantRate);
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

}  // namespace
}  // namespace frep
