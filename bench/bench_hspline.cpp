// Hsplines: a 5-level hierarchy of 10,339 CVs (a torus refined over shrinking
// regions, every movable CV given an offset), evaluated, flattened, tessellated, and updated
// after one level-0 CV moves (the work behind one frame of a drag). docs/performance.md.
#include <benchmark/benchmark.h>

#include <cmath>

#include "hspline/hspline.h"
#include "hspline/hspline_flatten.h"
#include "hspline/hspline_select.h"
#include "hspline/hspline_shapes.h"
#include "hspline/hspline_tessellate.h"

namespace {

using namespace frep;

// Level l + 1 over the level-l CVs with i and j below the limit (all of level 0).
HSpline fiveLevels() {
  HSpline h = hsplineTorus(16, 12, 30, 10);
  const int limits[] = {1 << 20, 16, 26, 32};
  for (int level = 0; level < 4; ++level) {
    std::vector<std::pair<int, int>> region;
    for (const HsCv& cv : h.level(level).cvs)
      if (cv.i < limits[level] && cv.j < limits[level]) region.push_back({cv.i, cv.j});
    h.refine(level, region);
  }
  for (int level = 1; level < h.levelCount(); ++level)
    for (const HsCvRef& c : selectMovable(h, level))
      h.setValue(level, c.i, c.j, {0, 0, 0.05 * std::sin(0.7 * c.i + 1.3 * c.j) / level});
  return h;
}

const HSpline& hierarchy() {
  static const HSpline h = fiveLevels();
  return h;
}

void BM_HsEvaluate(benchmark::State& state) {
  const HSpline& h = hierarchy();
  for (auto _ : state)
    for (int k = 0; k < 10000; ++k) benchmark::DoNotOptimize(h.evaluate(0.0016 * k, 0.00123 * k));
  state.counters["cvs"] = static_cast<double>(h.cvCount());
  state.counters["levels"] = h.levelCount();
  state.SetItemsProcessed(state.iterations() * 10000);
}
BENCHMARK(BM_HsEvaluate)->Unit(benchmark::kMillisecond);

void BM_HsFlatten(benchmark::State& state) {
  const HSpline& h = hierarchy();
  for (auto _ : state) benchmark::DoNotOptimize(flatten(h));
  const FlatBSpline f = flatten(h);
  state.counters["poles"] = static_cast<double>(f.poles.size());
}
BENCHMARK(BM_HsFlatten)->Unit(benchmark::kMillisecond);

void BM_HsTessellate(benchmark::State& state) {
  const FlatBSpline f = flatten(hierarchy());
  std::size_t triangles = 0;
  for (auto _ : state) triangles = tessellate(f, 0.01 * state.range(0)).mesh.triangles.size();
  state.counters["triangles"] = static_cast<double>(triangles);
}
BENCHMARK(BM_HsTessellate)->Arg(1)->Arg(5)->Unit(benchmark::kMillisecond);

// One frame of a drag: a level-0 CV moves, every finer CV's frame and displacement follow,
// and the flattened surface (what FreeCAD's face is built from) is made again.
void BM_HsMoveLevel0Cv(benchmark::State& state) {
  HSpline h = hierarchy();
  const Vec3 p = h.position(0, 5, 5);
  int k = 0;
  for (auto _ : state) {
    h.moveCv(0, 5, 5, {p[0], p[1], p[2] + 0.1 * (++k % 2)});
    benchmark::DoNotOptimize(flatten(h));
  }
}
BENCHMARK(BM_HsMoveLevel0Cv)->Unit(benchmark::kMillisecond);

}  // namespace
