// CGAL's judgement of one pair of faces: whether they intersect, with the exact predicates
// and the rules for faces that share an edge or a vertex that
// Polygon_mesh_processing::self_intersections uses. The check counts with it, and the
// simplifier asks it before every collapse, so what the simplifier allows the check accepts.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "base/triangle_mesh.h"

namespace frep {

// f and g index `points` and are faces of a polygon mesh (no face repeats a vertex; two faces
// sharing two vertices share that edge). A shared edge intersects only where the four points
// are coplanar and the two third vertices lie on the same side of it; a shared vertex where
// one face's opposite side crosses the other face; else wherever the triangles meet.
bool facesIntersect(const std::vector<Vec3f>& points, const Triangle& f, const Triangle& g);

// Whether the fan of faces round vertex v is proved embedded: `sectors` holds, for each face
// round v, its two other corners in the face's order (v, w1, w2). The faces must form one
// closed fan (each neighbour once a w1 and once a w2; the check's edge pass establishes it).
// Proved when, projected along one axis, every face keeps one orientation (exact: Shewchuk's
// bound, else not proved) and the sectors w1 -> w2 wind round v exactly once: then they tile
// the plane round v, two faces of the fan meet only in v or their shared edge, and
// facesIntersect is false for every pair of them. The check then skips those pairs, which
// are most of a fine mesh's candidates.
bool fanProvedEmbedded(const std::vector<Vec3f>& points, std::uint32_t v,
                       const std::pair<std::uint32_t, std::uint32_t>* sectors, std::size_t n);

// Whether the three points are collinear (exactly): such a face is degenerate.
bool collinear(const Vec3f& a, const Vec3f& b, const Vec3f& c);

}  // namespace frep
