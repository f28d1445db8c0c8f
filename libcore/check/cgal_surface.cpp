#include "check/cgal_surface.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <atomic>
#include <boost/iterator/function_output_iterator.hpp>
#include <string>

#include "base/errors.h"
#include "check/face_pair_test.h"

namespace frep {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

struct Enough {};  // thrown by a count that reached its limit

SurfaceMesh surfaceMesh(const std::vector<Vec3f>& points, const std::vector<FaceIndices>& faces,
                        bool polygonMesh) {
  constexpr std::size_t kUnused = static_cast<std::size_t>(-1);
  std::vector<std::size_t> renumber(points.size(), kUnused);
  std::vector<Point> used;
  std::vector<std::array<std::size_t, 3>> soup;
  soup.reserve(faces.size());
  for (const FaceIndices& f : faces) {
    std::array<std::size_t, 3> g{};
    for (int k = 0; k < 3; ++k) {
      std::size_t& id = renumber[f[k]];
      if (id == kUnused) {
        id = used.size();
        used.emplace_back(points[f[k]][0], points[f[k]][1], points[f[k]][2]);
      }
      g[k] = id;
    }
    soup.push_back(g);
  }
  if (!polygonMesh) PMP::orient_polygon_soup(used, soup);
  SurfaceMesh sm;
  PMP::polygon_soup_to_polygon_mesh(used, soup, sm);
  return sm;
}

}  // namespace

std::size_t countSelfIntersectionsWithCgal(const std::vector<Vec3f>& points,
                                           const std::vector<FaceIndices>& faces, bool polygonMesh,
                                           std::size_t limit) {
  const SurfaceMesh sm = surfaceMesh(points, faces, polygonMesh);
  std::atomic<std::size_t> pairs{0};
  auto counter = boost::make_function_output_iterator([&](const auto&) {
    if (++pairs >= limit) throw Enough();
  });
  // CGAL's search has no stop: the counting output throws at the limit, which ends it. Only
  // the sequential search reports pairs as it finds them (the parallel one tests every
  // candidate pair first), so a limited count runs sequentially.
  try {
    if (limit == static_cast<std::size_t>(-1))
      PMP::self_intersections<CGAL::Parallel_if_available_tag>(sm, counter);
    else
      PMP::self_intersections<CGAL::Sequential_tag>(sm, counter);
  } catch (const Enough&) {
    return limit;
  }
  return std::min<std::size_t>(pairs, limit);
}

bool boundsAVolume(const std::vector<Vec3f>& points, const std::vector<FaceIndices>& faces) {
  return PMP::does_bound_a_volume(surfaceMesh(points, faces, true));
}

std::size_t countSelfIntersectionsByBoxTree(const std::vector<Vec3f>& points,
                                            const std::vector<FaceIndices>& faces,
                                            const std::vector<char>& dead, std::size_t limit) {
  using BoxD = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::uint32_t>;
  std::vector<BoxD> boxes;
  boxes.reserve(faces.size());
  for (std::size_t i = 0; i < faces.size(); ++i) {
    if (dead[i]) continue;
    const FaceIndices& f = faces[i];
    double lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min({points[f[0]][k], points[f[1]][k], points[f[2]][k]});
      hi[k] = std::max({points[f[0]][k], points[f[1]][k], points[f[2]][k]});
    }
    boxes.emplace_back(lo, hi, static_cast<std::uint32_t>(i));
  }
  std::atomic<std::size_t> tested{0}, found{0};
  auto test = [&](const BoxD& a, const BoxD& b) {
    if (tested.fetch_add(1, std::memory_order_relaxed) >= kMaxBoxPairsTested)
      throw ModelError(
          "check: over " + std::to_string(kMaxBoxPairsTested / 1000000) +
          " million pairs of triangles lie on top of each other's boxes (slivers fanning "
          "from one vertex, or triangles piled in one place): too crowded to test for "
          "self-intersections in reasonable time; the mesh is refused");
    if (facesIntersect(points, faces[a.info()], faces[b.info()]) &&
        found.fetch_add(1, std::memory_order_relaxed) + 1 >= limit)
      throw Enough();
  };
  try {
    CGAL::box_self_intersection_d<CGAL::Parallel_if_available_tag>(boxes.begin(), boxes.end(),
                                                                   test);
  } catch (const Enough&) {
    return limit;
  }
  return std::min<std::size_t>(found, limit);
}

}  // namespace frep
