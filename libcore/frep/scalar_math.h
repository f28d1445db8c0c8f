// The scalar versions of the math functions the instruction set uses, so that one template
// per operation serves double (point, batch), Dual (gradient) and, where no tighter rule
// exists, Interval.
#pragma once

#include <cmath>
#include <cstddef>

namespace frep {

inline double sqr(double a) {
  return a * a;
}
// |a|^k for k > 0.
inline double powAbs(double a, double k) {
  return std::pow(std::abs(a), k);
}
// a^k as std::pow: a negative base only with an integer exponent (NaN otherwise).
inline double powConst(double a, double k) {
  return std::pow(a, k);
}
// a >= 0 ? b : c (a NaN condition picks c).
inline double select(double a, double b, double c) {
  return a >= 0.0 ? b : c;
}
using std::abs;
using std::atan;
using std::atan2;
using std::exp;
using std::floor;
using std::log;
using std::sqrt;
using std::tan;
// sin and cos as every mode evaluates them (scalar_math.cpp): on x86-64, our own lanes
// (frep/vector_trig.h: two at a time, or four with AVX2, the same bits), several times faster
// than glibc's scalar functions and within 4 ulps of the exact value (measured 2.4; the
// interval rules widen by kTrigUlps); the point and gradient modes put their argument in the
// lanes of the same code, so all modes agree bit for bit. Never outside [-1, 1].
double sin(double a);
double cos(double a);
// Both, the same bits as sin(a) and cos(a), in about the time of one (the gradient mode).
void sinCos(double a, double* s, double* c);
// The same for n values, both in one pass (four at a time with AVX2, else two): the batch
// modes' kernels. a is neither s nor c; either output may be null.
void sinCosMany(const double* a, std::size_t n, double* s, double* c);
// min/max that return the first argument on ties and propagate a NaN in the first one.
inline double min(double a, double b) {
  return b < a ? b : a;
}
inline double max(double a, double b) {
  return b > a ? b : a;
}

}  // namespace frep
