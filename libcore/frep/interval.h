// Interval arithmetic for the interval evaluator mode.
//
// Inclusion property, rigorous: the result interval contains the value that the point
// evaluator computes (in double precision, rounding to nearest) at every point of the input
// box, and `nan` is set wherever that value may be NaN. So a proof drawn from an interval
// ("every point of this brick is inside") needs no safety margin.
//
// How: each operation computes its end points by the natural formulas and widens them
// outwards (outward()): by one ulp for the correctly rounded operations (+ - * / sqrt),
// whose rounding is monotone, and by kLibmUlps for the library functions (exp, sin, pow,
// ...), whose documented error in glibc is at most 1-2 ulp. An end point that comes out NaN
// (inf - inf, 0 * inf) makes the interval the whole line with `nan` set. Results that are
// exact (negation, |a|, min, max, floor, the 0 of a square) are not widened.
//
// NaN semantics follow the point evaluator: min(a, b) and max(a, b) return a when either is
// NaN (scalar_math.h), select(NaN, b, c) is c, and the mesher counts NaN as outside.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace frep {

struct Interval {
  double lo = 0.0;
  double hi = 0.0;
  bool nan = false;  // some point of the box may evaluate to NaN; lo, hi bound the others

  Interval() = default;
  // A constant; a NaN constant is "anything, or NaN".
  constexpr Interval(double v)  // NOLINT: implicit from a constant
      : lo(v == v ? v : -std::numeric_limits<double>::infinity()),
        hi(v == v ? v : std::numeric_limits<double>::infinity()),
        nan(v != v) {}
  constexpr Interval(double l, double h, bool n = false) : lo(l), hi(h), nan(n) {}

  bool contains(double v) const { return v != v ? nan : (v >= lo && v <= hi); }
  double width() const { return hi - lo; }
  static Interval entire(bool nan = false) {
    return {-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
            nan};
  }
  static Interval allNan() { return entire(true); }
};

namespace interval_detail {
constexpr double kInf = std::numeric_limits<double>::infinity();
// Worst error of glibc's exp, log, sin, cos, tan, atan, atan2, pow on x86-64, plus one.
constexpr int kLibmUlps = 3;
// sin and cos are evaluated by glibc's vector library (scalar_math.h: 4 ulps from the exact
// value) and bounded here through the scalar ones (1 ulp): 4 + 1, plus one.
constexpr int kTrigUlps = 6;

// The next double above v (std::nextafter towards +inf, without the library call: interval
// evaluation runs for every cell of the mesher's octree and every sub-block of a brick).
inline double nextUp(double v) {
  if (!(v < kInf)) return v;  // +inf, NaN
  if (v == 0.0) return std::numeric_limits<double>::denorm_min();
  std::uint64_t u;
  std::memcpy(&u, &v, sizeof u);
  u = v > 0.0 ? u + 1 : u - 1;  // a negative v moves towards 0: its magnitude's bits shrink
  std::memcpy(&v, &u, sizeof v);
  return v;
}
inline double nextDown(double v) { return -nextUp(-v); }
inline double down(double v, int ulps) {
  for (int i = 0; i < ulps; ++i) v = nextDown(v);
  return v;
}
inline double up(double v, int ulps) {
  for (int i = 0; i < ulps; ++i) v = nextUp(v);
  return v;
}
}  // namespace interval_detail

// End points computed in round to nearest, widened outwards by `ulps`; NaN end points make the
// whole line (and NaN possible).
inline Interval outward(double lo, double hi, bool nan, int ulps = 1) {
  using namespace interval_detail;
  if (lo != lo || hi != hi) return Interval::entire(true);
  return {down(lo, ulps), up(hi, ulps), nan};
}

inline bool hasInfinity(const Interval& a) {
  return a.lo == -interval_detail::kInf || a.hi == interval_detail::kInf;
}
inline bool holdsZero(const Interval& a) { return a.lo <= 0.0 && a.hi >= 0.0; }

inline Interval operator+(Interval a, Interval b) {
  using interval_detail::kInf;
  const bool infMinusInf = (a.hi == kInf && b.lo == -kInf) || (a.lo == -kInf && b.hi == kInf);
  return outward(a.lo + b.lo, a.hi + b.hi, a.nan || b.nan || infMinusInf);
}
inline Interval operator-(Interval a) { return {-a.hi, -a.lo, a.nan}; }
inline Interval operator-(Interval a, Interval b) { return a + (-b); }

inline Interval operator*(Interval a, Interval b) {
  const double p1 = a.lo * b.lo, p2 = a.lo * b.hi, p3 = a.hi * b.lo, p4 = a.hi * b.hi;
  const bool zeroTimesInf =
      (holdsZero(a) && hasInfinity(b)) || (holdsZero(b) && hasInfinity(a));
  if (p1 != p1 || p2 != p2 || p3 != p3 || p4 != p4) return Interval::entire(true);
  return outward(std::min(std::min(p1, p2), std::min(p3, p4)),
                 std::max(std::max(p1, p2), std::max(p3, p4)), a.nan || b.nan || zeroTimesInf);
}

