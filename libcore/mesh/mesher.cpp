#include "mesh/mesher.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <future>
#include <limits>
#include <mutex>
#include <optional>
#include <sstream>

#include "base/errors.h"
#include "base/mesh_invariants.h"
#include "base/phase_times.h"
#include "base/progress.h"
#include "base/qef.h"
#include "base/triangle_geometry.h"
#include "mesh/brick_mesher.h"
#include "mesh/centred_cube.h"
#include "mesh/crease_flips.h"
#include "mesh/cube_loops.h"
#include "mesh/edge_roots.h"
#include "mesh/feature_point.h"
#include "mesh/flat_vertex_removal.h"
#include "mesh/hidden_parts.h"
#include "mesh/kuhn_tetrahedra.h"
#include "mesh/local_refinement.h"
#include "mesh/sampling_grid.h"

namespace frep {

using namespace meshing;

namespace {

struct ActiveBrick {
  CellRange range;
  // specialised to the brick's parent in the octree; null: the whole field. The brick's own
  // specialisation is made when it is meshed and dropped after: kept for every brick at
  // once, the copies were a third of the meshing's peak memory on a blend chain (the
  // helix: 16 of 48 MB), whose programs specialisation cannot shorten.
  std::shared_ptr<const Field> field;
};

// Octree descent over bricks: ranges proven uniform are dropped, and each level specialises
// the field to its box (region specialisation), so deep bricks evaluate short programs.
// The descent stops once `cap` bricks are found (more cannot fit the memory budget, and a
// part far too fine would otherwise be searched for minutes before the refusal) and polls
// the caller's cancel as it goes.
struct BrickSearch {
  std::vector<ActiveBrick>& out;
  std::size_t cap = std::numeric_limits<std::size_t>::max();
  Progress cancel;
  std::size_t visited = 0;
  bool full = false;
};

void collectBricks(const Field& field, const std::shared_ptr<const Field>& holder, const Grid& g,
                   const CellRange& cells, int bc, const std::int64_t b0[3],
                   const std::int64_t b1[3], BrickSearch& search) {
  if (search.full) return;
  if (++search.visited % 4096 == 0) search.cancel.step(0.0);
  CellRange r;
  for (int a = 0; a < 3; ++a) {
    r.lo[a] = b0[a] * bc;
    r.hi[a] = std::min(b1[a] * bc, cells.hi[a]);
  }
  if (provenUniform(field, g, r)) return;
  if (b1[0] - b0[0] == 1 && b1[1] - b0[1] == 1 && b1[2] - b0[2] == 1) {
    if (search.out.size() >= search.cap) {
      search.full = true;
      return;
    }
    search.out.push_back({r, holder});
    return;
  }
  std::shared_ptr<const Field> own = field.specialise(rangeBox(g, r));
  const std::shared_ptr<const Field>& here = own ? own : holder;
  const Field& f = own ? *own : field;
  std::int64_t mid[3];
  for (int a = 0; a < 3; ++a) mid[a] = b0[a] + std::max<std::int64_t>(1, (b1[a] - b0[a]) / 2);
  for (int child = 0; child < 8; ++child) {
    std::int64_t c0[3], c1[3];
    bool empty = false;
    for (int a = 0; a < 3; ++a) {
      const bool upper = (child >> a) & 1;
      c0[a] = upper ? mid[a] : b0[a];
      c1[a] = upper ? b1[a] : mid[a];
      empty = empty || c0[a] >= c1[a];
    }
    if (!empty) collectBricks(f, here, g, cells, bc, c0, c1, search);
  }
}

double trianglesPerBrick(const MeshingOptions& opt) {
  return static_cast<double>(opt.brickCells) * opt.brickCells *
         (opt.settings.mesher == Extraction::Cubes ? kCubeTrianglesPerFaceCell
                                                   : kTrianglesPerFaceCell);
}

// The most active bricks whose mesh fits the memory budget (none: no limit).
std::size_t bricksThatFit(const MeshingOptions& opt) {
  if (opt.memoryBudget == 0) return std::numeric_limits<std::size_t>::max();
  return static_cast<std::size_t>(static_cast<double>(opt.memoryBudget) /
                                  (trianglesPerBrick(opt) * opt.bytesPerTriangle)) +
         1;
}

// The active bricks in [b0, b1), counted, or where more than fit the budget, estimated
// from a coarse descent (at most 64 coarse bricks an axis, each of F x F x F bricks): a
// surface crosses about F^2 of the bricks of each coarse brick it crosses.
std::size_t collectOrEstimate(const Field& field, const Grid& g, const CellRange& cells,
                              const MeshingOptions& opt, const std::int64_t b0[3],
                              const std::int64_t b1[3], std::vector<ActiveBrick>& bricks) {
  BrickSearch search{bricks, bricksThatFit(opt), Progress(opt.progress)};
  collectBricks(field, nullptr, g, cells, opt.brickCells, b0, b1, search);
  if (!search.full) return bricks.size();
  bricks.clear();
  bricks.shrink_to_fit();
  std::int64_t factor = 1;
  for (int a = 0; a < 3; ++a)
    while ((b1[a] - b0[a] + factor - 1) / factor > 64) factor *= 2;
  std::int64_t c0[3], c1[3];
  for (int a = 0; a < 3; ++a) {
    c0[a] = b0[a] / factor;
    c1[a] = (b1[a] + factor - 1) / factor;
  }
  std::vector<ActiveBrick> coarse;
  BrickSearch coarseSearch{coarse, std::numeric_limits<std::size_t>::max(),
                           Progress(opt.progress)};
  collectBricks(field, nullptr, g, cells, opt.brickCells * static_cast<int>(factor), c0, c1,
                coarseSearch);
  const double estimate = static_cast<double>(coarse.size()) * static_cast<double>(factor) *
                          static_cast<double>(factor);
  return std::max(search.cap + 1, static_cast<std::size_t>(std::min(estimate, 1e18)));
}

// Every brick's vertices numbered in one row (brick by brick: `first` of each brick) and
// sorted by global edge key, with the brick each entry came from.
struct KeyOrder {
  std::vector<std::size_t> first, brickOf;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> order;  // (key, entry)
};
KeyOrder sortByKey(const std::vector<BrickResult>& results) {
  KeyOrder k;
  k.first.assign(results.size() + 1, 0);
  for (std::size_t i = 0; i < results.size(); ++i)
    k.first[i + 1] = k.first[i] + results[i].keys.size();
  k.order.resize(k.first.back());
  k.brickOf.resize(k.first.back());
  tbb::parallel_for(std::size_t(0), results.size(), [&](std::size_t i) {
    for (std::size_t v = 0; v < results[i].keys.size(); ++v) {
      k.order[k.first[i] + v] = {results[i].keys[v], static_cast<std::uint32_t>(k.first[i] + v)};
      k.brickOf[k.first[i] + v] = i;
    }
  });
  tbb::parallel_sort(k.order.begin(), k.order.end());
  return k;
}

// Weld, the reference way: sort every brick's vertices by global edge key and merge equal
// keys. Used where the ownership weld below cannot place a vertex (it never should).
TriangleMesh weldBySorting(std::vector<BrickResult>& results, bool normals,
                           std::vector<std::uint32_t>* flippable) {
  KeyOrder sorted = sortByKey(results);
  const std::vector<std::size_t>& first = sorted.first;
  const std::vector<std::size_t>& brickOf = sorted.brickOf;
  const auto& order = sorted.order;
  std::vector<std::uint32_t> unique(order.size());
  std::vector<std::uint32_t> owner;  // unique vertex -> its first entry
  owner.reserve(order.size());
  auto owned = [&](std::size_t entry) {
    return results[brickOf[entry]].owner[entry - first[brickOf[entry]]] != Ownership::Other;
  };
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (i == 0 || order[i].first != order[i - 1].first) owner.push_back(order[i].second);
    // the owner's copy where there is one (only it has a normal)
    if (!owned(owner.back()) && owned(order[i].second)) owner.back() = order[i].second;
    unique[order[i].second] = static_cast<std::uint32_t>(owner.size() - 1);
  }
  TriangleMesh mesh;
  mesh.positions.resize(owner.size());
  if (normals) mesh.normals.resize(owner.size());
  for (std::size_t u = 0; u < owner.size(); ++u) {
    const std::size_t entry = owner[u];
    const BrickResult& from = results[brickOf[entry]];
    mesh.positions[u] = from.positions[entry - first[brickOf[entry]]];
    if (normals) mesh.normals[u] = from.normals[entry - first[brickOf[entry]]];
  }
  std::size_t triangleCount = 0;
  for (const auto& r : results) triangleCount += r.triangles.size();
  mesh.triangles.reserve(triangleCount);
  for (std::size_t i = 0; i < results.size(); ++i) {
    const std::uint32_t base = static_cast<std::uint32_t>(first[i]);
    const std::uint32_t offset = static_cast<std::uint32_t>(mesh.triangles.size());
    for (std::uint32_t t : results[i].flippable) flippable->push_back(offset + t);
    for (const Triangle& t : results[i].triangles)
      mesh.triangles.push_back({unique[base + t[0]], unique[base + t[1]], unique[base + t[2]]});
  }
  return mesh;
}

// Weld by ownership: every grid edge belongs to the one brick whose half-open cell range
// holds its lower grid point (the last brick on an axis also holds the grid's last points).
// A vertex on an edge a brick owns gets the next number of that brick's block; a vertex on
// an edge another brick owns takes that brick's number for it, found by key in the owner's
// sorted list. The owner always made that vertex: its edge lies on the face the two bricks
// share, a brick proven uniform has no crossed edge on its closed box, and both bricks
// compute the edge identically. Every step is per brick, in parallel; no global sort.
TriangleMesh weld(const Grid& g, int bc, const std::int64_t bricksPerAxis[3],
                  const std::vector<ActiveBrick>& bricks, std::vector<BrickResult>& results,
                  bool normals, bool* bySorting, std::vector<std::uint32_t>* flippable) {
  const std::size_t count = bricks.size();
  auto brickLinear = [&](const std::int64_t b[3]) {
    return static_cast<std::uint64_t>(b[0] + bricksPerAxis[0] * (b[1] + bricksPerAxis[1] * b[2]));
  };
  // The owner of an edge key, as a brick linear index.
  auto ownerOf = [&](std::uint64_t key) {
    std::uint64_t p = key / 7;
    std::int64_t b[3];
    for (int a = 0; a < 3; ++a) {
      const std::int64_t at =
          static_cast<std::int64_t>(p % static_cast<std::uint64_t>(g.points[a]));
      p /= static_cast<std::uint64_t>(g.points[a]);
      b[a] = std::min(at / bc, bricksPerAxis[a] - 1);
    }
    return brickLinear(b);
  };
  std::optional<Phase> serial(std::in_place, "mesh: weld's serial parts", PhaseKind::Serial);
  // The output's arrays are zeroed by one thread, and most of that is the first touch of
  // fresh pages (0.1 s on the gyroid at 256 cells): done on a thread of their own while the
  // numbering below runs on the others. (Declared after `mesh`: joined before it goes.)
  TriangleMesh mesh;
  std::vector<std::size_t> firstTriangle(count + 1, 0);
  for (std::size_t i = 0; i < count; ++i)
    firstTriangle[i + 1] = firstTriangle[i] + results[i].triangles.size();
  std::future<void> zeroed = std::async(std::launch::async, [&mesh, &firstTriangle, count] {
    mesh.triangles.resize(firstTriangle[count]);
  });
  std::vector<std::pair<std::uint64_t, std::uint32_t>> brickIndex(count);
  for (std::size_t i = 0; i < count; ++i) {
    const std::int64_t b[3] = {bricks[i].range.lo[0] / bc, bricks[i].range.lo[1] / bc,
                               bricks[i].range.lo[2] / bc};
    brickIndex[i] = {brickLinear(b), static_cast<std::uint32_t>(i)};
  }
  std::sort(brickIndex.begin(), brickIndex.end());
  serial.reset();

  // 1. Per brick: its own vertices, numbered in local order; the keys others may ask for
  // (those on its lower faces: a neighbour's upper face), sorted.
  std::vector<std::vector<std::int32_t>> ownedRank(count);  // local vertex -> rank, or -1
  std::vector<std::vector<std::pair<std::uint64_t, std::uint32_t>>> ownedKeys(count);
  std::vector<std::size_t> base(count + 1, 0);
  tbb::parallel_for(std::size_t(0), count, [&](std::size_t i) {
    const BrickResult& r = results[i];
    std::vector<std::int32_t>& rank = ownedRank[i];
    rank.assign(r.keys.size(), -1);
    std::int32_t next = 0;
    for (std::size_t v = 0; v < r.keys.size(); ++v) {
      if (r.owner[v] == Ownership::Other) continue;
      if (r.owner[v] == Ownership::OwnShared)
        ownedKeys[i].emplace_back(r.keys[v], static_cast<std::uint32_t>(next));
      rank[v] = next++;
    }
    std::sort(ownedKeys[i].begin(), ownedKeys[i].end());
    base[i + 1] = static_cast<std::size_t>(next);
  });
  serial.emplace("mesh: weld's serial parts", PhaseKind::Serial);
  for (std::size_t i = 0; i < count; ++i) base[i + 1] += base[i];
  std::future<void> zeroedPositions =
      std::async(std::launch::async, [&mesh, &base, count, normals] {
        mesh.positions.resize(base[count]);
        if (normals) mesh.normals.resize(base[count]);
      });
  serial.reset();

  // 2. Per brick: the global number of every local vertex.
  std::vector<std::vector<std::uint32_t>> global(count);
  std::atomic<bool> lost{false};
  tbb::parallel_for(std::size_t(0), count, [&](std::size_t i) {
    const std::vector<std::uint64_t>& keys = results[i].keys;
    std::vector<std::uint32_t>& out = global[i];
    out.resize(keys.size());
    for (std::size_t v = 0; v < keys.size(); ++v) {
      if (ownedRank[i][v] >= 0) {
        out[v] = static_cast<std::uint32_t>(base[i] + static_cast<std::size_t>(ownedRank[i][v]));
        continue;
      }
      const std::uint64_t owner = ownerOf(keys[v]);
      const auto at = std::lower_bound(brickIndex.begin(), brickIndex.end(),
                                       std::make_pair(owner, std::uint32_t(0)));
      bool found = false;
      if (at != brickIndex.end() && at->first == owner) {
        const auto& list = ownedKeys[at->second];
        const auto k =
            std::lower_bound(list.begin(), list.end(), std::make_pair(keys[v], std::uint32_t(0)));
        if (k != list.end() && k->first == keys[v]) {
          out[v] = static_cast<std::uint32_t>(base[at->second] + k->second);
          found = true;
        }
      }
      if (!found) lost = true;
    }
  });
  if (lost) {
    *bySorting = true;
    return weldBySorting(results, normals, flippable);
  }

  // 3. Positions, normals and triangles, written in place per brick.
  serial.emplace("mesh: weld's serial parts", PhaseKind::Serial);
  zeroed.get();
  zeroedPositions.get();
  for (std::size_t i = 0; i < count; ++i)
    for (std::uint32_t t : results[i].flippable)
      flippable->push_back(static_cast<std::uint32_t>(firstTriangle[i]) + t);
  serial.reset();
  tbb::parallel_for(std::size_t(0), count, [&](std::size_t i) {
    BrickResult& r = results[i];
    for (std::size_t v = 0; v < r.keys.size(); ++v)
      if (ownedRank[i][v] >= 0) {
        mesh.positions[global[i][v]] = r.positions[v];
        if (normals) mesh.normals[global[i][v]] = r.normals[v];
      }
    Triangle* out = mesh.triangles.data() + firstTriangle[i];
    for (const Triangle& t : r.triangles)
      *out++ = {global[i][t[0]], global[i][t[1]], global[i][t[2]]};
    r = BrickResult();  // free as we go
  });
  return mesh;
}

}  // namespace

