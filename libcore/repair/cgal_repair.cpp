// The only translation unit of repair/ that includes CGAL (slow to compile: keep it alone).
#include "repair/cgal_repair.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/manifoldness.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_mesh_to_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/repair_self_intersections.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/stitch_borders.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <vector>

#include "base/errors.h"
#include "base/progress.h"

namespace frep {

namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using Halfedge = Mesh::Halfedge_index;
using Face = Mesh::Face_index;

// PMP::remove_degenerate_faces; returns how many degenerate faces it could not remove.
std::size_t removeDegenerateFaces(Mesh& mesh) {
  if (PMP::remove_degenerate_faces(mesh)) return 0;
  std::size_t left = 0;
  for (Face f : mesh.faces()) left += PMP::is_degenerate_triangle_face(f, mesh);
  return left;
}

}  // namespace

TriangleMesh repairWithCgal(const TriangleMesh& soup, const CgalRepairOptions& options,
                            CgalRepairLog& log) {
  const Progress bar(options.progress);
  auto tick = [&bar](double f) { bar.step(f); };
  std::vector<Point> points;
  points.reserve(soup.positions.size());
  for (const Vec3f& p : soup.positions) points.emplace_back(p[0], p[1], p[2]);
  std::vector<std::array<std::size_t, 3>> polygons;
  polygons.reserve(soup.triangles.size());
  for (const Triangle& t : soup.triangles) {
    bool finite = true;
    for (std::uint32_t v : t)
      finite = finite && v < soup.positions.size() && std::isfinite(soup.positions[v][0]) &&
               std::isfinite(soup.positions[v][1]) && std::isfinite(soup.positions[v][2]);
    if (finite) polygons.push_back({t[0], t[1], t[2]});
  }
  log.soupFacesRemoved = soup.triangles.size() - polygons.size();

  // The soup: identical points merged, faces that repeat a vertex or another face removed,
  // and faces of no area (collinear corners, exact predicate): such a face lying on a sound
  // edge makes it non-manifold, and the split that orienting the soup makes of it would
  // leave a flat pillow behind. Where a sliver closed a T-junction the crack it leaves is
  // filled below, and the filling's own slivers are collapsed in the mesh.
  const std::size_t pointsBefore = points.size(), facesBefore = polygons.size();
  polygons.erase(std::remove_if(polygons.begin(), polygons.end(),
                                [&](const std::array<std::size_t, 3>& f) {
                                  return CGAL::collinear(points[f[0]], points[f[1]], points[f[2]]);
                                }),
                 polygons.end());
  PMP::repair_polygon_soup(points, polygons);
  log.soupPointsMerged = pointsBefore - points.size();
  log.soupFacesRemoved += facesBefore - polygons.size();
  tick(0.1);
  // One orientation for every face that can have it; non-manifold vertices and edges are
  // split so that the soup becomes a polygon mesh.
  log.soupOriented = PMP::orient_polygon_soup(points, polygons);
  Mesh mesh;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, mesh);
  points.clear();
  polygons.clear();
  tick(0.2);

  log.bordersStitched = PMP::stitch_borders(mesh);
  log.degenerateFacesLeft = removeDegenerateFaces(mesh);
  mesh.collect_garbage();
  log.nonManifoldVerticesSplit = PMP::duplicate_non_manifold_vertices(mesh);
  tick(0.35);

  if (options.fillHoles) {
    std::vector<Halfedge> cycles;
    PMP::extract_boundary_cycles(mesh, std::back_inserter(cycles));
    const Progress holes = bar.sub(0.35, 0.2);
    for (std::size_t i = 0; i < cycles.size(); ++i) {
      std::vector<Face> added;
      std::vector<Mesh::Vertex_index> vertices;
      PMP::triangulate_and_refine_hole(mesh, cycles[i], std::back_inserter(added),
                                       std::back_inserter(vertices));
      if (added.empty())
        ++log.holesLeft;
      else
        ++log.holesFilled;
      log.facesAdded += added.size();
      holes.step(double(i + 1) / double(cycles.size()));
    }
  }
  if (log.holesFilled) log.degenerateFacesLeft = removeDegenerateFaces(mesh);
  // Closed shells of no volume: the pillows that a sliver split off a sound edge (or a
  // doubled triangle) becomes once its hole is filled. A cube of a ten-thousandth of the
  // mesh's diagonal is the threshold, far below any part a printer makes.
  if (!CGAL::is_empty(mesh)) {
    const CGAL::Bbox_3 box = PMP::bbox(mesh);
    const double diagonal =
        std::sqrt(CGAL::square(box.xmax() - box.xmin()) + CGAL::square(box.ymax() - box.ymin()) +
                  CGAL::square(box.zmax() - box.zmin()));
    const double side = 1e-4 * diagonal;
    log.flatShellsRemoved = PMP::remove_connected_components_of_negligible_size(
        mesh, CGAL::parameters::area_threshold(0).volume_threshold(side * side * side));
  }
  mesh.collect_garbage();
  tick(0.55);

  if (options.removeSelfIntersections && !CGAL::is_empty(mesh) && CGAL::is_triangle_mesh(mesh)) {
    log.selfIntersected = PMP::does_self_intersect(mesh);
    if (log.selfIntersected) {
      // The local removal (experimental in CGAL 5.5) may change the genus where it must.
      log.selfIntersectionsRemoved = PMP::experimental::remove_self_intersections(
          mesh, CGAL::parameters::preserve_genus(false));
      mesh.collect_garbage();
    }
  }
  tick(0.85);

  // (orient_to_bound_a_volume crashes on an empty mesh: the pillow removal may leave one)
  if (!CGAL::is_empty(mesh) && CGAL::is_closed(mesh) && CGAL::is_triangle_mesh(mesh) &&
      !PMP::does_self_intersect(mesh)) {
    PMP::orient_to_bound_a_volume(mesh);
    log.reoriented = true;
  }
  tick(0.95);

  TriangleMesh out;
  std::vector<std::uint32_t> index(mesh.number_of_vertices() + mesh.number_of_removed_vertices());
  out.positions.reserve(mesh.number_of_vertices());
  for (auto v : mesh.vertices()) {
    index[v] = static_cast<std::uint32_t>(out.positions.size());
    const Point& p = mesh.point(v);
    out.positions.push_back({float(p.x()), float(p.y()), float(p.z())});
  }
  out.triangles.reserve(mesh.number_of_faces());
  for (Face f : mesh.faces()) {
    std::vector<std::uint32_t> ring;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) ring.push_back(index[v]);
    // Faces are triangles (the soup was); a polygon left by a step is fanned.
    for (std::size_t k = 1; k + 1 < ring.size(); ++k)
      out.triangles.push_back({ring[0], ring[k], ring[k + 1]});
  }
  tick(1.0);
  return out;
}

}  // namespace frep
