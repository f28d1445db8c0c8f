#include "frep/hyperfun_expr.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

#include "base/errors.h"

namespace frep::hyperfun {

namespace {

// HyperFun's tolerance for zero (a divisor, a blend's reach, a comparison for equality).
constexpr double kEps = 1e-6;
// Values one program may make: a loop that builds millions of them is refused.
constexpr std::size_t kMostValues = 2000000;

std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

// HyperFun's rounding (halves up), as its array indices and mod use it.
double roundHalfUp(double v) {
  return std::floor(v + 0.5);
}

}  // namespace

void ExprBuilder::fail(const std::string& what) const {
  throw ModelError(located(source_, at_, what));
}

bool ExprBuilder::isSolid(const ExprPtr& e) {
  switch (e->kind) {
    case Expr::Kind::Union:
    case Expr::Kind::Intersection:
    case Expr::Kind::Difference:
    case Expr::Kind::Complement:
    case Expr::Kind::BlendUnion:
    case Expr::Kind::BlendIntersection:
    case Expr::Kind::Primitive:
      return true;
    default:
      return false;
  }
}

double ExprBuilder::constantOf(const ExprPtr& e, const std::string& what) const {
  if (!isConstant(e)) fail(what + " depends on the point (x); FRepCAD needs a number here");
  return e->value;
}

ExprPtr ExprBuilder::make(Expr e) {
  if (++made_ > kMostValues)
    fail("the program makes more than " + std::to_string(kMostValues) +
         " values (a loop that builds a model too large to keep as a tree)");
  return std::make_shared<const Expr>(std::move(e));
}

ExprPtr ExprBuilder::constant(double v) {
  if (!std::isfinite(v)) fail("a value overflows (" + number(v) + ")");
  Expr e;
  e.value = v;
  return make(std::move(e));
}

ExprPtr ExprBuilder::coordinate(int axis) {
  Expr e;
  e.kind = Expr::Kind::Coordinate;
  e.axis = axis;
  return make(std::move(e));
}

ExprPtr ExprBuilder::call(const std::string& formulaName, std::vector<ExprPtr> args) {
  static const std::map<std::string, std::function<double(const std::vector<double>&)>> folds = {
      {"sqrt", [](const std::vector<double>& a) { return std::sqrt(a[0]); }},
      {"sqr", [](const std::vector<double>& a) { return a[0] * a[0]; }},
      {"exp", [](const std::vector<double>& a) { return std::exp(a[0]); }},
      {"log", [](const std::vector<double>& a) { return std::log(a[0]); }},
      {"sin", [](const std::vector<double>& a) { return std::sin(a[0]); }},
      {"cos", [](const std::vector<double>& a) { return std::cos(a[0]); }},
      {"tan", [](const std::vector<double>& a) { return std::tan(a[0]); }},
      {"asin", [](const std::vector<double>& a) { return std::asin(a[0]); }},
      {"acos", [](const std::vector<double>& a) { return std::acos(a[0]); }},
      {"atan", [](const std::vector<double>& a) { return std::atan(a[0]); }},
      {"sinh", [](const std::vector<double>& a) { return std::sinh(a[0]); }},
      {"cosh", [](const std::vector<double>& a) { return std::cosh(a[0]); }},
      {"tanh", [](const std::vector<double>& a) { return std::tanh(a[0]); }},
      {"abs", [](const std::vector<double>& a) { return std::fabs(a[0]); }},
      {"floor", [](const std::vector<double>& a) { return std::floor(a[0]); }},
      {"ceil", [](const std::vector<double>& a) { return std::ceil(a[0]); }},
      {"atan2", [](const std::vector<double>& a) { return std::atan2(a[0], a[1]); }},
      {"max", [](const std::vector<double>& a) { return std::max(a[0], a[1]); }},
      {"min", [](const std::vector<double>& a) { return std::min(a[0], a[1]); }},
      {"clamp", [](const std::vector<double>& a) { return std::min(std::max(a[0], a[1]), a[2]); }},
  };
  if (std::all_of(args.begin(), args.end(), isConstant)) {
    const auto it = folds.find(formulaName);
    if (it != folds.end()) {
      std::vector<double> v;
      for (const ExprPtr& a : args) v.push_back(a->value);
      const double r = it->second(v);
      if (std::isnan(r)) fail(formulaName + " of " + number(v[0]) + " is not a number");
      return constant(r);
    }
  }
  Expr e;
  e.kind = Expr::Kind::Function;
  e.op = formulaName;
  e.args = std::move(args);
  return make(std::move(e));
}

namespace {

Expr operatorExpr(const char* op, std::vector<ExprPtr> args) {
  Expr e;
  e.kind = Expr::Kind::Operator;
  e.op = op;
  e.args = std::move(args);
  return e;
}

}  // namespace

ExprPtr ExprBuilder::add(ExprPtr a, ExprPtr b) {
  if (isConstant(a) && isConstant(b)) return constant(a->value + b->value);
  if (isConstant(b) && b->value == 0.0 && !isSolid(a)) return a;  // the same value
  return make(operatorExpr("+", {a, b}));
}

ExprPtr ExprBuilder::sub(ExprPtr a, ExprPtr b) {
  if (isConstant(a) && isConstant(b)) return constant(a->value - b->value);
  if (isConstant(b) && b->value == 0.0 && !isSolid(a)) return a;
  return make(operatorExpr("-", {a, b}));
}

ExprPtr ExprBuilder::mul(ExprPtr a, ExprPtr b) {
  if (isConstant(a) && isConstant(b)) return constant(a->value * b->value);
  return make(operatorExpr("*", {a, b}));
}

ExprPtr ExprBuilder::div(ExprPtr a, ExprPtr b) {
  if (isConstant(b) && std::fabs(b->value) < kEps)
    fail("division by zero (the divisor is " + number(b->value) + ")");
  if (isConstant(a) && isConstant(b)) return constant(a->value / b->value);
  return make(operatorExpr("/", {a, b}));
}

ExprPtr ExprBuilder::neg(ExprPtr a) {
  if (isConstant(a)) return constant(-a->value);
  return make(operatorExpr("neg", {a}));
}

ExprPtr ExprBuilder::pow(ExprPtr base, ExprPtr exponent) {
  if (!isConstant(exponent)) return make(operatorExpr("^", {base, exponent}));
  const double e = exponent->value;
  // HyperFun takes an exponent within 1e-6 above a whole number as that number (a product
  // of the base with itself, so negative bases are fine), any other as exp(e log base).
  const bool whole = e - std::floor(e) < kEps;
  const double k = whole ? std::copysign(roundHalfUp(std::fabs(e)), e) : e;
  if (isConstant(base)) {
    const double b = base->value;
    if (std::fabs(b) < kEps) {
      if (e <= kEps) fail("zero to the power " + number(e));
      return constant(0.0);
    }
    if (!whole && b < 0.0) fail("a negative number (" + number(b) + ") to a fractional power");
    return constant(whole ? std::pow(b, k) : std::exp(e * std::log(b)));
  }
  if (whole && k == 1.0) return base;
  return make(operatorExpr("^", {base, constant(k)}));
}

bool ExprBuilder::isFunction(const std::string& name) {
  static const char* const names[] = {
      "sqrt", "exp",  "log",  "logd", "sin", "cos", "tan",   "asin", "acos",  "atan", "abs", "sinh",
      "cosh", "tanh", "sign", "mod",  "max", "min", "atan2", "ceil", "floor", "int",  "frac"};
  return std::find(std::begin(names), std::end(names), name) != std::end(names);
}

ExprPtr ExprBuilder::function(const std::string& name, const std::vector<ExprPtr>& a) {
  const bool two = name == "mod" || name == "max" || name == "min" || name == "atan2";
  if (a.size() != (two ? 2u : 1u))
    fail(name + " takes " + (two ? "2 arguments" : "1 argument") + ", not " +
         std::to_string(a.size()));
  const bool constant1 = isConstant(a[0]);
  const double v = a[0]->value;
  // HyperFun's checks on the values it can see now.
  if (constant1) {
    if (name == "sqrt" && v < 0.0) fail("sqrt of a negative value (" + number(v) + ")");
    if ((name == "log" || name == "logd") && !(v > 0.0))
      fail(name + " of a value that is not positive (" + number(v) + ")");
    if ((name == "asin" || name == "acos") && std::fabs(v) > 1.0)
      fail(name + " of a value outside -1 to 1 (" + number(v) + ")");
    if (name == "tan" && std::fabs(std::cos(v)) < kEps) fail("tan at a pole (" + number(v) + ")");
  }
  if (name == "sign") return constant(1.0);  // HyperFun's sign() is 1 for every value
  if (name == "logd") return div(call("log", {a[0]}), constant(std::log(10.0)));
  // int: towards zero; frac: what int leaves
  auto truncated = [&](ExprPtr t) {
    if (isConstant(t)) return constant(std::trunc(t->value));
    return sub(call("floor", {call("max", {t, constant(0.0)})}),
               call("floor", {call("max", {neg(t), constant(0.0)})}));
  };
  if (name == "int") return truncated(a[0]);
  if (name == "frac") return sub(a[0], truncated(a[0]));
  if (name == "mod") {
    // HyperFun: fmod of the two values rounded to whole numbers
    const ExprPtr p = call("floor", {add(a[0], constant(0.5))});
    const ExprPtr q = call("floor", {add(a[1], constant(0.5))});
    if (isConstant(q) && q->value == 0.0) fail("mod by a number that rounds to 0");
    if (isConstant(p) && isConstant(q)) return constant(std::fmod(p->value, q->value));
    return sub(p, mul(q, truncated(div(p, q))));
  }
  return call(name, a);
}

ExprPtr ExprBuilder::setOperation(Expr::Kind kind, ExprPtr a, ExprPtr b) {
  if (isConstant(a) && isConstant(b)) {
    const double f1 = a->value;
    const double f2 = kind == Expr::Kind::Difference ? -b->value : b->value;
    const double root = std::sqrt(f1 * f1 + f2 * f2);
    return constant(kind == Expr::Kind::Union ? f1 + f2 + root : f1 + f2 - root);
  }
  Expr e;
  e.kind = kind;
  e.args = {a, b};
  return make(std::move(e));
}

ExprPtr ExprBuilder::complement(ExprPtr a) {
  if (isConstant(a)) return constant(-a->value);
  Expr e;
  e.kind = Expr::Kind::Complement;
  e.args = {a};
  return make(std::move(e));
}

ExprPtr ExprBuilder::blend(Expr::Kind kind, ExprPtr a, ExprPtr b, double a0, double a1, double a2) {
  if (std::fabs(a1) < kEps || std::fabs(a2) < kEps)
    fail("a blend's a1 and a2 must not be 0 (got " + number(a1) + " and " + number(a2) + ")");
  Expr e;
  e.kind = kind;
  e.args = {a, b};
  e.blend = {a0, a1, a2};
  return make(std::move(e));
}

ExprPtr ExprBuilder::primitive(const std::string& label, ExprPtr definition) {
  if (isConstant(definition)) return definition;
  Expr e;
  e.kind = Expr::Kind::Primitive;
  e.label = label;
  e.args = {definition};
  return make(std::move(e));
}

}  // namespace frep::hyperfun