namespace {

// The grid for the options: validated (box, resolution, brick size, float32 steps), with its
// cells (the outer layer included) and bricks per axis.
Grid makeGrid(const MeshingOptions& opt, CellRange* cells, std::int64_t bricks[3]) {
  const Box3& box = opt.bbox;
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(box.lo[a]) || !std::isfinite(box.hi[a]) || !(box.lo[a] < box.hi[a]))
      throw ModelError("mesher: the bounding box must be finite with min < max on every axis");
  if (!(opt.resolution > 0.0) || !std::isfinite(opt.resolution))
    throw ModelError("mesher: resolution (cell size) must be a number > 0");
  if (opt.brickCells < 2 || opt.brickCells > 64)
    throw ModelError("mesher: brick size must be between 2 and 64 cells");
  if (opt.settings.dropFlatVertices && opt.brickCells % 2 != 0)
    throw ModelError("mesher: flat vertices need an even brick size (blocks of 2 x 2 x 2 cubes)");
  opt.settings.validate();

  Grid g;
  g.lo = box.lo;
  g.hi = box.hi;
  for (int a = 0; a < 3; ++a) {
    const double extent = box.hi[a] - box.lo[a];
    const double want = std::ceil(extent / opt.resolution - 1e-9);
    if (want > static_cast<double>(kMaxCellsPerAxis)) {
      std::ostringstream os;
      os << "mesher: resolution " << opt.resolution << " needs " << want
         << " cells along an axis of the bounding box; at most " << kMaxCellsPerAxis
         << " are allowed: use a larger cell size";
      throw ModelError(os.str());
    }
    const std::int64_t n = std::max<std::int64_t>(1, static_cast<std::int64_t>(want));
    g.h[a] = extent / static_cast<double>(n);
    g.points[a] = n + 2;
    cells->lo[a] = 0;
    cells->hi[a] = n + 1;
    bricks[a] = (cells->hi[a] + opt.brickCells - 1) / opt.brickCells;
  }

