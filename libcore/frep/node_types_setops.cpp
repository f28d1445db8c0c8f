// Set-theoretic operations by R-functions and Pasko's blends. Variadic operations fold from
// the left: op(f1, f2, f3) = op(op(f1, f2), f3).
#include "frep/registry.h"
#include "frep/structural_bounds.h"
#include "frep/tree.h"

namespace frep {

namespace {

ParamTemplate alphaParam() {
  ParamTemplate p = realParam(
      "alpha", 1.0, "",
      "R-function parameter in (-1, 1]; 1 gives exactly max/min, smaller values smooth the field.");
  range(p, -1.0, 1.0, true, false);
  p.title = "Smoothing (alpha)";
  return p;
}

ParamTemplate blendParam(const char* name, double def, bool positive, const char* title,
                         const char* doc) {
  ParamTemplate p = realParam(name, def, "", doc);
  if (positive) range(p, 0.0, std::numeric_limits<double>::infinity(), true);
  p.title = title;
  return p;
}

// Pasko's blend adds a0 / (1 + (f1 / a1)^2 + (f2 / a2)^2) to the set operation: a0 is how
// much material the fillet adds (or, negative, takes), a1 and a2 how far it reaches along
// each solid, in units of that solid's field.
ParamTemplate strengthParam() {
  return blendParam("a0", 0.5, false, "Strength (a0)",
                    "Blend amount: height of the added displacement (negative: a groove). It "
                    "acts wherever both fields are small against a1 and a2, so a large a0 also "
                    "swells faces far from the joint (a bounded blend keeps it to a region).");
}

std::vector<ParamTemplate> reachParams() {
  return {blendParam("a1", 1.0, true, "Reach on the first (a1)",
                     "How far along the first solid the blend reaches."),
          blendParam("a2", 1.0, true, "Reach on the second (a2)",
                     "How far along the second solid the blend reaches.")};
}

std::vector<ParamTemplate> blendParams() {
  std::vector<ParamTemplate> params = {strengthParam()};
  for (const ParamTemplate& p : reachParams()) params.push_back(p);
  params.push_back(alphaParam());
  return params;
}

Slot fold(CompileContext& c, const std::function<Slot(Slot, Slot)>& op) {
  Slot acc = c.input(0);
  for (int i = 1; i < c.inputCount(); ++i) acc = op(acc, c.input(i));
  return acc;
}

// Pasko blend: the R-function `setOp` plus the displacement a0 / (1 + (f1/a1)^2 + (f2/a2)^2).
CompileFn blendCompiler(Op setOp) {
  return [setOp](CompileContext& c) {
    const double a = c.real("alpha"), k0 = c.real("a0"), k1 = c.real("a1"), k2 = c.real("a2");
    return fold(c, [&](Slot x, Slot y) {
      return c.b.add(c.b.emit(setOp, x, y, 0, {a}), c.b.emit(Op::BlendBump, x, y, 0, {k0, k1, k2}));
    });
  };
}

// The weight confining a bounded blend: 0 outside the bounding solid (f3 <= 0), 1 from depth
// a3 inside it, a C1 smooth step (3t^2 - 2t^3) between.
Slot boundWeight(ProgramBuilder& b, Slot f3, double a3) {
  const Slot t =
      b.min(b.max(b.affine(f3, f3, f3, 1.0 / a3, 0.0, 0.0, 0.0), b.constant(0.0)), b.constant(1.0));
  return b.mul(b.sqr(t), b.affine(t, t, t, -2.0, 0.0, 0.0, 3.0));
}

}  // namespace

void registerBoundedBlend(Registry& r) {
  std::vector<ParamTemplate> params = {
      choiceParam("operation", {"union", "intersection"}, "The set operation blended."),
      strengthParam(),
      reachParams()[0],
      reachParams()[1],
      blendParam("a3", 0.2, true, "Fade depth (a3)",
                 "Depth inside the bounding solid over which the blend fades in."),
      alphaParam()};
  r.add({"bounded_blend", "blend",
         "A Pasko blend confined to a bounding solid (the third input): full inside it, none "
         "outside, fading in over depth a3, so one edge or corner gets a fillet and the rest "
         "stays sharp.",
         "t = clamp(f3/a3, 0, 1);  F = op_alpha(f1, f2) + (3t^2 - 2t^3) a0 / (1 + (f1/a1)^2 + "
         "(f2/a2)^2)",
         3, 3, params, [](CompileContext& c) {
           auto& b = c.b;
           const Slot f1 = c.input(0), f2 = c.input(1), f3 = c.input(2);
           const Op op = c.param("operation").text == "union" ? Op::RUnion : Op::RIntersect;
           const Slot set = b.emit(op, f1, f2, 0, {c.real("alpha")});
           const Slot bump =
               b.emit(Op::BlendBump, f1, f2, 0, {c.real("a0"), c.real("a1"), c.real("a2")});
           return b.add(set, b.mul(boundWeight(b, f3, c.real("a3")), bump));
         }});
}

void registerSetOperations(Registry& r) {
  r.add({"union",
         "set operation",
         "Union of its inputs (R-function).",
         "F = (f1 + f2 + sqrt(f1^2 + f2^2 - 2 alpha f1 f2)) / (1 + alpha)",
         2,
         kVariadic,
         {alphaParam()},
         [](CompileContext& c) {
           const double a = c.real("alpha");
           return fold(c, [&](Slot x, Slot y) { return c.b.emit(Op::RUnion, x, y, 0, {a}); });
         },
         [](const Node&, const std::vector<Box3>& in) {
           // With alpha < 1 the R-function's zero set is still the union's.
           Box3 b = in[0];
           for (const Box3& i : in) b = boxHull(b, i);
           return b;
         }});

  r.add({"intersection",
         "set operation",
         "Intersection of its inputs (R-function).",
         "F = (f1 + f2 - sqrt(f1^2 + f2^2 - 2 alpha f1 f2)) / (1 + alpha)",
         2,
         kVariadic,
         {alphaParam()},
         [](CompileContext& c) {
           const double a = c.real("alpha");
           return fold(c, [&](Slot x, Slot y) { return c.b.emit(Op::RIntersect, x, y, 0, {a}); });
         },
         [](const Node&, const std::vector<Box3>& in) {
           Box3 b = in[0];
           for (const Box3& i : in) b = boxIntersection(b, i);
           return b;
         }});

  r.add({"difference",
         "set operation",
         "The first input minus all others: intersection with their complements.",
         "F = intersection(f1, -f2)",
         2,
         kVariadic,
         {alphaParam()},
         [](CompileContext& c) {
           const double a = c.real("alpha");
           return fold(
               c, [&](Slot x, Slot y) { return c.b.emit(Op::RIntersect, x, c.b.neg(y), 0, {a}); });
         },
         [](const Node&, const std::vector<Box3>& in) { return in[0]; }});

  r.add({"complement",
         "set operation",
         "Everything outside its input.",
         "F = -f",
         1,
         1,
         {},
         [](CompileContext& c) { return c.b.neg(c.input(0)); }});

  r.add({"blend_union", "blend",
         "Union with a smooth fillet where the inputs meet (Pasko's blending union).",
         "F = union_alpha(f1, f2) + a0 / (1 + (f1/a1)^2 + (f2/a2)^2)", 2, kVariadic, blendParams(),
         blendCompiler(Op::RUnion)});

  r.add({"blend_intersection", "blend",
         "Intersection with a smooth fillet along the common edge (Pasko's blending intersection).",
         "F = intersection_alpha(f1, f2) + a0 / (1 + (f1/a1)^2 + (f2/a2)^2)", 2, kVariadic,
         blendParams(), blendCompiler(Op::RIntersect)});
}

}  // namespace frep
