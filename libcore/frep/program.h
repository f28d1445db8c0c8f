// A compiled FRep program: a flat list of instructions in SSA form, shared sub-trees already
// merged. Slots 0, 1, 2 hold x, y, z; instruction i writes slot i + 3.
// Four evaluation modes: point, batch (structure of arrays), interval and gradient.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "frep/dual.h"
#include "frep/interval.h"
#include "frep/ops.h"

namespace frep {

class InstanceSet;

using Slot = std::uint32_t;
constexpr Slot kSlotX = 0, kSlotY = 1, kSlotZ = 2, kFirstInstructionSlot = 3;

struct Instruction {
  Op op;
  Slot a = 0, b = 0, c = 0;
  std::uint32_t k = 0;  // index of the first constant in Program::constants
};

class Program {
 public:
  // Number of points a batch call evaluates at once internally.
  static constexpr std::size_t kBatchSize = 256;

  Program() = default;
  Program(std::vector<Instruction> code, std::vector<double> constants, Slot result,
          std::vector<std::shared_ptr<const InstanceSet>> instanceSets = {});

  double eval(double x, double y, double z) const;
  // out[i] = F(x[i], y[i], z[i]); bit-identical to eval() for each point.
  void evalBatch(const double* x, const double* y, const double* z, std::size_t n,
                 double* out) const;
  Interval evalInterval(const Interval& x, const Interval& y, const Interval& z) const;
  // Value and gradient (dF/dx, dF/dy, dF/dz).
  Dual evalGradient(double x, double y, double z) const;

  std::size_t instructionCount() const { return code_.size(); }
  const std::vector<Instruction>& code() const { return code_; }
  const std::vector<double>& constants() const { return constants_; }
  Slot result() const { return result_; }
  std::string disassemble() const;

 private:
  template <class T>
  T evalGeneric(const T& x, const T& y, const T& z) const;
  void evalChunk(const double* x, const double* y, const double* z, std::size_t n, double* out,
                 double* slots) const;

  std::vector<Instruction> code_;
  std::vector<double> constants_;
  Slot result_ = kSlotX;
  // The data of `instances` instructions (the instancer), by the index in their constant.
  std::vector<std::shared_ptr<const InstanceSet>> instanceSets_;
};

}  // namespace frep
