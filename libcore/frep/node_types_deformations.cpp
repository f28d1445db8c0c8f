// Deformations: each evaluates its input at a point moved back by the inverse deformation,
// F(p) = f(D^-1 p). They are exact maps of space, but not isometries: the field is no longer
// a distance, so blends and offsets after a strong deformation act less uniformly.
#include "frep/node_helpers.h"
#include "frep/registry.h"
#include "frep/structural_bounds.h"
#include "frep/tree.h"

namespace frep {

namespace {
// p -> center + (I + (k - 1) d d^T)(p - center): the stretch by k along unit d.
Mat34 stretchMatrix(const Vec3& d, double k, const Vec3& c) {
  Mat34 m{};
  for (int i = 0; i < 3; ++i) {
    double shift = c[i];
    for (int j = 0; j < 3; ++j) {
      const double v = (i == j ? 1.0 : 0.0) + (k - 1.0) * d[i] * d[j];
      m[4 * i + j] = v;
      shift -= v * c[j];
    }
    m[4 * i + 3] = shift;
  }
  return m;
}
}  // namespace

void registerDeformations(Registry& r) {
  {
    ParamTemplate factor =
        positiveReal("factor", 1.5, "Stretch along the direction: 2 doubles, 0.5 halves.");
    ParamTemplate direction = vec3Param("direction", {0, 0, 1}, "", "The direction stretched.");
    direction.nonZeroVector = true;
    r.add({"stretch",
           "deformation",
           "Stretches (or squashes) its input along one direction about a centre, leaving the "
           "other two directions alone; along the axes it is a per-axis scale, but any "
           "direction works. The field is scaled by min(1, factor) so it stays a lower bound "
           "of the distance.",
           "h = (p - center).d;  F(p) = min(1, factor) f(p + (1/factor - 1) h d), d = "
           "direction/|direction|",
           1,
           1,
           {direction, factor, centerParam("The point that stays in place.")},
           [](CompileContext& c) {
             const double k = c.real("factor");
             if (k == 1.0) return c.input(0);
             const Vec3 d = normalized(c.vec3("direction"));
             const Slot f =
                 c.input(0, applyAffine(c.b, c.p, stretchMatrix(d, 1.0 / k, c.vec3("center"))));
             return k < 1.0 ? c.b.affine(f, f, f, k, 0, 0, 0) : f;
           },
           [](const Node& n, const std::vector<Box3>& in) {
             return affineImage(
                 stretchMatrix(normalized(n.vec3("direction")), n.real("factor"), n.vec3("center")),
                 in[0]);
           }});
  }

  r.add({"twist",
         "deformation",
         "Twists its input about an axis through a centre: each slice across the axis turns by "
         "`rate` per unit length along it (right-hand rule), so a twist of 0 changes nothing.",
         "h = (p - center).axis;  F(p) = f(center + R(axis, -rate h)(p - center))",
         1,
         1,
         {axisParam("Twist axis direction."),
          centerParam("A point on the axis; the slice through it does not turn."),
          realParam("rate", 90.0, "angle", "Turn per unit length along the axis, degrees.")},
         [](CompileContext& c) {
           const double rate = c.real("rate") * kPi / 180.0;
           if (rate == 0.0) return c.input(0);
           auto& b = c.b;
           const Vec3 o = c.vec3("center");
           const Frame f = frameAlong(c.vec3("axis"));
           const Point3Slots q = localCoordinates(b, c.p, o, f);
           const Slot theta = b.affine(q.z, q.z, q.z, -rate, 0.0, 0.0, 0.0);
           const Point3Slots t = turnedAboutW(b, q, theta);
           return c.input(0, fromLocalCoordinates(b, t.x, t.y, t.z, o, f));
         },
         [](const Node& n, const std::vector<Box3>& in) {
           return turnedAboutAxis(in[0], n.vec3("center"), n.vec3("axis"));
         }});

  {
    ParamTemplate direction =
        vec3Param("direction", {1, 0, 0}, "", "The direction along which the input is bent.");
    direction.nonZeroVector = true;
    ParamTemplate toward = vec3Param("toward", {0, 0, 1}, "",
                                     "Where the bend turns to (its component across "
                                     "`direction` is used; must not be parallel to it).");
    toward.nonZeroVector = true;
    r.add({"bend",
           "deformation",
           "Bends its input around an arc: the line through `center` along `direction` becomes "
           "a circle of radius length / angle turning towards `toward`, so `length` of the "
           "input turns by `angle`. Space on the far side of the circle's centre folds, so "
           "keep the input within half a turn of the arc.",
           "R = length / angle;  (a, b) = coordinates along direction and toward;  "
           "F(p) = f(center + R atan2(a, R - b) direction + (R - sqrt(a^2 + (R - b)^2)) toward)",
           1,
           1,
           {direction, toward, centerParam("Where the bend starts (a point on the line)."),
            realParam("angle", 90.0, "angle", "How far `length` of the input turns, degrees."),
            positiveLength("length", 1.0, "The length of the input that turns by `angle`.")},
           [](CompileContext& c) {
             const double angle = c.real("angle") * kPi / 180.0;
             if (angle == 0.0) return c.input(0);
             auto& b = c.b;
             const Vec3 o = c.vec3("center"), d = normalized(c.vec3("direction"));
             Vec3 t = c.vec3("toward");
             const double along = t[0] * d[0] + t[1] * d[1] + t[2] * d[2];
             t = normalized({t[0] - along * d[0], t[1] - along * d[1], t[2] - along * d[2]});
             const Vec3 w = {d[1] * t[2] - d[2] * t[1], d[2] * t[0] - d[0] * t[2],
                             d[0] * t[1] - d[1] * t[0]};
             const Frame f{d, t, w};
             const double radius = c.real("length") / angle;
             const Point3Slots q = localCoordinates(b, c.p, o, f);  // (a, b, across)
             const Slot fromCentre = b.affine(q.y, q.y, q.y, -1.0, 0.0, 0.0, radius);
             const Slot turned = b.emit(Op::Atan2, q.x, fromCentre);
             const Slot a = b.affine(turned, turned, turned, radius, 0.0, 0.0, 0.0);
             const Slot rho = b.length2(q.x, fromCentre);
             const Slot bb = b.affine(rho, rho, rho, -1.0, 0.0, 0.0, radius);
             return c.input(0, fromLocalCoordinates(b, a, bb, q.z, o, f));
           }});
  }

  r.add({"deform_point",
         "deformation",
         "Pulls the input's surface near a point by a displacement, fading smoothly to nothing "
         "at `radius` from it (seed 000's deform point): dents and bumps.",
         "w = (1 - min(|p - point|^2 / radius^2, 1))^2;  F(p) = f(p - w displacement)",
         1,
         1,
         {vec3Param("point", {0, 0, 0}, "length", "Centre of the deformation."),
          vec3Param("displacement", {0, 0, 0.3}, "length", "How far the centre moves."),
          positiveLength("radius", 0.5, "Reach of the deformation.")},
         [](CompileContext& c) {
           auto& b = c.b;
           const Vec3 m = c.vec3("displacement");
           if (m[0] == 0.0 && m[1] == 0.0 && m[2] == 0.0) return c.input(0);
           const double r = c.real("radius");
           const Point3Slots d = shifted(b, c.p, c.vec3("point"));
           const Slot r2 = b.add(b.add(b.sqr(d.x), b.sqr(d.y)), b.sqr(d.z));
           const Slot t =
               b.min(b.affine(r2, r2, r2, 1.0 / (r * r), 0.0, 0.0, 0.0), b.constant(1.0));
           const Slot w = b.sqr(b.affine(t, t, t, -1.0, 0.0, 0.0, 1.0));
           auto moved = [&](Slot v, double k) { return b.affine(v, w, w, 1.0, -k, 0.0, 0.0); };
           return c.input(0, {moved(c.p.x, m[0]), moved(c.p.y, m[1]), moved(c.p.z, m[2])});
         },
         [](const Node& n, const std::vector<Box3>& in) {
           // Points move by at most |displacement|.
           const Vec3 m = n.vec3("displacement");
           return paddedBox(in[0], std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]));
         }});

  r.add({"taper",
         "deformation",
         "Scales its input across an axis linearly along it: by scale1 at the start point, by "
         "scale2 at `length` along the axis, and held constant beyond both ends.",
         "h = (p - start).axis;  s = scale1 + (scale2 - scale1) clamp(h/length, 0, 1);  "
         "F(p) = f(start + (p_across / s) + h axis)",
         1,
         1,
         {axisParam("Taper axis direction."),
          vec3Param("start", {0, 0, 0}, "length", "Where the scale is scale1."),
          positiveLength("length", 1.0, "Distance along the axis to where the scale is scale2."),
          positiveReal("scale1", 1.0, "Scale across the axis at the start."),
          positiveReal("scale2", 0.5, "Scale across the axis at `length` from the start.")},
         [](CompileContext& c) {
           auto& b = c.b;
           const double s1 = c.real("scale1"), s2 = c.real("scale2"), len = c.real("length");
           if (s1 == 1.0 && s2 == 1.0) return c.input(0);
           const Vec3 o = c.vec3("start");
           const Frame f = frameAlong(c.vec3("axis"));
           const Point3Slots q = localCoordinates(b, c.p, o, f);
           const Slot t =
               b.min(b.max(b.affine(q.z, q.z, q.z, 1.0 / len, 0.0, 0.0, 0.0), b.constant(0.0)),
                     b.constant(1.0));
           const Slot inv = b.div(b.constant(1.0), b.affine(t, t, t, s2 - s1, 0.0, 0.0, s1));
           return c.input(0, fromLocalCoordinates(b, b.mul(q.x, inv), b.mul(q.y, inv), q.z, o, f));
         },
         [](const Node& n, const std::vector<Box3>& in) {
           if (!isFinite(in[0])) return unknownBounds();
           const Vec3 w = normalized(n.vec3("axis")), o = n.vec3("start");
           double radius, lo, hi;
           radialExtent(in[0], o, w, &radius, &lo, &hi);
           return cylinderBounds(o, w, lo, hi,
                                 radius * std::max(n.real("scale1"), n.real("scale2")));
         }});
}

}  // namespace frep
