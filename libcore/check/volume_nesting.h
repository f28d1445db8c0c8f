// Whether a closed, consistently oriented, self-intersection-free mesh of several components
// bounds a volume, outward, without CGAL's Surface_mesh and AABB tree (built on one thread:
// a fifth of the check of a gyroid of 265 pieces): each component outward when an even
// number of the others enclose it, inward when odd (PMP::does_bound_a_volume's rule, with the
// outermost components outward).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
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

// The same test for components known by their facts, the faces given by `forEachFace`
// (which may call the visitor from several threads at once, and is called once per round of
// rays): the check of a mesh in parts (partitioned_check.h) passes each part's faces in turn.
struct ComponentFacts {
  float lo[3] = {HUGE_VALF, HUGE_VALF, HUGE_VALF}, hi[3] = {-HUGE_VALF, -HUGE_VALF, -HUGE_VALF};
  double volume = 0.0;                           // signed
  std::vector<std::array<Vec3f, 3>> someFaces;  // up to 8, where rays may start
  void add(const Vec3f& a, const Vec3f& b, const Vec3f& c);
  void merge(const ComponentFacts& other);
};
using FaceVisitor =
    std::function<void(const Vec3f&, const Vec3f&, const Vec3f&, std::uint32_t component)>;
std::optional<bool> nestingByRays(const std::vector<ComponentFacts>& components,
                                  const std::function<void(const FaceVisitor&)>& forEachFace);

}  // namespace frep
