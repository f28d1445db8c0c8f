// Lattices for the tests: twisted about the rest box's vertical axis and shaken, mild or
// strong, and their control points as an ffd node's `points` parameter.
#pragma once

#include <cmath>
#include <random>

#include "frep/ffd_field.h"
#include "frep/registry.h"
#include "lattice/ffd_lattice.h"

namespace frep::testing {

const Box3 kLatticeRest{{-1.0, -0.5, 0.0}, {1.0, 0.5, 2.0}};

// Twists the lattice about the vertical line through the rest box's centre by up to `turns`
// radians at the top and shakes every control point by up to `jitter` of a cell.
inline FfdLattice twistedLattice(int l, int m, int n, double turns, double jitter, unsigned seed,
                                 const Box3& rest = kLatticeRest) {
  FfdLattice lattice(rest, l, m, n);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double size[3] = {rest.hi[0] - rest.lo[0], rest.hi[1] - rest.lo[1],
                          rest.hi[2] - rest.lo[2]};
  const double cx = 0.5 * (rest.lo[0] + rest.hi[0]), cy = 0.5 * (rest.lo[1] + rest.hi[1]);
  const double cell[3] = {size[0] / l, size[1] / m, size[2] / n};
  for (int i = 0; i <= l; ++i)
    for (int j = 0; j <= m; ++j)
      for (int k = 0; k <= n; ++k) {
        const Vec3 p = lattice.point(i, j, k);
        const double a = turns * (p[2] - rest.lo[2]) / size[2], c = std::cos(a), s = std::sin(a);
        Vec3 q{cx + c * (p[0] - cx) - s * (p[1] - cy), cy + s * (p[0] - cx) + c * (p[1] - cy),
               p[2]};
        for (int d = 0; d < 3; ++d) q[d] += jitter * cell[d] * u(rng);
        lattice.setPoint(i, j, k, q);
      }
  return lattice;
}

// A lattice of 4 x 1 x 1 divisions over `rest` (centred on x = 0) whose points are lifted along
// the parabola z += x^2 / 4: a beam bent upwards at its ends.
inline FfdLattice parabolaLattice(const Box3& rest) {
  FfdLattice lattice(rest, 4, 1, 1);
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; j <= 1; ++j)
      for (int k = 0; k <= 1; ++k) {
        Vec3 q = lattice.point(i, j, k);
        q[2] += 0.25 * (q[0] * q[0]);
        lattice.setPoint(i, j, k, q);
      }
  return lattice;
}

// The ffd node's parameters for a lattice.
inline std::map<std::string, ParamValue> ffdParams(const FfdLattice& lattice) {
  return frep::ffdParams(lattice);
}

}  // namespace frep::testing
