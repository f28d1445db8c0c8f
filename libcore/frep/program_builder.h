// Builds a Program instruction by instruction. Identical instructions (same op, operands and
// constants) are emitted once, which deduplicates shared and repeated sub-trees; instructions
// whose operands are all constants are folded.
#pragma once

#include <initializer_list>
#include <map>
#include <memory>
#include <cstdint>
#include <tuple>
#include <vector>

#include "frep/program.h"

namespace frep {

class ProgramBuilder {
 public:
  Slot x() const { return kSlotX; }
  Slot y() const { return kSlotY; }
  Slot z() const { return kSlotZ; }

  Slot constant(double value);
  Slot emit(Op op, Slot a, Slot b = 0, Slot c = 0, std::initializer_list<double> k = {});

  // Convenience wrappers.
  Slot add(Slot a, Slot b) { return emit(Op::Add, a, b); }
  Slot sub(Slot a, Slot b) { return emit(Op::Sub, a, b); }
  Slot mul(Slot a, Slot b) { return emit(Op::Mul, a, b); }
  Slot div(Slot a, Slot b) { return emit(Op::Div, a, b); }
  Slot neg(Slot a) { return emit(Op::Neg, a); }
  Slot sqr(Slot a) { return emit(Op::Sqr, a); }
  Slot sqrt(Slot a) { return emit(Op::Sqrt, a); }
  Slot abs(Slot a) { return emit(Op::Abs, a); }
  Slot min(Slot a, Slot b) { return emit(Op::Min, a, b); }
  Slot max(Slot a, Slot b) { return emit(Op::Max, a, b); }
  // k0*a + k1*b + k2*c + k3
  Slot affine(Slot a, Slot b, Slot c, double k0, double k1, double k2, double k3) {
    return emit(Op::Affine, a, b, c, {k0, k1, k2, k3});
  }
  // sqrt(a^2 + b^2 [+ c^2])
  Slot length2(Slot a, Slot b) { return sqrt(add(sqr(a), sqr(b))); }
  Slot length3(Slot a, Slot b, Slot c) { return sqrt(add(add(sqr(a), sqr(b)), sqr(c))); }

  // Another field evaluated at (x, y, z): an `external` instruction (the instancer's copies,
  // an external node's field). Never merged with another, never folded.
  Slot external(std::shared_ptr<const Field> field, Slot x, Slot y, Slot z);

  bool isConstant(Slot s) const;
  double constantValue(Slot s) const;

  // Drops instructions the result does not use and returns the finished program.
  Program finish(Slot result) const;

 private:
  // Constants by their bits: a NaN must not compare equal to every other constant.
  using Key = std::tuple<Op, Slot, Slot, Slot, std::vector<std::uint64_t>>;
  std::vector<Instruction> code_;
  std::vector<double> constants_;
  std::map<Key, Slot> seen_;
  std::vector<std::shared_ptr<const Field>> externals_;
};

}  // namespace frep
