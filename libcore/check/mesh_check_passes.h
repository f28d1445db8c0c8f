// The check's passes (mesh_check.cpp), shared by checkMesh and the check of a mesh in parts
// (partitioned_check.h). Internal to check/.
#pragma once

#include <cstdint>
#include <numeric>
#include <vector>

#include "check/mesh_check.h"
#include "check/self_intersections.h"

namespace frep {

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
                      double* area, double* volume);
// CGAL's collinear test per face; returns how many are.
std::size_t collinearFaces(const std::vector<Vec3f>& pos, const std::vector<FaceIndices>& faces,
                           std::vector<char>* collinearFace);
// The edges and vertex fans of the vertices `judged` marks (all when null), added to r's
// border, non-manifold and misoriented counts. An edge {v, w} is counted once, at the lower
// of two judged ends, or at its judged end when `edgesToOthers` (else not at all: the other
// end's judge counts it). Fills *fans (by vertex: proved embedded). `start` and `incident`
// are the vertex -> faces table vertexFaces makes.
void judgeVertices(const std::vector<Vec3f>& pos, const std::vector<FaceIndices>& faces,
                   const std::vector<char>* judged, bool edgesToOthers, CheckReport* r,
                   std::vector<char>* fans, const std::vector<std::uint32_t>& start,
                   const std::vector<std::uint32_t>& incident);
// The faces round each of `vertices` vertices: those of vertex v are
// incident[start[v] .. start[v + 1]), in increasing order.
void vertexFaces(std::size_t vertices, const std::vector<FaceIndices>& faces,
                 std::vector<std::uint32_t>* start, std::vector<std::uint32_t>* incident);
// The reasons a report's counts give (its `reasons`, appended).
void addReasons(CheckReport& r);

}  // namespace frep
