// An hspline as one ordinary B-spline surface, exactly: each level's knots are inserted into
// the surface so far wherever that level has CVs (and only there), and the level's
// displacements then add onto single control points. The result is what OpenCASCADE gets
// (hspline/occt) and what tessellation evaluates.
#pragma once

#include <vector>

#include "base/vec.h"
#include "hspline/hspline.h"
#include "hspline/spline_axis.h"

namespace frep {

struct FlatBSpline {
  SplineAxis u, v;
  std::vector<Vec3> poles;  // u.count() x v.count(), index i + u.count() * j

  const Vec3& pole(int i, int j) const {
    return poles[static_cast<std::size_t>(i) +
                 static_cast<std::size_t>(u.count()) * static_cast<std::size_t>(j)];
  }
  HsSurfacePoint evaluate(double s, double t) const;
};

// The levels up to `upTo` (all when negative): S_upTo, the surface at that level of detail.
FlatBSpline flatten(const HSpline& h, int upTo = -1);

// A closed surface's enclosed volume, (1/3) of the integral of p . (du x dv), by the midpoint
// rule on a 48 x 48 grid: enough for its sign, which says whether the normals point out.
double enclosedVolume(const FlatBSpline& f);

// An axis the way OpenCASCADE (and FreeCAD's Part.BSplineSurface) take it: distinct knots with
// multiplicities, a periodic one closed by its first knot one period on. Its pole k (from 0)
// is our CV ourPole(k): OpenCASCADE starts a periodic sequence three knots before the first.
struct OccStyleAxis {
  std::vector<double> knots;
  std::vector<int> mults;
  bool periodic = false;
};
OccStyleAxis occStyle(const SplineAxis& a);
inline int ourPole(const SplineAxis& a, int k) {
  return a.isPeriodic() ? a.wrap(k - 3) : k;
}

// Carries a pole grid (nu x nv on `from`'s axes) onto finer axes (their knots hold these).
std::vector<Vec3> refineGrid(const std::vector<Vec3>& poles, const SplineAxis& fromU,
                             const SplineAxis& fromV, const SplineAxis& toU, const SplineAxis& toV);

}  // namespace frep
