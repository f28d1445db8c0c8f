#include "frep/formula.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>

namespace frep {

namespace {

constexpr double kPiValue = 3.14159265358979323846;

using Emitter = std::function<Slot(ProgramBuilder&, const std::vector<Slot>&)>;

Slot emitPow(ProgramBuilder& b, Slot a, Slot e) {
  if (b.isConstant(e)) {
    const double k = b.constantValue(e);
    if (k == 1.0) return a;
    if (k == 2.0) return b.sqr(a);
    if (k == 0.5) return b.sqrt(a);
    return b.emit(Op::PowConst, a, 0, 0, {k});
  }
  // a variable exponent: defined for a > 0, as std::pow with a non-integer exponent
  return b.emit(Op::Exp, b.mul(e, b.emit(Op::Log, a)));
}

struct Function {
  int minArgs;
  int maxArgs;  // -1: any number from minArgs on
  const char* doc;
  Emitter emit;
};

Emitter unary(Op op) {
  return [op](ProgramBuilder& b, const std::vector<Slot>& a) { return b.emit(op, a[0]); };
}

const std::map<std::string, Function>& functions() {
  static const std::map<std::string, Function> table = [] {
    std::map<std::string, Function> f;
    f["sin"] = {1, 1, "sine (radians)", unary(Op::Sin)};
    f["cos"] = {1, 1, "cosine", unary(Op::Cos)};
    f["tan"] = {1, 1, "tangent", unary(Op::Tan)};
    f["atan"] = {1, 1, "arc tangent", unary(Op::Atan)};
    f["atan2"] = {2, 2, "atan2(y, x): the angle of the point (x, y)",
                  [](ProgramBuilder& b, const std::vector<Slot>& a) {
                    return b.emit(Op::Atan2, a[0], a[1]);
                  }};
    // asin and acos through atan2: exact on [-1, 1], NaN outside (from the square root)
    f["asin"] = {1, 1, "arc sine", [](ProgramBuilder& b, const std::vector<Slot>& a) {
                   const Slot c = b.sqrt(b.affine(b.sqr(a[0]), a[0], a[0], -1, 0, 0, 1));
                   return b.emit(Op::Atan2, a[0], c);
                 }};
    f["acos"] = {1, 1, "arc cosine", [](ProgramBuilder& b, const std::vector<Slot>& a) {
                   const Slot s = b.sqrt(b.affine(b.sqr(a[0]), a[0], a[0], -1, 0, 0, 1));
                   return b.emit(Op::Atan2, s, a[0]);
                 }};
    f["sinh"] = {1, 1, "hyperbolic sine", [](ProgramBuilder& b, const std::vector<Slot>& a) {
                   const Slot e = b.emit(Op::Exp, a[0]), m = b.emit(Op::Exp, b.neg(a[0]));
                   return b.affine(e, m, m, 0.5, -0.5, 0, 0);
                 }};
    f["cosh"] = {1, 1, "hyperbolic cosine", [](ProgramBuilder& b, const std::vector<Slot>& a) {
                   const Slot e = b.emit(Op::Exp, a[0]), m = b.emit(Op::Exp, b.neg(a[0]));
                   return b.affine(e, m, m, 0.5, 0.5, 0, 0);
                 }};
    f["tanh"] = {1, 1, "hyperbolic tangent", [](ProgramBuilder& b, const std::vector<Slot>& a) {
                   // 1 - 2 / (e^(2a) + 1): no overflow to inf/inf for large |a|
                   const Slot e = b.emit(Op::Exp, b.affine(a[0], a[0], a[0], 2, 0, 0, 0));
                   const Slot q = b.div(b.constant(2.0), b.affine(e, e, e, 1, 0, 0, 1));
                   return b.affine(q, q, q, -1, 0, 0, 1);
                 }};
    f["exp"] = {1, 1, "e to the power", unary(Op::Exp)};
    f["log"] = {1, 1, "natural logarithm", unary(Op::Log)};
    f["sqrt"] = {1, 1, "square root", unary(Op::Sqrt)};
    f["sqr"] = {1, 1, "square", unary(Op::Sqr)};
    f["abs"] = {1, 1, "absolute value", unary(Op::Abs)};
    f["floor"] = {1, 1, "largest integer not above", unary(Op::Floor)};
    f["ceil"] = {1, 1, "smallest integer not below",
                 [](ProgramBuilder& b, const std::vector<Slot>& a) {
                   return b.neg(b.emit(Op::Floor, b.neg(a[0])));
                 }};
    f["pow"] = {2, 2, "pow(a, b) = a^b", [](ProgramBuilder& b, const std::vector<Slot>& a) {
                  return emitPow(b, a[0], a[1]);
                }};
    f["mod"] = {2, 2, "mod(a, b) = a - b floor(a/b), the sign of b",
                [](ProgramBuilder& b, const std::vector<Slot>& a) {
                  return b.sub(a[0], b.mul(a[1], b.emit(Op::Floor, b.div(a[0], a[1]))));
                }};
    f["min"] = {2, -1, "smallest argument (intersection)",
                [](ProgramBuilder& b, const std::vector<Slot>& a) {
                  Slot r = a[0];
                  for (std::size_t i = 1; i < a.size(); ++i) r = b.min(r, a[i]);
                  return r;
                }};
    f["max"] = {2, -1, "largest argument (union)",
                [](ProgramBuilder& b, const std::vector<Slot>& a) {
                  Slot r = a[0];
                  for (std::size_t i = 1; i < a.size(); ++i) r = b.max(r, a[i]);
                  return r;
                }};
    f["clamp"] = {3, 3, "clamp(v, lo, hi)", [](ProgramBuilder& b, const std::vector<Slot>& a) {
                    return b.min(b.max(a[0], a[1]), a[2]);
                  }};
    f["hypot"] = {2, 3, "hypot(a, b[, c]) = sqrt(a^2 + b^2 [+ c^2])",
                  [](ProgramBuilder& b, const std::vector<Slot>& a) {
                    return a.size() == 2 ? b.length2(a[0], a[1]) : b.length3(a[0], a[1], a[2]);
                  }};
    return f;
  }();
  return table;
}

bool isNameStart(char c) {
  return std::isalpha(static_cast<unsigned char>(c)) || c == '_';
}
bool isNameChar(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
}

struct Token {
  enum Kind { Number, Name, Symbol, End } kind;
  std::string text;
  double value = 0.0;
  int column = 0;  // 1-based
};

std::vector<Token> tokenize(const std::string& s) {
  std::vector<Token> out;
  std::size_t i = 0;
  while (i < s.size()) {
    const char c = s[i];
    const int col = static_cast<int>(i) + 1;
    if (std::isspace(static_cast<unsigned char>(c))) {
      ++i;
    } else if (std::isdigit(static_cast<unsigned char>(c)) ||
               (c == '.' && i + 1 < s.size() &&
                std::isdigit(static_cast<unsigned char>(s[i + 1])))) {
      const char* start = s.c_str() + i;
      char* end = nullptr;
      const double v = std::strtod(start, &end);
      const std::size_t len = static_cast<std::size_t>(end - start);
      if (len < s.size() - i && isNameStart(s[i + len]) && s[i + len] != 'e' && s[i + len] != 'E')
        throw FormulaError(col + static_cast<int>(len),
                           "a number is followed by a name; write '*' to multiply");
      out.push_back({Token::Number, s.substr(i, len), v, col});
      i += len;
    } else if (isNameStart(c)) {
      std::size_t j = i;
      while (j < s.size() && isNameChar(s[j])) ++j;
      out.push_back({Token::Name, s.substr(i, j - i), 0.0, col});
      i = j;
    } else if (c == '*' && i + 1 < s.size() && s[i + 1] == '*') {
      out.push_back({Token::Symbol, "^", 0.0, col});
      i += 2;
    } else if (std::string("+-*/^(),").find(c) != std::string::npos) {
      out.push_back({Token::Symbol, std::string(1, c), 0.0, col});
      ++i;
    } else {
      throw FormulaError(col, std::string("unexpected character '") + c +
                                  "'; a formula uses numbers, names, + - * / ^, "
                                  "parentheses and commas");
    }
  }
  out.push_back({Token::End, "", 0.0, static_cast<int>(s.size()) + 1});
  return out;
}

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

}  // namespace

std::string formulaFunctionList() {
  std::vector<std::string> names;
  for (const auto& kv : functions()) names.push_back(kv.first);
  return joined(names);
}

class FormulaParser {
 public:
  FormulaParser(const std::string& text, const std::vector<std::string>& names)
      : tokens_(tokenize(text)), names_(names) {}

