// The check's passes; CGAL's predicates and routines stay in the check's few files that
// include CGAL (slow to compile).
#include "check/mesh_check.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <tuple>

#include "base/phase_times.h"
#include "base/progress.h"
#include "base/triangle_geometry.h"
#include "check/cgal_surface.h"
#include "check/face_pair_test.h"
#include "check/mesh_check_passes.h"
#include "check/self_intersections.h"
#include "check/volume_nesting.h"

namespace frep {

namespace {

// The same partition, joined from every thread at once: a root is linked below a smaller one
// by compare-and-swap, and finds halve their paths the same way. Parents only ever move to
// an ancestor with a smaller index, so no cycle can form, and a stale read costs a retry.
class ConcurrentUnionFind {
 public:
  explicit ConcurrentUnionFind(std::size_t n) : parent_(n) {
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
      parent_[i].store(static_cast<std::uint32_t>(i), std::memory_order_relaxed);
    });
  }
  std::uint32_t find(std::uint32_t x) {
    for (;;) {
      std::uint32_t p = parent_[x].load(std::memory_order_relaxed);
      if (p == x) return x;
      const std::uint32_t up = parent_[p].load(std::memory_order_relaxed);
      if (up != p) parent_[x].compare_exchange_weak(p, up, std::memory_order_relaxed);
      x = up;
    }
  }
  void join(std::uint32_t a, std::uint32_t b) {
    for (;;) {
      a = find(a);
      b = find(b);
      if (a == b) return;
      if (a < b) std::swap(a, b);
      std::uint32_t expected = a;
      if (parent_[a].compare_exchange_strong(expected, b, std::memory_order_acq_rel)) return;
    }
  }

 private:
  std::vector<std::atomic<std::uint32_t>> parent_;
};

std::string count(std::size_t n, const char* what) {
  return std::to_string(n) + " " + what;
}

// Several closed components bound a volume, outward, when each is outward at an even depth
// of nesting and inward at an odd one: ray parity with exact predicates
// (check/volume_nesting.h), else CGAL's does_bound_a_volume (which also takes a nest turned
// wholly inside out) and a positive volume, the rule this check had before. A test compares
// the two on 200 random nests.
bool severalBoundAVolume(const std::vector<Vec3f>& pos, const std::vector<FaceIndices>& faces,
                         const UnionFind& parts, double volume) {
  // Components numbered in their root vertices' order, each face's found in parallel (the
  // parts point straight at their roots: checkMesh flattens them).
  std::unique_ptr<std::atomic<std::uint8_t>[]> used(new std::atomic<std::uint8_t>[pos.size()]);
  tbb::parallel_for(std::size_t(0), pos.size(),
                    [&](std::size_t v) { used[v].store(0, std::memory_order_relaxed); });
  tbb::parallel_for(std::size_t(0), faces.size(), [&](std::size_t f) {
    used[parts.parent[faces[f][0]]].store(1, std::memory_order_relaxed);
  });
  std::vector<std::uint32_t> index(pos.size(), UINT32_MAX), component(faces.size());
  std::uint32_t components = 0;
  for (std::size_t v = 0; v < pos.size(); ++v)
    if (used[v].load(std::memory_order_relaxed)) index[v] = components++;
  tbb::parallel_for(std::size_t(0), faces.size(),
                    [&](std::size_t f) { component[f] = index[parts.parent[faces[f][0]]]; });
  const std::optional<bool> byRays = boundsAVolumeByRays(pos, faces, component, components);
  return byRays ? *byRays : boundsAVolume(pos, faces) && volume > 0;
}

}  // namespace

namespace {

// Equal means equal as floats, so -0 and +0 hash alike.
std::uint64_t pointHash(const Vec3f& p) {
  auto bits = [](float x) {
    if (x == 0.0f) x = 0.0f;
    std::uint32_t b;
    std::memcpy(&b, &x, sizeof b);
    return static_cast<std::uint64_t>(b);
  };
  std::uint64_t h = (bits(p[0]) * 0x9E3779B97F4A7C15ull) ^ (bits(p[1]) * 0xC2B2AE3D27D4EB4Full) ^
                    (bits(p[2]) * 0x165667B19E3779F9ull);
  return h ^ (h >> 29);
}

std::size_t tableSlots(std::size_t points) {  // twice as many slots as points, a power of 2
  std::size_t slots = 16;
  while (slots < 2 * points) slots *= 2;
  return slots;
}

}  // namespace

