// A brick's flat vertices dropped (mesh/flat_vertex_removal.h, docs/mesher.md "Flat
// vertices").
#include "mesh/brick_mesher.h"

namespace frep {
namespace meshing {

void BrickMesher::removeFlatVertices(const CellRange& r, const std::int64_t n[3], Scratch& s,
                                     BrickResult& out) const {
  const std::int64_t c[3] = {n[0] - 1, n[1] - 1, n[2] - 1};
  auto cube = [&](const std::int64_t i[3]) {  // (its lowest grid point: capLoops' fan index)
    return static_cast<std::size_t>(i[0] + n[0] * (i[1] + n[1] * i[2]));
  };
  // (an edge from a cube's lowest corner: edgeKey needs only that corner's offset, 0)
  static constexpr std::uint32_t kAtLowCorner[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  s.dropped.assign(out.positions.size(), 0);
  std::size_t removed = 0;
  std::int64_t start[3];
  for (int a = 0; a < 3; ++a) start[a] = r.lo[a] % 2 == 0 ? 1 : 2;  // odd global points
  std::int64_t o[3];
  for (o[2] = start[2]; o[2] < c[2]; o[2] += 2)
    for (o[1] = start[1]; o[1] < c[1]; o[1] += 2)
      for (o[0] = start[0]; o[0] < c[0]; o[0] += 2) {
        // Edge d (axis d / 2, from the centre down or up): its lower grid point and (unless
        // null) the brick-local indices of its four cubes ([low, low + 1] along the axis,
        // o - 1 and o across it).
        auto edgeAt = [&](int d, std::int64_t low[3], std::size_t* cubes) {
          const int axis = d / 2;
          for (int b = 0; b < 3; ++b) low[b] = o[b] - (b == axis && d % 2 == 0 ? 1 : 0);
          for (int q = 0; q < 4 && cubes; ++q) {
            std::int64_t at[3];
            for (int b = 0, bit = 0; b < 3; ++b)
              at[b] = b == axis ? low[b] : o[b] - 1 + ((q >> bit++) & 1);
            cubes[q] = cube(at);
          }
        };
        // The block's cubes with plain fans (bit x + 2 y + 4 z): most blocks have none,
        // or too few for an edge, and are passed over before any edge is looked up.
        unsigned fanned = 0;
        for (int q = 0; q < 8; ++q) {
          const std::int64_t at[3] = {o[0] - 1 + (q & 1), o[1] - 1 + ((q >> 1) & 1),
                                      o[2] - 1 + ((q >> 2) & 1)};
          if (s.fanCount[cube(at)] > 0) fanned |= 1u << q;
        }
        // (the four cubes on the low or high side of an axis)
        static constexpr unsigned kSide[6] = {0x55, 0xaa, 0x33, 0xcc, 0x0f, 0xf0};
        // The crossed edges whose four cubes all have plain fans.
        std::int32_t vertexOf[6];
        int order[6], count = 0;
        for (int d = 0; d < 6; ++d) {
          if ((fanned & kSide[d]) != kSide[d]) continue;
          std::int64_t low[3];
          edgeAt(d, low, nullptr);  // (its cubes: known to have fans from the mask)
          const std::uint32_t lowPoint =
              static_cast<std::uint32_t>(low[0] + n[0] * (low[1] + n[1] * low[2]));
          vertexOf[d] = s.edgeVertex[edgeKey(lowPoint, kAtLowCorner,
                                             TetEdge{0, static_cast<std::uint8_t>(1 << (d / 2))})];
          if (vertexOf[d] >= 0) order[count++] = d;
        }
        // The first that can go, then the one opposite it.
        auto tryRemoval = [&](int d) {
          const int axis = d / 2;
          std::int64_t low[3];
          std::size_t cubes[4];
          edgeAt(d, low, cubes);
          s.region.clear();
          s.regionIndex.clear();
          for (std::size_t id : cubes)
            for (std::uint32_t t = 0; t < s.fanCount[id]; ++t) {
              s.region.push_back(out.triangles[s.fanFirst[id] + t]);
              s.regionIndex.push_back(s.fanFirst[id] + t);
            }
          double boxLo[3], boxHi[3];
          for (int b = 0; b < 3; ++b) {
            const std::int64_t lo = r.lo[b] + (b == axis ? low[b] : o[b] - 1);
            boxLo[b] = g_.coord(b, lo);
            boxHi[b] = g_.coord(b, lo + (b == axis ? 1 : 2));
          }
          FlatVertexRemoval& plan = s.plan;
          if (!planFlatVertexRemoval(static_cast<std::uint32_t>(vertexOf[d]), out.positions,
                                     s.region, boxLo, boxHi, kFlatDeviation * g_.h[axis],
                                     kFlatQuality, &plan) ||
              !flatVertexRemovalIsClear(plan, out.positions, s.region))
            return false;
          for (std::size_t t = 0; t < plan.size; ++t)
            out.triangles[s.regionIndex[plan.star[t]]] =
                t + 2 < plan.size ? plan.replacement[t]
                                  : Triangle{UINT32_MAX, UINT32_MAX, UINT32_MAX};
          s.dropped[static_cast<std::size_t>(vertexOf[d])] = 1;
          ++removed;
          return true;
        };
        for (int i = 0; i < count; ++i) {
          const int d = order[i];
          if (!tryRemoval(d)) continue;
          for (int j = i + 1; j < count; ++j)
            if (order[j] == (d ^ 1)) tryRemoval(d ^ 1);
          break;
        }
      }
  if (removed == 0) return;
  // Compact: the dead triangles out (the crease flips' list renumbered), the vertices gone.
  std::vector<std::uint32_t> newTriangle(out.triangles.size());
  std::size_t kept = 0;
  for (std::size_t t = 0; t < out.triangles.size(); ++t) {
    newTriangle[t] = static_cast<std::uint32_t>(kept);
    if (out.triangles[t][0] != UINT32_MAX) out.triangles[kept++] = out.triangles[t];
  }
  out.triangles.resize(kept);
  for (std::uint32_t& t : out.flippable) t = newTriangle[t];
  std::vector<std::uint32_t> newVertex(out.positions.size());
  kept = 0;
  for (std::size_t v = 0; v < out.positions.size(); ++v) {
    newVertex[v] = static_cast<std::uint32_t>(kept);
    if (s.dropped[v]) continue;
    out.keys[kept] = out.keys[v];
    out.owner[kept] = out.owner[v];
    out.positions[kept] = out.positions[v];
    if (!out.normals.empty()) out.normals[kept] = out.normals[v];
    ++kept;
  }
  out.keys.resize(kept);
  out.owner.resize(kept);
  out.positions.resize(kept);
  if (!out.normals.empty()) out.normals.resize(kept);
  for (Triangle& t : out.triangles)
    for (std::uint32_t& v : t) v = newVertex[v];
}

}  // namespace meshing
}  // namespace frep
