// The HyperFun language (.hf programs), as its interpreter reads them: the syntax tree of a
// program of bodies ("my_model(x[3], a[1]) { ... }"). Names are case-insensitive (kept in
// lower case); `--` starts a comment. docs/hyperfun.md has the grammar and what FRepCAD does
// with each construct (hyperfun_import.h turns a program into an FRep tree).
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace frep::hyperfun {

struct Location {
  int line = 1;
  int column = 1;
};

// An expression or a condition. Operators are kept as written: "+", "-", "*", "/", "^", "|",
// "&", "\\", "@" (binary), "neg", "pos", "~" (unary), and in conditions "and", "or", "not",
// "<", "<=", ">", ">=", "=", "/=".
struct Ast {
  enum class Kind { Number, Name, Element, Call, Unary, Binary };
  Kind kind = Kind::Number;
  Location at;
  double number = 0.0;  // Number
  std::string text;     // Name, Element, Call: the name; Unary, Binary: the operator
  std::vector<std::unique_ptr<Ast>> args;  // Element: the index; Call: the arguments
};
using AstPtr = std::unique_ptr<Ast>;

struct Statement {
  enum class Kind { Assign, AssignElement, AssignArray, If, While };
  Kind kind = Kind::Assign;
  Location at;
  std::string name;                  // the variable or array assigned (not If, While)
  AstPtr index;                      // AssignElement
  AstPtr value;                      // Assign, AssignElement; If, While: the condition
  std::vector<double> numbers;       // AssignArray: name = [n1, n2, ...]
  std::vector<Statement> body;       // If: then-part; While: the loop
  std::vector<Statement> otherwise;  // If: else-part
};

struct ArrayDeclaration {
  std::string name;
  int size = 0;
  Location at;
};

// name(x[N], a[M]) or name(x[N], a[M], s[K]) { array ...; statements; name = expression; }
struct Body {
  std::string name;
  Location at;
  int coordinates = 3;  // N
  int parameters = 1;   // M
  std::vector<ArrayDeclaration> arrays;
  std::vector<Statement> statements;
  AstPtr result;  // the expression assigned to the body's own name, last
};

struct Program {
  std::vector<Body> bodies;
};

// Parses a program; `source` names it in errors ("model.hf:3:14: ..."). Throws ModelError.
Program parseProgram(const std::string& text, const std::string& source);

// "model.hf:3:14: what" (the error text every HyperFun message uses).
std::string located(const std::string& source, Location at, const std::string& what);

}  // namespace frep::hyperfun
