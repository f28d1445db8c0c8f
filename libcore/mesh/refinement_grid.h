// The local refinement's grids and its tests of a cube's finer points
// (mesh/local_refinement.h, docs/mesher.md "Local refinement" and "Deeper levels"). Internal
// to the mesh layer.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "mesh/sampling_grid.h"

namespace frep::refinement {

// The grid one level of refinement splits: the mesher's grid (level 0), or the points of the
// level above and those halfway between them (level L's point j is level L - 1's point j / 2
// where j is even, the middle of its points (j - 1) / 2 and (j + 1) / 2 where j is odd). Every
// level computes a shared point's coordinate by the same chain of midpoints, so a vertex one
// level put on a plane lies exactly on that plane for the next (level 1's points are the
// mesher's mid()).
struct RefinementGrid {
  const Grid* base = nullptr;
  int level = 0;
  std::int64_t points[3] = {0, 0, 0};
  double h[3] = {0, 0, 0};
  // level >= 1: the points' coordinates per axis (computed once per level)
  std::shared_ptr<const std::vector<double>> table[3];

  static RefinementGrid of(const Grid& g) {
    RefinementGrid r;
    r.base = &g;
    for (int a = 0; a < 3; ++a) {
      r.points[a] = g.points[a];
      r.h[a] = g.h[a];
    }
    return r;
  }
  RefinementGrid finer() const {
    RefinementGrid r = *this;
    ++r.level;
    for (int a = 0; a < 3; ++a) {
      r.points[a] = 2 * points[a] - 1;
      r.h[a] = 0.5 * h[a];
      auto t = std::make_shared<std::vector<double>>(static_cast<std::size_t>(r.points[a]));
      for (std::int64_t j = 0; j < r.points[a]; ++j)
        (*t)[static_cast<std::size_t>(j)] =
            j % 2 == 0 ? coord(a, j / 2) : 0.5 * (coord(a, j / 2) + coord(a, j / 2 + 1));
      r.table[a] = std::move(t);
    }
    return r;
  }
  double coord(int a, std::int64_t j) const {
    return level == 0 ? base->coord(a, j) : (*table[a])[static_cast<std::size_t>(j)];
  }
  double mid(int a, std::int64_t j) const { return 0.5 * (coord(a, j) + coord(a, j + 1)); }
  std::uint64_t linear(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return static_cast<std::uint64_t>(i + points[0] * (j + points[1] * k));
  }
  double boxField(double x, double y, double z) const { return base->boxField(x, y, z); }
};

// Whether a cube's 27 points (in(dx, dy, dz), each 0 to 2) show a side its corners miss: an
// edge whose midpoint differs from both its ends (onEdge(axis, db, dc) with the edge's
// offsets 0 or 2 on the other two axes), a face whose corners share a side another of its
// points lacks (onFace(axis, side 0 or 2)), or the cube's centre against its corners.
template <class In, class OnEdge, class OnFace>
inline bool showsHidden(const In& in, const OnEdge& onEdge, const OnFace& onFace) {
  auto at = [&](int a, int da, int b, int db, int cc, int dc) {
    int d[3];
    d[a] = da;
    d[b] = db;
    d[cc] = dc;
    return in(d[0], d[1], d[2]);
  };
  bool any = false;
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, cc = (a + 2) % 3;
    for (int e = 0; e < 4; ++e) {  // the cube's four edges along a
      const int db = 2 * (e & 1), dc = 2 * (e >> 1);
      const bool s0 = at(a, 0, b, db, cc, dc), s2 = at(a, 2, b, db, cc, dc);
      if (s0 != s2 || at(a, 1, b, db, cc, dc) == s0) continue;
      any = true;
      onEdge(a, db, dc);
    }
    for (int side = 0; side <= 2; side += 2) {  // the faces across a
      const bool s = at(a, side, b, 0, cc, 0);
      bool uniform = true, hidden = false;
      for (int db = 0; db <= 2; ++db)
        for (int dc = 0; dc <= 2; ++dc) {
          const bool v = at(a, side, b, db, cc, dc);
          if (db != 1 && dc != 1)
            uniform = uniform && v == s;
          else
            hidden = hidden || v != s;
        }
      if (!uniform || !hidden) continue;
      any = true;
      onFace(a, side);
    }
  }
  bool corners = true;
  const bool s = in(0, 0, 0);
  for (int d = 1; d < 8; ++d) corners = corners && in(2 * (d & 1), (d & 2), (d & 4) / 2) == s;
  return any || (corners && in(1, 1, 1) != s);
}

// Whether a face of the cube's eight cells (in(dx, dy, dz), each 0 to 2) has its two
// sides on the diagonals: a sliver narrower than the cells crossing it aslant (or a saddle),
// which the cells' corners see only as points touching at their corners.
template <class In>
inline bool anyFaceDiagonal(const In& in) {
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    for (int p = 0; p <= 2; ++p)
      for (int u = 0; u < 2; ++u)
        for (int w = 0; w < 2; ++w) {
          auto at = [&](int du, int dw) {
            int d[3];
            d[a] = p;
            d[b] = u + du;
            d[c] = w + dw;
            return in(d[0], d[1], d[2]);
          };
          const bool s00 = at(0, 0), s11 = at(1, 1);
          if (s00 == s11 && at(1, 0) == at(0, 1) && s00 != at(1, 0)) return true;
        }
  }
  return false;
}

// The half cubes (bit h: half cube h) whose 27 points of the quarter-cell grid (in(qx,
// qy, qz), each 0 to 4 across the cube) show a side their corners miss.
template <class In>
std::uint8_t halfCubesShowingHidden(const In& in) {
  std::uint8_t mask = 0;
  for (int h = 0; h < 8; ++h) {
    auto at = [&](int dx, int dy, int dz) {
      return in(2 * (h & 1) + dx, (h & 2) + dy, (h & 4) / 2 + dz);
    };
    if (showsHidden(
            at, [](int, int, int) {}, [](int, int) {}) ||
        anyFaceDiagonal(at))
      mask = static_cast<std::uint8_t>(mask | (1u << h));
  }
  return mask;
}

}  // namespace frep::refinement
