#include "check/self_intersections.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
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

  // Degenerate faces count as a pair with themselves and take part in nothing else, as in CGAL.
  // The faces' boxes and degeneracy in parallel (CGAL's exact collinearity test per face),
  // then the live faces in order.
  std::vector<Box> boxes(faces.size());
  std::vector<char> degenerate(faces.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, faces.size(), 4096),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        const FaceIndices& f = faces[i];
                        degenerate[i] = known.collinear ? (*known.collinear)[i]
                                                        : collinear(p[f[0]], p[f[1]], p[f[2]]);
                        Box& b = boxes[i];
                        for (int k = 0; k < 3; ++k) {  // floats: exact
                          b.lo[k] = std::min({p[f[0]][k], p[f[1]][k], p[f[2]][k]});
                          b.hi[k] = std::max({p[f[0]][k], p[f[1]][k], p[f[2]][k]});
                        }
                      }
                    });
  std::size_t count = 0;
  std::vector<std::uint32_t> live;
  live.reserve(faces.size());
  Box all{{HUGE_VALF, HUGE_VALF, HUGE_VALF}, {-HUGE_VALF, -HUGE_VALF, -HUGE_VALF}};
  for (std::uint32_t i = 0; i < faces.size(); ++i) {
    if (degenerate[i]) {
      ++count;
      continue;
    }
    const Box& b = boxes[i];
    for (int k = 0; k < 3; ++k) {
      all.lo[k] = std::min(all.lo[k], b.lo[k]);
      all.hi[k] = std::max(all.hi[k], b.hi[k]);
    }
    live.push_back(i);
  }
  std::vector<char>().swap(degenerate);
  if (live.size() < 2) return count;
  const double n = static_cast<double>(live.size());

  // Cells about as large as nine faces in ten (judged on a sample of up to 65,536 faces): a
  // typical face's box then covers at most two cells per axis.
  std::vector<double> extent;
  const std::size_t step = std::max<std::size_t>(1, live.size() / 65536);
  for (std::size_t l = 0; l < live.size(); l += step) {
    const Box& b = boxes[live[l]];
    double e = 0.0;
    for (int k = 0; k < 3; ++k) e = std::max(e, double(b.hi[k]) - b.lo[k]);
    extent.push_back(e);
  }
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
  const std::uint64_t dx = grid ? static_cast<std::uint64_t>(dims[0]) : 0;
  const std::uint64_t dxy = grid ? dx * static_cast<std::uint64_t>(dims[1]) : 0;
  // Each live face's lowest cell (12 bytes a face: the highest is found again from its box
  // when needed); the entries counted by blocks of faces, so no per-face offsets are kept.
  using Cell = std::array<std::uint32_t, 3>;
  std::vector<Cell> lows;
  constexpr std::size_t kBlock = 4096;
  const std::size_t blocks = (live.size() + kBlock - 1) / kBlock;
  std::vector<std::size_t> blockStart(blocks + 1, 0);
  auto highs = [&](std::size_t l) {
    const Box& b = boxes[live[l]];
    return Cell{index(b.hi[0], 0), index(b.hi[1], 1), index(b.hi[2], 2)};
  };
  if (grid) {
    lows.resize(live.size());
    tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t block) {
      double cells = 0.0;
      for (std::size_t l = block * kBlock; l < std::min(live.size(), (block + 1) * kBlock); ++l) {
        const Box& b = boxes[live[l]];
        Cell& lo = lows[l];
        const Cell hi = highs(l);
        double covered = 1.0;
        for (int k = 0; k < 3; ++k) {
          lo[k] = index(b.lo[k], k);
          covered *= static_cast<double>(hi[k] - lo[k] + 1);
        }
        cells += covered;
      }
      blockStart[block + 1] =
          static_cast<std::size_t>(std::min(cells, kMaxEntriesPerFace * n + 1.0));
    });
    for (std::size_t block = 0; block < blocks; ++block) blockStart[block + 1] += blockStart[block];
    grid = static_cast<double>(blockStart.back()) <= kMaxEntriesPerFace * n;
  }
  if (!grid) return countSelfIntersectionsWithCgal(points, faces, true, limit);

  // (cell << 32 | live index) for every cell a face's box covers, sorted by cell (a radix
  // sort, two passes of 16 bits: the low word is in order already): the cells' runs.
  std::vector<std::uint64_t> entries(blockStart.back());
  tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t block) {
    std::size_t at = blockStart[block];
    for (std::size_t l = block * kBlock; l < std::min(live.size(), (block + 1) * kBlock); ++l) {
      const Cell& lo = lows[l];
      const Cell hi = highs(l);
      for (std::uint64_t k = lo[2]; k <= hi[2]; ++k)
        for (std::uint64_t j = lo[1]; j <= hi[1]; ++j)
          for (std::uint64_t i = lo[0]; i <= hi[0]; ++i)
            entries[at++] = (k * dxy + j * dx + i) << 32 | l;
    }
  });
  {
    std::vector<std::uint64_t> sorted(entries.size());
    for (int shift = 32; shift < 64; shift += 16) {
      std::vector<std::size_t> at(65537, 0);
      for (std::uint64_t e : entries) ++at[((e >> shift) & 0xffff) + 1];
      for (std::size_t b = 1; b < at.size(); ++b) at[b] += at[b - 1];
      for (std::uint64_t e : entries) sorted[at[(e >> shift) & 0xffff]++] = e;
      entries.swap(sorted);
    }
  }
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
                          std::uint32_t lo[3];
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
                            const std::uint32_t l = static_cast<std::uint32_t>(entries[e]);
                            const Cell& c = lows[l];
                            items.push_back({boxes[live[l]], {c[0], c[1], c[2]}, live[l]});
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
