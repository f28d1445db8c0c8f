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
  return p;
}

ParamTemplate blendParam(const char* name, double def, bool positive, const char* doc) {
  ParamTemplate p = realParam(name, def, "", doc);
  if (positive) range(p, 0.0, std::numeric_limits<double>::infinity(), true);
  return p;
}

std::vector<ParamTemplate> blendParams() {
  return {blendParam("a0", 0.5, false, "Blend amount: height of the added displacement."),
          blendParam("a1", 1.0, true, "How far along the first solid the blend reaches."),
          blendParam("a2", 1.0, true, "How far along the second solid the blend reaches."),
          alphaParam()};
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

}  // namespace

void registerSetOperations(Registry& r) {
  r.add({"union", "set operation", "Union of its inputs (R-function).",
         "F = (f1 + f2 + sqrt(f1^2 + f2^2 - 2 alpha f1 f2)) / (1 + alpha)", 2, kVariadic,
         {alphaParam()},
         [](CompileContext& c) {
           const double a = c.real("alpha");
           return fold(c, [&](Slot x, Slot y) { return c.b.emit(Op::RUnion, x, y, 0, {a}); });
         },
         [](const Node& n, const std::vector<Box3>& in) {
           // With alpha < 1 the R-function's zero set is still the union's.
           Box3 b = in[0];
           for (const Box3& i : in) b = boxHull(b, i);
           return b;
         }});

  r.add({"intersection", "set operation", "Intersection of its inputs (R-function).",
         "F = (f1 + f2 - sqrt(f1^2 + f2^2 - 2 alpha f1 f2)) / (1 + alpha)", 2, kVariadic,
         {alphaParam()},
         [](CompileContext& c) {
           const double a = c.real("alpha");
           return fold(c, [&](Slot x, Slot y) { return c.b.emit(Op::RIntersect, x, y, 0, {a}); });
         },
         [](const Node& n, const std::vector<Box3>& in) {
           Box3 b = in[0];
           for (const Box3& i : in) b = boxIntersection(b, i);
           return b;
         }});

  r.add({"difference", "set operation",
         "The first input minus all others: intersection with their complements.",
         "F = intersection(f1, -f2)", 2, kVariadic, {alphaParam()},
         [](CompileContext& c) {
           const double a = c.real("alpha");
           return fold(c, [&](Slot x, Slot y) {
             return c.b.emit(Op::RIntersect, x, c.b.neg(y), 0, {a});
           });
         },
         [](const Node&, const std::vector<Box3>& in) { return in[0]; }});

  r.add({"complement", "set operation", "Everything outside its input.", "F = -f", 1, 1, {},
         [](CompileContext& c) { return c.b.neg(c.input(0)); }});

  r.add({"blend_union", "blend",
         "Union with a smooth fillet where the inputs meet (Pasko's blending union).",
         "F = union_alpha(f1, f2) + a0 / (1 + (f1/a1)^2 + (f2/a2)^2)", 2, kVariadic,
         blendParams(),
         blendCompiler(Op::RUnion)});

  r.add({"blend_intersection", "blend",
         "Intersection with a smooth fillet along the common edge (Pasko's blending intersection).",
         "F = intersection_alpha(f1, f2) + a0 / (1 + (f1/a1)^2 + (f2/a2)^2)", 2, kVariadic,
         blendParams(),
         blendCompiler(Op::RIntersect)});
}

}  // namespace frep
