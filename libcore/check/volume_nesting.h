// Whether a closed, consistently oriented, self-intersection-free mesh of several components
// bounds a volume, outward, without CGAL's Surface_mesh and AABB tree (built on one thread:
// a fifth of the check of a gyroid of 265 pieces): each component outward when an even
// number of the others enclose it, inward when odd (PMP::does_bound_a_volume's rule, with the
// outermost components outward).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "check/self_intersections.h"

namespace frep {

// `component[f]`: face f's component, 0 .. components - 1. Enclosure by ray parity with exact
// predicates: a ray along +x from the centroid of a face of one component counts the faces
// of each other component it crosses. Returns nothing where it cannot decide cheaply (over
// 8,192 components, over 4,096 whose boxes lie in others', or every ray tried grazes an
// edge): CGAL decides then.
std::optional<bool> boundsAVolumeByRays(const std::vector<Vec3f>& points,
                                        const std::vector<FaceIndices>& faces,
                                        const std::vector<std::uint32_t>& component,
                                        std::uint32_t components);

}  // namespace frep
