// Primitive solids (leaves of the tree). Fields are positive inside and, where the shape
// allows, equal to the Euclidean distance to the surface near it (so blends and offsets behave
// the same on every primitive).
#include <algorithm>

#include "frep/node_helpers.h"
#include "frep/registry.h"
#include "frep/structural_bounds.h"
#include "frep/tree.h"

namespace frep {

namespace {

// s/2 - |p| along one axis: positive inside a slab of width s centred on 0.
Slot slab(ProgramBuilder& b, Slot t, double width) {
  return b.sub(b.constant(width / 2), b.abs(t));
}

}  // namespace

void registerPrimitives(Registry& r) {
  r.add({"sphere", "primitive", "Ball with a centre and a radius (HyperFun hfSphere).",
         "F = radius - |p - center|", 0, 0,
         {centerParam("Centre of the sphere."), positiveLength("radius", 1.0, "Radius.")},
         [](CompileContext& c) {
           auto& b = c.b;
           const Point3Slots d = shifted(b, c.p, c.vec3("center"));
           return b.sub(b.constant(c.real("radius")), b.length3(d.x, d.y, d.z));
         },
         [](const Node& n, const std::vector<Box3>&) {
           const double r = n.real("radius");
           return boxAround(n.vec3("center"), {r, r, r});
         }});

  {
    ParamTemplate size = vec3Param("size", {1, 1, 1}, "length", "Edge lengths along x, y, z.");
    range(size, 0.0, kInf, true);
    r.add({"box", "primitive",
           "Axis-aligned block from a corner and its edge lengths (HyperFun hfBlock).",
           "F = min_i(size_i/2 - |p_i - m_i|), m = corner + size/2", 0, 0,
           {vec3Param("corner", {0, 0, 0}, "length", "Corner with the smallest coordinates."),
            size},
           [](CompileContext& c) {
             auto& b = c.b;
             const Vec3 lo = c.vec3("corner"), s = c.vec3("size");
             const Point3Slots d =
                 shifted(b, c.p, {lo[0] + s[0] / 2, lo[1] + s[1] / 2, lo[2] + s[2] / 2});
             return b.min(b.min(slab(b, d.x, s[0]), slab(b, d.y, s[1])), slab(b, d.z, s[2]));
           },
           [](const Node& n, const std::vector<Box3>&) {
             const Vec3 lo = n.vec3("corner"), s = n.vec3("size");
             return Box3{lo, {lo[0] + s[0], lo[1] + s[1], lo[2] + s[2]}};
           }});
  }

  {
    ParamTemplate length = realParam("length", 2.0, "length",
                                     "Length along the axis, centred on the centre; 0 = infinite.");
    range(length, 0.0, kInf);
    r.add({"cylinder", "primitive",
           "Circular cylinder around an axis through a centre; finite or infinite.",
           "F = min(radius - dist(p, axis), length/2 - |(p - center).axis|)", 0, 0,
           {centerParam("Middle of the cylinder's axis segment."),
            axisParam("Direction of the axis."), positiveLength("radius", 1.0, "Radius."), length},
           [](CompileContext& c) {
             auto& b = c.b;
             const Point3Slots q = localCoordinates(b, c.p, c.vec3("center"), frameAlong(c.vec3("axis")));
             const Slot side = b.sub(b.constant(c.real("radius")), b.length2(q.x, q.y));
             const double len = c.real("length");
             return len == 0.0 ? side : b.min(side, slab(b, q.z, len));
           },
           [](const Node& n, const std::vector<Box3>&) {
             const double half = n.real("length") == 0.0 ? kInf : n.real("length") / 2;
             return cylinderBounds(n.vec3("center"), normalized(n.vec3("axis")), -half, half,
                                   n.real("radius"));
           }});
  }

  {
    ParamTemplate r1 = realParam("radius1", 1.0, "length", "Radius at the base.");
    range(r1, 0.0, kInf);
    ParamTemplate r2 = realParam("radius2", 0.0, "length", "Radius at the top (0: pointed).");
    range(r2, 0.0, kInf);
    r.add({"cone", "primitive",
           "Cone or truncated cone from a base centre along an axis (base radius1, top radius2).",
           "t = (p - base).axis, rho = dist(p, axis), k = (radius2 - radius1)/height;\n"
           "F = min((radius1 + k t - rho)/sqrt(1 + k^2), t, height - t)",
           0, 0,
           {vec3Param("base", {0, 0, 0}, "length", "Centre of the base disc."),
            axisParam("Direction from the base to the top."), r1, r2,
            positiveLength("height", 1.0, "Distance from base to top.")},
           [](CompileContext& c) {
             auto& b = c.b;
             const double h = c.real("height"), ra = c.real("radius1"), rb = c.real("radius2");
             const double k = (rb - ra) / h, s = std::sqrt(1 + k * k);
             const Point3Slots q = localCoordinates(b, c.p, c.vec3("base"), frameAlong(c.vec3("axis")));
             const Slot rho = b.length2(q.x, q.y);
             const Slot side = b.affine(q.z, rho, rho, k / s, -1.0 / s, 0.0, ra / s);
             const Slot caps = slab(b, b.sub(q.z, b.constant(h / 2)), h);
             return b.min(side, caps);
           },
           [](const Node& n, const std::vector<Box3>&) {
             return cylinderBounds(n.vec3("base"), normalized(n.vec3("axis")), 0.0,
                                   n.real("height"),
                                   std::max(n.real("radius1"), n.real("radius2")));
           }});
  }

  r.add({"torus", "primitive", "Torus around an axis through its centre.",
         "F = minor_radius - sqrt((dist(p, axis) - major_radius)^2 + ((p - center).axis)^2)", 0, 0,
         {centerParam("Centre of the torus."), axisParam("Axis of revolution."),
          positiveLength("major_radius", 1.0, "Distance from the centre to the tube's centre."),
          positiveLength("minor_radius", 0.25, "Radius of the tube.")},
         [](CompileContext& c) {
           auto& b = c.b;
           const Point3Slots q = localCoordinates(b, c.p, c.vec3("center"), frameAlong(c.vec3("axis")));
           const Slot ring = b.sub(b.length2(q.x, q.y), b.constant(c.real("major_radius")));
           return b.sub(b.constant(c.real("minor_radius")), b.length2(ring, q.z));
         },
         [](const Node& n, const std::vector<Box3>&) {
           const double minor = n.real("minor_radius");
           return cylinderBounds(n.vec3("center"), normalized(n.vec3("axis")), -minor, minor,
                                 n.real("major_radius") + minor);
         }});

  {
    ParamTemplate radii = vec3Param("radii", {1, 1, 1}, "length", "Semi-axes along x, y, z.");
    range(radii, 0.0, kInf, true);
    r.add({"ellipsoid", "primitive", "Axis-aligned ellipsoid (HyperFun hfEllipsoid).",
           "F = min(radii) * (1 - sqrt(sum_i ((p_i - center_i)/radii_i)^2))", 0, 0,
           {centerParam("Centre of the ellipsoid."), radii},
           [](CompileContext& c) {
             auto& b = c.b;
             const Vec3 m = c.vec3("center"), a = c.vec3("radii");
             const double s = std::min(a[0], std::min(a[1], a[2]));
             auto axis = [&](Slot v, int i) {
               return b.affine(v, v, v, 1.0 / a[i], 0.0, 0.0, -m[i] / a[i]);
             };
             const Slot len = b.length3(axis(c.p.x, 0), axis(c.p.y, 1), axis(c.p.z, 2));
             return b.affine(len, len, len, -s, 0.0, 0.0, s);
           },
           [](const Node& n, const std::vector<Box3>&) {
             return boxAround(n.vec3("center"), n.vec3("radii"));
           }});
  }

  {
    ParamTemplate radii = vec3Param("radii", {1, 1, 1}, "length", "Semi-axes a, b, c along x, y, z.");
    range(radii, 0.0, kInf, true);
    ParamTemplate s1 = realParam("exponent1", 0.5, "",
                                 "North-south shape (HyperFun s1): 1 round, towards 0 square, 2 "
                                 "a double cone, above 2 pinched.");
    range(s1, 0.0, 10.0, true);
    ParamTemplate s2 = realParam("exponent2", 0.5, "",
                                 "East-west shape (HyperFun s2), as exponent1 across x and y.");
    range(s2, 0.0, 10.0, true);
    r.add({"superellipsoid", "primitive",
           "Barr's superellipsoid (HyperFun hfSuperell): boxes with rounded edges, cylinders, "
           "octahedra and stars from two exponents.",
           "u = p - center;  S = (|u_x/a|^(2/s2) + |u_y/b|^(2/s2))^(s2/s1) + |u_z/c|^(2/s1);  "
           "F = min(a, b, c) (1 - S) / 2",
           0, 0, {centerParam("Centre of the superellipsoid."), radii, s1, s2},
           [](CompileContext& c) {
             auto& b = c.b;
             const Vec3 m = c.vec3("center"), a = c.vec3("radii");
             const double e1 = c.real("exponent1"), e2 = c.real("exponent2");
             auto term = [&](Slot v, int i, double k) {
               return b.emit(Op::PowAbs, b.affine(v, v, v, 1.0 / a[i], 0.0, 0.0, -m[i] / a[i]),
                             0, 0, {k});
             };
             const Slot across = b.add(term(c.p.x, 0, 2.0 / e2), term(c.p.y, 1, 2.0 / e2));
             const Slot sum =
                 b.add(b.emit(Op::PowAbs, across, 0, 0, {e2 / e1}), term(c.p.z, 2, 2.0 / e1));
             const double h = 0.5 * std::min(a[0], std::min(a[1], a[2]));
             return b.affine(sum, sum, sum, -h, 0.0, 0.0, h);
           },
           [](const Node& n, const std::vector<Box3>&) {
             // Each term of S is at most 1 inside, so |u_i| <= radius_i.
             return boxAround(n.vec3("center"), n.vec3("radii"));
           }});
  }

  {
    ParamTemplate normal = vec3Param("normal", {0, 0, 1}, "", "Outward normal (points away from the solid).");
    normal.nonZeroVector = true;
    r.add({"halfspace", "primitive",
           "Half-space bounded by a plane: the solid is on the side opposite the normal.",
           "F = (point - p) . normal/|normal|", 0, 0,
           {vec3Param("point", {0, 0, 0}, "length", "A point on the plane."), normal},
           [](CompileContext& c) {
             const Vec3 n = normalized(c.vec3("normal")), o = c.vec3("point");
             return c.b.affine(c.p.x, c.p.y, c.p.z, -n[0], -n[1], -n[2],
                               n[0] * o[0] + n[1] * o[1] + n[2] * o[2]);
           }});
  }
}

}  // namespace frep