std::vector<std::uint32_t> distinctPoints(const std::vector<Vec3f>& pos,
                                          std::vector<std::uint32_t>* first,
                                          const Progress& cancel) {
  // In parallel, and the same on any number of threads: an open-addressing table of the
  // distinct points (twice as many slots as points) whose slot keeps the least index with
  // its coordinates, brought down to it by compare-and-swap (a slot, once it holds a point,
  // only ever holds indices with that point); then each point's least twin, and the twins'
  // numbers in order. (A serial pass with a table took 8 % of `frepcad check` of the
  // gyroid's STL, 8.6 million soup points.)
  const std::size_t n = pos.size();
  if (n >= UINT32_MAX) throw std::length_error("distinctPoints: over 2^32 points");
  const std::size_t slots = tableSlots(n);
  const std::uint64_t mask = slots - 1;
  std::unique_ptr<std::atomic<std::uint32_t>[]> table(new std::atomic<std::uint32_t>[slots]);
  slicedParallelFor(slots, 1 << 16, cancel.sub(0.0, 0.0),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i != r.end(); ++i)
                        table[i].store(UINT32_MAX, std::memory_order_relaxed);
                    });
  // (returns the slot p's twins share; *twin: another index with p's coordinates was there)
  auto slotOf = [&](std::uint32_t i, bool insert, bool* twin) -> std::atomic<std::uint32_t>& {
    const Vec3f& p = pos[i];
    for (std::uint64_t h = pointHash(p) & mask;; h = (h + 1) & mask) {
      std::uint32_t held = table[h].load(std::memory_order_acquire);
      while (held == UINT32_MAX && insert &&
             !table[h].compare_exchange_weak(held, i, std::memory_order_acq_rel)) {
      }
      if (held == UINT32_MAX) return table[h];  // (inserted)
      if (held == i || pos[held] == p) {        // (itself: a NaN equals nothing)
        *twin = *twin || held != i;
        while (insert && i < held &&
               !table[h].compare_exchange_weak(held, i, std::memory_order_acq_rel)) {
        }
        return table[h];
      }
    }
  };
  // Of two twins, the one inserted second meets the first: where no insertion met a twin,
  // all points are distinct (every mesh the mesher makes) and the map is the identity.
  std::atomic<bool> twins{false};
  slicedParallelFor(n, 4096, cancel, [&](const tbb::blocked_range<std::size_t>& r) {
    bool found = false;
    for (std::size_t i = r.begin(); i != r.end(); ++i)
      slotOf(static_cast<std::uint32_t>(i), true, &found);
    if (found) twins = true;
  });
  std::vector<std::uint32_t> map(n);
  cancel.step(0.0);
  if (!twins) {
    table.reset();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 16),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t i = r.begin(); i != r.end(); ++i)
                          map[i] = static_cast<std::uint32_t>(i);
                      });
    *first = map;
    return map;
  }
  // each point's least twin
  slicedParallelFor(n, 4096, cancel, [&](const tbb::blocked_range<std::size_t>& r) {
    bool unused = false;
    for (std::size_t i = r.begin(); i != r.end(); ++i)
      map[i] =
          slotOf(static_cast<std::uint32_t>(i), false, &unused).load(std::memory_order_relaxed);
  });
  table.reset();
  cancel.step(0.0);
  // The first of each set of twins, numbered in order: by fixed blocks, counted, then
  // written from each block's offset.
  constexpr std::size_t kBlock = 1 << 16;
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<std::uint32_t> offset(blocks + 1, 0);
  tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t b) {
    std::uint32_t c = 0;
    for (std::size_t i = b * kBlock; i < std::min(n, (b + 1) * kBlock); ++i) c += map[i] == i;
    offset[b + 1] = c;
  });
  for (std::size_t b = 0; b < blocks; ++b) offset[b + 1] += offset[b];
  first->resize(offset[blocks]);
  std::vector<std::uint32_t> number(n);
  tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t b) {
    std::uint32_t next = offset[b];
    for (std::size_t i = b * kBlock; i < std::min(n, (b + 1) * kBlock); ++i)
      if (map[i] == i) {
        (*first)[next] = static_cast<std::uint32_t>(i);
        number[i] = next++;
      }
  });
  slicedParallelFor(n, 4096, cancel, [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) map[i] = number[map[i]];
  });
  return map;
}

