// A HyperFun program's values, symbolic in the point: what a variable holds after the program
// ran with x = (x, y, z) unknown. Constants are folded as HyperFun computes them (its power,
// its division and function checks), so loops and conditions over constants run here; what
// depends on the point stays an expression, to become FRep nodes (hyperfun_import.cpp).
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "frep/hyperfun_syntax.h"

namespace frep::hyperfun {

struct Expr;
using ExprPtr = std::shared_ptr<const Expr>;

struct Expr {
  enum class Kind {
    Constant,
    Coordinate,  // x, y or z (axis 0, 1, 2)
    Operator,    // op: "+", "-", "*", "/", "^" (two args) or "neg" (one)
    Function,    // op: a function of the formula language (sqrt, min, floor, ...)
    Union,       // HyperFun's | & \ ~ (R-functions with alpha = 0)
    Intersection,
    Difference,
    Complement,
    BlendUnion,  // hfBlendUni, hfBlendInt: blend = a0, a1, a2
    BlendIntersection,
    Primitive,  // a library primitive: args[0] is its defining expression
  };
  Kind kind = Kind::Constant;
  double value = 0.0;
  int axis = 0;
  std::string op;
  std::vector<ExprPtr> args;
  std::array<double, 3> blend{};
  std::string label;  // Primitive: "hfSphere" (for messages)
};

// Makes values, folding constants; errors name the program's line and column.
class ExprBuilder {
 public:
  explicit ExprBuilder(std::string source) : source_(std::move(source)) {}

  // Where the next error is reported (the expression being evaluated).
  void at(Location where) { at_ = where; }
  Location where() const { return at_; }
  [[noreturn]] void fail(const std::string& what) const;

  static bool isConstant(const ExprPtr& e) { return e->kind == Expr::Kind::Constant; }
  static bool isSolid(const ExprPtr& e);  // a set operation, blend or primitive
  double constantOf(const ExprPtr& e, const std::string& what) const;

  ExprPtr constant(double v);
  ExprPtr coordinate(int axis);
  ExprPtr add(ExprPtr a, ExprPtr b);
  ExprPtr sub(ExprPtr a, ExprPtr b);
  ExprPtr mul(ExprPtr a, ExprPtr b);
  ExprPtr div(ExprPtr a, ExprPtr b);
  ExprPtr pow(ExprPtr a, ExprPtr b);  // HyperFun's ^
  ExprPtr neg(ExprPtr a);
  ExprPtr sqr(ExprPtr a) { return call("sqr", {std::move(a)}); }
  // A HyperFun function by its name (sqrt, exp, log, logd, sin, ..., mod, max, min, atan2,
  // ceil, floor, int, frac, sign); nullptr when `name` is none of them.
  ExprPtr function(const std::string& name, const std::vector<ExprPtr>& args);
  static bool isFunction(const std::string& name);
  ExprPtr setOperation(Expr::Kind kind, ExprPtr a, ExprPtr b);  // Union, Intersection, Difference
  ExprPtr complement(ExprPtr a);
  ExprPtr blend(Expr::Kind kind, ExprPtr a, ExprPtr b, double a0, double a1, double a2);
  ExprPtr primitive(const std::string& label, ExprPtr definition);

  // The formula language's own functions, for what HyperFun spells otherwise.
  ExprPtr call(const std::string& formulaName, std::vector<ExprPtr> args);

 private:
  ExprPtr make(Expr e);

  std::string source_;
  Location at_;
  std::size_t made_ = 0;
};

}  // namespace frep::hyperfun
