// A crease's feature point brought into a cell: shared by the cube extraction (mesher.cpp,
// placeFeature) and the local refinement's half cubes (local_refinement.cpp).
#pragma once

#include <algorithm>
#include <limits>

#include "base/triangle_mesh.h"
#include "base/vec.h"

namespace frep {

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
