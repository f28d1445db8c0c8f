// Transforms: each evaluates its input at the inversely transformed point, F(p) = f(T^-1 p).
// Scale multiplies the value by the smallest factor so the field keeps length units.
#include <algorithm>

#include "frep/node_helpers.h"
#include "frep/registry.h"
#include "frep/structural_bounds.h"
#include "frep/tree.h"

namespace frep {

void registerTransforms(Registry& r) {
  r.add({"translate", "transform", "Moves its input by an offset.", "F(p) = f(p - offset)", 1, 1,
         {vec3Param("offset", {0, 0, 0}, "length", "Displacement.")},
         [](CompileContext& c) { return c.input(0, shifted(c.b, c.p, c.vec3("offset"))); },
         [](const Node& n, const std::vector<Box3>& in) {
           const Vec3 o = n.vec3("offset");
           return affineImage({1, 0, 0, o[0], 0, 1, 0, o[1], 0, 0, 1, o[2]}, in[0]);
         }});

  {
    ParamTemplate axis = vec3Param("axis", {0, 0, 1}, "", "Rotation axis direction.");
    axis.nonZeroVector = true;
    r.add({"rotate", "transform",
           "Rotates its input about an axis through a centre (right-hand rule).",
           "F(p) = f(R^-1 (p - center) + center)", 1, 1,
           {axis, realParam("angle", 0.0, "angle", "Rotation angle in degrees."),
            vec3Param("center", {0, 0, 0}, "length", "A point on the rotation axis.")},
           [](CompileContext& c) {
             const Mat34 m = rotationMatrix(c.vec3("axis"), c.real("angle"), c.vec3("center"));
             return c.input(0, applyAffine(c.b, c.p, invertAffine(m)));
           },
           [](const Node& n, const std::vector<Box3>& in) {
             return affineImage(
                 rotationMatrix(n.vec3("axis"), n.real("angle"), n.vec3("center")), in[0]);
           }});
  }

  r.add({"transform", "transform",
         "Applies a full affine placement matrix (rows of [R | t], e.g. a FreeCAD Placement).",
         "F(p) = f(M^-1 p)", 1, 1,
         {matrixParam("matrix", "Row-major 3x4 matrix mapping the input's space to the result.")},
         [](CompileContext& c) {
           Mat34 m{};
           const auto& n = c.param("matrix").numbers;
           std::copy(n.begin(), n.end(), m.begin());
           return c.input(0, applyAffine(c.b, c.p, invertAffine(m)));
         },
         [](const Node& n, const std::vector<Box3>& in) {
           Mat34 m{};
           const auto& k = n.param("matrix").numbers;
           std::copy(k.begin(), k.end(), m.begin());
           return affineImage(m, in[0]);
         }});

  {
    ParamTemplate factor = realParam("factor", 1.0, "", "Uniform scale factor.");
    range(factor, 0.0, std::numeric_limits<double>::infinity(), true);
    ParamTemplate factors = vec3Param("factors", {1, 1, 1}, "", "Per-axis scale factors.");
    range(factors, 0.0, std::numeric_limits<double>::infinity(), true);
    r.add({"scale", "transform",
           "Scales its input about a centre, uniformly (factor) and per axis (factors).",
           "s_i = factor * factors_i;  F(p) = min(s) * f(center + (p - center)/s)", 1, 1,
           {factor, factors, vec3Param("center", {0, 0, 0}, "length", "Fixed point of the scaling.")},
           [](CompileContext& c) {
             auto& b = c.b;
             const double u = c.real("factor");
             const Vec3 f = c.vec3("factors"), o = c.vec3("center");
             const Vec3 s = {u * f[0], u * f[1], u * f[2]};
             auto axis = [&](Slot v, int i) {
               return b.affine(v, v, v, 1.0 / s[i], 0.0, 0.0, o[i] - o[i] / s[i]);
             };
             const Slot inner = c.input(0, {axis(c.p.x, 0), axis(c.p.y, 1), axis(c.p.z, 2)});
             return b.mul(b.constant(std::min(s[0], std::min(s[1], s[2]))), inner);
           },
           [](const Node& n, const std::vector<Box3>& in) {
             const double u = n.real("factor");
             const Vec3 f = n.vec3("factors"), o = n.vec3("center");
             Mat34 m{};
             for (int i = 0; i < 3; ++i) {
               m[i * 4 + i] = u * f[i];
               m[i * 4 + 3] = o[i] - u * f[i] * o[i];
             }
             return affineImage(m, in[0]);
           }});
  }
}

}  // namespace frep
