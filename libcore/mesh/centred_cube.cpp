#include "mesh/centred_cube.h"

#include <array>
#include <utility>

#include "mesh/cube_loops.h"

namespace frep {

namespace {

// Twice the coordinates of a cube vertex: corners 0 or 2 per axis, the centre 1.
int doubled(int v, int axis) {
  return v == kCubeCentre ? 1 : 2 * ((v >> axis) & 1);
}

int orientation(const std::array<int, 4>& t) {
  int d[3][3];
  for (int r = 0; r < 3; ++r)
    for (int a = 0; a < 3; ++a) d[r][a] = doubled(t[r + 1], a) - doubled(t[0], a);
  return d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1]) -
         d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0]) +
         d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0]);
}

}  // namespace

void centredCubeCrossings(int mask, bool centreInside, int flips, std::vector<TetCrossing>& out) {
  const CubeLoopTables& cl = cubeLoopTables();
  for (int f = 0; f < 6; ++f) {
    for (const auto& tri : cl.faceTriangles[f][(flips >> f) & 1]) {
      std::array<int, 4> tet = {kCubeCentre, tri[0], tri[1], tri[2]};
      if (orientation(tet) < 0) std::swap(tet[2], tet[3]);
      int m = 0;
      for (int i = 0; i < 4; ++i)
        m |= (tet[i] == kCubeCentre ? int(centreInside) : (mask >> tet[i]) & 1) << i;
      TetCrossing c = tetCrossing(m);
      if (c.count == 0) continue;
      for (int i = 0; i < c.count; ++i) {
        c.from[i] = static_cast<std::uint8_t>(tet[c.from[i]]);
        c.to[i] = static_cast<std::uint8_t>(tet[c.to[i]]);
      }
      out.push_back(c);
    }
  }
}

}  // namespace frep
