// The interval rule of the R-functions with alpha < 1 (ops.h), with its rounding bound.
#include <algorithm>
#include <cmath>
#include <limits>

#include "frep/ops.h"

namespace frep {

namespace {
// Unit roundoff of double.
constexpr double kU = std::numeric_limits<double>::epsilon() / 2;
// Beyond this magnitude a^2 may overflow and the point formula give inf - inf = NaN.
constexpr double kOverflow = 1e150;

double magnitude(const Interval& a) { return std::max(std::abs(a.lo), std::abs(a.hi)); }
}  // namespace

Interval rFunctionInterval(const Interval& a, const Interval& b, double alpha, bool isUnion) {
  const double ma = magnitude(a), mb = magnitude(b);
  const bool nan = a.nan || b.nan || !(ma < kOverflow) || !(mb < kOverflow);
  if (!(ma < kOverflow) || !(mb < kOverflow)) return Interval::entire(nan);
  const double lo = isUnion ? rUnion<double>(a.lo, b.lo, alpha) : rIntersect<double>(a.lo, b.lo, alpha);
  const double hi = isUnion ? rUnion<double>(a.hi, b.hi, alpha) : rIntersect<double>(a.hi, b.hi, alpha);

  // Rounding of the point formula (a + b +- sqrt(max(a^2 + b^2 - 2 alpha a b, 0))) / (1 + alpha)
  // at any point of the box, with M = max|a| + max|b|: the radicand s is computed within
  // 4u M^2 (bounded by 8u M^2 here); its square root then within min(sqrt(ds), ds / sqrt(s_lo))
  // where s_lo bounds s from below over the box (the root is ill-conditioned only where s
  // nears 0); the sums and the final scaling add 4u M relative to 1 + alpha.
  const double m = ma + mb;
  const double ds = 8.0 * kU * m * m;
  const Interval s = sqr(a) + sqr(b) - Interval(2.0 * alpha) * a * b;
  const double sLo = std::max(0.0, s.lo);
  const double rootError = sLo > 0.0 ? std::min(std::sqrt(ds), ds / std::sqrt(sLo)) : std::sqrt(ds);
  const double bound = 2.0 * (8.0 * kU * m + rootError) / (1.0 + alpha) * (1.0 + 1e-6) +
                       8.0 * std::numeric_limits<double>::denorm_min();
  // A point at a corner is itself in the box: twice the bound covers both the corner's
  // rounding and the point's.
  return outward(lo - 2.0 * bound, hi + 2.0 * bound, nan);
}

}  // namespace frep
