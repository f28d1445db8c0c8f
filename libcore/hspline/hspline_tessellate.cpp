#include "hspline/hspline_tessellate.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "base/errors.h"

namespace frep {

namespace {

std::vector<double> breakpoints(const SplineAxis& a) {
  std::vector<double> b;
  for (double k : a.knots())
    if (k >= a.lo() && k <= a.hi() && (b.empty() || k > b.back())) b.push_back(k);
  if (a.isPeriodic()) b.push_back(a.hi());
  return b;
}

// Parameters along one axis: each span cut into pieces short enough that a cubic's chord,
// about h^2 |S''| / 8, stays within the tolerance.
std::vector<double> samples(const std::vector<double>& spans, const std::vector<double>& curvature,
                            double tolerance, bool periodic) {
  std::vector<double> out;
  for (std::size_t s = 0; s + 1 < spans.size(); ++s) {
    const double h = spans[s + 1] - spans[s];
    const double pieces = std::ceil(h * std::sqrt(curvature[s] / (8 * tolerance)));
    const int n = static_cast<int>(std::clamp(pieces, 1.0, 4096.0));
    for (int q = 0; q < n; ++q) out.push_back(spans[s] + h * q / n);
  }
  if (!periodic) out.push_back(spans.back());
  return out;
}

}  // namespace

HsTessellation tessellate(const FlatBSpline& f, double tolerance, std::size_t maxTriangles) {
  if (!(std::isfinite(tolerance) && tolerance > 0))
    throw ModelError("hspline tessellation: the tolerance must be a positive distance");
  const std::vector<double> bu = breakpoints(f.u), bv = breakpoints(f.v);
  // The largest second derivative along each span, sampled across the other direction.
  std::vector<double> cu(bu.size() - 1, 0), cv(bv.size() - 1, 0);
  const std::size_t strideU = std::max<std::size_t>(1, bu.size() / 64),
                    strideV = std::max<std::size_t>(1, bv.size() / 64);
  for (std::size_t s = 0; s + 1 < bu.size(); ++s)
    for (std::size_t t = 0; t + 1 < bv.size(); t += strideV)
      for (double x : {0.0, 0.5, 1.0}) {
        const HsSurfacePoint p =
            f.evaluate(bu[s] + x * (bu[s + 1] - bu[s]), 0.5 * (bv[t] + bv[t + 1]));
        cu[s] = std::max(cu[s], vlength(p.duu));
      }
  for (std::size_t t = 0; t + 1 < bv.size(); ++t)
    for (std::size_t s = 0; s + 1 < bu.size(); s += strideU)
      for (double x : {0.0, 0.5, 1.0}) {
        const HsSurfacePoint p =
            f.evaluate(0.5 * (bu[s] + bu[s + 1]), bv[t] + x * (bv[t + 1] - bv[t]));
        cv[t] = std::max(cv[t], vlength(p.dvv));
      }
  const std::vector<double> us = samples(bu, cu, tolerance, f.u.isPeriodic());
  const std::vector<double> vs = samples(bv, cv, tolerance, f.v.isPeriodic());
  const std::size_t nu = us.size(), nv = vs.size();
  const std::size_t cellsU = f.u.isPeriodic() ? nu : nu - 1,
                    cellsV = f.v.isPeriodic() ? nv : nv - 1;
  if (2 * cellsU * cellsV > maxTriangles)
    throw ModelError("hspline tessellation: a tolerance of " + std::to_string(tolerance) +
                     " needs " + std::to_string(2 * cellsU * cellsV) +
                     " triangles, more than the " + std::to_string(maxTriangles) +
                     " allowed; give a larger tolerance");
  HsTessellation out;
  out.samplesU = static_cast<int>(nu), out.samplesV = static_cast<int>(nv);
  out.closed = f.u.isPeriodic() && f.v.isPeriodic();
  out.us = us, out.vs = vs;
  TriangleMesh& m = out.mesh;
  m.positions.resize(nu * nv);
  m.normals.resize(nu * nv);
  for (std::size_t j = 0; j < nv; ++j)
    for (std::size_t i = 0; i < nu; ++i) {
      const HsSurfacePoint p = f.evaluate(us[i], vs[j]);
      const Vec3 n = p.normal();
      m.positions[i + nu * j] = {float(p.position[0]), float(p.position[1]), float(p.position[2])};
      m.normals[i + nu * j] = {float(n[0]), float(n[1]), float(n[2])};
    }
  m.triangles.reserve(2 * cellsU * cellsV);
  auto vertex = [&](std::size_t i, std::size_t j) {
    return static_cast<std::uint32_t>(i % nu + nu * (j % nv));
  };
  auto add = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    const auto &pa = m.positions[a], &pb = m.positions[b], &pc = m.positions[c];
    if (pa == pb || pb == pc || pc == pa) return;  // a collapsed edge (a pole) leaves no triangle
    m.triangles.push_back({a, b, c});
  };
  for (std::size_t j = 0; j < cellsV; ++j)
    for (std::size_t i = 0; i < cellsU; ++i) {
      const auto a = vertex(i, j), b = vertex(i + 1, j), c = vertex(i + 1, j + 1),
                 d = vertex(i, j + 1);
      add(a, b, c);
      add(a, c, d);
    }
  return out;
}

}  // namespace frep
