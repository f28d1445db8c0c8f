#include "mesh/local_refinement.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <unordered_set>

#include "base/errors.h"
#include "base/progress.h"
#include "base/triangle_geometry.h"
#include "mesh/refined_cells.h"
#include "mesh/refinement_grid.h"
#include "mesh/refiner.h"

namespace frep {

using refinement::Abort;
using refinement::RefinementGrid;
using refinement::Refiner;

void refineHiddenParts(const Field& field, const Grid& g,
                       const std::vector<std::uint64_t>& seedEdges, std::size_t maxCubes,
                       TriangleMesh& mesh, LocalRefinementStats* stats, int levels,
                       const std::function<bool(double)>& progress) {
  LocalRefinementStats local;
  LocalRefinementStats& s = stats ? *stats : local;
  s = LocalRefinementStats();
  if (levels < 1 || levels > kMaxRefinementLevels)
    throw ModelError("mesher: refinementLevels must be 1 to " +
                     std::to_string(kMaxRefinementLevels) + "; got " + std::to_string(levels));
  if (seedEdges.empty() && levels == 1) return;
  // The bar: the look at the surface's cubes (deeper levels only) a third, the levels the
  // rest in equal parts (a deeper level refines about as many cubes, each smaller).
  const double lookShare = levels > 1 ? 0.3 : 0.0, levelShare = (1.0 - lookShare) / levels;
  const Progress bar(progress);
  auto aboveMesh = std::make_unique<TriangleMesh>(mesh);
  std::unique_ptr<Refiner> above;
  try {
    above = std::make_unique<Refiner>(field, RefinementGrid::of(g), *aboveMesh, s);
    std::vector<std::uint64_t> seeds = above->cubesRound(seedEdges);
    if (levels > 1) {
      above->keepSidesForNextLevel();
      std::vector<std::uint64_t> more, far;
      above->reportAt(bar.sub(0.0, lookShare));
      above->surfaceCubesToLookAt(&more, &far);
      seeds.insert(seeds.end(), more.begin(), more.end());
      seeds.insert(seeds.end(), far.begin(), far.end());
      above->refineWhateverTheyShow(far);
    }
    above->reportAt(bar.sub(lookShare, levelShare));
    above->run(seeds, maxCubes);
  } catch (const Abort& e) {
    const std::size_t evaluations = s.evaluations;
    s = LocalRefinementStats();
    s.evaluations = evaluations;
    s.skipped = e.what();
    return;
  }
  if (s.cubes == 0) return;
  mesh = *aboveMesh;
  s.levels = 1;
  // Deeper levels: each refines the half cubes of the one above where its own half cells
  // show what their corners miss, on that level's mesh. A level that fails leaves the mesh
  // as the level above made it.
  for (int level = 2; level <= levels; ++level) {
    std::vector<std::uint64_t> seeds = above->finerCandidates();
    auto deeper = std::make_unique<TriangleMesh>(mesh);
    LocalRefinementStats ls;
    auto next = std::make_unique<Refiner>(field, above->grid().finer(), *deeper, ls);
    above->handDown(*next);
    if (level < levels) next->keepSidesForNextLevel();
    const double start = lookShare + (level - 1) * levelShare;
    next->reportAt(bar.sub(start, 0.0));
    try {
      // where the level above was refined for lying far from the surface, its half cubes
      // are looked at again on its mesh (a sliver's tip, narrower than its half cells)
      const std::vector<std::uint64_t> halves = above->halvesOfFarCubes();
      if (!halves.empty()) {
        std::vector<std::uint64_t> more, far;
        next->surfaceCubesToLookAt(&more, &far, &halves);
        seeds.insert(seeds.end(), more.begin(), more.end());
        seeds.insert(seeds.end(), far.begin(), far.end());
        next->refineWhateverTheyShow(far);
      }
      if (seeds.empty()) break;
      next->reportAt(bar.sub(start, levelShare));
      next->run(seeds, maxCubes);
    } catch (const Abort& e) {
      s.evaluations += ls.evaluations;
      s.deeperSkipped = e.what();
      break;
    }
    s.evaluations += ls.evaluations;
    s.deeperCubesLeftOut += ls.cubesLeftOut;
    if (ls.cubes == 0) break;
    s.deeperCubes += ls.cubes;
    s.trianglesAdded += ls.trianglesAdded;
    s.trianglesRemoved += ls.trianglesRemoved;
    s.levels = level;
    mesh = *deeper;
    above = std::move(next);
    aboveMesh = std::move(deeper);  // (the Refiner's mesh, kept while it is asked)
  }
  if (progress && !progress(1.0)) throw Cancelled();
}

}  // namespace frep