  // Vertices are float32 (as STL stores them) and are kept kEdgeMargin of an edge away from
  // its grid points: a cell must span enough float steps at the box's coordinates for that
  // margin to survive rounding, or triangles collapse (a fine grid far from the origin).
  double far = 0.0, h = g.h[0];
  for (int a = 0; a < 3; ++a) {
    far = std::max({far, std::abs(box.lo[a]), std::abs(box.hi[a])});
    h = std::min(h, g.h[a]);
  }
  const float f = static_cast<float>(far);
  const double step =
      static_cast<double>(std::nextafter(f, std::numeric_limits<float>::infinity())) - f;
  if (h < kMinCellFloatSteps * step) {
    std::ostringstream os;
    os << "mesher: cells of " << h << " at coordinates up to " << far << " span only "
       << std::floor(h / step) << " float32 steps (meshes store float32 coordinates, as STL "
       << "does); allowed here: cells of at least " << kMinCellFloatSteps * step
       << ": use a larger cell size or move the model nearer the origin";
    throw ModelError(os.str());
  }
  return g;
}

// Memory guard: an ordinary surface makes about 6 triangles per cell of a brick's face by
// tetrahedra, a third by cubes (calibrated on the reference models; a gyroid's dense sheets
// make more, so the estimate never refuses a mesh that would fit).
void refuseOverBudget(const MeshingOptions& opt, const Grid& g, std::size_t activeBricks) {
  if (opt.memoryBudget == 0) return;
  const double triangles = static_cast<double>(activeBricks) * trianglesPerBrick(opt);
  const double bytes = triangles * opt.bytesPerTriangle;
  if (bytes <= static_cast<double>(opt.memoryBudget)) return;
  double h = g.h[0];
  for (int a = 1; a < 3; ++a) h = std::max(h, g.h[a]);
  std::ostringstream os;
  os.precision(3);
  // three significant digits, but whole numbers from 1,000 on (no 1.13e+04)
  auto readable = [](double v) {
    std::ostringstream t;
    t.precision(3);
    if (v >= 1000.0)
      t << std::llround(v);
    else
      t << v;
    return t.str();
  };
  os << "mesher: at cell size " << opt.resolution << " the mesh would have about "
     << readable(triangles / 1e6) << " million triangles, needing about " << readable(bytes / 1e9)
     << " GB, and " << static_cast<double>(opt.memoryBudget) / 1e9
     << " GB is available: use a cell size of at least "
     << h * std::sqrt(bytes / static_cast<double>(opt.memoryBudget)) * 1.1 << " (or a smaller box)";
  throw TooLargeError(os.str());
}

