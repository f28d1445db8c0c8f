#include "mesh/cube_loops.h"

#include <map>

namespace frep {

namespace {

// Face 2a + s is the cube's face at offset s along axis a. An edge from `low` along `dir`
// lies on it when the edge keeps coordinate a fixed at s.
std::uint8_t facesOf(const TetEdge& e) {
  std::uint8_t bits = 0;
  for (int a = 0; a < 3; ++a)
    if (!((e.dir >> a) & 1)) bits |= 1u << (2 * a + ((e.low >> a) & 1));
  return bits;
}

// The loops of one cube: every face split into two triangles (along Kuhn's diagonal, or the
// other one where `flips` says), each mixed triangle drawing one line between its two
// crossed edges. The line is oriented as the boundary of the outward-facing surface inside
// the cube: with u pointing from the triangle's inside corners to its outside ones and m the
// face's outward normal, the surface's normal at the line is about u and the cube's interior
// lies along -m, so the boundary runs along u x m.
CubeLoopCase loopsOf(const CubeLoopTables& t, int mask, int flips) {
  std::map<int, int> nextOf;
  for (int f = 0; f < 6; ++f) {
    const int a = f / 2;
    const double m[3] = {a == 0 ? (f % 2 ? 1.0 : -1.0) : 0.0, a == 1 ? (f % 2 ? 1.0 : -1.0) : 0.0,
                         a == 2 ? (f % 2 ? 1.0 : -1.0) : 0.0};
    for (const auto& tri : t.faceTriangles[f][(flips >> f) & 1]) {
      int in = 0;
      for (int v : tri) in += (mask >> v) & 1;
      if (in == 0 || in == 3) continue;
      int lone = 0;  // the corner whose sign the other two do not share
      for (int i = 0; i < 3; ++i)
        if (((mask >> tri[i]) & 1) == (in == 1)) lone = i;
      const int l = tri[lone], x = tri[(lone + 1) % 3], y = tri[(lone + 2) % 3];
      double u[3], px[3], py[3];
      for (int c = 0; c < 3; ++c) {
        auto at = [c](int corner) { return static_cast<double>((corner >> c) & 1); };
        const double others = 0.5 * (at(x) + at(y));
        u[c] = in == 1 ? others - at(l) : at(l) - others;
        px[c] = 0.5 * (at(l) + at(x));
        py[c] = 0.5 * (at(l) + at(y));
      }
      const double along[3] = {u[1] * m[2] - u[2] * m[1], u[2] * m[0] - u[0] * m[2],
                               u[0] * m[1] - u[1] * m[0]};
      double dot = 0.0;
      for (int c = 0; c < 3; ++c) dot += (py[c] - px[c]) * along[c];
      auto id = [&t](int p, int r) {
        const TetEdge e = edgeBetween(p, r);
        return static_cast<int>(t.idOf[e.low][e.dir]);
      };
      const int from = id(l, x), to = id(l, y);
      if (dot > 0)
        nextOf[from] = to;
      else
        nextOf[to] = from;
    }
  }
  return loopsFromLines(nextOf);
}

CubeLoopTables build() {
  CubeLoopTables t{};
  for (auto& row : t.idOf)
    for (auto& v : row) v = 255;
  int next = 0;
  // cube edges first, then face diagonals, then the main diagonal: the ids the header names
  for (int dirs : {0, 1}) {
    for (int dir = 1; dir < 8; ++dir) {
      const int bits = (dir & 1) + ((dir >> 1) & 1) + ((dir >> 2) & 1);
      if ((dirs == 0) != (bits == 1)) continue;
      for (int low = 0; low < 8; ++low) {
        if (low & dir) continue;
        if (bits == 2 && low != 0 && (low | dir) != 7) continue;  // Kuhn: diagonals via 0 or 7
        if (bits == 3) continue;
        t.edges[next] = {static_cast<std::uint8_t>(low), static_cast<std::uint8_t>(dir)};
        t.idOf[low][dir] = static_cast<std::uint8_t>(next++);
      }
    }
  }
  t.edges[next] = {0, 7};
  t.idOf[0][7] = static_cast<std::uint8_t>(next++);
  for (int id = 0; id < kCubeEdgeIds; ++id) t.faces[id] = facesOf(t.edges[id]);
  for (int f = 0; f < 6; ++f) {
    const int a = f / 2, b = 1 << ((a + 1) % 3), c = 1 << ((a + 2) % 3), q0 = (f % 2) << a;
    const int corners[4] = {q0, q0 | b, q0 | b | c, q0 | c};
    for (int i = 0; i < 4; ++i) t.faceCorners[f][i] = static_cast<std::uint8_t>(corners[i]);
    const int split[2][2][3] = {{{0, 1, 2}, {0, 2, 3}}, {{1, 2, 3}, {1, 3, 0}}};
    for (int d = 0; d < 2; ++d)
      for (int k = 0; k < 2; ++k)
        for (int i = 0; i < 3; ++i)
          t.faceTriangles[f][d][k][i] = static_cast<std::uint8_t>(corners[split[d][k][i]]);
  }
  for (int mask = 0; mask < 256; ++mask) {
    std::uint8_t bits = 0;
    for (int f = 0; f < 6; ++f) {
      auto in = [&](int i) { return (mask >> t.faceCorners[f][i]) & 1; };
      if (in(0) == in(2) && in(1) == in(3) && in(0) != in(1)) bits |= 1u << f;
    }
    t.ambiguous[mask] = bits;
  }
  // Flips of faces that are not ambiguous never happen: those entries repeat the case with
  // the ambiguous faces' flips alone.
  t.cases.resize(64 * 256);
  for (int flips = 0; flips < 64; ++flips)
    for (int mask = 1; mask < 255; ++mask) {
      const int own = flips & t.ambiguous[mask];
      t.cases[flips * 256 + mask] =
          own == flips ? loopsOf(t, mask, flips) : t.cases[own * 256 + mask];
    }
  return t;
}

}  // namespace

CubeLoopCase loopsFromLines(const std::map<int, int>& nextOf) {
  CubeLoopCase c;
  std::map<int, bool> seen;
  for (const auto& [start, unused] : nextOf) {
    (void)unused;
    if (seen[start]) continue;
    ++c.loops;
    int length = 0;
    for (int v = start; !seen[v]; v = nextOf.at(v)) {
      seen[v] = true;
      if (c.loops == 1) c.ids[length] = static_cast<std::uint8_t>(v);
      ++length;
    }
    if (c.loops == 1) c.length = static_cast<std::uint8_t>(length);
  }
  if (c.loops != 1) c.length = 0;
  return c;
}

const CubeLoopTables& cubeLoopTables() {
  static const CubeLoopTables tables = build();
  return tables;
}

}  // namespace frep