  Formula run() {
    if (tokens_.front().kind == Token::End) throw FormulaError(1, "the formula is empty");
    f_.root_ = expr();
    const Token& t = peek();
    if (t.kind != Token::End) {
      if (t.text == ")") throw FormulaError(t.column, "unmatched ')'");
      throw FormulaError(t.column, "unexpected '" + t.text + "' after a complete expression" +
                                       (t.kind == Token::Symbol ? "" : "; missing an operator?"));
    }
    return std::move(f_);
  }

 private:
  const Token& peek() const { return tokens_[pos_]; }
  bool accept(const char* symbol) {
    if (peek().kind == Token::Symbol && peek().text == symbol) {
      ++pos_;
      return true;
    }
    return false;
  }
  int add(Formula::Expr e) {
    f_.nodes_.push_back(std::move(e));
    return static_cast<int>(f_.nodes_.size()) - 1;
  }
  int binary(Formula::Expr::Kind k, int a, int b) { return add({k, 0.0, "", {a, b}}); }

  // A left-associative chain: next { (op1 | op2) next }.
  int chain(const char* op1, Formula::Expr::Kind k1, const char* op2, Formula::Expr::Kind k2,
            int (FormulaParser::*next)()) {
    int left = (this->*next)();
    for (;;) {
      if (accept(op1))
        left = binary(k1, left, (this->*next)());
      else if (accept(op2))
        left = binary(k2, left, (this->*next)());
      else
        return left;
    }
  }
  // Parentheses, signs and powers recurse: their nesting is limited, so a hostile formula
  // (a million '(') is an error, not a stack overflow.
  struct Nesting {
    explicit Nesting(FormulaParser& p) : p_(p) {
      if (++p_.depth_ > kMaxFormulaNesting)
        throw FormulaError(p_.peek().column,
                           "nested deeper than " + std::to_string(kMaxFormulaNesting) +
                               " levels (parentheses, signs, powers and calls)");
    }
    ~Nesting() { --p_.depth_; }
    FormulaParser& p_;
  };
  int expr() {
    Nesting guard(*this);
    return chain("+", Formula::Expr::Add, "-", Formula::Expr::Sub, &FormulaParser::term);
  }
  int term() {
    return chain("*", Formula::Expr::Mul, "/", Formula::Expr::Div, &FormulaParser::unaryExpr);
  }
  int unaryExpr() {
    Nesting guard(*this);
    if (accept("-")) return add({Formula::Expr::Neg, 0.0, "", {unaryExpr()}});
    if (accept("+")) return unaryExpr();
    return power();
  }
  int power() {
    const int base = primary();
    if (accept("^")) return binary(Formula::Expr::Pow, base, unaryExpr());
    return base;
  }
  int primary() {
    const Token t = peek();
    if (t.kind == Token::Number) {
      ++pos_;
      return add({Formula::Expr::Number, t.value, "", {}});
    }
    if (t.kind == Token::Name) {
      ++pos_;
      if (accept("(")) return call(t);
      if (functions().count(t.text))
        throw FormulaError(t.column,
                           "'" + t.text + "' is a function; call it as " + t.text + "(...)");
      if (t.text == "pi") return add({Formula::Expr::Number, kPiValue, "", {}});
      const bool known = t.text == "x" || t.text == "y" || t.text == "z" ||
                         std::find(names_.begin(), names_.end(), t.text) != names_.end();
      if (!known) {
        std::vector<std::string> all = {"x", "y", "z", "pi"};
        all.insert(all.end(), names_.begin(), names_.end());
        throw FormulaError(t.column, "unknown name '" + t.text + "'; names: " + joined(all));
      }
      return add({Formula::Expr::Name, 0.0, t.text, {}});
    }
    if (accept("(")) {
      const int inner = expr();
      if (!accept(")"))
        throw FormulaError(peek().column,
                           "missing ')' (opened at column " + std::to_string(t.column) + ")");
      return inner;
    }
    if (t.kind == Token::End)
      throw FormulaError(t.column, "the formula ends where a value is expected");
    throw FormulaError(t.column, "expected a value, got '" + t.text + "'");
  }
  int call(const Token& name) {
    auto it = functions().find(name.text);
    if (it == functions().end())
      throw FormulaError(
          name.column, "unknown function '" + name.text + "'; functions: " + formulaFunctionList());
    std::vector<int> args;
    if (!accept(")")) {
      do args.push_back(expr());
      while (accept(","));
      if (!accept(")"))
        throw FormulaError(peek().column, "missing ')' or ',' in the call of '" + name.text + "'");
    }
    const Function& fn = it->second;
    const int n = static_cast<int>(args.size());
    if (n < fn.minArgs || (fn.maxArgs >= 0 && n > fn.maxArgs)) {
      const std::string want = fn.maxArgs < 0             ? std::to_string(fn.minArgs) + " or more"
                               : fn.minArgs == fn.maxArgs ? std::to_string(fn.minArgs)
                                                          : std::to_string(fn.minArgs) + " or " +
                                                                std::to_string(fn.maxArgs);
      throw FormulaError(name.column, "'" + name.text + "' takes " + want + " argument" +
                                          (want == "1" ? "" : "s") + ", got " + std::to_string(n));
    }
    return add({Formula::Expr::Call, 0.0, name.text, args});
  }

