#include "frep/program.h"

#include <algorithm>
#include <cstdint>
#include <deque>
#include <sstream>
#include <type_traits>
#include <utility>

namespace frep {

namespace {
struct OpInfo {
  const char* name;
  int arity;
  int constants;
  bool commutative;
};
constexpr OpInfo kOpInfo[] = {
    {"const", 0, 1, false},    {"add", 2, 0, true},        {"sub", 2, 0, false},
    {"mul", 2, 0, true},       {"div", 2, 0, false},       {"neg", 1, 0, false},
    {"sqr", 1, 0, false},      {"sqrt", 1, 0, false},      {"abs", 1, 0, false},
    {"min", 2, 0, true},       {"max", 2, 0, true},        {"exp", 1, 0, false},
    {"sin", 1, 0, false},      {"cos", 1, 0, false},       {"affine", 3, 4, false},
    {"runion", 2, 1, true},    {"rintersect", 2, 1, true}, {"blendbump", 2, 3, false},
    {"atan2", 2, 0, false},    {"powabs", 1, 1, false},    {"floor", 1, 0, false},
    {"tan", 1, 0, false},      {"atan", 1, 0, false},      {"log", 1, 0, false},
    {"powconst", 1, 1, false}, {"select", 3, 0, false},    {"segsq", 3, 7, false},
    {"external", 3, 1, false},
};
static_assert(sizeof(kOpInfo) / sizeof(kOpInfo[0]) == static_cast<int>(Op::Count_),
              "every op needs an entry");

// Scratch slots per thread and nesting depth: an instancer's copy is a program evaluated
// from within an instruction of its parent program, on the same thread.
template <class T>
class Scratch {
 public:
  explicit Scratch(std::size_t n) {
    std::deque<std::vector<T>>& p = pool();
    if (depth() == p.size()) p.emplace_back();  // a deque keeps the outer buffers in place
    buffer_ = &p[depth()++];
    buffer_->resize(n);
  }
  ~Scratch() { --depth(); }
  Scratch(const Scratch&) = delete;
  Scratch& operator=(const Scratch&) = delete;
  T* data() { return buffer_->data(); }

 private:
  static std::deque<std::vector<T>>& pool() {
    thread_local std::deque<std::vector<T>> p;
    return p;
  }
  static std::size_t& depth() {
    thread_local std::size_t d = 0;
    return d;
  }
  std::vector<T>* buffer_;
};

double externalAt(const Field& f, double x, double y, double z) {
  return f.eval(x, y, z);
}
Interval externalAt(const Field& f, const Interval& x, const Interval& y, const Interval& z) {
  return f.evalInterval(x, y, z);
}
Dual externalAt(const Field& f, const Dual& x, const Dual& y, const Dual& z) {
  return f.evalGradient(x, y, z);
}
}  // namespace

const char* opName(Op op) {
  return kOpInfo[static_cast<int>(op)].name;
}
int opArity(Op op) {
  return kOpInfo[static_cast<int>(op)].arity;
}
int opConstantCount(Op op) {
  return kOpInfo[static_cast<int>(op)].constants;
}
bool opIsCommutative(Op op) {
  return kOpInfo[static_cast<int>(op)].commutative;
}

Program::Program(std::vector<Instruction> code, std::vector<double> constants, Slot result,
                 std::vector<std::shared_ptr<const Field>> externals)
    : code_(std::move(code)),
      constants_(std::move(constants)),
      result_(result),
      externals_(std::move(externals)) {
  makePlan();
}

// Linear-scan slot assignment over the SSA code: a value's physical slot is released after its
// last use and taken by the next value. An instruction's output never shares a slot with its
// own operands (so that kernels and external fields may read their inputs while writing), and
// x, y, z and the result are never released. The arithmetic is unchanged, only where values
// are kept: every mode stays bit-identical to the SSA order.
void Program::makePlan() {
  const std::size_t n = code_.size();
  const std::size_t ssaSlots = n + kFirstInstructionSlot;
  std::vector<std::size_t> lastUse(ssaSlots, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Instruction& in = code_[i];
    const Slot args[3] = {in.a, in.b, in.c};
    lastUse[i + kFirstInstructionSlot] = i;  // a value nothing reads is released at once
    for (int j = 0; j < opArity(in.op); ++j) lastUse[args[j]] = i;
  }
  constexpr std::size_t kForever = static_cast<std::size_t>(-1);
  lastUse[result_] = kForever;
  for (Slot s = 0; s < kFirstInstructionSlot; ++s) lastUse[s] = kForever;

  std::vector<Slot> physical(ssaSlots, 0);
  for (Slot s = 0; s < kFirstInstructionSlot; ++s) physical[s] = s;
  std::vector<Slot> freeSlots;
  Slot next = kFirstInstructionSlot;
  plan_.clear();
  plan_.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Instruction& in = code_[i];
    const int arity = opArity(in.op);
    Step step{in.op, 0, 0, 0, 0, in.k};
    Slot* operands[3] = {&step.a, &step.b, &step.c};
    const Slot args[3] = {in.a, in.b, in.c};
    for (int j = 0; j < arity; ++j) *operands[j] = physical[args[j]];
    if (freeSlots.empty()) {
      step.out = next++;
    } else {
      step.out = freeSlots.back();
      freeSlots.pop_back();
    }
    physical[i + kFirstInstructionSlot] = step.out;
    for (int j = 0; j < arity; ++j) {
      const Slot arg = args[j];
      const bool repeated = (j > 0 && args[0] == arg) || (j > 1 && args[1] == arg);
      if (!repeated && lastUse[arg] == i) freeSlots.push_back(physical[arg]);
    }
    if (lastUse[i + kFirstInstructionSlot] == i) freeSlots.push_back(step.out);
    plan_.push_back(step);
  }
  planResult_ = physical[result_];
  planSlots_ = next;
}

