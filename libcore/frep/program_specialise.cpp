// Region specialisation (libfive calls it tape pushing): the program restricted to a box.
//
// Every rewrite keeps the value at every point of the box bit for bit, NaN included, so a
// brick meshed with its specialised program welds exactly to its neighbours:
// - min(a, b) is `b < a ? b : a`: it is a wherever b >= a can be proven (a NaN on either side
//   also gives a), and b only where b < a is proven and neither can be NaN;
// - max likewise; R-functions with alpha = 1 are max and min;
// - select(a, b, c) is b where a >= 0 is proven (and a cannot be NaN), c where a < 0 is;
// - |a| is a where a > 0 is proven (not at 0: |-0| is +0) and -a where a < 0 is.
// Interval results over sub-boxes stay identical too, since interval rules are inclusion
// isotone: a decision proven over the box holds over every sub-box.
#include <memory>

#include "frep/program.h"

namespace frep {

namespace {

enum class Decision { Keep, First, Second, Third, Negate };

// The operand intervals a and b (a select's branches need none: its condition decides).
Decision decide(const Instruction& in, const double* k, const Interval& a, const Interval& b) {
  Op op = in.op;
  if (op == Op::RUnion && k[0] == 1.0) op = Op::Max;
  if (op == Op::RIntersect && k[0] == 1.0) op = Op::Min;
  switch (op) {
    case Op::Min:
      if (b.lo >= a.hi) return Decision::First;
      if (b.hi < a.lo && !a.nan && !b.nan) return Decision::Second;
      return Decision::Keep;
    case Op::Max:
      if (b.hi <= a.lo) return Decision::First;
      if (b.lo > a.hi && !a.nan && !b.nan) return Decision::Second;
      return Decision::Keep;
    case Op::Select:
      if (a.lo >= 0.0 && !a.nan) return Decision::Second;
      if (a.hi < 0.0) return Decision::Third;
      return Decision::Keep;
    case Op::Abs:
      if (a.lo > 0.0) return Decision::First;
      if (a.hi < 0.0 && !a.nan) return Decision::Negate;
      return Decision::Keep;
    default:
      return Decision::Keep;
  }
}

}  // namespace

Program Program::specialised(const Box3& box, bool* changed) const {
  const std::size_t n = code_.size();
  const std::size_t slots = n + kFirstInstructionSlot;
  const double* k = constants_.data();

  // 1. The interval of every slot over the box, by the same rules evalInterval uses.
  std::vector<Interval> iv(slots);
  for (int a = 0; a < 3; ++a) iv[a] = Interval(box.lo[a], box.hi[a]);
  for (std::size_t i = 0; i < n; ++i) {
    const Instruction& in = code_[i];
    iv[i + kFirstInstructionSlot] =
        in.op == Op::External
            ? externals_[static_cast<std::size_t>(k[in.k])]->evalInterval(iv[in.a], iv[in.b],
                                                                        iv[in.c])
            : applyOp<Interval>(in.op, iv[in.a], iv[in.b], iv[in.c], k + in.k);
  }

  // 2. Decided instructions become an alias of their live operand (or its negation).
  std::vector<Slot> alias(slots);
  for (Slot s = 0; s < kFirstInstructionSlot; ++s) alias[s] = s;
  std::vector<char> negated(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Instruction& in = code_[i];
    const Slot self = static_cast<Slot>(i + kFirstInstructionSlot);
    alias[self] = self;
    switch (decide(in, k + in.k, iv[in.a], iv[in.b])) {
      case Decision::Keep: break;
      case Decision::First: alias[self] = alias[in.a]; break;
      case Decision::Second: alias[self] = alias[in.b]; break;
      case Decision::Third: alias[self] = alias[in.c]; break;
      case Decision::Negate: negated[i] = 1; break;
    }
  }

  // 3. Live instructions from the result back, through the aliases.
  std::vector<char> live(slots, 0);
  live[alias[result_]] = 1;
  for (std::size_t i = n; i-- > 0;) {
    const Slot self = static_cast<Slot>(i + kFirstInstructionSlot);
    if (!live[self] || alias[self] != self) continue;
    const Instruction& in = code_[i];
    if (negated[i]) {
      live[alias[in.a]] = 1;
      continue;
    }
    const Slot args[3] = {in.a, in.b, in.c};
    for (int j = 0; j < opArity(in.op); ++j) live[alias[args[j]]] = 1;
  }

  // 4. Renumber; external fields are specialised in turn.
  bool any = false;
  std::vector<Slot> remap(slots, 0);
  for (Slot s = 0; s < kFirstInstructionSlot; ++s) remap[s] = s;
  std::vector<Instruction> code;
  std::vector<double> constants;
  std::vector<std::shared_ptr<const Field>> externals;
  for (std::size_t i = 0; i < n; ++i) {
    const Slot self = static_cast<Slot>(i + kFirstInstructionSlot);
    if (alias[self] != self) {
      any = true;
      continue;
    }
    if (!live[self]) {
      any = true;
      continue;
    }
    Instruction in = code_[i];
    if (negated[i]) {
      in = Instruction{Op::Neg, alias[in.a], 0, 0, 0};
      any = true;
    } else {
      in.a = alias[in.a];
      in.b = alias[in.b];
      in.c = alias[in.c];
    }
    in.a = remap[in.a];
    in.b = remap[in.b];
    in.c = remap[in.c];
    const std::uint32_t first = static_cast<std::uint32_t>(constants.size());
    if (in.op == Op::External) {
      const std::shared_ptr<const Field>& f = externals_[static_cast<std::size_t>(k[in.k])];
      // specialised to the box its own operands range over (a transformed point)
      const Interval &x = iv[code_[i].a], &y = iv[code_[i].b], &z = iv[code_[i].c];
      std::shared_ptr<const Field> s =
          x.nan || y.nan || z.nan ? nullptr : f->specialise(Box3{{x.lo, y.lo, z.lo}, {x.hi, y.hi, z.hi}});
      any = any || s != nullptr;
      externals.push_back(s ? std::move(s) : f);
      constants.push_back(static_cast<double>(externals.size() - 1));
    } else {
      for (int j = 0; j < opConstantCount(in.op); ++j) constants.push_back(k[in.k + j]);
    }
    in.k = first;
    remap[self] = static_cast<Slot>(code.size() + kFirstInstructionSlot);
    code.push_back(in);
  }
  if (changed) *changed = any;
  return Program(std::move(code), std::move(constants), remap[alias[result_]],
                 std::move(externals));
}

std::shared_ptr<const Field> Program::specialise(const Box3& box) const {
  bool changed = false;
  Program p = specialised(box, &changed);
  if (!changed) return nullptr;
  return std::make_shared<const Program>(std::move(p));
}

}  // namespace frep