// Meshes every brick in parallel, with progress (to 95 %) and cancel; returns the points
// evaluated.
std::size_t meshBricks(const Field& field, const Grid& g, const MeshingOptions& opt,
                       const std::vector<ActiveBrick>& bricks, std::vector<BrickResult>& results) {
  results.resize(bricks.size());
  tbb::enumerable_thread_specific<Scratch> scratch;
  BrickMesher mesher(g, opt);
  std::atomic<std::size_t> evaluated{0};
  ThreadedProgress bar(Progress(opt.progress).sub(0.0, 0.95), bricks.size());
  tbb::parallel_for(std::size_t(0), bricks.size(), [&](std::size_t i) {
    if (bar.cancelled()) return;
    const ActiveBrick& b = bricks[i];
    const Field& parent = b.field ? *b.field : field;
    const std::shared_ptr<const Field> own = parent.specialise(rangeBox(g, b.range));
    evaluated += mesher.run(own ? *own : parent, field, b.range, scratch.local(), results[i]);
    bar.itemDone();
  });
  if (bar.cancelled()) throw Cancelled();
  return evaluated;
}

// The bricks' parts thinner than a cell, summed into the stats (before the weld frees them).
void countThinParts(const std::vector<BrickResult>& results, MeshingStats* stats) {
  if (!stats) return;
  bool unseen = false;
  std::uint64_t first = std::numeric_limits<std::uint64_t>::max();
  stats->thinSolidEdges = stats->thinGapEdges = stats->tipEdges = 0;
  for (const BrickResult& b : results) {
    stats->thinSolidEdges += b.thinSolid;
    stats->thinGapEdges += b.thinGaps;
    stats->tipEdges += b.tips;
    if (b.exampleKey != std::numeric_limits<std::uint64_t>::max() &&
        (b.exampleUnseen > unseen || (b.exampleUnseen == unseen && b.exampleKey < first))) {
      unseen = b.exampleUnseen;
      first = b.exampleKey;
      stats->thinExample = b.example;
    }
  }
}