template <class T>
T Program::evalGeneric(const T& x, const T& y, const T& z) const {
  // Scratch per thread and type: evaluation is called from TBB workers.
  Scratch<T> slots(planSlots_);
  T* s = slots.data();
  s[kSlotX] = x;
  s[kSlotY] = y;
  s[kSlotZ] = z;
  const double* k = constants_.data();
  for (const Step& in : plan_) {
    s[in.out] = in.op == Op::External ? externalAt(*externals_[static_cast<std::size_t>(k[in.k])],
                                                   s[in.a], s[in.b], s[in.c])
                                      : applyOp<T>(in.op, s[in.a], s[in.b], s[in.c], k + in.k);
  }
  return s[planResult_];
}

double Program::eval(double x, double y, double z) const {
  return evalGeneric<double>(x, y, z);
}

Interval Program::evalInterval(const Interval& x, const Interval& y, const Interval& z) const {
  return evalGeneric<Interval>(x, y, z);
}

Dual Program::evalGradient(const Dual& x, const Dual& y, const Dual& z) const {
  return evalGeneric<Dual>(x, y, z);
}

namespace {
// How a batch keeps one slot's values. Doubles: one array of kBatchSize. Duals: four arrays
// (values, d/dx, d/dy, d/dz), so that the dual kernels vectorise across points too.
struct DoubleSlots {
  using Value = double;
  static constexpr std::size_t kWidth = Program::kBatchSize;  // doubles per slot
  static double load(const double* p, std::size_t j) { return p[j]; }
  static void store(double* p, std::size_t j, double v) { p[j] = v; }
  static void external(const Field& f, const double* a, const double* b, const double* c,
                       std::size_t n, double* o) {
    f.evalBatch(a, b, c, n, o);
  }
  // sin and/or cos of the slot a (either output may be null; a is neither): the batch kernels,
  // the same bits as sin(A) and cos(A).
  static void sinCos(const double* a, std::size_t n, double* sinOut, double* cosOut) {
    sinCosMany(a, n, sinOut, cosOut);
  }
};

struct DualSlots {
  using Value = Dual;
  static constexpr std::size_t kStride = Program::kDualBatchSize;  // between a slot's arrays
  static constexpr std::size_t kWidth = 4 * kStride;
  static Dual load(const double* p, std::size_t j) {
    return Dual(p[j], p[kStride + j], p[2 * kStride + j], p[3 * kStride + j]);
  }
  static void store(double* p, std::size_t j, const Dual& v) {
    p[j] = v.v;
    p[kStride + j] = v.d[0];
    p[2 * kStride + j] = v.d[1];
    p[3 * kStride + j] = v.d[2];
  }
  // An external field takes duals one after another: unpack, evaluate, pack (in scratch per
  // nesting depth: the field may be a program with externals of its own).
  static void external(const Field& f, const double* a, const double* b, const double* c,
                       std::size_t n, double* o) {
    Scratch<Dual> buffer(4 * n);
    Dual *xa = buffer.data(), *ya = xa + n, *za = ya + n, *ra = za + n;
    for (std::size_t j = 0; j < n; ++j) {
      xa[j] = load(a, j);
      ya[j] = load(b, j);
      za[j] = load(c, j);
    }
    f.evalGradientBatch(xa, ya, za, n, ra);
    for (std::size_t j = 0; j < n; ++j) store(o, j, ra[j]);
  }
  // sin and/or cos of the slot a (either output may be null): the values in one batch pass of
  // sinCosMany, the derivatives by the chain rule, the same bits as Dual's sin and cos.
  // (An output may be a itself: each point's derivatives are read before they are written.)
  static void sinCos(const double* a, std::size_t n, double* sinOut, double* cosOut) {
    alignas(32) double s[kStride], c[kStride];
    sinCosMany(a, n, s, c);
    for (int k = 1; k <= 3; ++k) {
      const double* da = a + k * kStride;
      for (std::size_t j = 0; j < n; ++j) {
        const double d = da[j];
        if (sinOut) sinOut[k * kStride + j] = d * c[j];
        if (cosOut) cosOut[k * kStride + j] = d * -s[j];
      }
    }
    for (std::size_t j = 0; j < n; ++j) {
      if (sinOut) sinOut[j] = s[j];
      if (cosOut) cosOut[j] = c[j];
    }
  }
};

// segmentSq's value (and r, when asked) at n <= S points, the same bits as the point function:
// first t at every point, then the rest (in one loop the compiler does not vectorise the
// clamp). The constants are copied: it cannot tell that o is not them, and would read them
// again at every point.
template <std::size_t S, bool kWithR>
void segmentSqMany(const double* x, const double* y, const double* z, const double* k,
                   std::size_t n, double* o, double (*r)[S]) {
  double kk[7];
  std::copy(k, k + 7, kk);
  alignas(32) double t[S];
  for (std::size_t j = 0; j < n; ++j)
    t[j] = segmentAlong(x[j] - kk[0], y[j] - kk[1], z[j] - kk[2], kk);
  for (std::size_t j = 0; j < n; ++j) {
    const double rx = (x[j] - kk[0]) - t[j] * kk[3], ry = (y[j] - kk[1]) - t[j] * kk[4],
                 rz = (z[j] - kk[2]) - t[j] * kk[5];
    o[j] = sqr(rx) + sqr(ry) + sqr(rz);
    if constexpr (kWithR) r[0][j] = rx, r[1][j] = ry, r[2][j] = rz;
  }
}

// The choices of min, max, abs, select and floor on duals, component array by component
// array: the same picks as Dual's own functions (so the same bits), without copying a Dual
// per point, which kept the compiler from vectorising those kernels (gradients of a strut
// lattice, all mins and clamps, ran at a tenth of its values' rate).
struct DualPicks {
  static constexpr std::size_t S = Program::kDualBatchSize;
  using Mask = std::int64_t;  // (as wide as a double: the picks vectorise)
  // o = take ? b : sign * a, the first component deciding; o may be a or b.
  static void pick(const Mask* take, const double* a, const double* b, double sign, std::size_t n,
                   double* o) {
    for (int k = 0; k < 4; ++k)
      for (std::size_t j = 0; j < n; ++j)
        o[k * S + j] = take[j] ? b[k * S + j] : a[k * S + j] * sign;
  }
  static void min(const double* a, const double* b, std::size_t n, double* o) {
    Mask take[S];
    for (std::size_t j = 0; j < n; ++j) take[j] = b[j] < a[j];
    pick(take, a, b, 1.0, n, o);
  }
  static void max(const double* a, const double* b, std::size_t n, double* o) {
    Mask take[S];
    for (std::size_t j = 0; j < n; ++j) take[j] = b[j] > a[j];
    pick(take, a, b, 1.0, n, o);
  }
  static void abs(const double* a, std::size_t n, double* o) {  // a.v < 0 ? -a : a
    Mask keep[S];
    for (std::size_t j = 0; j < n; ++j) keep[j] = !(a[j] < 0.0);
    pick(keep, a, a, -1.0, n, o);
  }
  static void select(const double* a, const double* b, const double* c, std::size_t n,
                     double* o) {  // a.v >= 0 ? b : c
    Mask take[S];
    for (std::size_t j = 0; j < n; ++j) take[j] = a[j] >= 0.0;
    pick(take, c, b, 1.0, n, o);
  }
  // sqrt(A): the value and the slope (0.5 / value where it is > 0, else 0) as Dual's sqrt,
  // the quotient taken for every point and then chosen (inside the choice the compiler kept
  // the division there, one point at a time); o may be a.
  static void sqrt(const double* a, std::size_t n, double* o) {
    alignas(32) double value[S], slope[S];
    for (std::size_t j = 0; j < n; ++j) {
      value[j] = std::sqrt(a[j]);
      slope[j] = 0.5 / value[j];
    }
    for (std::size_t j = 0; j < n; ++j) slope[j] = value[j] > 0.0 ? slope[j] : 0.0;
    for (int k = 1; k < 4; ++k)
      for (std::size_t j = 0; j < n; ++j) o[k * S + j] = a[k * S + j] * slope[j];
    for (std::size_t j = 0; j < n; ++j) o[j] = value[j];
  }
  // segmentSq(A, B, C): the value and r at every point, then each derivative as
  // segmentSqSlope; o is none of a, b, c.
  static void segmentSq(const double* a, const double* b, const double* c, const double* k,
                        std::size_t n, double* o) {
    alignas(32) double r[3][S];
    segmentSqMany<S, true>(a, b, c, k, n, o, r);
    for (int d = 1; d < 4; ++d)
      for (std::size_t j = 0; j < n; ++j) {
        const double rj[3] = {r[0][j], r[1][j], r[2][j]};
        o[d * S + j] = segmentSqSlope(rj, a[d * S + j], b[d * S + j], c[d * S + j]);
      }
  }
  static void floor(const double* a, std::size_t n, double* o) {
    for (std::size_t j = 0; j < n; ++j) o[j] = std::floor(a[j]);
    for (int k = 1; k < 4; ++k)
      for (std::size_t j = 0; j < n; ++j) o[k * S + j] = 0.0;
  }
};

// Runs the plan over one chunk of points (the slots of x, y, z filled). The switch is outside
// the loops so that each loop is a straight vectorisable kernel; each kernel calls the same
// scalar function applyOp uses, so values are bit-identical to the point modes. (An operand
// an op does not use is loaded from a valid slot and the load is dropped by the compiler.)
template <class Slots, class Step>
__attribute__((always_inline)) inline void runPlan(const Step* plan, std::size_t steps,
                                                   const double* kbase,
                                                   const std::shared_ptr<const Field>* externals,
                                                   std::size_t n, double* slots) {
  using V = typename Slots::Value;
  constexpr std::size_t W = Slots::kWidth;
  constexpr bool kDuals = std::is_same_v<Slots, DualSlots>;
  for (std::size_t s = 0; s < steps; ++s) {
    const Step& in = plan[s];
    double* o = slots + in.out * W;
    const double* a = slots + in.a * W;
    const double* b = slots + in.b * W;
    const double* c = slots + in.c * W;
    const double* k = kbase + in.k;
// (The plan never gives an instruction an output slot that is one of its inputs: for duals,
// ivdep tells the compiler so, and it vectorises their kernels instead of checking twelve
// arrays against four for overlap and running one point at a time. The kernels on doubles
// are faster left as the compiler makes them.)
#define FREP_KERNEL_LOOP(expr)                                               \
  for (std::size_t j = 0; j < n; ++j) {                                      \
    [[maybe_unused]] const V A = Slots::load(a, j), B = Slots::load(b, j),   \
                             C = Slots::load(c, j);                          \
    Slots::store(o, j, (expr));                                              \
  }
#define FREP_KERNEL(expr)                                                    \
  {                                                                          \
    if constexpr (kDuals) {                                                  \
      _Pragma("GCC ivdep") FREP_KERNEL_LOOP(expr)                            \
    } else {                                                                 \
      FREP_KERNEL_LOOP(expr)                                                 \
    }                                                                        \
  }                                                                          \
  break
    switch (in.op) {
      case Op::Const:
        FREP_KERNEL(V(k[0]));
      case Op::Add:
        FREP_KERNEL(A + B);
      case Op::Sub:
        FREP_KERNEL(A - B);
      case Op::Mul:
        FREP_KERNEL(A * B);
      case Op::Div:
        FREP_KERNEL(A / B);
      case Op::Neg:
        FREP_KERNEL(-A);
      case Op::Sqr:
        FREP_KERNEL(sqr(A));
      case Op::Sqrt:
        if constexpr (kDuals) {
          DualPicks::sqrt(a, n, o);
          break;
        }
        FREP_KERNEL(sqrt(A));
      case Op::Abs:
        if constexpr (kDuals) {
          DualPicks::abs(a, n, o);
          break;
        }
        FREP_KERNEL(abs(A));
      case Op::Min:
        if constexpr (kDuals) {
          DualPicks::min(a, b, n, o);
          break;
        }
        FREP_KERNEL(min(A, B));
      case Op::Max:
        if constexpr (kDuals) {
          DualPicks::max(a, b, n, o);
          break;
        }
        FREP_KERNEL(max(A, B));
      case Op::Exp:
        FREP_KERNEL(exp(A));
      case Op::Sin:
        // The lattices take sin and cos of one argument, emitted one after the other: one
        // pass gives both (the same bits), unless an output overwrites the argument.
        if (s + 1 < steps && plan[s + 1].op == Op::Cos && plan[s + 1].a == in.a && in.out != in.a &&
            plan[s + 1].out != in.a && plan[s + 1].out != in.out) {
          Slots::sinCos(a, n, o, slots + plan[s + 1].out * W);
          ++s;
          break;
        }
        Slots::sinCos(a, n, o, nullptr);  // the same bits as sin(A)
        break;
      case Op::Cos:
        Slots::sinCos(a, n, nullptr, o);
        break;
      case Op::Affine:
        FREP_KERNEL(affine<V>(A, B, C, k));
      case Op::RUnion:
        FREP_KERNEL(rUnion<V>(A, B, k[0]));
      case Op::RIntersect:
        FREP_KERNEL(rIntersect<V>(A, B, k[0]));
      case Op::BlendBump:
        FREP_KERNEL(blendBump<V>(A, B, k));
      case Op::Atan2:
        FREP_KERNEL(atan2(A, B));
      case Op::PowAbs:
        FREP_KERNEL(powAbs(A, k[0]));
      case Op::Floor:
        if constexpr (kDuals) {
          DualPicks::floor(a, n, o);
          break;
        }
        FREP_KERNEL(floor(A));
      case Op::Tan:
        FREP_KERNEL(tan(A));
      case Op::Atan:
        FREP_KERNEL(atan(A));
      case Op::Log:
        FREP_KERNEL(log(A));
      case Op::PowConst:
        FREP_KERNEL(powConst(A, k[0]));
      case Op::Select:
        if constexpr (kDuals) {
          DualPicks::select(a, b, c, n, o);
          break;
        }
        FREP_KERNEL(select(A, B, C));
      case Op::SegmentSq:
        if constexpr (kDuals)
          DualPicks::segmentSq(a, b, c, k, n, o);
        else
          segmentSqMany<Program::kBatchSize, false>(a, b, c, k, n, o, nullptr);
        break;
      case Op::External:
        Slots::external(*externals[static_cast<std::size_t>(k[0])], a, b, c, n, o);
        break;
      case Op::Count_:
        break;
    }
#undef FREP_KERNEL
#undef FREP_KERNEL_LOOP
  }
}

// On x86-64 the kernels are also compiled for AVX2 (four doubles per instruction), chosen at
// load time where the processor has it. Only the vector width changes: every operation is
// still one IEEE operation on doubles (no FMA: -ffp-contract=off), so the values are the
// same bits on every processor.
#if defined(__x86_64__) && defined(__GNUC__)
#define FREP_VECTOR_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define FREP_VECTOR_CLONES
#endif

template <class Step>
FREP_VECTOR_CLONES void runPlanDouble(const Step* plan, std::size_t steps, const double* kbase,
                                      const std::shared_ptr<const Field>* externals, std::size_t n,
                                      double* slots) {
  runPlan<DoubleSlots>(plan, steps, kbase, externals, n, slots);
}
template <class Step>
FREP_VECTOR_CLONES void runPlanDual(const Step* plan, std::size_t steps, const double* kbase,
                                    const std::shared_ptr<const Field>* externals, std::size_t n,
                                    double* slots) {
  runPlan<DualSlots>(plan, steps, kbase, externals, n, slots);
}
}  // namespace

