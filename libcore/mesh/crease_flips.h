// Creases joined across cubes: extended marching cubes' edge flip (Kobbelt et al. 2001).
#pragma once

#include <cstdint>
#include <vector>

#include "base/triangle_mesh.h"

namespace frep {

// `flippable` lists fan triangles (apex, a, b) whose apex is a feature vertex inside its cube
// and whose edge a-b is the only line that cube's loop draws on the face holding it. Where the
// neighbour cube across that face has such a triangle (apex2, b, a) too, the pair becomes
// (apex, a, apex2), (apex, apex2, b): the crease runs from feature vertex to feature vertex
// instead of being cut across at the face.
//
// Why no flip can make two triangles cross (docs/mesher.md, "Sharp features"): the two new
// triangles lie in the box the two cubes form and meet its boundary only at a and b; in each
// cube they are cones from that cube's apex over a line on the face (a to where apex-apex2
// crosses it, on to b), which meets no other line of the loop since the face holds one, so
// each cube's fan stays a cone over a simple loop on its boundary, embedded as before.
// A flip is skipped where a new triangle would be (nearly) degenerate, and taken where both
// new triangles face as the old pair does together, where the old pair folds by over 90
// degrees (a crease cut across) or where the new pair folds less than the old; the new
// triangles never overlap (crease_flips.cpp says why). Returns the listed triangles that found no
// partner (brick jobs: their partner may lie in a neighbouring job's piece).
std::vector<std::uint32_t> flipCreases(TriangleMesh& mesh,
                                       const std::vector<std::uint32_t>& flippable);

// The decision for one pair, first = (v1, a, b) and second = (v2, b, a): the two triangles
// that replace them, or false to keep them. It depends on the four positions alone, and the
// pair is taken in a fixed order (the apex with the smaller coordinates first), so a pair
// decided in one piece, in the merge or in one process comes out bit for bit the same.
bool flipCrease(const Triangle& first, const Triangle& second, const std::vector<Vec3f>& positions,
                Triangle* newFirst, Triangle* newSecond);

}  // namespace frep