// A brick job's bricks welded by key (each key once, sorted), positions from any brick that
// made the vertex (all make it bit-identically); the fan triangles crease flips may pair.
MeshPiece weldPiece(std::vector<BrickResult>& results, std::vector<std::uint32_t>* flippable) {
  KeyOrder sorted = sortByKey(results);
  const std::vector<std::size_t>& first = sorted.first;
  const std::vector<std::size_t>& brickOf = sorted.brickOf;
  const auto& order = sorted.order;
  std::vector<std::uint32_t> unique(order.size());
  MeshPiece piece;
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (i == 0 || order[i].first != order[i - 1].first) {
      const std::size_t entry = order[i].second;
      piece.keys.push_back(order[i].first);
      piece.positions.push_back(results[brickOf[entry]].positions[entry - first[brickOf[entry]]]);
    }
    unique[order[i].second] = static_cast<std::uint32_t>(piece.keys.size() - 1);
  }
  for (std::size_t i = 0; i < results.size(); ++i) {
    const std::uint32_t base = static_cast<std::uint32_t>(first[i]);
    const std::uint32_t offset = static_cast<std::uint32_t>(piece.triangles.size());
    for (std::uint32_t t : results[i].flippable) flippable->push_back(offset + t);
    for (const Triangle& t : results[i].triangles)
      piece.triangles.push_back({unique[base + t[0]], unique[base + t[1]], unique[base + t[2]]});
    results[i] = BrickResult();
  }
  return piece;
}

}  // namespace

