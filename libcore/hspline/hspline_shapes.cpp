#include "hspline/hspline_shapes.h"

#include <cmath>
#include <string>

#include "base/errors.h"

namespace frep {

namespace {

void checkCount(const char* shape, const char* name, int n) {
  if (n < 4 || n > 1000)
    throw ModelError(std::string("hspline ") + shape + ": " + name + " is " + std::to_string(n) +
                     "; it must be 4 to 1,000 CVs");
}

void checkLength(const char* shape, const char* name, double x) {
  if (!(std::isfinite(x) && x > 0))
    throw ModelError(std::string("hspline ") + shape + ": " + name + " must be a positive length");
}

// The radius of a regular n-gon of CVs whose uniform cubic B-spline passes through the circle
// of radius r at its knots: the curve there is (P[i-1] + 4 P[i] + P[i+1]) / 6.
double netRadius(double r, int n) {
  return r * 6 / (4 + 2 * std::cos(2 * M_PI / n));
}

// Evenly spread values over [0, length] at the Greville abscissae of a clamped axis, so the
// surface's parametrisation along it is linear.
double clampedPosition(const SplineAxis& a, int i, double length) {
  return length * (a.reference(i) - a.lo()) / (a.hi() - a.lo());
}

}  // namespace

HSpline hsplinePlane(int cvsU, int cvsV, double sizeU, double sizeV) {
  checkCount("plane", "cvsU", cvsU), checkCount("plane", "cvsV", cvsV);
  checkLength("plane", "sizeU", sizeU), checkLength("plane", "sizeV", sizeV);
  SplineAxis u = SplineAxis::clampedUniform(cvsU - 3), v = SplineAxis::clampedUniform(cvsV - 3);
  std::vector<Vec3> p;
  for (int j = 0; j < cvsV; ++j)
    for (int i = 0; i < cvsU; ++i)
      p.push_back(
          {clampedPosition(u, i, sizeU) - sizeU / 2, clampedPosition(v, j, sizeV) - sizeV / 2, 0});
  return HSpline(std::move(u), std::move(v), std::move(p));
}

HSpline hsplineCylinder(int cvsAround, int cvsAlong, double radius, double height) {
  checkCount("cylinder", "cvsAround", cvsAround), checkCount("cylinder", "cvsAlong", cvsAlong);
  checkLength("cylinder", "radius", radius), checkLength("cylinder", "height", height);
  SplineAxis u = SplineAxis::periodicUniform(cvsAround),
             v = SplineAxis::clampedUniform(cvsAlong - 3);
  const double rho = netRadius(radius, cvsAround);
  std::vector<Vec3> p;
  for (int j = 0; j < cvsAlong; ++j)
    for (int i = 0; i < cvsAround; ++i) {
      const double a = 2 * M_PI * i / cvsAround;
      p.push_back({rho * std::cos(a), rho * std::sin(a), clampedPosition(v, j, height)});
    }
  return HSpline(std::move(u), std::move(v), std::move(p));
}

HSpline hsplineTorus(int cvsAround, int cvsTube, double majorRadius, double minorRadius) {
  checkCount("torus", "cvsAround", cvsAround), checkCount("torus", "cvsTube", cvsTube);
  checkLength("torus", "majorRadius", majorRadius),
      checkLength("torus", "minorRadius", minorRadius);
  if (!(minorRadius < majorRadius))
    throw ModelError(
        "hspline torus: minorRadius must be smaller than majorRadius, or the tube meets itself");
  SplineAxis u = SplineAxis::periodicUniform(cvsAround), v = SplineAxis::periodicUniform(cvsTube);
  // A tensor product of two circle nets: the around scale applies to the whole tube section.
  const double ku = netRadius(1, cvsAround), kv = netRadius(1, cvsTube);
  std::vector<Vec3> p;
  for (int j = 0; j < cvsTube; ++j)
    for (int i = 0; i < cvsAround; ++i) {
      const double a = 2 * M_PI * i / cvsAround, b = 2 * M_PI * j / cvsTube;
      const double r = majorRadius + kv * minorRadius * std::cos(b);
      p.push_back({ku * r * std::cos(a), ku * r * std::sin(a), kv * minorRadius * std::sin(b)});
    }
  return HSpline(std::move(u), std::move(v), std::move(p));
}

}  // namespace frep