std::vector<std::uint32_t> weldIdenticalVertices(const std::vector<Vec3f>& pos,
                                                 std::vector<Vec3f>& welded) {
  std::vector<std::uint32_t> first;
  std::vector<std::uint32_t> map = distinctPoints(pos, &first);
  welded.reserve(welded.size() + first.size());
  const std::uint32_t base = static_cast<std::uint32_t>(welded.size());
  for (std::uint32_t i : first) welded.push_back(pos[i]);
  if (base != 0)
    for (std::uint32_t& m : map) m += base;
  return map;
}

void sumAreaAndVolume(const std::vector<Vec3f>& pos, const std::vector<FaceIndices>& faces,
                      double* area, double* volume, const Progress& progress) {
  // Summed by fixed blocks of faces in parallel and the blocks in order: the same sums on
  // any number of threads.
  constexpr std::size_t kBlock = 16384;
  const std::size_t blocks = (faces.size() + kBlock - 1) / kBlock;
  std::vector<std::array<double, 2>> partial(blocks, {0.0, 0.0});
  slicedParallelFor(
      blocks, 1, progress,
      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t block = r.begin(); block != r.end(); ++block)
          for (std::size_t i = block * kBlock; i < std::min(faces.size(), (block + 1) * kBlock);
               ++i) {
            const FaceIndices& f = faces[i];
            partial[block][0] += triangleArea(pos[f[0]], pos[f[1]], pos[f[2]]);
            partial[block][1] += signedTetraVolume(pos[f[0]], pos[f[1]], pos[f[2]]);
          }
      },
      kPassSlice / kBlock);
  for (const auto& [a, v] : partial) {
    *area += a;
    *volume += v;
  }
}

std::size_t collinearFaces(const std::vector<Vec3f>& pos, const std::vector<FaceIndices>& faces,
                           std::vector<char>* collinearFace, const Progress& progress) {
  // CGAL's exact test, in parallel.
  collinearFace->assign(faces.size(), 0);
  return slicedParallelReduce(
      faces.size(), 4096, progress, std::size_t(0),
      [&](const tbb::blocked_range<std::size_t>& range, std::size_t n) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          const FaceIndices& f = faces[i];
          (*collinearFace)[i] = collinear(pos[f[0]], pos[f[1]], pos[f[2]]);
          n += (*collinearFace)[i];
        }
        return n;
      },
      std::plus<std::size_t>());
}

// Vertices of up to this many faces are judged on the quick path first.
constexpr std::uint32_t kQuickFan = 24;

void vertexFaces(std::size_t vertices, const std::vector<FaceIndices>& faces,
                 std::vector<std::uint32_t>* startOut, std::vector<std::uint32_t>* incidentOut,
                 const Progress& progress) {
  // In parallel: each vertex's faces counted and then placed through atomic cursors (in any
  // order), then each vertex's few faces sorted, so the table is the same on any number of
  // threads. (Filled serially, the table was 4 % of the gyroid's whole export on one thread,
  // all of it serial.)
  std::vector<std::uint32_t>& start = *startOut;
  std::vector<std::uint32_t>& incident = *incidentOut;
  std::unique_ptr<std::atomic<std::uint32_t>[]> cursor(new std::atomic<std::uint32_t>[vertices]);
  constexpr std::size_t kGrain = 1 << 14;
  slicedParallelFor(vertices, kGrain, progress, [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t v = r.begin(); v != r.end(); ++v)
      cursor[v].store(0, std::memory_order_relaxed);
  });
  slicedParallelFor(faces.size(), kGrain, progress, [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t f = r.begin(); f != r.end(); ++f)
      for (std::uint32_t v : faces[f]) cursor[v].fetch_add(1, std::memory_order_relaxed);
  });
  start.resize(vertices + 1);
  start[0] = 0;
  for (std::size_t v = 0; v < vertices; ++v)
    start[v + 1] = start[v] + cursor[v].load(std::memory_order_relaxed);
  incident.resize(faces.size() * 3);
  slicedParallelFor(vertices, kGrain, progress, [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t v = r.begin(); v != r.end(); ++v)
      cursor[v].store(start[v], std::memory_order_relaxed);
  });
  slicedParallelFor(faces.size(), kGrain, progress, [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t f = r.begin(); f != r.end(); ++f)
      for (std::uint32_t v : faces[f])
        incident[cursor[v].fetch_add(1, std::memory_order_relaxed)] = static_cast<std::uint32_t>(f);
  });
  slicedParallelFor(vertices, kGrain, progress, [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t v = r.begin(); v != r.end(); ++v) {
      std::uint32_t* b = incident.data() + start[v];
      std::uint32_t* e = incident.data() + start[v + 1];
      if (e - b > 32) {  // (a pile of copies: 100,000 faces on a vertex)
        std::sort(b, e);
        continue;
      }
      for (std::uint32_t* i = b + 1; i < e; ++i)  // (insertion: a few each)
        for (std::uint32_t* j = i; j > b && j[-1] > j[0]; --j) std::swap(j[-1], j[0]);
    }
  });
}

