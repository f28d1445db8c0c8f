// The instruction set of compiled FRep programs and the meaning of each instruction.
// Every operation is written once as a template over the number type, so the point, batch
// and gradient modes share the same arithmetic; the interval mode uses the overloads in
// interval.h, plus tighter monotonicity rules where a generic formula would be loose.
#pragma once

#include <cstdint>

#include "frep/dual.h"
#include "frep/interval.h"
#include "frep/scalar_math.h"

namespace frep {

enum class Op : std::uint8_t {
  Const,       // k0
  Add,         // a + b
  Sub,         // a - b
  Mul,         // a * b
  Div,         // a / b
  Neg,         // -a
  Sqr,         // a^2
  Sqrt,        // sqrt(a)
  Abs,         // |a|
  Min,         // min(a, b)
  Max,         // max(a, b)
  Exp,         // e^a
  Sin,         // sin(a)
  Cos,         // cos(a)
  Affine,      // k0*a + k1*b + k2*c + k3
  RUnion,      // R-function union with alpha = k0
  RIntersect,  // R-function intersection with alpha = k0
  BlendBump,   // k0 / (1 + (a/k1)^2 + (b/k2)^2): Pasko's blend displacement
  Atan2,       // atan2(a, b): the angle of the point (b, a), in (-pi, pi]
  PowAbs,      // |a|^k0, k0 > 0 (superquadrics)
  Floor,       // floor(a): which copy of a repetition (arrays)
  Tan,         // tan(a)
  Atan,        // atan(a)
  Log,         // natural logarithm of a (NaN below 0)
  PowConst,    // a^k0 as std::pow: any base for an integer k0, a >= 0 otherwise (formulas)
  Select,      // a >= 0 ? b : c (pieces of piecewise functions: arcs, metaballs)
  SegmentSq,   // squared distance from (a, b, c) to the segment from k0..k2 along k3..k5
               // (k6 = 1 / its length squared; 0 for a point): struts, capsules
  External,    // another Field at the point (a, b, c); k0 = its index in Program::externals
  Count_
};

const char* opName(Op op);
int opArity(Op op);
int opConstantCount(Op op);
bool opIsCommutative(Op op);

// R-functions (Rvachev): alpha in (-1, 1]. Normalised by 1/(1+alpha) so that alpha = 1 is
// exactly max / min. Both are non-decreasing in each argument for |alpha| <= 1.
template <class T>
inline T rUnion(const T& a, const T& b, double alpha) {
  if (alpha == 1.0) return max(a, b);
  const T s = max(sqr(a) + sqr(b) - T(2.0 * alpha) * a * b, T(0.0));
  return (a + b + sqrt(s)) * T(1.0 / (1.0 + alpha));
}
template <class T>
inline T rIntersect(const T& a, const T& b, double alpha) {
  if (alpha == 1.0) return min(a, b);
  const T s = max(sqr(a) + sqr(b) - T(2.0 * alpha) * a * b, T(0.0));
  return (a + b - sqrt(s)) * T(1.0 / (1.0 + alpha));
}
// The R-functions are monotone, so their range over a box lies between their values at the
// lowest and highest corners. The values the point evaluator computes differ from the exact
// ones by rounding, which is bounded here (rFunctionRoundingBound) and added on both sides,
// so the result encloses every computed value (interval.h).
Interval rFunctionInterval(const Interval& a, const Interval& b, double alpha, bool isUnion);
inline Interval rUnion(const Interval& a, const Interval& b, double alpha) {
  if (alpha == 1.0) return max(a, b);
  return rFunctionInterval(a, b, alpha, true);
}
inline Interval rIntersect(const Interval& a, const Interval& b, double alpha) {
  if (alpha == 1.0) return min(a, b);
  return rFunctionInterval(a, b, alpha, false);
}

template <class T>
inline T blendBump(const T& a, const T& b, const double* k) {
  return T(k[0]) / (T(1.0) + sqr(a * T(1.0 / k[1])) + sqr(b * T(1.0 / k[2])));
}

template <class T>
inline T affine(const T& a, const T& b, const T& c, const double* k) {
  return T(k[0]) * a + T(k[1]) * b + T(k[2]) * c + T(k[3]);
}
// The squared distance from (x, y, z) to the segment from (k0, k1, k2) along e = (k3, k4, k5):
// d = p - k0..2, t = d.e * k6 clamped to [0, 1] (k6 = 1 / |e|^2; 0 with e = 0 for a point),
// |d - t e|^2. One instruction for what is a dozen when written out: a strut lattice's
// program is mostly these (struts, and node spheres as points).
template <class T>
inline T segmentSq(const T& x, const T& y, const T& z, const double* k) {
  const T dx = x - T(k[0]), dy = y - T(k[1]), dz = z - T(k[2]);
  const T t = min(max((dx * T(k[3]) + dy * T(k[4]) + dz * T(k[5])) * T(k[6]), T(0.0)), T(1.0));
  return sqr(dx - t * T(k[3])) + sqr(dy - t * T(k[4])) + sqr(dz - t * T(k[5]));
}
// On doubles: t from d = p - k0..2, and the squared distance with r = p - its nearest point
// of the segment (the gradient's direction).
inline double segmentAlong(double dx, double dy, double dz, const double* k) {
  return min(max((dx * k[3] + dy * k[4] + dz * k[5]) * k[6], 0.0), 1.0);
}
inline double segmentSq(double x, double y, double z, const double* k, double r[3]) {
  const double dx = x - k[0], dy = y - k[1], dz = z - k[2];
  const double t = segmentAlong(dx, dy, dz, k);
  r[0] = dx - t * k[3];
  r[1] = dy - t * k[4];
  r[2] = dz - t * k[5];
  return sqr(r[0]) + sqr(r[1]) + sqr(r[2]);
}
// The gradient of |r|^2 is 2 r: where t is clamped it does not move, and where it is not, r is
// perpendicular to e, so t's own derivative adds nothing (written out, the instructions add
// rounding noise for it).
inline double segmentSqSlope(const double r[3], double dx, double dy, double dz) {
  return 2.0 * (r[0] * dx + r[1] * dy + r[2] * dz);
}
template <>
inline double segmentSq<double>(const double& x, const double& y, const double& z,
                                const double* k) {
  double r[3];
  return segmentSq(x, y, z, k, r);
}
template <>
inline Dual segmentSq<Dual>(const Dual& x, const Dual& y, const Dual& z, const double* k) {
  double r[3];
  Dual out(segmentSq(x.v, y.v, z.v, k, r));
  for (int i = 0; i < 3; ++i) out.d[i] = segmentSqSlope(r, x.d[i], y.d[i], z.d[i]);
  return out;
}

// Applies one instruction to its operand values. k points at its constants.
template <class T>
inline T applyOp(Op op, const T& a, const T& b, const T& c, const double* k) {
  switch (op) {
    case Op::Const: return T(k[0]);
    case Op::Add: return a + b;
    case Op::Sub: return a - b;
    case Op::Mul: return a * b;
    case Op::Div: return a / b;
    case Op::Neg: return -a;
    case Op::Sqr: return sqr(a);
    case Op::Sqrt: return sqrt(a);
    case Op::Abs: return abs(a);
    case Op::Min: return min(a, b);
    case Op::Max: return max(a, b);
    case Op::Exp: return exp(a);
    case Op::Sin: return sin(a);
    case Op::Cos: return cos(a);
    case Op::Affine: return affine(a, b, c, k);
    case Op::RUnion: return rUnion(a, b, k[0]);
    case Op::RIntersect: return rIntersect(a, b, k[0]);
    case Op::BlendBump: return blendBump(a, b, k);
    case Op::Atan2: return atan2(a, b);
    case Op::PowAbs: return powAbs(a, k[0]);
    case Op::Floor: return floor(a);
    case Op::Tan: return tan(a);
    case Op::Atan: return atan(a);
    case Op::Log: return log(a);
    case Op::PowConst: return powConst(a, k[0]);
    case Op::Select: return select(a, b, c);
    case Op::SegmentSq:
      return segmentSq(a, b, c, k);
    case Op::External: break;  // needs the program's external fields: see Program
    case Op::Count_: break;
  }
  return T(0.0);
}

}  // namespace frep
