// The Field seam: anything that can be evaluated at points, over boxes and with gradients.
//
// A compiled FRep tree (Program) is a Field; so are the instancer's set of copies, an OpenVDB
// grid (volume/grid_field.h), a mesh's signed distance and a lattice deformation of another
// field (lattice/). The mesher, the bounds finder and the export pipeline take a
// `const Field&`; a tree holds any
// other field through one generic instruction (Op::External, see program.h) made by an external
// node (makeFieldNode in tree.h). A new kind of geometry implements this interface and needs
// no special case in the evaluator (docs/architecture.md, "Adding a kind of field").
//
// Contract, for every implementation:
// - eval and evalBatch agree bit for bit at every point (bricks meshed apart weld exactly);
// - evalInterval encloses every value eval can return at a point of the box (NaN included:
//   a result that may be NaN somewhere has `nan` set), whatever the rounding;
// - evalGradient's value is eval's value, and its derivatives are taken with respect to the
//   caller's coordinates (x, y, z carry their own derivatives: the chain rule under
//   transforms);
// - specialise(box), when it returns a field, returns one equal to this one in all four modes
//   at every point and sub-box of `box`, usually cheaper (dead branches dropped).
#pragma once

#include <cstddef>
#include <memory>

#include "base/vec.h"
#include "frep/dual.h"
#include "frep/interval.h"

namespace frep {

class Field {
 public:
  virtual ~Field() = default;

  virtual double eval(double x, double y, double z) const = 0;
  // out[i] = eval(x[i], y[i], z[i]); the default loops over eval.
  virtual void evalBatch(const double* x, const double* y, const double* z, std::size_t n,
                         double* out) const;
  virtual Interval evalInterval(const Interval& x, const Interval& y, const Interval& z) const = 0;
  virtual Dual evalGradient(const Dual& x, const Dual& y, const Dual& z) const = 0;
  // out[i] = evalGradient(x[i], y[i], z[i]); the default loops over evalGradient. (Normals
  // of a whole brick's vertices at once.)
  virtual void evalGradientBatch(const Dual* x, const Dual* y, const Dual* z, std::size_t n,
                                 Dual* out) const;

  // The value and gradient in world coordinates at a point. (A class that overrides the
  // virtual one brings this one back with `using Field::evalGradient;`.)
  Dual evalGradient(double x, double y, double z) const {
    return evalGradient(Dual(x, 1, 0, 0), Dual(y, 0, 1, 0), Dual(z, 0, 0, 1));
  }

  // A field equal to this one inside `box` (see the contract above), or nullptr when this
  // field has nothing cheaper to offer there.
  virtual std::shared_ptr<const Field> specialise(const Box3& box) const;

  // A box the solid {F >= 0} is known to lie in; infinite sides where unknown (the default).
  virtual Box3 bounds() const;
};

// The field to evaluate inside `box`: the specialised one when there is one, else `field`.
// `holder` keeps a specialised field alive.
const Field& specialiseInto(const Field& field, const Box3& box,
                            std::shared_ptr<const Field>& holder);

// The field the mesher meshes inside `box`, min(F, distance to the box's nearest face) (a
// solid the box cuts gets a flat cap), at p, from F's value and gradient there: the box
// face's distance and its inward unit normal where that is smaller.
Dual cappedByBox(const Dual& f, const Box3& box, const Vec3& p);

}  // namespace frep