  std::vector<Token> tokens_;
  const std::vector<std::string>& names_;
  std::size_t pos_ = 0;
  int depth_ = 0;
  Formula f_;
};

Formula Formula::parse(const std::string& text, const std::vector<std::string>& names) {
  return FormulaParser(text, names).run();
}

bool Formula::uses(const std::string& name) const {
  for (const Expr& e : nodes_)
    if (e.kind == Expr::Name && e.name == name) return true;
  return false;
}

Slot Formula::emit(ProgramBuilder& b, Slot x, Slot y, Slot z,
                   const std::function<Slot(const std::string&)>& name) const {
  return emitNode(root_, b, x, y, z, name);
}

// Iterative, not recursive: a node's operands are always made before it (lower indices), so
// one pass in order emits every node after its operands, whatever the depth of the formula
// (a sum of a million terms is a chain a million deep).
Slot Formula::emitNode(int root, ProgramBuilder& b, Slot x, Slot y, Slot z,
                       const std::function<Slot(const std::string&)>& name) const {
  std::vector<Slot> slots(nodes_.size(), 0);
  for (std::size_t i = 0; i <= static_cast<std::size_t>(root); ++i)
    slots[i] = emitOne(nodes_[i], slots, b, x, y, z, name);
  return slots[static_cast<std::size_t>(root)];
}

Slot Formula::emitOne(const Expr& e, const std::vector<Slot>& slots, ProgramBuilder& b, Slot x,
                      Slot y, Slot z, const std::function<Slot(const std::string&)>& name) const {
  std::vector<Slot> a;
  for (int arg : e.args) a.push_back(slots[static_cast<std::size_t>(arg)]);
  switch (e.kind) {
    case Expr::Number:
      return b.constant(e.value);
    case Expr::Name:
      if (e.name == "x") return x;
      if (e.name == "y") return y;
      if (e.name == "z") return z;
      return name(e.name);
    case Expr::Call:
      return functions().at(e.name).emit(b, a);
    case Expr::Neg:
      return b.neg(a[0]);
    case Expr::Add:
      return b.add(a[0], a[1]);
    case Expr::Sub:
      return b.sub(a[0], a[1]);
    case Expr::Mul:
      return b.mul(a[0], a[1]);
    case Expr::Div:
      return b.div(a[0], a[1]);
    case Expr::Pow:
      return emitPow(b, a[0], a[1]);
  }
  return b.constant(0.0);
}

std::vector<FormulaParameter> parseFormulaParameters(const std::string& text) {
  std::vector<FormulaParameter> out;
  std::vector<std::string> names;
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find_first_of(",;\n", start);
    if (end == std::string::npos) end = text.size();
    const std::string entry = text.substr(start, end - start);
    const int base = static_cast<int>(start);  // columns of the entry are offset by this
    const std::size_t first = entry.find_first_not_of(" \t\r");
    if (first != std::string::npos) {
      const std::size_t eq = entry.find('=');
      if (eq == std::string::npos)
        throw FormulaError(base + static_cast<int>(first) + 1,
                           "expected 'name = value' (entries are separated by commas)");
      std::size_t nameEnd = eq;
      while (nameEnd > first && std::isspace(static_cast<unsigned char>(entry[nameEnd - 1])))
        --nameEnd;
      const std::string name = entry.substr(first, nameEnd - first);
      const int nameCol = base + static_cast<int>(first) + 1;
      if (name.empty() || !isNameStart(name[0]) ||
          !std::all_of(name.begin(), name.end(), isNameChar))
        throw FormulaError(nameCol, "'" + name +
                                        "' is not a name (letters, digits and _, "
                                        "starting with a letter)");
      if (name == "x" || name == "y" || name == "z" || name == "pi" || functions().count(name))
        throw FormulaError(nameCol, "'" + name + "' is reserved (x, y, z, pi and the functions)");
      if (std::find(names.begin(), names.end(), name) != names.end())
        throw FormulaError(nameCol, "'" + name + "' is defined twice");
      const std::string valueText = entry.substr(eq + 1);
      Formula f;
      try {
        f = Formula::parse(valueText, names);
      } catch (const FormulaError& e) {
        throw FormulaError(base + static_cast<int>(eq) + 1 + e.column, e.what());
      }
      if (f.uses("x") || f.uses("y") || f.uses("z"))
        throw FormulaError(base + static_cast<int>(eq) + 2,
                           "the value of '" + name + "' must be a constant, not use x, y or z");
      ProgramBuilder b;
      const Slot v = f.emit(b, b.x(), b.y(), b.z(), [&](const std::string& n) {
        for (const auto& p : out)
          if (p.name == n) return b.constant(p.value);
        return b.constant(0.0);
      });
      const double value = b.constantValue(v);
      if (!std::isfinite(value))
        throw FormulaError(base + static_cast<int>(eq) + 2,
                           "the value of '" + name + "' is not a finite number");
      out.push_back({name, value});
      names.push_back(name);
    }
    start = end + 1;
  }
  return out;
}

std::string formulaCaret(const std::string& text, int column) {
  // only the line holding the column, so a multi-line parameter list stays readable
  std::size_t lineStart = 0, pos = static_cast<std::size_t>(std::max(column, 1) - 1);
  pos = std::min(pos, text.size());
  const std::size_t nl = text.rfind('\n', pos == 0 ? 0 : pos - 1);
  if (nl != std::string::npos && nl < pos) lineStart = nl + 1;
  std::size_t lineEnd = text.find('\n', lineStart);
  if (lineEnd == std::string::npos) lineEnd = text.size();
  return "  " + text.substr(lineStart, lineEnd - lineStart) + "\n  " +
         std::string(pos - lineStart, ' ') + "^";
}

}  // namespace frep
