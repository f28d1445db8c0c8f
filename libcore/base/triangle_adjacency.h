// Facet neighbours of an indexed triangle mesh: for facet f and edge i (from corner i to
// corner i+1), the facet on the other side of that edge.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "base/triangle_mesh.h"

namespace frep {

constexpr std::uint32_t kNoNeighbour = 0xFFFFFFFFu;

// kNoNeighbour on a border edge and on a non-manifold edge (more than two facets share it),
// where "the" neighbour is not defined. Linear time: a vertex-to-facet table, then each edge
// looks only at the facets around its first vertex.
std::vector<std::array<std::uint32_t, 3>> facetNeighbours(const TriangleMesh& mesh);

}  // namespace frep
