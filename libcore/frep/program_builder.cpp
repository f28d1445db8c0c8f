#include "frep/program_builder.h"

#include <cstring>
#include <utility>

namespace frep {

bool ProgramBuilder::isConstant(Slot s) const {
  return s >= kFirstInstructionSlot && code_[s - kFirstInstructionSlot].op == Op::Const;
}

double ProgramBuilder::constantValue(Slot s) const {
  return constants_[code_[s - kFirstInstructionSlot].k];
}

Slot ProgramBuilder::external(std::shared_ptr<const Field> field, Slot x, Slot y, Slot z) {
  externals_.push_back(std::move(field));
  return emit(Op::External, x, y, z, {static_cast<double>(externals_.size() - 1)});
}

Slot ProgramBuilder::constant(double value) { return emit(Op::Const, 0, 0, 0, {value}); }

Slot ProgramBuilder::emit(Op op, Slot a, Slot b, Slot c, std::initializer_list<double> k) {
  const int arity = opArity(op);
  if (arity < 3) c = 0;
  if (arity < 2) b = 0;
  if (arity < 1) a = 0;
  if (opIsCommutative(op) && b < a) std::swap(a, b);

  // Constant folding: all operands constant -> evaluate now.
  if (op != Op::Const && op != Op::External && arity > 0) {
    const Slot args[3] = {a, b, c};
    bool allConstant = true;
    double values[3] = {0, 0, 0};
    for (int i = 0; i < arity; ++i) {
      allConstant = allConstant && isConstant(args[i]);
      if (allConstant) values[i] = constantValue(args[i]);
    }
    if (allConstant) {
      std::vector<double> kv(k);
      return constant(applyOp<double>(op, values[0], values[1], values[2], kv.data()));
    }
  }

  // Exact algebraic identities (x+0, x-0, x*1) so that default parameters cost nothing.
  if ((op == Op::Add || op == Op::Sub) && isConstant(b) && constantValue(b) == 0.0) return a;
  if (op == Op::Add && isConstant(a) && constantValue(a) == 0.0) return b;
  if (op == Op::Mul && isConstant(b) && constantValue(b) == 1.0) return a;
  if (op == Op::Mul && isConstant(a) && constantValue(a) == 1.0) return b;

  std::vector<std::uint64_t> bits;
  for (double v : k) {
    std::uint64_t u;
    std::memcpy(&u, &v, sizeof u);
    bits.push_back(u);
  }
  Key key{op, a, b, c, std::move(bits)};
  auto it = seen_.find(key);
  if (it != seen_.end()) return it->second;

  Instruction in{op, a, b, c, static_cast<std::uint32_t>(constants_.size())};
  constants_.insert(constants_.end(), k.begin(), k.end());
  code_.push_back(in);
  const Slot slot = static_cast<Slot>(code_.size() - 1 + kFirstInstructionSlot);
  seen_.emplace(std::move(key), slot);
  return slot;
}

Program ProgramBuilder::finish(Slot result) const {
  // Mark live instructions backwards from the result, then renumber.
  const std::size_t n = code_.size();
  std::vector<char> live(n + kFirstInstructionSlot, 0);
  live[result] = 1;
  for (std::size_t i = n; i-- > 0;) {
    if (!live[i + kFirstInstructionSlot]) continue;
    const Instruction& in = code_[i];
    const Slot args[3] = {in.a, in.b, in.c};
    for (int j = 0; j < opArity(in.op); ++j) live[args[j]] = 1;
  }
  std::vector<Slot> remap(n + kFirstInstructionSlot, 0);
  for (Slot s = 0; s < kFirstInstructionSlot; ++s) remap[s] = s;
  std::vector<Instruction> code;
  std::vector<double> constants;
  for (std::size_t i = 0; i < n; ++i) {
    if (!live[i + kFirstInstructionSlot]) continue;
    Instruction in = code_[i];
    in.a = remap[in.a];
    in.b = remap[in.b];
    in.c = remap[in.c];
    const std::uint32_t k = static_cast<std::uint32_t>(constants.size());
    for (int j = 0; j < opConstantCount(in.op); ++j) constants.push_back(constants_[in.k + j]);
    in.k = k;
    remap[i + kFirstInstructionSlot] = static_cast<Slot>(code.size() + kFirstInstructionSlot);
    code.push_back(in);
  }
  return Program(std::move(code), std::move(constants), remap[result], externals_);
}

}  // namespace frep
