// Flat vertices removed: a vertex where the mesh is all but flat goes, and the polygon of its
// neighbours is fanned again with two triangles fewer (docs/mesher.md, "Flat vertices").
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "base/triangle_mesh.h"

namespace frep {

struct FlatVertexRemoval {
  static constexpr std::size_t kMaxRing = 12;
  std::size_t size = 0;                // the star's triangles (k)
  std::uint32_t star[kMaxRing];        // their places in the region, ascending
  std::uint32_t ring[kMaxRing];        // the neighbours, in the star's order
  Triangle replacement[kMaxRing - 2];  // k - 2 of them, over the same polygon
  double deviation = 0.0;              // how far the surface moves (at most; model units)
  double quality = 0.0;                // the worst new triangle's triangleQuality
  // the plane it is judged in: the vertex, the star's unit normal n and axes u, w across it
  std::array<double, 3> origin, n, u, w;
  double poly[kMaxRing][2];  // the ring there
  double eps2 = 0.0;         // the squared margin kept over rounding
};

// Plans the removal of vertex `v`: the fan over its neighbours that moves the surface least.
// `region` must hold every triangle of the mesh that meets the box [boxLo, boxHi] anywhere but
// on its boundary, and v's whole star must lie in it: the mesher passes the triangles of the
// four cubes round v's grid edge.
//
// Everything is judged in the plane the star faces (its area-weighted normal). Refused
// (false) unless the star winds once round v with every triangle facing that way (its polygon
// of neighbours is then simple there), the new fan covers that polygon with triangles facing
// that way too, none thinner than `minQuality` and none moving the surface by more than
// `maxDeviation`, and no new edge is an edge already or lies in a face of the box.
bool planFlatVertexRemoval(std::uint32_t v, const std::vector<Vec3f>& positions,
                           const std::vector<Triangle>& region, const double boxLo[3],
                           const double boxHi[3], double maxDeviation, double minQuality,
                           FlatVertexRemoval* plan);

// Whether no other triangle of the region reaches into the plan's polygon (in its plane): then
// the new fan meets no triangle but where they share a vertex or an edge
// (flat_vertex_removal.cpp says why). Each test keeps a margin over rounding: a doubtful case
// is refused. Apart from planning, as it is the dearer half: only the chosen plans need it.
bool flatVertexRemovalIsClear(const FlatVertexRemoval& plan, const std::vector<Vec3f>& positions,
                              const std::vector<Triangle>& region);

}  // namespace frep
