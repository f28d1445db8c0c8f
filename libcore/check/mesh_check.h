// Printability check of a triangle mesh. CGAL's Polygon Mesh Processing is the judge of
// self-intersections and orientation; the counts below are computed on the mesh with
// identical coordinates welded (STL has no indices, so a mesh that only looks closed through
// near-duplicate vertices fails).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "base/progress.h"
#include "base/triangle_mesh.h"
#include "base/vec.h"

namespace frep {

struct CheckReport {
  std::size_t inputVertices = 0;
  std::size_t vertices = 0;  // after welding identical coordinates
  std::size_t faces = 0;
  std::size_t borderEdges = 0;          // edges with one triangle: holes
  std::size_t nonManifoldEdges = 0;     // edges with more than two triangles
  std::size_t nonManifoldVertices = 0;  // vertices whose triangles form more than one fan
  std::size_t misorientedEdges = 0;     // edges whose two triangles run the same way
  std::size_t degenerateFaces = 0;      // repeated or collinear vertices
  std::size_t selfIntersections = 0;    // pairs of intersecting triangles
  bool selfIntersectionsAtLeast = false;  // counting stopped at kSelfIntersectionLimit
  std::size_t components = 0;
  std::size_t nonFiniteVertices = 0;
  bool closed = false;
  bool outward = false;  // bounds a volume with normals pointing out (CGAL does_bound_a_volume)
  double volume = 0.0;   // signed
  double area = 0.0;
  Box3 bbox;
  std::vector<std::string> reasons;  // empty when printable

  bool printable() const { return reasons.empty(); }
};

// progress(fraction) is called between the check's phases (welding, topology, CGAL's
// self-intersection test, orientation); it may throw to stop the check there.
// Self-intersecting pairs are counted up to this many (then "at least"): 30,000 coincident
// triangles make 450 million, which took CGAL over a minute to count.
constexpr std::size_t kSelfIntersectionLimit = 1000000;

// The distinct coordinates of `positions`, in the order they first come, appended to
// `welded`; returns each old vertex's index there (STL shares no vertices: this is how its
// triangles meet).
// Each of `positions`' index among the distinct coordinates, numbered in the order they
// first come, and (in `first`) where each distinct one first comes. All are distinct
// exactly when `first` is as long as `positions` (the map is then the identity).
// `cancel` is looked at between its parallel steps (each a fraction of a second at 50
// million points).
std::vector<std::uint32_t> distinctPoints(const std::vector<Vec3f>& positions,
                                          std::vector<std::uint32_t>* first,
                                          const Progress& cancel = {});
std::vector<std::uint32_t> weldIdenticalVertices(const std::vector<Vec3f>& positions,
                                                 std::vector<Vec3f>& welded);

CheckReport checkMesh(const TriangleMesh& mesh,
                      const std::function<void(double)>& progress = nullptr,
                      std::size_t selfIntersectionLimit = kSelfIntersectionLimit);

std::string reportToText(const CheckReport& r, const std::string& name);
std::string reportToJson(const CheckReport& r, const std::string& name);

}  // namespace frep