void Program::evalChunk(const double* x, const double* y, const double* z, std::size_t n,
                        double* out, double* slots) const {
  constexpr std::size_t B = kBatchSize;
  for (std::size_t j = 0; j < n; ++j) {
    slots[kSlotX * B + j] = x[j];
    slots[kSlotY * B + j] = y[j];
    slots[kSlotZ * B + j] = z[j];
  }
  runPlanDouble(plan_.data(), plan_.size(), constants_.data(), externals_.data(), n, slots);
  const double* r = slots + planResult_ * B;
  for (std::size_t j = 0; j < n; ++j) out[j] = r[j];
}

void Program::evalDualChunk(const Dual* x, const Dual* y, const Dual* z, std::size_t n, Dual* out,
                            double* slots) const {
  constexpr std::size_t W = 4 * kDualBatchSize;
  for (std::size_t j = 0; j < n; ++j) {
    DualSlots::store(slots + kSlotX * W, j, x[j]);
    DualSlots::store(slots + kSlotY * W, j, y[j]);
    DualSlots::store(slots + kSlotZ * W, j, z[j]);
  }
  runPlanDual(plan_.data(), plan_.size(), constants_.data(), externals_.data(), n, slots);
  const double* r = slots + planResult_ * W;
  for (std::size_t j = 0; j < n; ++j) out[j] = DualSlots::load(r, j);
}

