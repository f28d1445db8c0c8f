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
constexpr double kMaxEntriesPerFace = 12.0;     // cells a face's box covers, on average
constexpr double kMaxPairsPerFace = 64.0;       // candidate pairs, on average

}  // namespace

std::size_t countSelfIntersections(const std::vector<Vec3f>& points,
                                   const std::vector<FaceIndices>& faces,
                                   const std::function<void(double)>& progress,
                                   std::size_t limit) {
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
                        degenerate[i] = collinear(p[f[0]], p[f[1]], p[f[2]]);
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
  std::vector<double> extent;
  extent.reserve(faces.size());
  Box all{{HUGE_VALF, HUGE_VALF, HUGE_VALF}, {-HUGE_VALF, -HUGE_VALF, -HUGE_VALF}};
  for (std::uint32_t i = 0; i < faces.size(); ++i) {
    if (degenerate[i]) {
      ++count;
      continue;
    }
    const Box& b = boxes[i];
    double e = 0.0;
    for (int k = 0; k < 3; ++k) {
      e = std::max(e, double(b.hi[k]) - b.lo[k]);
      all.lo[k] = std::min(all.lo[k], b.lo[k]);
      all.hi[k] = std::max(all.hi[k], b.hi[k]);
    }
    live.push_back(i);
    extent.push_back(e);
  }
  std::vector<char>().swap(degenerate);
  if (live.size() < 2) return count;
  const double n = static_cast<double>(live.size());

  // Cells about as large as nine faces in ten: a typical face's box then covers at most two
  // cells per axis.
  std::nth_element(extent.begin(), extent.begin() + static_cast<std::ptrdiff_t>(0.9 * (n - 1)),
                   extent.end());
  double cell = extent[static_cast<std::size_t>(0.9 * (n - 1))];
  std::vector<double>().swap(extent);  // (its memory is needed for the grid's entries)
  // An entry is one 64-bit word, cell above face, so the cells must number under 2^32: a
  // grid finer than that (over 1,600 cells a side) gets larger cells.
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
    return static_cast<std::uint64_t>(std::floor((v - all.lo[k]) / cell));
  };
  auto key = [&](std::uint64_t i, std::uint64_t j, std::uint64_t k) {
    return (k * static_cast<std::uint64_t>(dims[1]) + j) * static_cast<std::uint64_t>(dims[0]) + i;
  };
  // (cell << 32 | face) for every cell a face's box covers: sorted, the cells' runs.
  std::vector<std::uint64_t> entries;
  auto cellOf = [&](std::size_t e) { return entries[e] >> 32; };
  auto faceOf = [&](std::size_t e) { return static_cast<std::uint32_t>(entries[e]); };
  // Each live face's cells, counted and then written in parallel at its place in `entries`.
  std::vector<std::size_t> firstEntry;
  if (grid) {
    firstEntry.assign(live.size() + 1, 0);
    const double most = kMaxEntriesPerFace * n;
    tbb::parallel_for(std::size_t(0), live.size(), [&](std::size_t l) {
      const Box& b = boxes[live[l]];
      double cells = 1.0;
      for (int k = 0; k < 3; ++k)
        cells *= static_cast<double>(index(b.hi[k], k) - index(b.lo[k], k) + 1);
      firstEntry[l + 1] = static_cast<std::size_t>(std::min(cells, most + 1.0));
    });
    for (std::size_t l = 0; l < live.size(); ++l) firstEntry[l + 1] += firstEntry[l];
    grid = static_cast<double>(firstEntry.back()) <= most;
  }
  if (grid) {
    entries.resize(firstEntry.back());
    tbb::parallel_for(std::size_t(0), live.size(), [&](std::size_t l) {
      const std::uint32_t f = live[l];
      const Box& b = boxes[f];
      const std::uint64_t i0 = index(b.lo[0], 0), i1 = index(b.hi[0], 0);
      const std::uint64_t j0 = index(b.lo[1], 1), j1 = index(b.hi[1], 1);
      const std::uint64_t k0 = index(b.lo[2], 2), k1 = index(b.hi[2], 2);
      std::size_t at = firstEntry[l];
      for (std::uint64_t k = k0; k <= k1; ++k)
        for (std::uint64_t j = j0; j <= j1; ++j)
          for (std::uint64_t i = i0; i <= i1; ++i) entries[at++] = key(i, j, k) << 32 | f;
    });
    std::vector<std::size_t>().swap(firstEntry);
    tbb::parallel_sort(entries.begin(), entries.end());
  }
  // The cells, as runs of entries; and the work their pairs make.
  std::vector<std::size_t> runs;
  if (grid) {
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
    grid = pairs <= kMaxPairsPerFace * n;
  }
  if (!grid) return countSelfIntersectionsWithCgal(points, faces, true, limit);

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
    tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end, 64),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        std::size_t& local = found.local();
                        for (std::size_t r = range.begin(); r != range.end(); ++r) {
                          const std::size_t from = runs[r], to = runs[r + 1];
                          const std::uint64_t here = cellOf(from);
                          for (std::size_t a = from; a < to; ++a)
                            for (std::size_t b = a + 1; b < to; ++b) {
                              const std::uint32_t fa = faceOf(a), fb = faceOf(b);
                              const Box &ba = boxes[fa], &bb = boxes[fb];
                              if (!overlap(ba, bb)) continue;
                              const std::uint64_t owner =
                                  key(index(std::max(ba.lo[0], bb.lo[0]), 0),
                                      index(std::max(ba.lo[1], bb.lo[1]), 1),
                                      index(std::max(ba.lo[2], bb.lo[2]), 2));
                              if (owner != here) continue;
                              if (facesIntersect(points, faces[fa], faces[fb])) ++local;
                            }
                        }
                      });
  }
  if (progress) progress(1.0);
  for (std::size_t c : found) count += c;
  return std::min(count, limit);
}

}  // namespace frep
