// A compiled FRep program: a flat list of instructions in SSA form, shared sub-trees already
// merged. Slots 0, 1, 2 hold x, y, z; instruction i writes slot i + 3. For evaluation the SSA
// slots are mapped onto as few physical slots as the values live at once (a plan made when
// the program is built), so a batch's working set stays in the first-level cache.
// Four evaluation modes: point, batch (structure of arrays), interval and gradient. A Program
// is a Field; other fields (the instancer's copies, grids, ...) sit inside it through
// `external` instructions.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "frep/dual.h"
#include "frep/field.h"
#include "frep/interval.h"
#include "frep/ops.h"

namespace frep {

using Slot = std::uint32_t;
constexpr Slot kSlotX = 0, kSlotY = 1, kSlotZ = 2, kFirstInstructionSlot = 3;

struct Instruction {
  Op op;
  Slot a = 0, b = 0, c = 0;
  std::uint32_t k = 0;  // index of the first constant in Program::constants
};

class Program final : public Field {
 public:
  // Number of points a batch call evaluates at once internally.
  static constexpr std::size_t kBatchSize = 256;
  // The same for gradients: four arrays a slot, so fewer points keep a program's slots in the
  // first-level cache (docs/struts.md, "Measured").
  static constexpr std::size_t kDualBatchSize = 64;

  Program() = default;
  Program(std::vector<Instruction> code, std::vector<double> constants, Slot result,
          std::vector<std::shared_ptr<const Field>> externals = {});

  double eval(double x, double y, double z) const override;
  // out[i] = F(x[i], y[i], z[i]); bit-identical to eval() for each point.
  void evalBatch(const double* x, const double* y, const double* z, std::size_t n,
                 double* out) const override;
  Interval evalInterval(const Interval& x, const Interval& y, const Interval& z) const override;
  // Value and gradient; x, y, z carry their derivatives (evalGradient(x, y, z) on doubles
  // gives dF/dx, dF/dy, dF/dz).
  Dual evalGradient(const Dual& x, const Dual& y, const Dual& z) const override;
  using Field::evalGradient;
  // Gradients of many points, bit-identical to evalGradient at each.
  void evalGradientBatch(const Dual* x, const Dual* y, const Dual* z, std::size_t n,
                         Dual* out) const override;

  // Region specialisation: the program restricted to `box`. Where the intervals over the box
  // decide a min or max (and R-functions with alpha = 1, selects, absolute values), the
  // instruction becomes its live operand, external fields are specialised in turn, and the
  // instructions no longer used are dropped. nullptr when nothing changes.
  std::shared_ptr<const Field> specialise(const Box3& box) const override;
  // The same, as a Program (an unchanged copy when nothing changes).
  Program specialised(const Box3& box, bool* changed = nullptr) const;

  std::size_t instructionCount() const { return code_.size(); }
  const std::vector<Instruction>& code() const { return code_; }
  const std::vector<double>& constants() const { return constants_; }
  Slot result() const { return result_; }
  const std::vector<std::shared_ptr<const Field>>& externals() const { return externals_; }
  std::string disassemble() const;
  // Physical slots evaluation uses (x, y, z included).
  std::size_t evaluationSlotCount() const { return planSlots_; }

 private:
  // One instruction of the evaluation plan: the SSA instruction on physical slots.
  struct Step {
    Op op;
    Slot out, a, b, c;
    std::uint32_t k;
  };
  void makePlan();

  template <class T>
  T evalGeneric(const T& x, const T& y, const T& z) const;
  void evalChunk(const double* x, const double* y, const double* z, std::size_t n, double* out,
                 double* slots) const;
  // Gradients of one chunk; `slots` holds each slot's duals as four arrays.
  void evalDualChunk(const Dual* x, const Dual* y, const Dual* z, std::size_t n, Dual* out,
                     double* slots) const;

  std::vector<Instruction> code_;
  std::vector<double> constants_;
  Slot result_ = kSlotX;
  // The fields of `external` instructions (the instancer, ...), by the index in their constant.
  std::vector<std::shared_ptr<const Field>> externals_;
  std::vector<Step> plan_;
  Slot planResult_ = kSlotX;
  std::size_t planSlots_ = kFirstInstructionSlot;
};

}  // namespace frep
