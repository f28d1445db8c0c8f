// CGAL's own judgements on a triangle soup, through a CGAL Surface_mesh of the vertices the
// faces use (CGAL's orientation test crashes on isolated vertices, and a file may well list
// vertices no triangle uses).
#pragma once

#include <cstddef>
#include <vector>

#include "check/self_intersections.h"

namespace frep {

// The pairs of intersecting faces, as PMP::self_intersections counts them (a degenerate face
// counts as a pair with itself). A soup that is not a polygon mesh is first made one by
// PMP::orient_polygon_soup (which splits non-manifold vertices): pass polygonMesh = false.
// Counting stops at `limit` pairs (returned then): a pile of coincident faces would make
// billions.
std::size_t countSelfIntersectionsWithCgal(const std::vector<Vec3f>& points,
                                           const std::vector<FaceIndices>& faces,
                                           bool polygonMesh = true,
                                           std::size_t limit = static_cast<std::size_t>(-1));

// PMP::does_bound_a_volume on a closed, manifold, consistently oriented polygon mesh: the
// faces bound a volume with their normals pointing out (nested cavities allowed).
bool boundsAVolume(const std::vector<Vec3f>& points, const std::vector<FaceIndices>& faces);

}  // namespace frep