void judgeVertices(const std::vector<Vec3f>& pos, const std::vector<FaceIndices>& faces,
                   const std::vector<char>* judged, bool edgesToOthers, CheckReport* r,
                   std::vector<char>* fans, const std::vector<std::uint32_t>& start,
                   const std::vector<std::uint32_t>& incident, const Progress& progress) {
  std::vector<char>& embeddedFan = *fans;
  // Edges and vertices, in one pass over every vertex's incident faces (no table of all 3F
  // edges to sort): an edge {v, w}, w > v, lies in exactly the faces round v that hold w, so
  // the run of w among v's neighbours gives its face count (1: a border edge, over 2:
  // non-manifold) and its directions (two faces must run it opposite ways); and the faces
  // round v that share a neighbour must join into a single fan (else a non-manifold vertex).
  // Vertices whose fan of faces is proved embedded (face_pair_test.h): the self-intersection
  // pass need not test two faces that share one of them.
  embeddedFan.assign(pos.size(), 0);
  struct Counts {
    std::size_t border = 0, nonManifoldEdges = 0, misoriented = 0, nonManifoldVertices = 0;
  };
  const Counts counts = slicedParallelReduce(
      pos.size(), 4096, progress, Counts(),
      [&](const tbb::blocked_range<std::size_t>& range, Counts c) {
        // (other vertex, local face, 1 when the face runs v -> other)
        std::vector<std::tuple<std::uint32_t, std::uint32_t, std::uint8_t>> neighbours;
        std::vector<std::pair<std::uint32_t, std::uint32_t>> sectors;
        UnionFind fans;
        for (std::size_t v = range.begin(); v != range.end(); ++v) {
          const std::uint32_t b = start[v], e = start[v + 1];
          if (e == b || (judged && !(*judged)[v])) continue;
          // The common case first, without sorting: the faces round v form one closed fan
          // whose every edge at v lies in two faces run opposite ways (each face's next
          // vertex is exactly one face's previous one, no two faces share a next vertex,
          // and the walk from face to face visits them all). Such a vertex adds to no
          // count; anything else takes the general path below.
          const std::uint32_t d = e - b;
          if (d <= kQuickFan) {
            std::uint32_t next[kQuickFan], prev[kQuickFan], across[kQuickFan];
            for (std::uint32_t k = 0; k < d; ++k) {
              const FaceIndices& f = faces[incident[b + k]];
              const int at = f[0] == v ? 0 : f[1] == v ? 1 : 2;
              next[k] = f[(at + 1) % 3];
              prev[k] = f[(at + 2) % 3];
            }
            bool oneFan = true;
            for (std::uint32_t k = 0; k < d && oneFan; ++k) {
              std::uint32_t found = 0;
              for (std::uint32_t m = 0; m < d; ++m) {
                if (prev[m] == next[k]) across[k] = m, ++found;
                if (m != k && next[m] == next[k]) found += 2;  // (fails the test below)
              }
              oneFan = found == 1;
            }
            if (oneFan) {
              std::uint32_t k = 0, walked = 0;
              do {
                k = across[k];
                ++walked;
              } while (k != 0 && walked <= d);
              oneFan = walked == d;
            }
            if (oneFan) {
              sectors.clear();
              for (std::uint32_t m = 0; m < d; ++m) sectors.emplace_back(next[m], prev[m]);
              embeddedFan[v] = fanProvedEmbedded(pos, static_cast<std::uint32_t>(v), sectors.data(),
                                                 sectors.size());
              continue;
            }
          }
          neighbours.clear();
          for (std::uint32_t k = b; k < e; ++k) {
            const FaceIndices& f = faces[incident[k]];
            const int at = f[0] == v ? 0 : f[1] == v ? 1 : 2;
            neighbours.emplace_back(static_cast<std::uint32_t>(f[(at + 1) % 3]), k - b, 1);
            neighbours.emplace_back(static_cast<std::uint32_t>(f[(at + 2) % 3]), k - b, 0);
          }
          std::sort(neighbours.begin(), neighbours.end());
          fans.reset(e - b);
          bool sound = true;  // every edge at v in two faces, run opposite ways
          for (std::size_t i = 0; i < neighbours.size();) {
            std::size_t j = i, forward = 0;
            const std::uint32_t w = std::get<0>(neighbours[i]);
            for (; j < neighbours.size() && std::get<0>(neighbours[j]) == w; ++j) {
              forward += std::get<2>(neighbours[j]);
              if (j > i) fans.join(std::get<1>(neighbours[j]), std::get<1>(neighbours[i]));
            }
            sound = sound && j - i == 2 && forward == 1;
            const bool wJudged = !judged || (*judged)[w];
            if (wJudged ? w > v : edgesToOthers) {
              const std::size_t n = j - i;
              c.border += n == 1;
              c.nonManifoldEdges += n > 2;
              c.misoriented += n == 2 && forward != 1;
            }
            i = j;
          }
          std::size_t roots = 0;
          for (std::uint32_t k = 0; k < e - b; ++k) roots += fans.find(k) == k;
          c.nonManifoldVertices += roots > 1;
          if (sound && roots == 1) {  // one closed fan: is it embedded?
            sectors.clear();
            for (std::uint32_t k = b; k < e; ++k) {
              const FaceIndices& f = faces[incident[k]];
              const int at = f[0] == v ? 0 : f[1] == v ? 1 : 2;
              sectors.emplace_back(f[(at + 1) % 3], f[(at + 2) % 3]);
            }
            embeddedFan[v] = fanProvedEmbedded(pos, static_cast<std::uint32_t>(v), sectors.data(),
                                               sectors.size());
          }
        }
        return c;
      },
      [](Counts x, const Counts& y) {
        x.border += y.border;
        x.nonManifoldEdges += y.nonManifoldEdges;
        x.misoriented += y.misoriented;
        x.nonManifoldVertices += y.nonManifoldVertices;
        return x;
      });
  r->borderEdges += counts.border;
  r->nonManifoldEdges += counts.nonManifoldEdges;
  r->misorientedEdges += counts.misoriented;
  r->nonManifoldVertices += counts.nonManifoldVertices;
}

