// Forward-mode automatic differentiation: a value and its gradient in x, y, z.
// Used by the gradient evaluator mode (analytic normals).
#pragma once

#include <algorithm>
#include <cmath>

#include "frep/scalar_math.h"

namespace frep {

struct Dual {
  double v = 0.0;
  double d[3] = {0.0, 0.0, 0.0};

  Dual() = default;
  Dual(double value) : v(value) {}  // NOLINT: implicit from a constant
  Dual(double value, double dx, double dy, double dz) : v(value), d{dx, dy, dz} {}
};

inline Dual operator+(const Dual& a, const Dual& b) {
  return {a.v + b.v, a.d[0] + b.d[0], a.d[1] + b.d[1], a.d[2] + b.d[2]};
}
inline Dual operator-(const Dual& a, const Dual& b) {
  return {a.v - b.v, a.d[0] - b.d[0], a.d[1] - b.d[1], a.d[2] - b.d[2]};
}
inline Dual operator-(const Dual& a) { return {-a.v, -a.d[0], -a.d[1], -a.d[2]}; }
inline Dual operator*(const Dual& a, const Dual& b) {
  return {a.v * b.v, a.d[0] * b.v + a.v * b.d[0], a.d[1] * b.v + a.v * b.d[1],
          a.d[2] * b.v + a.v * b.d[2]};
}
inline Dual operator/(const Dual& a, const Dual& b) {
  const double inv = 1.0 / b.v;
  const double q = a.v * inv;
  return {q, (a.d[0] - q * b.d[0]) * inv, (a.d[1] - q * b.d[1]) * inv, (a.d[2] - q * b.d[2]) * inv};
}
// A field's value v and gradient g (with respect to the point x.v, y.v, z.v) composed with the
// derivatives the coordinates carry: the chain rule under the caller's transforms. (Fields
// that compute their own gradient, such as grids and mesh distances, end with this.)
inline Dual composed(double v, const double g[3], const Dual& x, const Dual& y, const Dual& z) {
  Dual out(v);
  for (int k = 0; k < 3; ++k) out.d[k] = g[0] * x.d[k] + g[1] * y.d[k] + g[2] * z.d[k];
  return out;
}
inline Dual chain(const Dual& a, double value, double slope) {
  return {value, a.d[0] * slope, a.d[1] * slope, a.d[2] * slope};
}
inline Dual sqr(const Dual& a) { return chain(a, a.v * a.v, 2.0 * a.v); }
inline Dual sqrt(const Dual& a) {
  const double s = std::sqrt(a.v);
  return chain(a, s, s > 0.0 ? 0.5 / s : 0.0);
}
inline Dual abs(const Dual& a) { return a.v < 0.0 ? -a : a; }
inline Dual min(const Dual& a, const Dual& b) { return b.v < a.v ? b : a; }
inline Dual max(const Dual& a, const Dual& b) { return b.v > a.v ? b : a; }
inline Dual exp(const Dual& a) {
  const double e = std::exp(a.v);
  return chain(a, e, e);
}
// d|a|^k = k |a|^(k-1) sign(a) da. At a = 0 the slope is 0 for k > 1 and 1 for k = 1; for
// k < 1 it is infinite, and 0 is returned so that one point of a cusp gives no NaN normal.
inline Dual powAbs(const Dual& a, double k) {
  const double m = std::abs(a.v);
  const double slope = m == 0.0 ? (k == 1.0 ? 1.0 : 0.0) : k * std::pow(m, k - 1.0);
  return chain(a, std::pow(m, k), a.v < 0 ? -slope : slope);
}
// A step function: flat between the integers (its jumps only pick which copy is evaluated).
inline Dual floor(const Dual& a) { return Dual(std::floor(a.v)); }
// d atan2(y, x) = (x dy - y dx) / (x^2 + y^2)
inline Dual atan2(const Dual& y, const Dual& x) {
  Dual r;
  r.v = std::atan2(y.v, x.v);
  const double n = x.v * x.v + y.v * y.v;
  for (int i = 0; i < 3; ++i) r.d[i] = n > 0 ? (x.v * y.d[i] - y.v * x.d[i]) / n : 0.0;
  return r;
}
inline Dual tan(const Dual& a) {
  const double t = std::tan(a.v);
  return chain(a, t, 1.0 + t * t);
}
inline Dual atan(const Dual& a) { return chain(a, std::atan(a.v), 1.0 / (1.0 + a.v * a.v)); }
inline Dual log(const Dual& a) { return chain(a, std::log(a.v), 1.0 / a.v); }
// d a^k = k a^(k-1) da; where that slope is infinite (a = 0, k < 1) 0 is returned, as powAbs.
inline Dual powConst(const Dual& a, double k) {
  const double slope = k == 0.0 ? 0.0 : k * std::pow(a.v, k - 1.0);
  return chain(a, std::pow(a.v, k), std::isfinite(slope) ? slope : 0.0);
}
// The branch the value takes; its derivatives are the branch's.
inline Dual select(const Dual& a, const Dual& b, const Dual& c) { return a.v >= 0.0 ? b : c; }
// (frep::sin and cos, as the other modes evaluate them: scalar_math.h)
inline Dual sin(const Dual& a) {
  double s, c;
  frep::sinCos(a.v, &s, &c);
  return chain(a, s, c);
}
inline Dual cos(const Dual& a) {
  double s, c;
  frep::sinCos(a.v, &s, &c);
  return chain(a, c, -s);
}

}  // namespace frep
