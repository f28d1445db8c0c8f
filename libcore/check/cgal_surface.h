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

// The same count for a polygon mesh through CGAL's box intersection (a segment tree: time in
// the boxes and the pairs found), each pair of overlapping boxes tested by the grid's own
// rules (facesIntersect, face_pair_test.h); faces marked `dead` (degenerate: the caller
// counts them) take no part. For what the grid does not pay for: faces of very different
// sizes, or piled in one place. Faces that crowd so that the pairs to test pass
// kMaxBoxPairsTested (a fan of 30,000 slivers round one vertex makes 450 million: minutes)
// are refused with a ModelError rather than ground through.
constexpr std::size_t kMaxBoxPairsTested = 100000000;  // about 5 s on 2 cores
std::size_t countSelfIntersectionsByBoxTree(const std::vector<Vec3f>& points,
                                            const std::vector<FaceIndices>& faces,
                                            const std::vector<char>& dead, std::size_t limit);

// PMP::does_bound_a_volume on a closed, manifold, consistently oriented polygon mesh: the
// faces bound a volume with their normals pointing out (nested cavities allowed).
bool boundsAVolume(const std::vector<Vec3f>& points, const std::vector<FaceIndices>& faces);

}  // namespace frep