void addReasons(CheckReport& r) {
  if (r.borderEdges)
    r.reasons.push_back(count(r.borderEdges, "border edges: the mesh is not closed (holes)"));
  if (r.nonManifoldEdges)
    r.reasons.push_back(
        count(r.nonManifoldEdges, "non-manifold edges (shared by more than two triangles)"));
  if (r.nonManifoldVertices)
    r.reasons.push_back(
        count(r.nonManifoldVertices, "non-manifold vertices (triangles touching at a point)"));
  if (r.misorientedEdges)
    r.reasons.push_back(
        count(r.misorientedEdges, "edges where neighbouring triangles disagree on orientation"));
  if (r.degenerateFaces)
    r.reasons.push_back(
        count(r.degenerateFaces, "degenerate triangles (repeated or collinear vertices)"));
  if (r.selfIntersections)
    r.reasons.push_back((r.selfIntersectionsAtLeast ? "at least " : "") +
                        count(r.selfIntersections, "pairs of self-intersecting triangles") +
                        (r.selfIntersectionsAtLeast ? " (counting stops there)" : ""));
  if (!r.outward && r.closed && r.nonManifoldEdges == 0 && r.misorientedEdges == 0 &&
      r.selfIntersections == 0 && r.nonManifoldVertices == 0)
    r.reasons.push_back("not outward-oriented: the triangles face into the solid");
}

