// CGAL's judgement of one pair of faces: whether they intersect, with the exact predicates
// and the rules for faces that share an edge or a vertex that
// Polygon_mesh_processing::self_intersections uses. The check counts with it, and the
// simplifier asks it before every collapse, so what the simplifier allows the check accepts.
#pragma once

#include <vector>

#include "base/triangle_mesh.h"

namespace frep {

// f and g index `points` and are faces of a polygon mesh (no face repeats a vertex; two faces
// sharing two vertices share that edge). A shared edge intersects only where the four points
// are coplanar and the two third vertices lie on the same side of it; a shared vertex where
// one face's opposite side crosses the other face; else wherever the triangles meet.
bool facesIntersect(const std::vector<Vec3f>& points, const Triangle& f, const Triangle& g);

// Whether the three points are collinear (exactly): such a face is degenerate.
bool collinear(const Vec3f& a, const Vec3f& b, const Vec3f& c);

}  // namespace frep
