// Minimal fixed-size vector and box types shared across libcore's public interfaces.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

namespace frep {

using Vec3 = std::array<double, 3>;
using Mat34 = std::array<double, 12>;  // row-major 3x4 affine matrix [R | t]

// Inline arithmetic for hot loops (affine.h's cross and normalized go through Eigen).
inline Vec3 vadd(const Vec3& a, const Vec3& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
inline Vec3 vsub(const Vec3& a, const Vec3& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
inline Vec3 vscale(const Vec3& a, double s) {
  return {a[0] * s, a[1] * s, a[2] * s};
}
inline double vdot(const Vec3& a, const Vec3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
inline Vec3 vcross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double vlength(const Vec3& a) {
  return std::sqrt(vdot(a, a));
}
// a += s * b
inline void vaxpy(Vec3& a, double s, const Vec3& b) {
  a[0] += s * b[0], a[1] += s * b[1], a[2] += s * b[2];
}

struct Box3 {
  Vec3 lo{0, 0, 0};
  Vec3 hi{0, 0, 0};
  bool valid() const { return lo[0] < hi[0] && lo[1] < hi[1] && lo[2] < hi[2]; }
};

// The smallest box holding both.
inline Box3 boxHull(const Box3& a, const Box3& b) {
  Box3 r;
  for (int i = 0; i < 3; ++i)
    r.lo[i] = std::min(a.lo[i], b.lo[i]), r.hi[i] = std::max(a.hi[i], b.hi[i]);
  return r;
}
// Their common part (lo > hi on some axis where they do not meet).
inline Box3 boxIntersection(const Box3& a, const Box3& b) {
  Box3 r;
  for (int i = 0; i < 3; ++i)
    r.lo[i] = std::max(a.lo[i], b.lo[i]), r.hi[i] = std::min(a.hi[i], b.hi[i]);
  return r;
}
// Whether two closed boxes share a point.
inline bool boxesMeet(const Box3& a, const Box3& b) {
  for (int i = 0; i < 3; ++i)
    if (a.hi[i] < b.lo[i] || b.hi[i] < a.lo[i]) return false;
  return true;
}
// Whether the closed box holds p (false for a NaN coordinate).
inline bool boxHolds(const Box3& b, const Vec3& p) {
  for (int i = 0; i < 3; ++i)
    if (!(p[i] >= b.lo[i] && p[i] <= b.hi[i])) return false;
  return true;
}
// Whether `inner` lies within `outer`.
inline bool boxWithin(const Box3& inner, const Box3& outer) {
  for (int i = 0; i < 3; ++i)
    if (inner.lo[i] < outer.lo[i] || inner.hi[i] > outer.hi[i]) return false;
  return true;
}

}  // namespace frep
