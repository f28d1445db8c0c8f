#include "check/self_intersections.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <optional>
#include <string>

#include "base/phase_times.h"
#include "check/cgal_surface.h"
#include "check/face_pair_test.h"

namespace frep {

namespace {

struct Box {  // a face's box: floats, exact (the coordinates are floats)
  float lo[3], hi[3];
};

// The faces whose boxes reach one grid cell, copied side by side (one array per coordinate,
// so the compiler tests a face against many at once) with what the pair rules read: bits
// 0-2 of a face's flags say its box starts in this cell along x, y, z; bit 3 + c that its
// corner c's fan is proved embedded.
class CellFaces {
 public:
  // Room for m faces, set by set().
  void resize(std::size_t m) {
    for (int k = 0; k < 3; ++k) {
      lo_[k].resize(m);
      hi_[k].resize(m);
      corner_[k].resize(m);
    }
    flags_.resize(m);
  }
  void set(std::size_t i, const Box& b, const FaceIndices& corners, std::uint32_t flags) {
    for (int k = 0; k < 3; ++k) {
      lo_[k][i] = b.lo[k];
      hi_[k][i] = b.hi[k];
      corner_[k][i] = corners[k];
    }
    flags_[i] = flags;
  }
  FaceIndices corners(std::size_t i) const { return {corner_[0][i], corner_[1][i], corner_[2][i]}; }

  // Calls test(a, b), a < b, for each pair that must be tested here: their boxes overlap
  // (closed boxes, as CGAL's box intersection), this cell holds the lowest corner of the
  // boxes' intersection (along each axis one of the two starts here: both reach it), so each
  // pair is met in one cell only, and they share no vertex whose fan is proved embedded (two
  // such faces cannot intersect).
  template <class Test>
  void forEachCandidate(Test&& test) {
    const std::size_t m = flags_.size();
    keep_.resize(m);
    for (std::size_t a = 0; a + 1 < m; ++a) {
      const float alx = lo_[0][a], aly = lo_[1][a], alz = lo_[2][a];
      const float ahx = hi_[0][a], ahy = hi_[1][a], ahz = hi_[2][a];
      const std::uint32_t fa = flags_[a];
      // a's corners with proved fans (an index that matches nothing where unproved)
      const std::uint32_t e0 = (fa & 8) ? corner_[0][a] : kNone;
      const std::uint32_t e1 = (fa & 16) ? corner_[1][a] : kNone;
      const std::uint32_t e2 = (fa & 32) ? corner_[2][a] : kNone;
      const float *blx = lo_[0].data(), *bly = lo_[1].data(), *blz = lo_[2].data();
      const float *bhx = hi_[0].data(), *bhy = hi_[1].data(), *bhz = hi_[2].data();
      const std::uint32_t *c0 = corner_[0].data(), *c1 = corner_[1].data(), *c2 = corner_[2].data();
      const std::uint32_t* fb = flags_.data();
      std::uint32_t* keep = keep_.data();
      std::uint32_t any = 0;
      // (branch-free, so that it vectorises: most pairs fail one rule or another)
      for (std::size_t b = a + 1; b < m; ++b) {
        const bool corner = ((fa | fb[b]) & 7u) == 7u;
        const bool boxes = (ahx >= blx[b]) & (bhx[b] >= alx) & (ahy >= bly[b]) & (bhy[b] >= aly) &
                           (ahz >= blz[b]) & (bhz[b] >= alz);
        const bool shared = (e0 == c0[b]) | (e0 == c1[b]) | (e0 == c2[b]) | (e1 == c0[b]) |
                            (e1 == c1[b]) | (e1 == c2[b]) | (e2 == c0[b]) | (e2 == c1[b]) |
                            (e2 == c2[b]);
        keep[b] = static_cast<std::uint32_t>(corner & boxes & !shared);
        any |= keep[b];
      }
      if (!any) continue;
      for (std::size_t b = a + 1; b < m; ++b)
        if (keep[b]) test(a, b);
    }
  }