void brickGrid(const MeshingOptions& opt, std::int64_t bricks[3]) {
  CellRange cells;
  makeGrid(opt, &cells, bricks);
}

TriangleMesh polygonize(const Field& field, const MeshingOptions& opt, MeshingStats* stats) {
  const auto start = std::chrono::steady_clock::now();
  CellRange cells;
  std::int64_t b0[3] = {0, 0, 0}, b1[3];
  const Grid g = makeGrid(opt, &cells, b1);
  const int bc = opt.brickCells;
  std::vector<ActiveBrick> bricks;
  {
    const Phase phase("mesh: the octree of bricks", PhaseKind::Serial);
    refuseOverBudget(opt, g, collectOrEstimate(field, g, cells, opt, b0, b1, bricks));
  }

  // The bar: the bricks up to 0.95, or, where the thin parts are refined (several times the
  // meshing's time, ten times and more with deeper levels), up to `bricksEnd` and the
  // refinement from there.
  const bool refining = opt.settings.refining();
  const double bricksEnd = !refining ? 1.0 : opt.settings.refineLevels > 1 ? 0.05 : 0.2;
  const Progress bar(opt.progress);
  MeshingOptions brickOptions = opt;
  brickOptions.progress = bar.sub(0.0, bricksEnd).callback();
  std::vector<BrickResult> results;
  std::size_t evaluated = 0;
  {
    const Phase phase("mesh: bricks", PhaseKind::Parallel);
    evaluated = meshBricks(field, g, brickOptions, bricks, results);
  }
  std::size_t refinementEvaluations = 0;
  const Phase gather("mesh: thin parts and hidden edges gathered", PhaseKind::Serial);
  countThinParts(results, stats);
  std::vector<std::uint64_t> hiddenEdges;
  for (const BrickResult& b : results) {
    if (opt.settings.refining())
      hiddenEdges.insert(hiddenEdges.end(), b.hiddenEdges.begin(), b.hiddenEdges.end());
    if (opt.settings.refine == Refinement::Tips)
      hiddenEdges.insert(hiddenEdges.end(), b.tipEdges.begin(), b.tipEdges.end());
  }
  bool bySorting = false;
  std::vector<std::uint32_t> flippable;
  TriangleMesh mesh;
  {
    const Phase phase("mesh: weld", PhaseKind::Parallel);
    mesh = weld(g, bc, b1, bricks, results, opt.normals, &bySorting, &flippable);
  }
  {
    const Phase phase("mesh: crease flips", PhaseKind::Serial);
    flipCreases(mesh, flippable);
  }
  if (!hiddenEdges.empty() || (refining && opt.settings.refineLevels > 1)) {
    const Phase phase("mesh: refinement", PhaseKind::Parallel);
    std::sort(hiddenEdges.begin(), hiddenEdges.end());
    LocalRefinementStats rs;
    // (the bricks' own bar ends at 0.95 of theirs: the weld takes the rest)
    refineHiddenParts(field, g, hiddenEdges, opt.refinementCubes, mesh, &rs,
                      opt.settings.refineLevels,
                      bar.sub(0.0, 0.95).sub(bricksEnd, 1.0 - bricksEnd).callback());
    refinementEvaluations = rs.evaluations;
    if (stats) {
      stats->refinedCubes = rs.cubes;
      stats->refinementSkipped = rs.skipped;
      stats->refinementLevelsReached = rs.levels;
      stats->refinedDeeperCubes = rs.deeperCubes;
      stats->refinedDeeperLeftOut = rs.deeperCubesLeftOut;
      stats->refinementDeeperSkipped = rs.deeperSkipped;
    }
  }
  FREP_ASSERT_MESH(mesh, "the mesher");
  bar.report(1.0);

  if (stats) {
    stats->settings = opt.settings;
    for (int a = 0; a < 3; ++a) stats->cells[a] = static_cast<std::size_t>(cells.hi[a]);
    stats->bricksTotal = static_cast<std::size_t>(b1[0] * b1[1] * b1[2]);
    stats->bricksActive = bricks.size();
    stats->pointsEvaluated = evaluated + refinementEvaluations;
    stats->weldedBySorting = bySorting;
    stats->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return mesh;
}

MeshPiece polygonizePiece(const Field& field, const MeshingOptions& opt,
                          const std::int64_t brickLo[3], const std::int64_t brickHi[3],
                          MeshingStats* stats) {
  const auto start = std::chrono::steady_clock::now();
  CellRange cells;
  std::int64_t all[3];
  const Grid g = makeGrid(opt, &cells, all);
  for (int a = 0; a < 3; ++a)
    if (brickLo[a] < 0 || brickHi[a] > all[a] || brickLo[a] >= brickHi[a]) {
      std::ostringstream os;
      os << "mesher: a brick job's bricks must lie in [0, " << all[a] << ") on axis " << a
         << " with lo < hi; got [" << brickLo[a] << ", " << brickHi[a] << ")";
      throw ModelError(os.str());
    }
  const int bc = opt.brickCells;
  std::vector<ActiveBrick> bricks;
  refuseOverBudget(opt, g, collectOrEstimate(field, g, cells, opt, brickLo, brickHi, bricks));

  MeshingOptions withoutNormals = opt;
  withoutNormals.normals = false;  // a piece carries positions only (STL and 3MF need no more)
  std::vector<BrickResult> results;
  const std::size_t evaluated = meshBricks(field, g, withoutNormals, bricks, results);
  countThinParts(results, stats);
  std::vector<std::uint32_t> flippable;
  MeshPiece piece = weldPiece(results, &flippable);
  for (int a = 0; a < 3; ++a) {
    piece.gridCells[a] = cells.hi[a];
    piece.cellLo[a] = brickLo[a] * bc;
    piece.cellHi[a] = std::min(brickHi[a] * bc, cells.hi[a]);
  }
  // Pairs inside the job are decided here; a fan triangle left without its partner may pair
  // with one of a neighbouring job across their shared face (its edge then lies there).
  TriangleMesh mesh;
  mesh.positions = std::move(piece.positions);
  mesh.triangles = std::move(piece.triangles);
  for (std::uint32_t t : flipCreases(mesh, flippable)) {
    const Triangle& tr = mesh.triangles[t];
    if (onJobSeam(piece, piece.keys[tr[1]]) && onJobSeam(piece, piece.keys[tr[2]]))
      piece.pendingFlips.push_back(t);
  }
  piece.positions = std::move(mesh.positions);
  piece.triangles = std::move(mesh.triangles);
  if (opt.progress) opt.progress(1.0);
  if (stats) {
    stats->settings = opt.settings;
    for (int a = 0; a < 3; ++a) stats->cells[a] = static_cast<std::size_t>(cells.hi[a]);
    stats->bricksTotal = static_cast<std::size_t>(
        (brickHi[0] - brickLo[0]) * (brickHi[1] - brickLo[1]) * (brickHi[2] - brickLo[2]));
    stats->bricksActive = bricks.size();
    stats->pointsEvaluated = evaluated;
    stats->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return piece;
}

}  // namespace frep
