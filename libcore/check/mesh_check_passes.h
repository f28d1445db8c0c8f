// The check's passes (mesh_check.cpp), shared by checkMesh and the check of a mesh in parts
// (partitioned_check.h). Internal to check/.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

#include "base/progress.h"
#include "check/mesh_check.h"
#include "check/self_intersections.h"

namespace frep {

// The passes run over their items in slices of this many, with a look at the caller's
// Progress on the calling thread between two: a pass over 150 million points otherwise kept a
// Ctrl-C waiting for 9 s; a slice takes 0.1-0.7 s on 2 cores.
constexpr std::size_t kPassSlice = std::size_t(1) << 22;

// tbb::parallel_for(blocked_range(0, n, grain), body), `slice` items at a time, with
// progress.step(done / n) before each slice (which throws Cancelled when asked to stop).
template <class Body>
void slicedParallelFor(std::size_t n, std::size_t grain, const Progress& progress, const Body& body,
                       std::size_t slice = kPassSlice) {
  for (std::size_t s = 0; s < n; s += slice) {
    progress.step(static_cast<double>(s) / static_cast<double>(n));
    tbb::parallel_for(tbb::blocked_range<std::size_t>(s, std::min(n, s + slice), grain), body);
  }
}

// tbb::parallel_reduce the same way: the slices' results joined in order.
template <class T, class Body, class Join>
T slicedParallelReduce(std::size_t n, std::size_t grain, const Progress& progress, T value,
                       const Body& body, const Join& join) {
  for (std::size_t s = 0; s < n; s += kPassSlice) {
    progress.step(static_cast<double>(s) / static_cast<double>(n));
    value = join(value, tbb::parallel_reduce(
                            tbb::blocked_range<std::size_t>(s, std::min(n, s + kPassSlice), grain),
                            T(), body, join));
  }
  return value;
}

// A partition of 0 .. n-1 (union-find with path halving).
struct UnionFind {
  std::vector<std::uint32_t> parent;
  explicit UnionFind(std::size_t n = 0) { reset(n); }
  void reset(std::size_t n) {  // n singletons, keeping the storage
    parent.resize(n);
    std::iota(parent.begin(), parent.end(), 0u);
  }
  std::uint32_t find(std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void join(std::uint32_t a, std::uint32_t b) { parent[find(a)] = find(b); }
};

// Area and signed volume of the faces, added to *area and *volume (summed by fixed blocks:
// the same sums on any number of threads).
void sumAreaAndVolume(const std::vector<Vec3f>& pos, const std::vector<FaceIndices>& faces,
                      double* area, double* volume, const Progress& progress = {});
// CGAL's collinear test per face; returns how many are.
std::size_t collinearFaces(const std::vector<Vec3f>& pos, const std::vector<FaceIndices>& faces,
                           std::vector<char>* collinearFace, const Progress& progress = {});
// The edges and vertex fans of the vertices `judged` marks (all when null), added to r's
// border, non-manifold and misoriented counts. An edge {v, w} is counted once, at the lower
// of two judged ends, or at its judged end when `edgesToOthers` (else not at all: the other
// end's judge counts it). Fills *fans (by vertex: proved embedded). `start` and `incident`
// are the vertex -> faces table vertexFaces makes.
void judgeVertices(const std::vector<Vec3f>& pos, const std::vector<FaceIndices>& faces,
                   const std::vector<char>* judged, bool edgesToOthers, CheckReport* r,
                   std::vector<char>* fans, const std::vector<std::uint32_t>& start,
                   const std::vector<std::uint32_t>& incident, const Progress& progress = {});
// The faces round each of `vertices` vertices: those of vertex v are
// incident[start[v] .. start[v + 1]), in increasing order.
void vertexFaces(std::size_t vertices, const std::vector<FaceIndices>& faces,
                 std::vector<std::uint32_t>* start, std::vector<std::uint32_t>* incident,
                 const Progress& progress = {});
// The reasons a report's counts give (its `reasons`, appended).
void addReasons(CheckReport& r);

}  // namespace frep