void Program::evalBatch(const double* x, const double* y, const double* z, std::size_t n,
                        double* out) const {
  Scratch<double> slots(planSlots_ * kBatchSize);
  for (std::size_t start = 0; start < n; start += kBatchSize) {
    const std::size_t m = std::min(kBatchSize, n - start);
    evalChunk(x + start, y + start, z + start, m, out + start, slots.data());
  }
}

void Program::evalGradientBatch(const Dual* x, const Dual* y, const Dual* z, std::size_t n,
                                Dual* out) const {
  Scratch<double> slots(planSlots_ * 4 * kDualBatchSize);
  for (std::size_t start = 0; start < n; start += kDualBatchSize) {
    const std::size_t m = std::min(kDualBatchSize, n - start);
    evalDualChunk(x + start, y + start, z + start, m, out + start, slots.data());
  }
}

std::string Program::disassemble() const {
  std::ostringstream os;
  for (std::size_t i = 0; i < code_.size(); ++i) {
    const Instruction& in = code_[i];
    os << '%' << i + kFirstInstructionSlot << " = " << opName(in.op);
    const Slot args[3] = {in.a, in.b, in.c};
    for (int j = 0; j < opArity(in.op); ++j) os << " %" << args[j];
    for (int j = 0; j < opConstantCount(in.op); ++j) os << ' ' << constants_[in.k + j];
    os << '\n';
  }
  os << "result %" << result_ << '\n';
  return os.str();
}

}  // namespace frep
