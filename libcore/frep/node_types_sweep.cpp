// Sphere sweep: a sphere of a radius varying linearly along a polyline, swept along it (seed
// 000's sphere sweep, HyperFun's hfConvLine shape without the convolution). The field is
// the exact distance to the polyline subtracted from the radius, so it is a distance field
// for a constant radius; with a varying one each segment is a tapered capsule.
#include <algorithm>
#include <cmath>

#include "frep/node_helpers.h"
#include "frep/registry.h"
#include "frep/structural_bounds.h"
#include "frep/tree.h"

namespace frep {

namespace {

// r(t) - |p - (a + t (b - a))| with t the clamped projection of p on the segment [a, b].
Slot capsule(ProgramBuilder& b, const Point3Slots& p, const Vec3& a, const Vec3& e, double ra,
             double rb) {
  const double l2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
  const Slot dx = b.affine(p.x, p.x, p.x, 1.0, 0.0, 0.0, -a[0]);
  const Slot dy = b.affine(p.y, p.y, p.y, 1.0, 0.0, 0.0, -a[1]);
  const Slot dz = b.affine(p.z, p.z, p.z, 1.0, 0.0, 0.0, -a[2]);
  if (l2 == 0.0) return b.sub(b.constant(ra), b.length3(dx, dy, dz));
  const double dot = e[0] * a[0] + e[1] * a[1] + e[2] * a[2];
  const Slot raw = b.affine(p.x, p.y, p.z, e[0] / l2, e[1] / l2, e[2] / l2, -dot / l2);
  const Slot t = b.min(b.max(raw, b.constant(0.0)), b.constant(1.0));
  const Slot ox = b.affine(dx, t, t, 1.0, -e[0], 0.0, 0.0);
  const Slot oy = b.affine(dy, t, t, 1.0, -e[1], 0.0, 0.0);
  const Slot oz = b.affine(dz, t, t, 1.0, -e[2], 0.0, 0.0);
  const Slot dist = b.length3(ox, oy, oz);
  return b.affine(t, dist, dist, rb - ra, -1.0, 0.0, ra);
}

}  // namespace

void registerSweeps(Registry& r) {
  ParamTemplate r1 = positiveLength("radius1", 0.2, "Radius at the first point.");
  ParamTemplate r2 = realParam("radius2", 0.2, "length", "Radius at the last point (0: a point).");
  range(r2, 0.0, kInf);
  ParamTemplate path =
      pointsParam("points", {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}, 2, "length", "The polyline, in order.");
  path.path = true;
  r.add({"sweep",
         "primitive",
         "A sphere swept along a polyline, its radius going linearly from radius1 to radius2 "
         "along the length. In FreeCAD the points can come from any edge, wire, sketch or "
         "Draft wire (property PointsSource).",
         "F = max_i (r(s_i(t_i)) - |p - (P_i + t_i (P_i+1 - P_i))|),  t_i = clamp of the "
         "projection of p on segment i, s = arc length",
         0,
         0,
         {path, r1, r2},
         [](CompileContext& c) {
           auto& b = c.b;
           const std::vector<Vec3> pts = pointsOf(c.param("points"));
           std::vector<double> at(pts.size(), 0.0);  // arc length at each point
           for (std::size_t i = 1; i < pts.size(); ++i) {
             const Vec3& p = pts[i - 1];
             const Vec3& q = pts[i];
             at[i] = at[i - 1] +
                     std::sqrt((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) +
                               (q[2] - p[2]) * (q[2] - p[2]));
           }
           const double total = at.back(), ra = c.real("radius1"), rb = c.real("radius2");
           auto radiusAt = [&](double s) { return total > 0 ? ra + (rb - ra) * s / total : ra; };
           Slot field = 0;
           bool first = true;
           for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
             const Vec3 e = {pts[i + 1][0] - pts[i][0], pts[i + 1][1] - pts[i][1],
                             pts[i + 1][2] - pts[i][2]};
             const Slot f = capsule(b, c.p, pts[i], e, radiusAt(at[i]), radiusAt(at[i + 1]));
             field = first ? f : b.max(field, f);
             first = false;
           }
           return field;
         },
         [](const Node& n, const std::vector<Box3>&) {
           return pointsBounds(pointsOf(n.param("points")),
                               std::max(n.real("radius1"), n.real("radius2")));
         }});
}

}  // namespace frep
