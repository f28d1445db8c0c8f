#include "check/self_intersections.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>

#include "check/cgal_surface.h"
#include "check/face_pair_test.h"

namespace frep {

namespace {

struct Box {  // a face's box: floats, exact (the coordinates are floats)
  float lo[3], hi[3];
};

bool overlap(const Box& a, const Box& b) {  // closed boxes, as CGAL's box intersection
  for (int k = 0; k < 3; ++k)
    if (a.hi[k] < b.lo[k] || b.hi[k] < a.lo[k]) return false;
  return true;
}

// Grid limits: beyond them the grid would not pay and CGAL's box tree is used.
constexpr double kMaxEntriesPerFace = 12.0;  // cells a face's box covers, on average
constexpr double kMaxPairsPerFace = 64.0;    // candidate pairs, on average

}  // namespace

std::size_t countSelfIntersections(const std::vector<Vec3f>& points,
                                   const std::vector<FaceIndices>& faces,
                                   const std::function<void(double)>& progress, std::size_t limit,
                                   const FaceFacts& known) {
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
  std::size_t count = whole.dead;
  const Box& all = whole.all;
  if (faces.size() - count < 2) return count;
  const double n = static_cast<double>(faces.size() - count);

  // Cells about as large as nine faces in ten (judged on a sample of up to 65,536 faces): a
  // typical face's box then covers at most two cells per axis.
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
  double cell = extent[tenth];
  // The cells must number under 2^32 (a cell index is 32 bits): a grid finer than that (over
  // 1,600 cells a side) gets larger cells.
  double dims[3];
  bool grid = cell > 0.0 && std::isfinite(cell);
  for (int attempt = 0; grid; ++attempt) {
    double product = 1.0;
    for (int k = 0; k < 3; ++k) {
      dims[k] = std::floor((double(all.hi[k]) - all.lo[k]) / cell) + 1.0;
      product *= dims[k];
    }
    if (product < 4294967296.0) break;
    cell *= 1.25;
    grid = attempt < 200;
  }
  auto index = [&](double v, int k) {
    return static_cast<std::uint32_t>(std::floor((v - all.lo[k]) / cell));
  };
  using Cell = std::array<std::uint32_t, 3>;
  auto cellsOf = [&](const Box& b, Cell& lo, Cell& hi) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = index(b.lo[k], k);
      hi[k] = index(b.hi[k], k);
    }
  };
  const std::uint64_t dx = grid ? static_cast<std::uint64_t>(dims[0]) : 0;
  const std::uint64_t dxy = grid ? dx * static_cast<std::uint64_t>(dims[1]) : 0;
  // The entries, (cell << 32 | face) for every cell a face's box covers, grouped by cell:
  // a counting sort on the cell's top 8 bits straight into place (each block of faces
  // counts its entries per bucket, then writes them where its counts say), then each bucket
  // sorted on the remaining bits in parallel, with a scratch the size of one bucket. (Two
  // whole-array radix passes needed a second array as large as the entries: 105 MB on a
  // 2.9 million triangle mesh.)
  constexpr std::size_t kBlock = 4096, kBuckets = 256;
  const std::size_t blocks = (faces.size() + kBlock - 1) / kBlock;
  int keyBits = 1;
  while (grid && keyBits < 32 &&
         (std::uint64_t(1) << keyBits) < dxy * static_cast<std::uint64_t>(dims[2]))
    ++keyBits;
  const int topShift = std::max(0, keyBits - 8);
  // Calls use(cell key, face) for every cell each live face of the block covers; false,
  // stopping there, at a face that covers more cells than all faces together may have (a
  // giant face: CGAL's box tree takes over).
  auto forEachEntry = [&](std::size_t block, auto&& use) {
    for (std::size_t f = block * kBlock; f < std::min(faces.size(), (block + 1) * kBlock); ++f) {
      if (dead[f]) continue;
      Cell lo, hi;
      cellsOf(boxOf(static_cast<std::uint32_t>(f)), lo, hi);
      double covered = 1.0;
      for (int k = 0; k < 3; ++k) covered *= static_cast<double>(hi[k] - lo[k] + 1);
      if (covered > kMaxEntriesPerFace * n) return false;
      for (std::uint64_t k = lo[2]; k <= hi[2]; ++k)
        for (std::uint64_t j = lo[1]; j <= hi[1]; ++j)
          for (std::uint64_t i = lo[0]; i <= hi[0]; ++i) use(k * dxy + j * dx + i, f);
    }
    return true;
  };
  std::vector<std::size_t> at;  // by block, then bucket: where the block writes next
  std::size_t total = 0;
  if (grid) {
    at.assign(blocks * kBuckets, 0);
    tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t block) {
      std::size_t* mine = &at[block * kBuckets];
      if (!forEachEntry(block, [&](std::uint64_t key, std::size_t) { ++mine[key >> topShift]; }))
        mine[0] += static_cast<std::size_t>(kMaxEntriesPerFace * n) + 1;  // (over the limit)
    });
    for (std::size_t bucket = 0; bucket < kBuckets; ++bucket)
      for (std::size_t block = 0; block < blocks; ++block) {
        const std::size_t c = at[block * kBuckets + bucket];
        at[block * kBuckets + bucket] = total;
        total += c;
      }
    grid = static_cast<double>(total) <= kMaxEntriesPerFace * n;
  }
  if (!grid) return countSelfIntersectionsWithCgal(points, faces, true, limit);
  std::vector<std::uint64_t> entries(total);
  std::vector<std::size_t> bucketStart(kBuckets + 1, total);
  for (std::size_t bucket = 0; bucket < kBuckets; ++bucket) bucketStart[bucket] = at[bucket];
  tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t block) {
    std::size_t* next = &at[block * kBuckets];
    forEachEntry(block, [&](std::uint64_t key, std::size_t f) {
      entries[next[key >> topShift]++] = key << 32 | f;
    });
  });
  std::vector<std::size_t>().swap(at);
  tbb::enumerable_thread_specific<std::vector<std::uint64_t>> scratch;
  tbb::parallel_for(std::size_t(0), kBuckets, [&](std::size_t bucket) {
    const std::size_t from = bucketStart[bucket], size = bucketStart[bucket + 1] - from;
    if (size < 2) return;
    std::vector<std::uint64_t>& temp = scratch.local();
    temp.resize(size);
    std::uint64_t* in = &entries[from];
    std::uint64_t* out = temp.data();
    // LSD passes of up to 12 bits over the cell bits below the top 8 (stable: a cell's faces
    // stay in order)
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
  });
  auto cellOf = [&](std::size_t e) { return entries[e] >> 32; };
  // The cells, as runs of entries; and the work their pairs make.
  std::vector<std::size_t> runs;
  double pairs = 0.0;
  for (std::size_t e = 0; e < entries.size();) {
    std::size_t end = e + 1;
    while (end < entries.size() && cellOf(end) == cellOf(e)) ++end;
    runs.push_back(e);
    const double m = static_cast<double>(end - e);
    pairs += m * (m - 1) / 2;
    e = end;
  }
  runs.push_back(entries.size());
  if (pairs > kMaxPairsPerFace * n)
    return countSelfIntersectionsWithCgal(points, faces, true, limit);

  // Two faces with a common vertex whose fan is proved embedded cannot intersect.
  auto shareEmbeddedFan = [&](const FaceIndices& f, const FaceIndices& g) {
    for (std::uint32_t v : f)
      if ((v == g[0] || v == g[1] || v == g[2]) && (*embeddedFans)[v]) return true;
    return false;
  };
  // Each pair of overlapping boxes is tested once: in the cell holding the lowest corner of
  // the two boxes' intersection (both boxes cover that cell).
  // In parts of about a twentieth each, so progress (and a cancel) comes between them.
  tbb::enumerable_thread_specific<std::size_t> found(0);
  const std::size_t cells = runs.size() - 1, part = std::max<std::size_t>(1, cells / 20);
  for (std::size_t begin = 0; begin < cells; begin += part) {
    if (progress) progress(static_cast<double>(begin) / static_cast<double>(cells));
    std::size_t sofar = count;
    for (std::size_t c : found) sofar += c;
    if (sofar >= limit) return limit;
    const std::size_t end = std::min(cells, begin + part);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end, 256),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        std::size_t& local = found.local();
                        // A cell's faces, copied together first: each pair then reads nearby
                        // memory.
                        struct Item {
                          Box box;
                          Cell lo;
                          std::uint32_t face;
                        };
                        std::vector<Item> items;
                        for (std::size_t r = range.begin(); r != range.end(); ++r) {
                          const std::size_t from = runs[r], to = runs[r + 1];
                          if (to - from < 2) continue;
                          const std::uint64_t here = cellOf(from);
                          const std::uint32_t ci = static_cast<std::uint32_t>(here % dx),
                                              cj = static_cast<std::uint32_t>(here % dxy / dx),
                                              ck = static_cast<std::uint32_t>(here / dxy);
                          items.clear();
                          for (std::size_t e = from; e < to; ++e) {
                            const std::uint32_t f = static_cast<std::uint32_t>(entries[e]);
                            Item item;
                            item.box = boxOf(f);
                            Cell hi;
                            cellsOf(item.box, item.lo, hi);
                            item.face = f;
                            items.push_back(item);
                          }
                          for (std::size_t a = 0; a < items.size(); ++a) {
                            const Item& ia = items[a];
                            for (std::size_t b = a + 1; b < items.size(); ++b) {
                              const Item& ib = items[b];
                              if (!overlap(ia.box, ib.box)) continue;
                              if (std::max(ia.lo[0], ib.lo[0]) != ci ||
                                  std::max(ia.lo[1], ib.lo[1]) != cj ||
                                  std::max(ia.lo[2], ib.lo[2]) != ck)
                                continue;
                              const FaceIndices &fa = faces[ia.face], &fb = faces[ib.face];
                              if (embeddedFans && shareEmbeddedFan(fa, fb)) continue;
                              if (facesIntersect(points, fa, fb)) ++local;
                            }
                          }
                        }
                      });
  }
  if (progress) progress(1.0);
  for (std::size_t c : found) count += c;
  return std::min(count, limit);
}

}  // namespace frep