inline Interval operator/(Interval a, Interval b) {
  if (holdsZero(b))  // 0/0 and inf/inf are NaN, x/0 infinite
    return Interval::entire(a.nan || b.nan || holdsZero(a) || hasInfinity(a));
  const double p1 = a.lo / b.lo, p2 = a.lo / b.hi, p3 = a.hi / b.lo, p4 = a.hi / b.hi;
  if (p1 != p1 || p2 != p2 || p3 != p3 || p4 != p4) return Interval::entire(true);
  return outward(std::min(std::min(p1, p2), std::min(p3, p4)),
                 std::max(std::max(p1, p2), std::max(p3, p4)),
                 a.nan || b.nan || (hasInfinity(a) && hasInfinity(b)));
}

inline Interval sqr(Interval a) {
  using namespace interval_detail;
  const double l2 = a.lo * a.lo, h2 = a.hi * a.hi;
  if (a.lo >= 0.0) return {std::max(0.0, down(l2, 1)), up(h2, 1), a.nan};
  if (a.hi <= 0.0) return {std::max(0.0, down(h2, 1)), up(l2, 1), a.nan};
  return {0.0, up(std::max(l2, h2), 1), a.nan};
}

// sqrt is NaN below 0: a box reaching below 0 may give NaN.
inline Interval sqrt(Interval a) {
  using namespace interval_detail;
  if (a.hi < 0.0) return Interval::allNan();
  const double lo = a.lo <= 0.0 ? 0.0 : std::max(0.0, down(std::sqrt(a.lo), 1));
  return {lo, up(std::sqrt(a.hi), 1), a.nan || a.lo < 0.0};
}

inline Interval abs(Interval a) {
  if (a.lo >= 0.0) return a;
  if (a.hi <= 0.0) return -a;
  return {0.0, std::max(-a.lo, a.hi), a.nan};
}

// min(a, b) is `b < a ? b : a`: a NaN a gives NaN, a NaN b gives a.
inline Interval min(Interval a, Interval b) {
  return {std::min(a.lo, b.lo), b.nan ? a.hi : std::min(a.hi, b.hi), a.nan};
}
inline Interval max(Interval a, Interval b) {
  return {b.nan ? a.lo : std::max(a.lo, b.lo), std::max(a.hi, b.hi), a.nan};
}

inline Interval exp(Interval a) {
  using interval_detail::kLibmUlps;
  const Interval r = outward(std::exp(a.lo), std::exp(a.hi), a.nan, kLibmUlps);
  return {std::max(0.0, r.lo), r.hi, r.nan};
}

namespace interval_detail {
// A 2 pi periodic function over an interval: its end point values, plus 1 where a maximum
// (at maxAt + 2k pi) and -1 where a minimum (at minAt + 2k pi) lies inside. One ulp of
// slack on the tests, so an extremum that rounding puts just outside still counts. +-inf
// arguments give NaN.
inline Interval periodicRange(Interval a, double (*f)(double), double maxAt, double minAt,
                              int ulps) {
  constexpr double kTwoPi = 6.283185307179586476925286766559;
  const bool nan = a.nan || hasInfinity(a);
  // Over a period or more, or where the argument is so large that k*pi is not resolved.
  if (!(a.hi - a.lo < kTwoPi) || std::max(-a.lo, a.hi) > 1e15) return {-1.0, 1.0, nan};
  double lo = std::min(f(a.lo), f(a.hi));
  double hi = std::max(f(a.lo), f(a.hi));
  const double slack = 4e-16 * std::max(1.0, std::max(-a.lo, a.hi));
  const double kMax = std::ceil((a.lo - maxAt - slack) / kTwoPi);
  if (maxAt + kMax * kTwoPi <= a.hi + slack) hi = 1.0;
  const double kMin = std::ceil((a.lo - minAt - slack) / kTwoPi);
  if (minAt + kMin * kTwoPi <= a.hi + slack) lo = -1.0;
  const Interval r = outward(lo, hi, nan, ulps);
  return {std::max(-1.0, r.lo), std::min(1.0, r.hi), nan};
}
}  // namespace interval_detail

// sin: maxima at pi/2 + 2k pi, minima at -pi/2 + 2k pi.
inline Interval sin(Interval a) {
  constexpr double kHalfPi = 1.5707963267948966192313216916398;
  return interval_detail::periodicRange(a, [](double v) { return std::sin(v); }, kHalfPi,
                                        -kHalfPi, interval_detail::kTrigUlps);
}

// cos: maxima at 2k pi, minima at pi + 2k pi (not sin(a + pi/2): the shift would round).
inline Interval cos(Interval a) {
  constexpr double kPi = 3.14159265358979323846;
  return interval_detail::periodicRange(a, [](double v) { return std::cos(v); }, 0.0, kPi,
                                        interval_detail::kTrigUlps);
}

