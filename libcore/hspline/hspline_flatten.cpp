#include "hspline/hspline_flatten.h"

#include <algorithm>

namespace frep {

namespace {

// The knots of `axis` at the ends of the spans that the basis functions of the given CVs
// cover: what the flattened surface needs of this level.
std::vector<double> coveredKnots(const SplineAxis& axis, const std::vector<int>& cvs) {
  std::vector<char> span(
      static_cast<std::size_t>(axis.isPeriodic() ? axis.count() : axis.count() + 3), 0);
  for (int k : cvs)
    for (int s = k; s < k + 4; ++s)
      span[static_cast<std::size_t>(axis.isPeriodic() ? axis.wrap(s) : s)] = 1;
  std::vector<double> out;
  for (std::size_t s = 0; s < span.size(); ++s)
    if (span[s]) {
      for (long e : {long(s), long(s) + 1}) {
        double x = axis.knot(e);
        if (axis.isPeriodic() && x >= axis.hi()) x -= axis.period();
        out.push_back(x);
      }
    }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

// `base` with the values of `extra` that it lacks added (each once: an hspline's new knots are
// midpoints, never repeated).
SplineAxis withKnots(const SplineAxis& base, const std::vector<double>& extra) {
  std::vector<double> k = base.knots();
  for (double x : extra)
    if (!std::binary_search(base.knots().begin(), base.knots().end(), x)) k.push_back(x);
  std::sort(k.begin(), k.end());
  return base.isPeriodic() ? SplineAxis::periodic(std::move(k), base.period())
                           : SplineAxis::open(std::move(k));
}

// Index in `flat` of the basis function that `level`'s basis k is: the same five knots.
int indexIn(const SplineAxis& flat, const SplineAxis& level, int k) {
  const double t = level.knot(k);
  const auto& lk = level.knots();
  const auto& fk = flat.knots();
  const long repeat = k - (std::lower_bound(lk.begin(), lk.end(), t) - lk.begin());
  return static_cast<int>((std::lower_bound(fk.begin(), fk.end(), t) - fk.begin()) + repeat);
}

}  // namespace

std::vector<Vec3> refineGrid(const std::vector<Vec3>& poles, const SplineAxis& fromU,
                             const SplineAxis& fromV, const SplineAxis& toU,
                             const SplineAxis& toV) {
  const auto rowsU = fromU.rowsOnto(toU), rowsV = fromV.rowsOnto(toV);
  const std::size_t nu = static_cast<std::size_t>(fromU.count()),
                    mu = static_cast<std::size_t>(toU.count());
  const std::size_t nv = static_cast<std::size_t>(fromV.count()),
                    mv = static_cast<std::size_t>(toV.count());
  std::vector<Vec3> half(mu * nv, Vec3{0, 0, 0}), out(mu * mv, Vec3{0, 0, 0});
  for (std::size_t j = 0; j < nv; ++j)
    for (std::size_t i = 0; i < mu; ++i)
      for (const auto& [a, w] : rowsU[i])
        vaxpy(half[i + mu * j], w, poles[static_cast<std::size_t>(a) + nu * j]);
  for (std::size_t j = 0; j < mv; ++j)
    for (const auto& [b, w] : rowsV[j])
      for (std::size_t i = 0; i < mu; ++i)
        vaxpy(out[i + mu * j], w, half[i + mu * static_cast<std::size_t>(b)]);
  return out;
}

FlatBSpline flatten(const HSpline& h, int upTo) {
  const HsLevel& base = h.level(0);
  FlatBSpline flat{base.u, base.v, h.positions(0)};
  const int last = upTo < 0 ? h.levelCount() - 1 : std::min(upTo, h.levelCount() - 1);
  for (int level = 1; level <= last; ++level) {
    const HsLevel& l = h.level(level);
    if (l.cvs.empty()) continue;
    std::vector<int> is, js;
    for (const HsCv& cv : l.cvs) is.push_back(cv.i), js.push_back(cv.j);
    SplineAxis u = withKnots(flat.u, coveredKnots(l.u, is)),
               v = withKnots(flat.v, coveredKnots(l.v, js));
    flat.poles = refineGrid(flat.poles, flat.u, flat.v, u, v);
    flat.u = std::move(u), flat.v = std::move(v);
    // Each CV's displacement is the flattened net's at its own basis function.
    for (std::size_t k = 0; k < l.cvs.size(); ++k) {
      const HsCv& cv = l.cvs[k];
      if (cv.value == Vec3{0, 0, 0}) continue;
      const int fi = indexIn(flat.u, l.u, cv.i), fj = indexIn(flat.v, l.v, cv.j);
      Vec3& p = flat.poles[static_cast<std::size_t>(fi) +
                           static_cast<std::size_t>(flat.u.count()) * static_cast<std::size_t>(fj)];
      p = vadd(p, h.displacement(level, static_cast<int>(k)));
    }
  }
  return flat;
}

double enclosedVolume(const FlatBSpline& f) {
  const int n = 48;
  double sum = 0;
  const double hu = (f.u.hi() - f.u.lo()) / n, hv = (f.v.hi() - f.v.lo()) / n;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const HsSurfacePoint p = f.evaluate(f.u.lo() + (i + 0.5) * hu, f.v.lo() + (j + 0.5) * hv);
      sum += vdot(p.position, vcross(p.du, p.dv));
    }
  return sum * hu * hv / 3;
}

OccStyleAxis occStyle(const SplineAxis& a) {
  OccStyleAxis o;
  o.periodic = a.isPeriodic();
  for (double x : a.knots()) {
    if (!o.knots.empty() && o.knots.back() == x)
      ++o.mults.back();
    else
      o.knots.push_back(x), o.mults.push_back(1);
  }
  if (o.periodic) o.knots.push_back(a.lo() + a.period()), o.mults.push_back(o.mults.front());
  return o;
}

HsSurfacePoint FlatBSpline::evaluate(double s, double t) const {
  HsSurfacePoint p;
  const SpanBasis bu = u.basis(s), bv = v.basis(t);
  for (int b = 0; b < 4; ++b) {
    const int j = v.wrap(bv.span - 3 + b);
    for (int a = 0; a < 4; ++a) {
      p.add(bu, bv, a, b, pole(u.wrap(bu.span - 3 + a), j));
    }
  }
  return p;
}

}  // namespace frep
