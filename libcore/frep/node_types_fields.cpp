// Operations on the field value itself: offset (grow or shrink), shell (hollow) and
// metamorphosis (morph between two solids). On distance-like fields (every primitive near its
// surface) offset and shell distances are lengths.
#include "frep/node_helpers.h"
#include "frep/registry.h"
#include "frep/structural_bounds.h"
#include "frep/tree.h"

namespace frep {

void registerFieldOperations(Registry& r) {
  r.add({"offset",
         "field operation",
         "Grows its input by a distance (shrinks it when negative): exact on distance fields, "
         "such as primitives near their surface.",
         "F = f + distance",
         1,
         1,
         {realParam("distance", 0.1, "length", "How far the surface moves outwards.")},
         [](CompileContext& c) { return c.b.add(c.input(0), c.b.constant(c.real("distance"))); }});

  r.add({"shell",
         "field operation",
         "Hollows its input, keeping a wall of the given thickness inside its surface (for a "
         "part printed hollow, open it with a difference to let the powder or resin out).",
         "F = min(f, thickness - f)",
         1,
         1,
         {positiveLength("thickness", 0.1, "Wall thickness, measured inwards.")},
         [](CompileContext& c) {
           const Slot f = c.input(0);
           return c.b.min(f, c.b.sub(c.b.constant(c.real("thickness")), f));
         },
         [](const Node&, const std::vector<Box3>& in) { return in[0]; }});

  {
    ParamTemplate t =
        realParam("t", 0.5, "", "Morph parameter: 0 gives the first solid, 1 the second.");
    range(t, 0.0, 1.0);
    r.add({"metamorphosis",
           "field operation",
           "Morphs between two solids by blending their fields linearly; animate `t` from 0 to "
           "1 (e.g. from a spreadsheet) to watch one turn into the other.",
           "F = (1 - t) f1 + t f2",
           2,
           2,
           {t},
           [](CompileContext& c) {
             const double t = c.real("t");
             if (t == 0.0) return c.input(0);
             if (t == 1.0) return c.input(1);
             const Slot a = c.input(0), b = c.input(1);
             return c.b.affine(a, b, b, 1.0 - t, t, 0.0, 0.0);
           },
           [](const Node& n, const std::vector<Box3>& in) {
             // (1 - t) f1 + t f2 > 0 needs f1 > 0 or f2 > 0.
             const double t = n.real("t");
             return t == 0.0 ? in[0] : t == 1.0 ? in[1] : boxHull(in[0], in[1]);
           }});
  }
}

}  // namespace frep
