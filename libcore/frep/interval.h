// Interval arithmetic for the interval evaluator mode.
// Inclusion property: the result interval contains f(x) for every x in the input intervals.
// Rounding is round-to-nearest (no directed rounding); callers that need a proof of sign
// leave a small relative margin (see mesh/mesher.cpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

namespace frep {

struct Interval {
  double lo = 0.0;
  double hi = 0.0;

  Interval() = default;
  constexpr Interval(double v) : lo(v), hi(v) {}  // NOLINT: implicit from a constant
  constexpr Interval(double l, double h) : lo(l), hi(h) {}

  bool contains(double v) const { return v >= lo && v <= hi; }
  double width() const { return hi - lo; }
  static Interval entire() {
    return {-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  }
};

inline Interval operator+(Interval a, Interval b) { return {a.lo + b.lo, a.hi + b.hi}; }
inline Interval operator-(Interval a, Interval b) { return {a.lo - b.hi, a.hi - b.lo}; }
inline Interval operator-(Interval a) { return {-a.hi, -a.lo}; }

inline Interval operator*(Interval a, Interval b) {
  const double p1 = a.lo * b.lo, p2 = a.lo * b.hi, p3 = a.hi * b.lo, p4 = a.hi * b.hi;
  return {std::min(std::min(p1, p2), std::min(p3, p4)), std::max(std::max(p1, p2), std::max(p3, p4))};
}

inline Interval operator/(Interval a, Interval b) {
  if (b.lo <= 0.0 && b.hi >= 0.0) return Interval::entire();
  const double p1 = a.lo / b.lo, p2 = a.lo / b.hi, p3 = a.hi / b.lo, p4 = a.hi / b.hi;
  return {std::min(std::min(p1, p2), std::min(p3, p4)), std::max(std::max(p1, p2), std::max(p3, p4))};
}

inline Interval sqr(Interval a) {
  const double l2 = a.lo * a.lo, h2 = a.hi * a.hi;
  if (a.lo >= 0.0) return {l2, h2};
  if (a.hi <= 0.0) return {h2, l2};
  return {0.0, std::max(l2, h2)};
}

// sqrt of the non-negative part; a fully negative argument has no real value (NaN interval).
inline Interval sqrt(Interval a) {
  if (a.hi < 0.0) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    return {nan, nan};
  }
  return {std::sqrt(std::max(a.lo, 0.0)), std::sqrt(a.hi)};
}

inline Interval abs(Interval a) {
  if (a.lo >= 0.0) return a;
  if (a.hi <= 0.0) return -a;
  return {0.0, std::max(-a.lo, a.hi)};
}

inline Interval min(Interval a, Interval b) { return {std::min(a.lo, b.lo), std::min(a.hi, b.hi)}; }
inline Interval max(Interval a, Interval b) { return {std::max(a.lo, b.lo), std::max(a.hi, b.hi)}; }

inline Interval exp(Interval a) { return {std::exp(a.lo), std::exp(a.hi)}; }

// sin over an interval: the endpoint values plus any extremum (pi/2 + k*pi) inside.
inline Interval sin(Interval a) {
  constexpr double kTwoPi = 6.283185307179586476925286766559;
  constexpr double kHalfPi = 1.5707963267948966192313216916398;
  if (!(a.hi - a.lo < kTwoPi)) return {-1.0, 1.0};
  double lo = std::min(std::sin(a.lo), std::sin(a.hi));
  double hi = std::max(std::sin(a.lo), std::sin(a.hi));
  // maxima at pi/2 + 2k*pi, minima at -pi/2 + 2k*pi
  const double kMax = std::ceil((a.lo - kHalfPi) / kTwoPi);
  if (kHalfPi + kMax * kTwoPi <= a.hi) hi = 1.0;
  const double kMin = std::ceil((a.lo + kHalfPi) / kTwoPi);
  if (-kHalfPi + kMin * kTwoPi <= a.hi) lo = -1.0;
  return {lo, hi};
}

inline Interval cos(Interval a) {
  constexpr double kHalfPi = 1.5707963267948966192313216916398;
  return sin(Interval{a.lo + kHalfPi, a.hi + kHalfPi});
}

inline Interval floor(Interval a) { return {std::floor(a.lo), std::floor(a.hi)}; }

// |a|^k is increasing in |a| (k > 0).
inline Interval powAbs(Interval a, double k) {
  const Interval m = abs(a);
  return {std::pow(m.lo, k), std::pow(m.hi, k)};
}

// tan is increasing between its poles at pi/2 + k pi; an interval holding a pole is unbounded.
inline Interval tan(Interval a) {
  constexpr double kPi = 3.14159265358979323846;
  constexpr double kHalfPi = 1.5707963267948966192313216916398;
  if (!(a.hi - a.lo < kPi)) return Interval::entire();
  const double pole = kHalfPi + std::ceil((a.lo - kHalfPi) / kPi) * kPi;
  if (pole <= a.hi) return Interval::entire();
  return {std::tan(a.lo), std::tan(a.hi)};
}

inline Interval atan(Interval a) { return {std::atan(a.lo), std::atan(a.hi)}; }

// log of the positive part (log 0 = -inf); a fully negative argument has no real value.
inline Interval log(Interval a) {
  if (a.hi < 0.0) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    return {nan, nan};
  }
  return {std::log(std::max(a.lo, 0.0)), std::log(a.hi)};
}

// a^k as std::pow. Integer k: |a|^k for even k, increasing for odd k, 1/a^|k| for k < 0.
// Other k: defined for a >= 0 only (like sqrt), monotone in a.
inline Interval powConst(Interval a, double k) {
  if (k == std::floor(k) && std::abs(k) < 1e15) {
    if (k < 0.0) return Interval(1.0) / powConst(a, -k);
    if (k == 0.0) return {1.0, 1.0};
    const bool even = std::fmod(k, 2.0) == 0.0;
    if (!even) return {std::pow(a.lo, k), std::pow(a.hi, k)};
    const Interval m = abs(a);
    return {std::pow(m.lo, k), std::pow(m.hi, k)};
  }
  if (a.hi < 0.0) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    return {nan, nan};
  }
  const double lo = std::pow(std::max(a.lo, 0.0), k), hi = std::pow(a.hi, k);
  return k > 0.0 ? Interval{lo, hi} : Interval{hi, lo};
}

// a >= 0 ? b : c: one branch where the condition's sign is known, else both.
inline Interval select(Interval a, Interval b, Interval c) {
  if (a.lo >= 0.0) return b;
  if (a.hi < 0.0) return c;
  return {std::min(b.lo, c.lo), std::max(b.hi, c.hi)};
}

// atan2(y, x) over a box: the angles of its corners, unless the box touches the origin or the
// branch cut along the negative x axis, where every angle may occur.
inline Interval atan2(Interval y, Interval x) {
  constexpr double kPi = 3.14159265358979323846;
  if (x.lo <= 0.0 && y.lo <= 0.0 && y.hi >= 0.0) return {-kPi, kPi};
  const double c[4] = {std::atan2(y.lo, x.lo), std::atan2(y.lo, x.hi), std::atan2(y.hi, x.lo),
                       std::atan2(y.hi, x.hi)};
  return {std::min(std::min(c[0], c[1]), std::min(c[2], c[3])),
          std::max(std::max(c[0], c[1]), std::max(c[2], c[3]))};
}

}  // namespace frep