 private:
  static constexpr std::uint32_t kNone = UINT32_MAX;  // (no vertex has this index)
  std::vector<float> lo_[3], hi_[3];
  std::vector<std::uint32_t> corner_[3], flags_;
  std::vector<std::uint32_t> keep_;
};

// Grid limits: beyond them the grid would not pay and CGAL's box tree is used.
constexpr double kMaxEntriesPerFace = 12.0;  // cells a face's box covers, on average
constexpr double kMaxPairsPerFace = 128.0;   // candidate pairs, on average

}  // namespace

std::size_t countSelfIntersections(const std::vector<Vec3f>& points,
                                   const std::vector<FaceIndices>& faces,
                                   const std::function<void(double)>& progress, std::size_t limit,
                                   const FaceFacts& known, std::size_t slabEntries) {
  const std::vector<char>* const embeddedFans = known.embeddedFans;
  const std::vector<Vec3f>& p = points;

  // Memory: nothing is kept per face but one byte (degenerate or not) and the grid's
  // entries; a face's box is found again from its corners wherever it is needed (on a large
  // mesh the tables cost more, in time to fault their memory in, than the recomputing).
  auto boxOf = [&](std::uint32_t face) {
    const FaceIndices& f = faces[face];
    Box b;
    for (int k = 0; k < 3; ++k) {  // floats: exact
      b.lo[k] = std::min({p[f[0]][k], p[f[1]][k], p[f[2]][k]});
      b.hi[k] = std::max({p[f[0]][k], p[f[1]][k], p[f[2]][k]});
    }
    return b;
  };
  // Degenerate faces count as a pair with themselves and take part in nothing else, as in
  // CGAL (CGAL's exact collinearity test per face, unless the caller has it).
  std::vector<char> own;
  if (!known.collinear) {
    own.resize(faces.size());
    tbb::parallel_for(std::size_t(0), faces.size(), [&](std::size_t i) {
      const FaceIndices& f = faces[i];
      own[i] = collinear(p[f[0]], p[f[1]], p[f[2]]);
    });
  }
  const std::vector<char>& dead = known.collinear ? *known.collinear : own;
  struct Extent {
    std::size_t dead = 0;
    Box all{{HUGE_VALF, HUGE_VALF, HUGE_VALF}, {-HUGE_VALF, -HUGE_VALF, -HUGE_VALF}};
  };
  const Extent whole = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, faces.size(), 4096), Extent(),
      [&](const tbb::blocked_range<std::size_t>& range, Extent e) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          if (dead[i]) {
            ++e.dead;
            continue;
          }
          const Box b = boxOf(static_cast<std::uint32_t>(i));
          for (int k = 0; k < 3; ++k) {
            e.all.lo[k] = std::min(e.all.lo[k], b.lo[k]);
            e.all.hi[k] = std::max(e.all.hi[k], b.hi[k]);
          }
        }
        return e;
      },
      [](Extent x, const Extent& y) {
        x.dead += y.dead;
        for (int k = 0; k < 3; ++k) {
          x.all.lo[k] = std::min(x.all.lo[k], y.all.lo[k]);
          x.all.hi[k] = std::max(x.all.hi[k], y.all.hi[k]);
        }
        return x;
      });
  // (a cancel is looked at between the passes over all faces, each 0.3-0.5 s at 48 million)
  auto poll = [&](double fraction) {
    if (progress) progress(fraction);
  };
  poll(0.0);
  std::size_t count = whole.dead;
  const Box& all = whole.all;
  if (faces.size() - count < 2) return count;
  const double n = static_cast<double>(faces.size() - count);

  // Cells twice as large as nine faces in ten (judged on a sample of up to 65,536 faces): a
  // typical face's box then covers one or two cells per axis. (Cells as large as the faces
  // made 4.7 entries a face on the gyroid; each entry reads the face's corners again, while
  // a pair in a cell costs a few vector lanes: twice the size cut the pass by a fifth on
  // the gyroid and the helix at 256 cells, with about 50 pairs a face at most.)
  std::vector<double> extent;
  const std::size_t step = std::max<std::size_t>(1, faces.size() / 65536);
  for (std::size_t f = 0; f < faces.size(); f += step) {
    if (dead[f]) continue;
    const Box b = boxOf(static_cast<std::uint32_t>(f));
    double e = 0.0;
    for (int k = 0; k < 3; ++k) e = std::max(e, double(b.hi[k]) - b.lo[k]);
    extent.push_back(e);
  }
  if (extent.empty()) extent.push_back(0.0);
  const std::size_t tenth = static_cast<std::size_t>(0.9 * static_cast<double>(extent.size() - 1));
  std::nth_element(extent.begin(), extent.begin() + static_cast<std::ptrdiff_t>(tenth),
                   extent.end());
  double cell = 2.0 * extent[tenth];
  // The cells must number under 2^32 (a cell index is 32 bits): a grid finer than that (over
  // 1,600 cells a side) gets larger cells.
  double dims[3];
  bool grid = cell > 0.0 && std::isfinite(cell);
  for (int attempt = 0; grid; ++attempt) {
    double product = 1.0;
    for (int k = 0; k < 3; ++k) {
      dims[k] = std::floor((double(all.hi[k]) - all.lo[k]) * (1.0 / cell)) + 1.0;  // (as index)
      product *= dims[k];
    }
    if (product < 4294967296.0) break;
    cell *= 1.25;
    grid = attempt < 200;
  }
  // (By the reciprocal: every cell index comes from this one function, so entries and the
  // pair rule agree whatever the rounding; v >= all.lo, so truncation is the floor.)
  const double perCell = 1.0 / cell;
  auto index = [&](double v, int k) {
    return static_cast<std::uint32_t>((v - all.lo[k]) * perCell);
  };
  using Cell = std::array<std::uint32_t, 3>;
  auto cellsOf = [&](const Box& b, Cell& lo, Cell& hi) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = index(b.lo[k], k);
      hi[k] = index(b.hi[k], k);
    }
  };
  auto byBoxTree = [&] {
    return count >= limit
               ? limit
               : count + countSelfIntersectionsByBoxTree(points, faces, dead, limit - count);
  };
  if (!grid) return byBoxTree();
  const std::uint64_t dx = static_cast<std::uint64_t>(dims[0]);
  const std::uint64_t dxy = dx * static_cast<std::uint64_t>(dims[1]);
  const std::uint64_t layers = static_cast<std::uint64_t>(dims[2]);

  // The grid is built and searched in slabs of z layers, one after the other, each holding
  // about an eighth of the entries (at least 2^20; `slabEntries` where given): the entries were
  // the check's largest array (105 MB of a 227 MB peak on the gyroid's 2.9 million triangles), and
  // a pair is still tested once, in the one cell (so the one slab) that holds the lowest corner of
  // the two boxes' intersection.
  constexpr std::size_t kBlock = 4096, kBuckets = 256;
  const std::size_t blocks = (faces.size() + kBlock - 1) / kBlock;
  // Calls use(key, face) for every cell in layers [k0, k1) each live face of the block
  // covers, the key counted from the slab's first layer.
  // (Runs of kRun faces that do not reach the slab are skipped: the mesher's faces come
  // brick by brick, so a run spans few layers, and each face is visited about once a pass.)
  struct Layers {
    std::uint32_t lo = UINT32_MAX, hi = 0;
    bool reach(std::uint64_t k0, std::uint64_t k1) const { return lo < k1 && hi >= k0; }
  };
  constexpr std::size_t kRun = 256;  // (divides kBlock: a block's runs are its own)
  std::vector<Layers> runLayers((faces.size() + kRun - 1) / kRun);
  auto forEachEntry = [&](std::size_t block, std::uint64_t k0, std::uint64_t k1, auto&& use) {
    const std::size_t end = std::min(faces.size(), (block + 1) * kBlock);
    for (std::size_t f = block * kBlock; f < end; ++f) {
      if (f % kRun == 0 && !runLayers[f / kRun].reach(k0, k1)) {
        f += kRun - 1;
        continue;
      }
      if (dead[f]) continue;
      Cell lo, hi;
      cellsOf(boxOf(static_cast<std::uint32_t>(f)), lo, hi);
      const std::uint64_t from = std::max<std::uint64_t>(lo[2], k0);
      const std::uint64_t to = std::min<std::uint64_t>(hi[2] + std::uint64_t(1), k1);
      for (std::uint64_t k = from; k < to; ++k)
        for (std::uint64_t j = lo[1]; j <= hi[1]; ++j)
          for (std::uint64_t i = lo[0]; i <= hi[0]; ++i) use((k - k0) * dxy + j * dx + i, f);
    }
  };
  std::optional<Phase> phase(std::in_place, "check: self-intersections: layers",
                             PhaseKind::Parallel);
  // 1. Each block's and run's layers (a slab visits only those that reach into it), the entries
  // by layer, and whether a face covers more cells than all faces together may have (a
  // giant face: CGAL's box tree takes over).
  std::vector<Layers> blockLayers(blocks);
  const bool byLayer = layers <= (std::uint64_t(1) << 16);  // else one slab
  tbb::enumerable_thread_specific<std::vector<double>> perLayer(
      std::vector<double>(byLayer ? layers : 1, 0.0));
  std::atomic<bool> giant{false};
  tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t block) {
    std::vector<double>& counts = perLayer.local();
    Layers& mine = blockLayers[block];
    for (std::size_t f = block * kBlock; f < std::min(faces.size(), (block + 1) * kBlock); ++f) {
      if (dead[f]) continue;
      Cell lo, hi;
      cellsOf(boxOf(static_cast<std::uint32_t>(f)), lo, hi);
      const double across = static_cast<double>(hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1);
      if (across * (hi[2] - lo[2] + 1) > kMaxEntriesPerFace * n) {
        giant = true;
        return;
      }
      for (Layers* l : {&mine, &runLayers[f / kRun]}) {
        l->lo = std::min(l->lo, lo[2]);
        l->hi = std::max(l->hi, hi[2]);
      }
      for (std::uint64_t k = lo[2]; k <= hi[2]; ++k) counts[byLayer ? k : 0] += across;
    }
  });
  poll(0.0);
  std::vector<double> layerEntries(byLayer ? layers : 1, 0.0);
  for (const std::vector<double>& counts : perLayer)
    for (std::size_t k = 0; k < counts.size(); ++k) layerEntries[k] += counts[k];
  double totalEntries = 0.0;
  for (double e : layerEntries) totalEntries += e;
  if (giant || totalEntries > kMaxEntriesPerFace * n) return byBoxTree();
  std::vector<std::uint64_t> slabStart{0};
  const double perSlab = slabEntries > 0
                             ? static_cast<double>(slabEntries)
                             : std::max(static_cast<double>(1 << 20), totalEntries / 8.0);
  if (byLayer) {
    double inSlab = 0.0;
    for (std::uint64_t k = 0; k < layers; ++k) {
      if (inSlab > 0.0 && inSlab + layerEntries[k] > perSlab) {
        slabStart.push_back(k);
        inSlab = 0.0;
      }
      inSlab += layerEntries[k];
    }
  }
  slabStart.push_back(layers);

  tbb::enumerable_thread_specific<std::size_t> found(0);
  tbb::enumerable_thread_specific<CellFaces> cellFaces;
  std::vector<std::uint64_t> entries;
  std::vector<std::size_t> at;  // by block, then bucket: where the block writes next
  tbb::enumerable_thread_specific<std::vector<std::uint64_t>> scratch;
  double pairs = 0.0, entriesBefore = 0.0;
  for (std::size_t slab = 0; slab + 1 < slabStart.size(); ++slab) {
    const std::uint64_t k0 = slabStart[slab], k1 = slabStart[slab + 1];
    auto reaches = [&](std::size_t block) { return blockLayers[block].reach(k0, k1); };
    phase.emplace("check: self-intersections: entries", PhaseKind::Parallel);
    // 2. The slab's entries, (cell << 32 | face) for every cell a face's box covers,
    // grouped by cell: a counting sort on the cell's top 8 bits straight into place (each
    // block of faces counts its entries per bucket, then writes them where its counts
    // say), then each bucket sorted on the remaining bits in parallel, with a scratch the
    // size of one bucket. (Two whole-array radix passes needed a second array as large as
    // the entries.)
    int keyBits = 1;
    while (keyBits < 32 && (std::uint64_t(1) << keyBits) < dxy * (k1 - k0)) ++keyBits;
    const int topShift = std::max(0, keyBits - 8);
    at.assign(blocks * kBuckets, 0);
    poll(std::min(1.0, entriesBefore / totalEntries));
    tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t block) {
      if (!reaches(block)) return;
      std::size_t* mine = &at[block * kBuckets];
      forEachEntry(block, k0, k1, [&](std::uint64_t key, std::size_t) { ++mine[key >> topShift]; });
    });
    std::size_t total = 0;
    std::vector<std::size_t> bucketStart(kBuckets + 1, 0);
    for (std::size_t bucket = 0; bucket < kBuckets; ++bucket) {
      bucketStart[bucket] = total;
      for (std::size_t block = 0; block < blocks; ++block) {
        const std::size_t c = at[block * kBuckets + bucket];
        at[block * kBuckets + bucket] = total;
        total += c;
      }
    }
    bucketStart[kBuckets] = total;
    entries.resize(total);
    poll(std::min(1.0, entriesBefore / totalEntries));
    tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t block) {
      if (!reaches(block)) return;
      std::size_t* next = &at[block * kBuckets];
      forEachEntry(block, k0, k1, [&](std::uint64_t key, std::size_t f) {
        entries[next[key >> topShift]++] = key << 32 | f;
      });
    });
    auto cellOf = [&](std::size_t e) { return entries[e] >> 32; };
    tbb::enumerable_thread_specific<double> bucketPairs(0.0);
    phase.emplace("check: self-intersections: cells sorted", PhaseKind::Parallel);
    poll(std::min(1.0, entriesBefore / totalEntries));
    tbb::parallel_for(std::size_t(0), kBuckets, [&](std::size_t bucket) {
      const std::size_t from = bucketStart[bucket], size = bucketStart[bucket + 1] - from;
      if (size < 2) return;
      std::vector<std::uint64_t>& temp = scratch.local();
      temp.resize(size);
      std::uint64_t* in = &entries[from];
      std::uint64_t* out = temp.data();
      // LSD passes of up to 12 bits over the cell bits below the top 8 (stable: a cell's
      // faces stay in order)
      for (int shift = 0; shift < topShift; shift += 12) {
        const int width = std::min(12, topShift - shift);
        std::vector<std::size_t> start((std::size_t(1) << width) + 1, 0);
        const std::uint64_t mask = (std::uint64_t(1) << width) - 1;
        for (std::size_t e = 0; e < size; ++e) ++start[((in[e] >> (32 + shift)) & mask) + 1];
        for (std::size_t d = 1; d < start.size(); ++d) start[d] += start[d - 1];
        for (std::size_t e = 0; e < size; ++e) out[start[(in[e] >> (32 + shift)) & mask]++] = in[e];
        std::swap(in, out);
      }
      if (in != &entries[from]) std::copy(in, in + size, &entries[from]);
      // The cells are runs of entries (a cell's entries lie in one bucket); no table of them
      // is kept. The work their pairs make:
      double& mine = bucketPairs.local();
      for (std::size_t e = from, last = from + size; e < last;) {
        std::size_t end = e + 1;
        while (end < last && cellOf(end) == cellOf(e)) ++end;
        const double m = static_cast<double>(end - e);
        mine += m * (m - 1) / 2;
        e = end;
      }
    });
    // (all slabs so far)
    for (double& b : bucketPairs) {
      pairs += b;
      b = 0.0;
    }
    if (pairs > kMaxPairsPerFace * n) return byBoxTree();
    // A range of entries [begin, end) stands for the cells that start in it.
    auto startsCell = [&](std::size_t e) { return e == 0 || cellOf(e) != cellOf(e - 1); };

    phase.emplace("check: self-intersections: pairs", PhaseKind::Parallel);
    // 3. Each pair of overlapping boxes is tested once: in the cell holding the lowest
    // corner of the two boxes' intersection (both boxes cover that cell). In parts of
    // about a twentieth of the slab each, so progress (and a cancel) comes between them.
    const std::size_t part = std::max<std::size_t>(1, total / 20);
    for (std::size_t begin = 0; begin < total; begin += part) {
      if (progress)
        progress(std::min(1.0, (entriesBefore + static_cast<double>(begin)) / totalEntries));
      std::size_t sofar = count;
      for (std::size_t c : found) sofar += c;
      if (sofar >= limit) return limit;
      const std::size_t end = std::min(total, begin + part);
      tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end, 1024),
                        [&](const tbb::blocked_range<std::size_t>& range) {
                          std::size_t& local = found.local();
                          CellFaces& cell = cellFaces.local();
                          for (std::size_t next = range.begin(); next < range.end();) {
                            if (!startsCell(next)) {
                              ++next;
                              continue;
                            }
                            const std::size_t from = next;
                            std::size_t to = from + 1;
                            while (to < total && cellOf(to) == cellOf(from)) ++to;
                            next = to;
                            if (to - from < 2) continue;
                            const std::uint64_t here = cellOf(from);
                            const Cell c = {static_cast<std::uint32_t>(here % dx),
                                            static_cast<std::uint32_t>(here % dxy / dx),
                                            static_cast<std::uint32_t>(here / dxy + k0)};
                            cell.resize(to - from);
                            for (std::size_t e = from; e < to; ++e) {
                              const std::uint32_t f = static_cast<std::uint32_t>(entries[e]);
                              const Box box = boxOf(f);
                              Cell lo, hi;
                              cellsOf(box, lo, hi);
                              std::uint32_t flags = 0;
                              for (int k = 0; k < 3; ++k) {
                                flags |= static_cast<std::uint32_t>(lo[k] == c[k]) << k;
                                if (embeddedFans && (*embeddedFans)[faces[f][k]]) flags |= 8u << k;
                              }
                              cell.set(e - from, box, faces[f], flags);
                            }
                            cell.forEachCandidate([&](std::size_t a, std::size_t b) {
                              if (facesIntersect(points, cell.corners(a), cell.corners(b))) ++local;
                            });
                          }
                        });
    }
    entriesBefore += static_cast<double>(total);
  }
  if (progress) progress(1.0);
  for (std::size_t c : found) count += c;
  return std::min(count, limit);
}

}  // namespace frep