inline Interval floor(Interval a) { return {std::floor(a.lo), std::floor(a.hi), a.nan}; }

// |a|^k is increasing in |a| (k > 0).
inline Interval powAbs(Interval a, double k) {
  using interval_detail::kLibmUlps;
  const Interval m = abs(a);
  const Interval r = outward(std::pow(m.lo, k), std::pow(m.hi, k), a.nan, kLibmUlps);
  return {std::max(0.0, r.lo), r.hi, r.nan};
}

// tan is increasing between its poles at pi/2 + k pi; an interval holding a pole is unbounded.
inline Interval tan(Interval a) {
  using interval_detail::kLibmUlps;
  constexpr double kPi = 3.14159265358979323846;
  constexpr double kHalfPi = 1.5707963267948966192313216916398;
  const bool nan = a.nan || hasInfinity(a);
  if (!(a.hi - a.lo < kPi) || std::max(-a.lo, a.hi) > 1e15) return Interval::entire(nan);
  const double slack = 4e-16 * std::max(1.0, std::max(-a.lo, a.hi));
  const double pole = kHalfPi + std::ceil((a.lo - kHalfPi - slack) / kPi) * kPi;
  if (pole <= a.hi + slack) return Interval::entire(nan);
  return outward(std::tan(a.lo), std::tan(a.hi), nan, kLibmUlps);
}

inline Interval atan(Interval a) {
  using interval_detail::kLibmUlps;
  return outward(std::atan(a.lo), std::atan(a.hi), a.nan, kLibmUlps);
}

// log is NaN below 0 and -inf at 0.
inline Interval log(Interval a) {
  using interval_detail::kLibmUlps;
  if (a.hi < 0.0) return Interval::allNan();
  const double lo = a.lo <= 0.0 ? -interval_detail::kInf : std::log(a.lo);
  return outward(lo, std::log(a.hi), a.nan || a.lo < 0.0, kLibmUlps);
}

// a^k as std::pow. Integer k: |a|^k for even k, increasing for odd k, 1/a^|k| for k < 0.
// Other k: defined for a >= 0 only (like sqrt), monotone in a.
inline Interval powConst(Interval a, double k) {
  using interval_detail::kLibmUlps;
  if (k == std::floor(k) && std::abs(k) < 1e15) {
    if (k < 0.0) return Interval(1.0) / powConst(a, -k);
    if (k == 0.0) return {1.0, 1.0, false};  // pow(x, 0) is 1 even for NaN x
    const bool even = std::fmod(k, 2.0) == 0.0;
    if (!even) return outward(std::pow(a.lo, k), std::pow(a.hi, k), a.nan, kLibmUlps);
    const Interval m = abs(a);
    const Interval r = outward(std::pow(m.lo, k), std::pow(m.hi, k), a.nan, kLibmUlps);
    return {std::max(0.0, r.lo), r.hi, r.nan};
  }
  // pow(-inf, k) is 0 or inf (IEEE), not NaN like other negative bases
  if (a.lo == -interval_detail::kInf) return {0.0, interval_detail::kInf, true};
  if (a.hi < 0.0) return Interval::allNan();
  const double lo = std::pow(std::max(a.lo, 0.0), k), hi = std::pow(a.hi, k);
  const Interval r = k > 0.0 ? outward(lo, hi, a.nan || a.lo < 0.0, kLibmUlps)
                             : outward(hi, lo, a.nan || a.lo < 0.0, kLibmUlps);
  return {std::max(0.0, r.lo), r.hi, r.nan};
}

inline Interval hull(Interval a, Interval b) {
  return {std::min(a.lo, b.lo), std::max(a.hi, b.hi), a.nan || b.nan};
}

// a >= 0 ? b : c: one branch where the condition's sign is known (NaN picks c), else both.
inline Interval select(Interval a, Interval b, Interval c) {
  if (a.lo >= 0.0 && !a.nan) return b;
  if (a.hi < 0.0) return c;
  return hull(b, c);
}

// atan2(y, x) over a box: the angles of its corners, unless the box touches the origin or the
// branch cut along the negative x axis, where every angle may occur.
inline Interval atan2(Interval y, Interval x) {
  using interval_detail::kLibmUlps;
  constexpr double kPi = 3.14159265358979323846;
  const bool nan = y.nan || x.nan;
  if (x.lo <= 0.0 && y.lo <= 0.0 && y.hi >= 0.0) return outward(-kPi, kPi, nan, kLibmUlps);
  const double c[4] = {std::atan2(y.lo, x.lo), std::atan2(y.lo, x.hi), std::atan2(y.hi, x.lo),
                       std::atan2(y.hi, x.hi)};
  return outward(std::min(std::min(c[0], c[1]), std::min(c[2], c[3])),
                 std::max(std::max(c[0], c[1]), std::max(c[2], c[3])), nan, kLibmUlps);
}

}  // namespace frep
