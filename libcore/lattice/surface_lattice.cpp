#include "lattice/surface_lattice.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "base/errors.h"

namespace frep {

namespace {

// Samples per division along each parameter for the fit (and the check between them).
constexpr int kSamplesPerDivision = 3;

// A number as a stream writes it (1, 0.5, 1e-07), as ffd_lattice.cpp's messages do.
std::string text(double x) {
  std::ostringstream o;
  o << x;
  return o.str();
}

SurfaceSample sampleAt(const SurfaceSampler& surface, double s, double t) {
  const SurfaceSample p = surface(s, t);
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(p.point[a]) || !std::isfinite(p.normal[a]))
      throw ModelError("surface lattice: the surface is not finite at parameters (" + text(s) +
                       ", " + text(t) + ")");
  return p;
}

}  // namespace

SurfaceLattice latticeAlongSurface(const SurfaceSampler& surface, const Vec3& size, int l, int m) {
  for (int a = 0; a < 3; ++a)
    if (!(size[a] > 0.0) || !std::isfinite(size[a]))
      throw ModelError("surface lattice: its size along " + std::string(1, "xyz"[a]) + " is " +
                       text(size[a]) + "; it must be a positive length");
  for (int d : {l, m})
    if (d < 1 || d > kMaxSurfaceDivisions)
      throw ModelError("surface lattice: " + std::to_string(d) +
                       " divisions along the surface; allowed 1 to " +
                       std::to_string(kMaxSurfaceDivisions));
  const double thickness = size[2];
  // Least squares, one fit for the middle layer (the surface) and one for the difference of
  // the two faces (the thickness along the normal): the map is linear across, so its middle
  // is the average of the faces' control points and its slope across their difference.
  const int ns = kSamplesPerDivision * l + 1, nt = kSamplesPerDivision * m + 1;
  const int columns = (l + 1) * (m + 1);
  Eigen::MatrixXd basis(ns * nt, columns), targets(ns * nt, 6);
  std::vector<double> bs(l + 1), dbs(l + 1), bt(m + 1), dbt(m + 1);
  for (int a = 0; a < ns; ++a) {
    const double s = double(a) / (ns - 1);
    bernstein(l, s, bs.data(), dbs.data());
    for (int b = 0; b < nt; ++b) {
      const double t = double(b) / (nt - 1);
      bernstein(m, t, bt.data(), dbt.data());
      const int row = a * nt + b;
      for (int i = 0; i <= l; ++i)
        for (int j = 0; j <= m; ++j) basis(row, i * (m + 1) + j) = bs[i] * bt[j];
      const SurfaceSample p = sampleAt(surface, s, t);
      for (int k = 0; k < 3; ++k) {
        targets(row, k) = p.point[k];
        targets(row, 3 + k) = thickness * p.normal[k];
      }
    }
  }
  const Eigen::MatrixXd fit = basis.colPivHouseholderQr().solve(targets);
  SurfaceLattice out{FfdLattice({{0, 0, 0}, size}, l, m, 1), 0.0};
  for (int i = 0; i <= l; ++i)
    for (int j = 0; j <= m; ++j) {
      const int c = i * (m + 1) + j;
      Vec3 low, high;
      for (int k = 0; k < 3; ++k) {
        low[k] = fit(c, k) - 0.5 * fit(c, 3 + k);
        high[k] = fit(c, k) + 0.5 * fit(c, 3 + k);
      }
      out.lattice.setPoint(i, j, 0, low);
      out.lattice.setPoint(i, j, 1, high);
    }
  // How close: between the fit's samples, the middle and both faces.
  for (int a = 0; a < ns - 1; ++a)
    for (int b = 0; b < nt - 1; ++b) {
      const double s = (a + 0.5) / (ns - 1), t = (b + 0.5) / (nt - 1);
      const SurfaceSample p = sampleAt(surface, s, t);
      for (double u : {0.0, 0.5, 1.0}) {
        const Vec3 want = vadd(p.point, vscale(p.normal, (u - 0.5) * thickness));
        out.deviation =
            std::max(out.deviation, vlength(vsub(out.lattice.forward({s, t, u}), want)));
      }
    }
  return out;
}

}  // namespace frep
