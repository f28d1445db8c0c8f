// A crease's feature point brought into a cell: shared by the cube extraction (mesher.cpp,
// placeFeature) and the local refinement's half cubes (local_refinement.cpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "base/triangle_mesh.h"
#include "base/vec.h"

namespace frep {

// The two most different of n unit normals (normal(i) gives the i-th): the least cosine
// between two of them, and which two (*a > *b). False where a normal is zero or not finite
// (no feature can be judged).
template <class NormalAt>
bool mostDifferentNormals(std::size_t n, NormalAt normal, double* leastCos, std::size_t* a,
                          std::size_t* b) {
  *leastCos = 1.0;
  *a = *b = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3f u = normal(i);
    if (!(std::isfinite(u[0]) && (u[0] != 0 || u[1] != 0 || u[2] != 0))) return false;
    for (std::size_t j = 0; j < i; ++j) {
      const Vec3f w = normal(j);
      const double c = double(u[0]) * w[0] + double(u[1]) * w[1] + double(u[2]) * w[2];
      if (c < *leastCos) {
        *leastCos = c;
        *a = i;
        *b = j;
      }
    }
  }
  return true;
}

// A crease line through x (the tangent planes' point nearest their mean) along na x nb (the
// two most different normals) may cross the box [lo, hi] although x lies outside it: then x
// moves along the line to the crossing's point nearest x; else x stays.
inline void moveAlongCreaseIntoBox(Vec3& x, const Vec3f& na, const Vec3f& nb, const double lo[3],
                                   const double hi[3]) {
  const double d[3] = {double(na[1]) * nb[2] - double(na[2]) * nb[1],
                       double(na[2]) * nb[0] - double(na[0]) * nb[2],
                       double(na[0]) * nb[1] - double(na[1]) * nb[0]};
  double t0 = -std::numeric_limits<double>::infinity(), t1 = -t0;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (x[a] < lo[a] || x[a] > hi[a]) t0 = t1 + 1.0;  // parallel, outside: no crossing
      continue;
    }
    double u = (lo[a] - x[a]) / d[a], w = (hi[a] - x[a]) / d[a];
    if (u > w) std::swap(u, w);
    t0 = std::max(t0, u);
    t1 = std::min(t1, w);
  }
  if (t0 <= t1) {
    const double t = std::clamp(0.0, t0, t1);
    for (int a = 0; a < 3; ++a) x[a] += t * d[a];
  }
}

}  // namespace frep
