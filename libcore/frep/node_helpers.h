// Small compile-time helpers shared by the node type definitions.
#pragma once

#include <cmath>
#include <limits>

#include "base/affine.h"
#include "frep/registry.h"

namespace frep {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();

// Parameter templates several node families share.
inline ParamTemplate positiveLength(const char* name, double def, const char* doc) {
  ParamTemplate p = realParam(name, def, "length", doc);
  range(p, 0.0, kInf, true);
  return p;
}
inline ParamTemplate positiveReal(const char* name, double def, const char* doc) {
  ParamTemplate p = realParam(name, def, "", doc);
  range(p, 0.0, kInf, true);
  return p;
}
inline ParamTemplate axisParam(const char* doc) {
  ParamTemplate p = vec3Param("axis", {0, 0, 1}, "", doc);
  p.nonZeroVector = true;
  return p;
}
inline ParamTemplate centerParam(const char* doc) {
  return vec3Param("center", {0, 0, 0}, "length", doc);
}

// Orthonormal frame (u, v, w) with w along `axis`.
struct Frame {
  Vec3 u, v, w;
};
inline Frame frameAlong(const Vec3& axis) {
  const Vec3 w = normalized(axis);
  // Pick the world axis least aligned with w to build u.
  const Vec3 helper = std::abs(w[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const double d = helper[0] * w[0] + helper[1] * w[1] + helper[2] * w[2];
  const Vec3 u = normalized({helper[0] - d * w[0], helper[1] - d * w[1], helper[2] - d * w[2]});
  const Vec3 v = {w[1] * u[2] - w[2] * u[1], w[2] * u[0] - w[0] * u[2], w[0] * u[1] - w[1] * u[0]};
  return {u, v, w};
}

// Coordinates of p relative to `origin` in the frame (u, v, w): three affine instructions.
inline Point3Slots localCoordinates(ProgramBuilder& b, Point3Slots p, const Vec3& origin,
                                    const Frame& f) {
  auto along = [&](const Vec3& d) {
    const double off = -(d[0] * origin[0] + d[1] * origin[1] + d[2] * origin[2]);
    return b.affine(p.x, p.y, p.z, d[0], d[1], d[2], off);
  };
  return {along(f.u), along(f.v), along(f.w)};
}

// The inverse of localCoordinates: the world point origin + a u + b v + h w.
inline Point3Slots fromLocalCoordinates(ProgramBuilder& b, Slot a, Slot bb, Slot h,
                                        const Vec3& origin, const Frame& f) {
  return {b.affine(a, bb, h, f.u[0], f.v[0], f.w[0], origin[0]),
          b.affine(a, bb, h, f.u[1], f.v[1], f.w[1], origin[1]),
          b.affine(a, bb, h, f.u[2], f.v[2], f.w[2], origin[2])};
}

// Frame coordinates q turned about the frame's w axis by the angle held in `angle` (radians,
// computed per point, as in a twist or a polar array).
inline Point3Slots turnedAboutW(ProgramBuilder& b, const Point3Slots& q, Slot angle) {
  const Slot cs = b.emit(Op::Cos, angle), sn = b.emit(Op::Sin, angle);
  return {b.sub(b.mul(q.x, cs), b.mul(q.y, sn)), b.add(b.mul(q.x, sn), b.mul(q.y, cs)), q.z};
}

// p - origin, component-wise (no rotation).
inline Point3Slots shifted(ProgramBuilder& b, Point3Slots p, const Vec3& origin) {
  return {b.sub(p.x, b.constant(origin[0])), b.sub(p.y, b.constant(origin[1])),
          b.sub(p.z, b.constant(origin[2]))};
}

// Applies the affine map q = M p + t given as a row-major 3x4 matrix.
inline Point3Slots applyAffine(ProgramBuilder& b, Point3Slots p, const Mat34& m) {
  return {b.affine(p.x, p.y, p.z, m[0], m[1], m[2], m[3]),
          b.affine(p.x, p.y, p.z, m[4], m[5], m[6], m[7]),
          b.affine(p.x, p.y, p.z, m[8], m[9], m[10], m[11])};
}

// |p - (a + t e)|, t the projection of p on the segment from a along e clamped to [0, 1]
// (*along: the slot of t, when asked); |p - a| where e is zero.
inline Slot segmentDistance(ProgramBuilder& b, const Point3Slots& p, const Vec3& a, const Vec3& e,
                            Slot* along = nullptr) {
  const Slot dx = b.affine(p.x, p.x, p.x, 1.0, 0.0, 0.0, -a[0]);
  const Slot dy = b.affine(p.y, p.y, p.y, 1.0, 0.0, 0.0, -a[1]);
  const Slot dz = b.affine(p.z, p.z, p.z, 1.0, 0.0, 0.0, -a[2]);
  const double l2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
  if (l2 == 0.0) {
    if (along) *along = b.constant(0.0);
    return b.length3(dx, dy, dz);
  }
  const double dot = e[0] * a[0] + e[1] * a[1] + e[2] * a[2];
  const Slot raw = b.affine(p.x, p.y, p.z, e[0] / l2, e[1] / l2, e[2] / l2, -dot / l2);
  const Slot t = b.min(b.max(raw, b.constant(0.0)), b.constant(1.0));
  if (along) *along = t;
  const Slot ox = b.affine(dx, t, t, 1.0, -e[0], 0.0, 0.0);
  const Slot oy = b.affine(dy, t, t, 1.0, -e[1], 0.0, 0.0);
  const Slot oz = b.affine(dz, t, t, 1.0, -e[2], 0.0, 0.0);
  return b.length3(ox, oy, oz);
}

// The squared distance from p to the segment from a along e (to the point a where e is
// zero): one instruction.
inline Slot segmentDistanceSquared(ProgramBuilder& b, const Point3Slots& p, const Vec3& a,
                                   const Vec3& e) {
  const double l2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
  return b.emit(Op::SegmentSq, p.x, p.y, p.z,
                {a[0], a[1], a[2], e[0], e[1], e[2], l2 > 0.0 ? 1.0 / l2 : 0.0});
}

}  // namespace frep
