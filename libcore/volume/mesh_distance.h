// A closed triangle mesh's exact signed distance as a Field (positive inside): the distance to
// the nearest triangle (CGAL's AABB tree, its closest-point query), the side from the angle-
// weighted pseudo-normal of the face, edge or corner that nearest point lies on (Baerentzen and
// Aanaes, 2005), which is exact on a closed, manifold, self-intersection-free mesh and costs
// no ray cast. Exact at any resolution: nothing is sampled.
#pragma once

#include <memory>
#include <string>

#include "base/triangle_mesh.h"
#include "frep/field.h"

namespace frep {

// The mesh must be closed, manifold along its edges, consistently oriented (either way) and
// free of self-intersections, as the check judges it; otherwise FileError names `where`, what
// is wrong, and the alternative (method 'grid', which resolves overlaps). Intervals come from
// the distance's Lipschitz bound (|F(p) - F(c)| <= |p - c|): one query per box.
std::shared_ptr<const Field> meshDistanceField(const TriangleMesh& mesh, const std::string& where);

}  // namespace frep
