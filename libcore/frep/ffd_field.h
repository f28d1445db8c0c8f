// The free-form deformation of a field by a lattice (lattice/ffd_map.h): the `ffd` node's
// external instruction. Gap-free because it pulls back rather than pushes forward: the value
// at p is the input's value where the lattice came from,
//
//   F(p) = f(R(s))           where X(s) = p for some s in [0, 1]^3 (p in the deformed lattice D;
//                            R(s) the rest-box point of local coordinates s),
//   F(p) = f(p)              outside D and outside the rest box (untouched),
//   F(p) = min(f(p), -eps)   outside D but inside the rest box: space the lattice moved away
//                            from, so no ghost of the undeformed solid is left there.
//
// All four modes: intervals from the leaves of the lattice whose image boxes (restricted
// control hulls) meet the box; gradients by the chain rule through the inverse Jacobian;
// specialise(box) keeps only the leaves that reach the box and specialises the input to the
// rest-space box they come from.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "frep/field.h"
#include "frep/tree.h"

namespace frep {

class FfdLattice;
class FfdMap;

class FfdField final : public Field {
 public:
  // leaves: the only leaves of the map that may hold points this field is asked about (a
  // specialised copy's); nullptr for all.
  FfdField(std::shared_ptr<const Field> input, std::shared_ptr<const FfdMap> map,
           std::shared_ptr<const std::vector<int>> leaves = nullptr);

  double eval(double x, double y, double z) const override;
  Interval evalInterval(const Interval& x, const Interval& y, const Interval& z) const override;
  Dual evalGradient(const Dual& x, const Dual& y, const Dual& z) const override;
  using Field::evalGradient;
  std::shared_ptr<const Field> specialise(const Box3& box) const override;
  Box3 bounds() const override;

  // The value inside the rest box where the lattice left no material is at most -eps.
  double vacatedValue() const { return -eps_; }

 private:
  std::shared_ptr<const Field> input_;
  std::shared_ptr<const FfdMap> map_;
  std::shared_ptr<const std::vector<int>> leaves_;
  double eps_;
};

// Where the deformed solid can be, given the box `input` the input's solid lies in: the image
// of its part in the rest box, and its part outside (untouched).
Box3 deformedBounds(const FfdMap& map, const Box3& input);

// The lattice of an `ffd` node (its rest box, divisions and points; lattice/ffd_lattice.h).
FfdLattice ffdLatticeOf(const Node& ffd);
// An `ffd` node's parameters for a lattice (what ffdLatticeOf reads back).
std::map<std::string, ParamValue> ffdParams(const FfdLattice& lattice);

}  // namespace frep
