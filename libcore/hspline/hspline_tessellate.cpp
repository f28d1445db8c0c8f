#include "hspline/hspline_tessellate.h"

#include <algorithm>
#include <cmath>
#include <sstream>
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

// For each span of `along` (u when alongU), the largest |second derivative| along it.
std::vector<double> spanCurvature(const FlatBSpline& f, const std::vector<double>& along,
                                  const std::vector<double>& across, bool alongU) {
  const SplineAxis& a = alongU ? f.u : f.v;
  const SplineAxis& c = alongU ? f.v : f.u;
  std::vector<SpanBasis> at;
  for (std::size_t s = 0; s + 1 < along.size(); ++s)
    for (double x : {0.0, 0.5, 1.0})
      at.push_back(a.basis(along[s] + x * (along[s + 1] - along[s])));
  std::vector<SpanBasis> lines;
  const std::size_t stride = std::max<std::size_t>(1, across.size() / 64);
  for (std::size_t t = 0; t + 1 < across.size(); t += stride)
    lines.push_back(c.basis(0.5 * (across[t] + across[t + 1])));
  std::vector<double> out(along.size() - 1, 0);
  for (std::size_t k = 0; k < at.size(); ++k)
    for (const SpanBasis& line : lines) {
      Vec3 second{0, 0, 0};
      for (int p = 0; p < 4; ++p)
        for (int q = 0; q < 4; ++q) {
          const int i = a.wrap(at[k].span - 3 + p), j = c.wrap(line.span - 3 + q);
          vaxpy(second, at[k].second[p] * line.value[q], alongU ? f.pole(i, j) : f.pole(j, i));
        }
      out[k / 3] = std::max(out[k / 3], vlength(second));
    }
  return out;
}

}  // namespace

HsTessellation tessellate(const FlatBSpline& f, double tolerance, std::size_t maxTriangles) {
  if (!(std::isfinite(tolerance) && tolerance > 0))
    throw ModelError("hspline tessellation: the tolerance must be a positive distance");
  const std::vector<double> bu = breakpoints(f.u), bv = breakpoints(f.v);
  // The largest second derivative along each span, sampled at its ends and middle across up
  // to 64 lines of the other direction (bases computed once per sample parameter).
  const std::vector<double> cu = spanCurvature(f, bu, bv, true),
                            cv = spanCurvature(f, bv, bu, false);
  const std::vector<double> us = samples(bu, cu, tolerance, f.u.isPeriodic());
  const std::vector<double> vs = samples(bv, cv, tolerance, f.v.isPeriodic());
  const std::size_t nu = us.size(), nv = vs.size();
  const std::size_t cellsU = f.u.isPeriodic() ? nu : nu - 1,
                    cellsV = f.v.isPeriodic() ? nv : nv - 1;
  if (2 * cellsU * cellsV > maxTriangles) {
    std::ostringstream message;  // (to_string would print a tolerance of 1e-9 as 0.000000)
    message << "hspline tessellation: a tolerance of " << tolerance << " needs "
            << 2 * cellsU * cellsV << " triangles, more than the " << maxTriangles
            << " allowed; give a larger tolerance";
    throw ModelError(message.str());
  }
  HsTessellation out;
  out.samplesU = static_cast<int>(nu), out.samplesV = static_cast<int>(nv);
  out.closed = f.u.isPeriodic() && f.v.isPeriodic();
  out.us = us, out.vs = vs;
  TriangleMesh& m = out.mesh;
  m.positions.resize(nu * nv);
  m.normals.resize(nu * nv);
  // The basis once per sample column and row, not once per vertex; each vertex then sums its
  // 16 poles for the point and the two tangents.
  std::vector<SpanBasis> basisU(nu), basisV(nv);
  for (std::size_t i = 0; i < nu; ++i) basisU[i] = f.u.basis(us[i]);
  for (std::size_t j = 0; j < nv; ++j) basisV[j] = f.v.basis(vs[j]);
  for (std::size_t j = 0; j < nv; ++j) {
    const SpanBasis& bv = basisV[j];
    int rows[4];
    for (int b = 0; b < 4; ++b) rows[b] = f.v.wrap(bv.span - 3 + b);
    for (std::size_t i = 0; i < nu; ++i) {
      const SpanBasis& bu = basisU[i];
      Vec3 p{0, 0, 0}, du{0, 0, 0}, dv{0, 0, 0};
      for (int a = 0; a < 4; ++a) {
        const int column = f.u.wrap(bu.span - 3 + a);
        for (int b = 0; b < 4; ++b) {
          const Vec3& c = f.pole(column, rows[b]);
          vaxpy(p, bu.value[a] * bv.value[b], c);
          vaxpy(du, bu.first[a] * bv.value[b], c);
          vaxpy(dv, bu.value[a] * bv.first[b], c);
        }
      }
      Vec3 n = vcross(du, dv);
      const double l = vlength(n);
      n = l > 0 ? vscale(n, 1 / l) : Vec3{0, 0, 0};
      m.positions[i + nu * j] = {float(p[0]), float(p[1]), float(p[2])};
      m.normals[i + nu * j] = {float(n[0]), float(n[1]), float(n[2])};
    }
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