CheckReport checkMesh(const TriangleMesh& mesh, const std::function<void(double)>& progress,
                      std::size_t selfIntersectionLimit) {
  // (the check cannot be cancelled but by its caller's throwing from `progress`, which is
  // called between every two passes: each pass is the longest a cancel waits, 0.6 s at
  // 12 million triangles on 2 cores)
  const Progress bar(progress ? ProgressCallback([&progress](double f) {
    progress(f);
    return true;
  })
                              : ProgressCallback());
  auto tick = [&bar](double f) { bar.report(f); };
  std::optional<Phase> phase(std::in_place, "check: finite coordinates, indices",
                             PhaseKind::Serial);
  CheckReport r;
  r.inputVertices = mesh.positions.size();
  r.faces = mesh.triangles.size();
  for (const Vec3f& p : mesh.positions)
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) ++r.nonFiniteVertices;
  if (r.faces == 0) r.reasons.push_back("empty: the mesh has no triangles");
  if (r.nonFiniteVertices) {
    r.reasons.push_back(count(r.nonFiniteVertices, "vertices with non-finite coordinates"));
    return r;
  }
  for (const Triangle& t : mesh.triangles)
    for (std::uint32_t v : t)
      if (v >= mesh.positions.size()) {
        r.reasons.push_back("a triangle refers to a vertex that does not exist");
        return r;
      }

  // Memory: each pass keeps only what the later ones need (the check of a large file must
  // not cost many times the file): 12 bytes per face for the welded faces, the rest freed
  // as soon as its pass is done. Where no two vertices share coordinates and no face
  // repeats a vertex (every mesh the mesher makes), the mesh's own arrays are checked, not
  // copies (a third of the check's peak memory on the gyroid).
  std::vector<Vec3f> weldedPositions;
  std::vector<FaceIndices> weldedFaces;  // faces with three distinct vertices
  const std::vector<Vec3f>* posOf = &mesh.positions;
  const std::vector<FaceIndices>* facesOf = &mesh.triangles;
  {
    phase.emplace("check: distinct points", PhaseKind::Parallel);
    std::vector<std::uint32_t> first;
    const std::vector<std::uint32_t> map =
        distinctPoints(mesh.positions, &first, bar.sub(0.0, 0.02));
    tick(0.02);
    phase.emplace("check: repeated vertices, welded copies", PhaseKind::Serial);
    r.vertices = first.size();
    auto repeats = [](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
      return a == b || b == c || a == c;
    };
    const bool identity = first.size() == mesh.positions.size();
    const bool repeating =
        !identity || std::any_of(mesh.triangles.begin(), mesh.triangles.end(),
                                 [&](const Triangle& t) { return repeats(t[0], t[1], t[2]); });
    if (!identity) {
      weldedPositions.reserve(first.size());
      for (std::uint32_t i : first) weldedPositions.push_back(mesh.positions[i]);
      posOf = &weldedPositions;
    }
    if (repeating) {
      // Faces, degenerate ones.
      weldedFaces.reserve(mesh.triangles.size());
      for (const Triangle& t : mesh.triangles) {
        const std::uint32_t a = map[t[0]], b = map[t[1]], c = map[t[2]];
        if (repeats(a, b, c)) {
          ++r.degenerateFaces;
          continue;
        }
        weldedFaces.push_back({a, b, c});
      }
      facesOf = &weldedFaces;
    }
  }
  const std::vector<Vec3f>& pos = *posOf;
  const std::vector<FaceIndices>& faces = *facesOf;
  // Volume, area, bounding box.
  tick(0.04);
  phase.emplace("check: area, volume, degenerate faces", PhaseKind::Parallel);
  sumAreaAndVolume(pos, faces, &r.area, &r.volume, bar.sub(0.04, 0.015));
  std::vector<char> collinearFace;
  r.degenerateFaces += collinearFaces(pos, faces, &collinearFace, bar.sub(0.055, 0.015));
  tick(0.07);
  phase.emplace("check: bounding box", PhaseKind::Serial);
  if (!pos.empty()) {
    r.bbox.lo = {pos[0][0], pos[0][1], pos[0][2]};
    r.bbox.hi = r.bbox.lo;
    for (const Vec3f& p : pos)
      for (int a = 0; a < 3; ++a) {
        r.bbox.lo[a] = std::min(r.bbox.lo[a], double(p[a]));
        r.bbox.hi[a] = std::max(r.bbox.hi[a], double(p[a]));
      }
  }

  tick(0.1);
  std::vector<char> embeddedFan;
  phase.emplace("check: the vertex -> faces table", PhaseKind::Parallel);
  std::vector<std::uint32_t> start, incident;
  vertexFaces(pos.size(), faces, &start, &incident, bar.sub(0.1, 0.1));
  tick(0.2);
  phase.emplace("check: edges and fans", PhaseKind::Parallel);
  judgeVertices(pos, faces, nullptr, true, &r, &embeddedFan, start, incident, bar.sub(0.2, 0.1));
  r.closed = r.borderEdges == 0 && !faces.empty();

  tick(0.3);
  // Connected components (through shared edges and vertices), joined in parallel, then each
  // vertex pointed straight at its root.
  phase.emplace("check: components", PhaseKind::Parallel);
  UnionFind parts(pos.size());
  {
    ConcurrentUnionFind joined(pos.size());
    slicedParallelFor(faces.size(), 4096, bar.sub(0.3, 0.02),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t i = r.begin(); i != r.end(); ++i) {
                          const FaceIndices& f = faces[i];
                          joined.join(f[0], f[1]);
                          joined.join(f[0], f[2]);
                        }
                      });
    slicedParallelFor(pos.size(), 4096, bar.sub(0.32, 0.01),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t v = r.begin(); v != r.end(); ++v)
                          parts.parent[v] = joined.find(static_cast<std::uint32_t>(v));
                      });
  }
  tick(0.33);
  phase.emplace("check: components counted", PhaseKind::Serial);
  for (std::uint32_t v = 0; v < pos.size(); ++v)
    if (start[v + 1] > start[v] && parts.parent[v] == v) ++r.components;
  std::vector<std::uint32_t>().swap(incident);  // (16 bytes a face, not needed again)
  std::vector<std::uint32_t>().swap(start);

  tick(0.35);
  // Self-intersections and orientation, CGAL's judgements. Whether the soup is a polygon
  // mesh follows from the counts above, which test exactly what CGAL's
  // is_polygon_soup_a_polygon_mesh does (every edge in at most two faces, in opposite
  // directions; one fan of faces round every vertex; no face repeating a vertex, those
  // having been set aside), in a fraction of its time (it took 40 % of the check on a
  // 1.4 million triangle mesh).
  if (!faces.empty()) {
    const bool polygonMesh =
        r.nonManifoldEdges == 0 && r.misorientedEdges == 0 && r.nonManifoldVertices == 0;
    const std::vector<FaceIndices>& indexed = faces;
    tick(0.45);
    const Progress intersections = bar.sub(0.45, 0.5);
    phase.emplace("check: self-intersections", PhaseKind::Parallel);
    // A polygon mesh (every export the mesher makes) through the hash grid; any other soup
    // through CGAL's own routine, once orient_polygon_soup has made it a polygon mesh.
    r.selfIntersections =
        polygonMesh ? countSelfIntersections(
                          pos, indexed, [&intersections](double f) { intersections.report(f); },
                          selfIntersectionLimit, FaceFacts{&collinearFace, &embeddedFan})
                    : countSelfIntersectionsWithCgal(pos, indexed, false, selfIntersectionLimit);
    r.selfIntersectionsAtLeast = r.selfIntersections >= selfIntersectionLimit;
    tick(0.95);
    phase.emplace("check: outward", PhaseKind::Parallel);
    if (r.closed && polygonMesh && r.selfIntersections == 0)
      // One closed, consistently oriented, self-intersection-free component bounds a volume,
      // outward exactly when its signed volume is positive: CGAL's does_bound_a_volume (a
      // Surface_mesh, about 110 bytes a face, 0.5 s for a million) decides only nestings.
      r.outward =
          r.components == 1 ? r.volume > 0 : severalBoundAVolume(pos, indexed, parts, r.volume);
  }

  phase.reset();
  tick(1.0);
  addReasons(r);
  return r;
}

}  // namespace frep
