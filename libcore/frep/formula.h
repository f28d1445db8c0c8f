// User formulas: an expression in x, y, z, named parameters and input fields, parsed once into
// a small syntax tree and then emitted into the same program as every other node, so a formula
// runs in all four evaluator modes (point, batch, interval, gradient) at compiled speed.
//
// Grammar (precedence from low to high; ^ is right-associative and binds tighter than unary
// minus, so -x^2 = -(x^2)):
//   expr    = term { ("+" | "-") term }
//   term    = unary { ("*" | "/") unary }
//   unary   = ("-" | "+") unary | power
//   power   = primary [ ("^" | "**") unary ]
//   primary = number | name | name "(" expr { "," expr } ")" | "(" expr ")"
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "frep/program_builder.h"

namespace frep {

// A parse or name error at a 1-based column of the text.
struct FormulaError : std::runtime_error {
  FormulaError(int col, const std::string& what) : std::runtime_error(what), column(col) {}
  int column;
};

// How deep parentheses, signs, powers and calls may nest in a formula.
constexpr int kMaxFormulaNesting = 500;

// Names of the functions a formula may call, for docs and error messages.
std::string formulaFunctionList();

class Formula {
 public:
  // Parses `text`. Every name used must be x, y, z, pi or one of `names`; functions must be
  // known and called with the right number of arguments. Throws FormulaError.
  static Formula parse(const std::string& text, const std::vector<std::string>& names);

  // Emits the formula; `name` gives the slot of each of the names passed to parse().
  Slot emit(ProgramBuilder& b, Slot x, Slot y, Slot z,
            const std::function<Slot(const std::string&)>& name) const;

  // Whether the formula uses the name (x, y, z or one of the parse names).
  bool uses(const std::string& name) const;

 private:
  struct Expr {
    enum Kind { Number, Name, Call, Neg, Add, Sub, Mul, Div, Pow } kind;
    double value = 0.0;
    std::string name;       // Name, Call
    std::vector<int> args;  // operands, indices into nodes_
  };
  friend class FormulaParser;
  Slot emitNode(int root, ProgramBuilder& b, Slot x, Slot y, Slot z,
                const std::function<Slot(const std::string&)>& name) const;
  Slot emitOne(const Expr& e, const std::vector<Slot>& slots, ProgramBuilder& b, Slot x, Slot y,
               Slot z, const std::function<Slot(const std::string&)>& name) const;
  std::vector<Expr> nodes_;
  int root_ = -1;
};

// A parameter list "name = value, name = value" (commas, semicolons or new lines between
// entries). A value is a constant formula and may use pi and the parameters before it.
struct FormulaParameter {
  std::string name;
  double value;
};
// Throws FormulaError at the column of the problem (duplicate or reserved names included).
std::vector<FormulaParameter> parseFormulaParameters(const std::string& text);

// The text with a caret under the column, for error messages: "  r - sqrt(x)\n      ^".
std::string formulaCaret(const std::string& text, int column);

}  // namespace frep
