// Self-intersections of a triangle mesh, counted as CGAL's
// Polygon_mesh_processing::self_intersections counts them (its exact predicates, its rules for
// triangles sharing an edge or a vertex, a degenerate triangle counted as one pair with
// itself), but found through a hash grid of the triangles' boxes instead of a general box
// tree: the meshes the mesher writes are many small triangles of similar size, for which a
// grid finds the candidate pairs in a fraction of the time.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "base/triangle_mesh.h"

namespace frep {

using FaceIndices = std::array<std::uint32_t, 3>;

// `faces` index `points` and form a polygon mesh: no face repeats a vertex, every edge is in
// at most two faces, in opposite directions, and the faces round each vertex form one fan
// (so two faces sharing two vertices share that edge). Uses CGAL's box tree instead where
// the grid would not pay (triangles of very different sizes, or many piled in one place):
// countSelfIntersectionsWithCgal (cgal_surface.h), the reference the tests compare with.
// progress(fraction) is called on the calling thread between parts of the work (it may throw
// to stop there).
// Counting stops soon after `limit` pairs, and returns `limit` then.
// `known` passes what the caller has already found of the faces (the check's own passes),
// so the count does not find it again.
struct FaceFacts {
  // By face: whether CGAL's collinear() holds for its corners (a degenerate face).
  const std::vector<char>* collinear = nullptr;
  // By vertex: whether fanProvedEmbedded (face_pair_test.h) proved its fan embedded; two
  // faces sharing such a vertex are not tested (they cannot intersect).
  const std::vector<char>* embeddedFans = nullptr;
};
// The grid is built and searched in slabs of z layers of about `slabEntries` entries (a
// face's box covering k cells makes k entries of 8 bytes); 0: an eighth of them, at least
// 2^20. (Small slabs are for tests: they put many pairs on slab boundaries.)
std::size_t countSelfIntersections(const std::vector<Vec3f>& points,
                                   const std::vector<FaceIndices>& faces,
                                   const std::function<void(double)>& progress = nullptr,
                                   std::size_t limit = static_cast<std::size_t>(-1),
                                   const FaceFacts& known = {}, std::size_t slabEntries = 0);

}  // namespace frep
