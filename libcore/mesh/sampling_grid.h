// The mesher's sampling grid: where its points lie, and the box as a field. Shared by the
// brick mesher and the local refinement that follows it (mesh/local_refinement.h).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "base/triangle_mesh.h"
#include "base/vec.h"
#include "frep/dual.h"
#include "frep/field.h"
#include "frep/interval.h"

namespace frep {

// The sampling grid. Grid point j on an axis sits at lo + (j - 0.5) h, j = 0 .. n + 1: points 0
// and n + 1 lie half a cell outside the box, so the surface closes there (box caps).
struct Grid {
  Vec3 lo, hi;
  double h[3];
  std::int64_t points[3];  // grid points per axis (n + 2)

  double coord(int axis, std::int64_t j) const {
    return lo[axis] + (static_cast<double>(j) - 0.5) * h[axis];
  }
  // Halfway between grid points j and j + 1: a cube's or a face's centre on that axis, the
  // same wherever it is computed (the value evaluated there and the edges from there agree).
  double mid(int axis, std::int64_t j) const { return 0.5 * (coord(axis, j) + coord(axis, j + 1)); }
  std::uint64_t linear(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return static_cast<std::uint64_t>(i + points[0] * (j + points[1] * k));
  }
  // The key of the vertex on the edge from the centre of the cube whose lowest grid point is
  // (i, j, k) to its corner c: after the keys of every grid edge (point x 7 + direction).
  std::uint64_t centreEdgeKey(std::int64_t i, std::int64_t j, std::int64_t k, int c) const {
    const std::uint64_t edges = static_cast<std::uint64_t>(points[0] * points[1] * points[2]) * 7;
    return edges + linear(i, j, k) * 8 + static_cast<std::uint64_t>(c);
  }
  // The box as a field: positive inside, intersected (min) with the model's field.
  double boxField(double x, double y, double z) const {
    const double dx = std::min(x - lo[0], hi[0] - x), dy = std::min(y - lo[1], hi[1] - y),
                 dz = std::min(z - lo[2], hi[2] - z);
    return std::min(dx, std::min(dy, dz));
  }
  Interval boxField(const Interval& x, const Interval& y, const Interval& z) const {
    const Interval dx = min(x - Interval(lo[0]), Interval(hi[0]) - x);
    const Interval dy = min(y - Interval(lo[1]), Interval(hi[1]) - y);
    const Interval dz = min(z - Interval(lo[2]), Interval(hi[2]) - z);
    return min(dx, min(dy, dz));
  }
};

// The unit normal at a vertex from the field's value and gradient there: minus the gradient
// of the box-capped field (the field grows inward), so the box face on a box cap.
inline Vec3f vertexNormal(const Dual& d, const Grid& g, const Vec3f& p) {
  const Dual c = cappedByBox(d, Box3{g.lo, g.hi}, Vec3{p[0], p[1], p[2]});
  double n[3] = {-d.d[0], -d.d[1], -d.d[2]};
  if (c.v < d.v)  // a cap: the face's outward normal (+0 across it, as files have always had)
    for (int a = 0; a < 3; ++a) n[a] = c.d[a] != 0.0 ? -c.d[a] : 0.0;
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  return len > 0 && std::isfinite(len)
             ? Vec3f{float(n[0] / len), float(n[1] / len), float(n[2] / len)}
             : Vec3f{0.f, 0.f, 0.f};
}

}  // namespace frep
