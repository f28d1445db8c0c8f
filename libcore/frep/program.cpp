#include "frep/program.h"

#include <deque>
#include <sstream>
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
    {"const", 0, 1, false},    {"add", 2, 0, true},         {"sub", 2, 0, false},
    {"mul", 2, 0, true},       {"div", 2, 0, false},        {"neg", 1, 0, false},
    {"sqr", 1, 0, false},      {"sqrt", 1, 0, false},       {"abs", 1, 0, false},
    {"min", 2, 0, true},       {"max", 2, 0, true},         {"exp", 1, 0, false},
    {"sin", 1, 0, false},      {"cos", 1, 0, false},        {"affine", 3, 4, false},
    {"runion", 2, 1, true},    {"rintersect", 2, 1, true},  {"blendbump", 2, 3, false},
    {"atan2", 2, 0, false},    {"powabs", 1, 1, false},     {"floor", 1, 0, false},
    {"tan", 1, 0, false},      {"atan", 1, 0, false},       {"log", 1, 0, false},
    {"powconst", 1, 1, false}, {"select", 3, 0, false},     {"external", 3, 1, false},
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

double externalAt(const Field& f, double x, double y, double z) { return f.eval(x, y, z); }
Interval externalAt(const Field& f, const Interval& x, const Interval& y, const Interval& z) {
  return f.evalInterval(x, y, z);
}
Dual externalAt(const Field& f, const Dual& x, const Dual& y, const Dual& z) {
  return f.evalGradient(x, y, z);
}
}  // namespace

const char* opName(Op op) { return kOpInfo[static_cast<int>(op)].name; }
int opArity(Op op) { return kOpInfo[static_cast<int>(op)].arity; }
int opConstantCount(Op op) { return kOpInfo[static_cast<int>(op)].constants; }
bool opIsCommutative(Op op) { return kOpInfo[static_cast<int>(op)].commutative; }

Program::Program(std::vector<Instruction> code, std::vector<double> constants, Slot result,
                 std::vector<std::shared_ptr<const Field>> externals)
    : code_(std::move(code)),
      constants_(std::move(constants)),
      result_(result),
      externals_(std::move(externals)) {}

template <class T>
T Program::evalGeneric(const T& x, const T& y, const T& z) const {
  // Scratch per thread and type: evaluation is called from TBB workers.
  Scratch<T> slots(code_.size() + kFirstInstructionSlot);
  T* s = slots.data();
  s[kSlotX] = x;
  s[kSlotY] = y;
  s[kSlotZ] = z;
  const double* k = constants_.data();
  for (std::size_t i = 0; i < code_.size(); ++i) {
    const Instruction& in = code_[i];
    s[i + kFirstInstructionSlot] =
        in.op == Op::External
            ? externalAt(*externals_[static_cast<std::size_t>(k[in.k])], s[in.a], s[in.b],
                         s[in.c])
            : applyOp<T>(in.op, s[in.a], s[in.b], s[in.c], k + in.k);
  }
  return s[result_];
}

double Program::eval(double x, double y, double z) const { return evalGeneric<double>(x, y, z); }

Interval Program::evalInterval(const Interval& x, const Interval& y, const Interval& z) const {
  return evalGeneric<Interval>(x, y, z);
}

Dual Program::evalGradient(const Dual& x, const Dual& y, const Dual& z) const {
  return evalGeneric<Dual>(x, y, z);
}

// The switch is outside the loops so that each loop is a straight vectorisable kernel; each
// kernel calls the same scalar function applyOp uses, so values are bit-identical.
void Program::evalChunk(const double* x, const double* y, const double* z, std::size_t n,
                        double* out, double* slots) const {
  constexpr std::size_t B = kBatchSize;
  for (std::size_t j = 0; j < n; ++j) {
    slots[kSlotX * B + j] = x[j];
    slots[kSlotY * B + j] = y[j];
    slots[kSlotZ * B + j] = z[j];
  }
  const double* kbase = constants_.data();
  for (std::size_t i = 0; i < code_.size(); ++i) {
    const Instruction& in = code_[i];
    double* o = slots + (i + kFirstInstructionSlot) * B;
    const double* a = slots + in.a * B;
    const double* b = slots + in.b * B;
    const double* c = slots + in.c * B;
    const double* k = kbase + in.k;
#define FREP_KERNEL(expr) \
  for (std::size_t j = 0; j < n; ++j) o[j] = (expr); \
  break
    switch (in.op) {
      case Op::Const: FREP_KERNEL(k[0]);
      case Op::Add: FREP_KERNEL(a[j] + b[j]);
      case Op::Sub: FREP_KERNEL(a[j] - b[j]);
      case Op::Mul: FREP_KERNEL(a[j] * b[j]);
      case Op::Div: FREP_KERNEL(a[j] / b[j]);
      case Op::Neg: FREP_KERNEL(-a[j]);
      case Op::Sqr: FREP_KERNEL(sqr(a[j]));
      case Op::Sqrt: FREP_KERNEL(std::sqrt(a[j]));
      case Op::Abs: FREP_KERNEL(std::abs(a[j]));
      case Op::Min: FREP_KERNEL(frep::min(a[j], b[j]));
      case Op::Max: FREP_KERNEL(frep::max(a[j], b[j]));
      case Op::Exp: FREP_KERNEL(std::exp(a[j]));
      case Op::Sin: FREP_KERNEL(std::sin(a[j]));
      case Op::Cos: FREP_KERNEL(std::cos(a[j]));
      case Op::Affine: FREP_KERNEL(affine<double>(a[j], b[j], c[j], k));
      case Op::RUnion: FREP_KERNEL(rUnion<double>(a[j], b[j], k[0]));
      case Op::RIntersect: FREP_KERNEL(rIntersect<double>(a[j], b[j], k[0]));
      case Op::BlendBump: FREP_KERNEL(blendBump<double>(a[j], b[j], k));
      case Op::Atan2: FREP_KERNEL(std::atan2(a[j], b[j]));
      case Op::PowAbs: FREP_KERNEL(powAbs(a[j], k[0]));
      case Op::Floor: FREP_KERNEL(std::floor(a[j]));
      case Op::Tan: FREP_KERNEL(std::tan(a[j]));
      case Op::Atan: FREP_KERNEL(std::atan(a[j]));
      case Op::Log: FREP_KERNEL(std::log(a[j]));
      case Op::PowConst: FREP_KERNEL(powConst(a[j], k[0]));
      case Op::Select: FREP_KERNEL(select(a[j], b[j], c[j]));
      case Op::External:
        externals_[static_cast<std::size_t>(k[0])]->evalBatch(a, b, c, n, o);
        break;
      case Op::Count_: break;
    }
#undef FREP_KERNEL
  }
  const double* r = slots + result_ * B;
  for (std::size_t j = 0; j < n; ++j) out[j] = r[j];
}

void Program::evalBatch(const double* x, const double* y, const double* z, std::size_t n,
                        double* out) const {
  Scratch<double> slots((code_.size() + kFirstInstructionSlot) * kBatchSize);
  for (std::size_t start = 0; start < n; start += kBatchSize) {
    const std::size_t m = std::min(kBatchSize, n - start);
    evalChunk(x + start, y + start, z + start, m, out + start, slots.data());
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
