// Mending a triangle soup with CGAL 5.5's Polygon Mesh Processing, step by step, each step
// counted: the soup's own repair (duplicate points, degenerate and duplicate faces), one
// orientation for the soup, stitching of coincident borders, degenerate faces, non-manifold
// vertices split, holes filled, CGAL's experimental local removal of self-intersections, and
// the orientation that bounds a volume. CGAL is in cgal_repair.cpp only.
#pragma once

#include <cstddef>
#include <functional>

#include "base/triangle_mesh.h"

namespace frep {

struct CgalRepairOptions {
  bool fillHoles = true;
  bool removeSelfIntersections = true;
  // Called with the fraction done between steps; false cancels (throws Cancelled).
  std::function<bool(double)> progress;
};

// What each step changed (counts of CGAL's own reports).
struct CgalRepairLog {
  std::size_t soupPointsMerged = 0;  // repair_polygon_soup: points and faces removed
  std::size_t soupFacesRemoved = 0;
  bool soupOriented = true;             // orient_polygon_soup made it one orientation
  std::size_t bordersStitched = 0;      // pairs of border halfedges
  std::size_t degenerateFacesLeft = 0;  // remove_degenerate_faces could not remove them all
  std::size_t nonManifoldVerticesSplit = 0;
  std::size_t holesFilled = 0;
  std::size_t holesLeft = 0;
  std::size_t facesAdded = 0;             // by hole filling
  std::size_t flatShellsRemoved = 0;      // closed components of no volume (pillows)
  bool selfIntersected = false;           // before the local removal
  bool selfIntersectionsRemoved = false;  // the removal reported success
  bool reoriented = false;                // orient_to_bound_a_volume ran (closed, no crossings)
};

// The mended mesh (float coordinates, as files hold them: the caller checks it again).
// Throws Cancelled.
TriangleMesh repairWithCgal(const TriangleMesh& soup, const CgalRepairOptions& options,
                            CgalRepairLog& log);

}  // namespace frep
