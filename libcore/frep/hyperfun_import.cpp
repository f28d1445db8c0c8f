#include "frep/hyperfun_import.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>

#include "base/errors.h"
#include "base/file_names.h"
#include "frep/hyperfun_expr.h"
#include "frep/hyperfun_library.h"
#include "frep/hyperfun_syntax.h"

namespace frep {

namespace hyperfun {

namespace {

constexpr double kEps = 1e-6;                // HyperFun's zero in conditions
constexpr std::size_t kMostSteps = 1000000;  // statements one program may run
constexpr std::size_t kMostFormulaChars = 1000000;

struct Variable {
  bool isArray = false;
  ExprPtr scalar;
  std::vector<ExprPtr> items;  // an array's; null: not given a value yet
};

// Runs a body with the point symbolic (hyperfun_expr.h).
class Evaluator {
 public:
  Evaluator(const Program& program, ExprBuilder& b) : program_(program), b_(b) {}

  // `point`: the body's x; `parameters`: its a (null items: given from outside).
  ExprPtr run(const Body& body, std::vector<ExprPtr> point, std::vector<ExprPtr> parameters) {
    if (body.coordinates != 3) {
      b_.at(body.at);
      b_.fail(body.name + " is a model in " + std::to_string(body.coordinates) + " dimensions (x[" +
              std::to_string(body.coordinates) + "]); FRepCAD's models are 3D: x[3]");
    }
    Frame f;
    f.body = &body;
    f.vars["x"] = {true, nullptr, std::move(point)};
    parameters.resize(static_cast<std::size_t>(body.parameters));
    f.vars["a"] = {true, nullptr, std::move(parameters)};
    for (const ArrayDeclaration& d : body.arrays) {
      b_.at(d.at);
      if (d.name == "x" || d.name == "a" || d.name == "s")
        b_.fail("'" + d.name + "' is HyperFun's own array; name yours otherwise");
      f.vars[d.name] = {true, nullptr, std::vector<ExprPtr>(static_cast<std::size_t>(d.size))};
    }
    execute(body.statements, f);
    const ExprPtr result = value(*body.result, f);
    if (!ExprBuilder::isConstant(result)) names.emplace(result.get(), body.name);
    return result;
  }

  // The variable (or body) each value was first given to: its feature's label.
  std::map<const Expr*, std::string> names;

 private:
  struct Frame {
    const Body* body = nullptr;
    std::map<std::string, Variable> vars;
  };

  void step(Location at) {
    if (++steps_ > kMostSteps) {
      b_.at(at);
      b_.fail("the program runs more than " + std::to_string(kMostSteps) +
              " statements (a loop that does not end?)");
    }
  }

  // Item `index` (a HyperFun index, from 1) of an array, checked.
  std::size_t slot(const Variable& v, const std::string& name, const ExprPtr& index) {
    const double i = std::floor(b_.constantOf(index, "the index of " + name) + 0.5);
    if (i < 1 || i > static_cast<double>(v.items.size()))
      b_.fail("index " + std::to_string(static_cast<long long>(i)) + " is out of range for " +
              name + "[1.." + std::to_string(v.items.size()) + "]");
    return static_cast<std::size_t>(i) - 1;
  }

  Variable& arrayNamed(const std::string& name, Frame& f) {
    const auto it = f.vars.find(name);
    if (it == f.vars.end() || !it->second.isArray)
      b_.fail("'" + name + "' is not an array (declare it: array " + name + "[N];)");
    return it->second;
  }

  void execute(const std::vector<Statement>& list, Frame& f) {
    for (const Statement& s : list) {
      step(s.at);
      b_.at(s.at);
      if (s.name == "s") continue;  // attributes (colours): not shape
      switch (s.kind) {
        case Statement::Kind::Assign: {
          if (s.name == "x" || s.name == "a")
            b_.fail("'" + s.name + "' is HyperFun's own array and cannot be assigned");
          const auto it = f.vars.find(s.name);
          if (it != f.vars.end() && it->second.isArray)
            b_.fail("'" + s.name + "' is an array: give it [numbers] or assign " + s.name + "[i]");
          const ExprPtr v = value(*s.value, f);
          if (!ExprBuilder::isConstant(v)) names.emplace(v.get(), s.name);  // the first name
          f.vars[s.name] = {false, v, {}};
          break;
        }
        case Statement::Kind::AssignElement: {
          if (s.name == "x" || s.name == "a")
            b_.fail("'" + s.name + "' is HyperFun's own array; copy it into an array of your own");
          Variable& v = arrayNamed(s.name, f);
          const ExprPtr index = value(*s.index, f);
          b_.at(s.at);
          const std::size_t i = slot(v, s.name, index);
          v.items[i] = value(*s.value, f);
          break;
        }
        case Statement::Kind::AssignArray: {
          Variable& v = arrayNamed(s.name, f);
          if (s.numbers.size() != v.items.size())
            b_.fail(s.name + " has " + std::to_string(v.items.size()) + " items; " +
                    std::to_string(s.numbers.size()) + " numbers given");
          for (std::size_t i = 0; i < s.numbers.size(); ++i) v.items[i] = b_.constant(s.numbers[i]);
          break;
        }
        case Statement::Kind::If:
          execute(truth(*s.value, f) ? s.body : s.otherwise, f);
          break;
        case Statement::Kind::While:
          while (truth(*s.value, f)) {
            step(s.at);
            execute(s.body, f);
          }
          break;
      }
    }
  }

  // A condition, as HyperFun decides it: a value is true when it is not 0.
  bool truth(const Ast& a, Frame& f) { return std::fabs(conditionValue(a, f)) >= kEps; }

  double conditionValue(const Ast& a, Frame& f) {
    if (a.kind == Ast::Kind::Unary && a.text == "not") return truth(*a.args[0], f) ? 0.0 : 1.0;
    if (a.kind == Ast::Kind::Binary) {
      const std::string& op = a.text;
      if (op == "and") return truth(*a.args[0], f) && truth(*a.args[1], f) ? 1.0 : 0.0;
      if (op == "or") return truth(*a.args[0], f) || truth(*a.args[1], f) ? 1.0 : 0.0;
      if (op == "<" || op == "<=" || op == ">" || op == ">=" || op == "=" || op == "/=") {
        const double l = conditionValue(*a.args[0], f), r = conditionValue(*a.args[1], f);
        if (op == "<") return l < r;
        if (op == "<=") return l <= r;
        if (op == ">") return l > r;
        if (op == ">=") return l >= r;
        if (op == "=") return std::fabs(l - r) < kEps;
        return std::fabs(l - r) >= kEps;
      }
    }
    const ExprPtr v = value(a, f);
    b_.at(a.at);
    return b_.constantOf(v, "this condition");
  }

  ExprPtr value(const Ast& a, Frame& f) {
    b_.at(a.at);
    switch (a.kind) {
      case Ast::Kind::Number:
        return b_.constant(a.number);
      case Ast::Kind::Name:
        return named(a, f);
      case Ast::Kind::Element:
        return element(a, f);
      case Ast::Kind::Call:
        return call(a, f);
      case Ast::Kind::Unary: {
        const ExprPtr v = value(*a.args[0], f);
        b_.at(a.at);
        if (a.text == "neg") return b_.neg(v);
        if (a.text == "~") return b_.complement(v);
        if (a.text == "pos") return v;
        b_.fail("'" + a.text + "' belongs in a condition (if ... then, while ... loop)");
      }
      case Ast::Kind::Binary: {
        const ExprPtr l = value(*a.args[0], f);
        const ExprPtr r = value(*a.args[1], f);
        b_.at(a.at);
        const std::string& op = a.text;
        if (op == "+") return b_.add(l, r);
        if (op == "-") return b_.sub(l, r);
        if (op == "*") return b_.mul(l, r);
        if (op == "/") return b_.div(l, r);
        if (op == "^") return b_.pow(l, r);
        if (op == "|") return b_.setOperation(Expr::Kind::Union, l, r);
        if (op == "&") return b_.setOperation(Expr::Kind::Intersection, l, r);
        if (op == "\\") return b_.setOperation(Expr::Kind::Difference, l, r);
        if (op == "@")
          b_.fail(
              "the Cartesian product @ makes a model of more dimensions; FRepCAD's models "
              "are 3D");
        b_.fail("'" + op + "' belongs in a condition (if ... then, while ... loop)");
      }
    }
    return nullptr;
  }

  ExprPtr named(const Ast& a, Frame& f) {
    const auto it = f.vars.find(a.text);
    if (it == f.vars.end()) {
      if (findBody(a.text)) b_.fail("'" + a.text + "' is a body; call it as " + a.text + "(x, a)");
      b_.fail("'" + a.text + "' is used before it is given a value");
    }
    if (it->second.isArray) b_.fail("'" + a.text + "' is an array; use " + a.text + "[i]");
    return it->second.scalar;
  }

  ExprPtr element(const Ast& a, Frame& f) {
    if (a.text == "s") b_.fail("s[...] holds attributes (colours), which FRepCAD does not read");
    const auto it = f.vars.find(a.text);
    if (it == f.vars.end() || !it->second.isArray)
      b_.fail("'" + a.text + "' is not an array (declare it: array " + a.text + "[N];)");
    const ExprPtr index = value(*a.args[0], f);
    b_.at(a.at);
    const std::size_t i = slot(it->second, a.text, index);
    const ExprPtr& v = it->second.items[i];
    if (!v) {
      if (a.text == "a")
        b_.fail("a[" + std::to_string(i + 1) +
                "] is a parameter given to HyperFun from outside; FRepCAD is given none: "
                "write the value into the program");
      b_.fail(a.text + "[" + std::to_string(i + 1) + "] is used before it is given a value");
    }
    return v;
  }

  const Body* findBody(const std::string& name) const {
    for (const Body& body : program_.bodies)
      if (body.name == name) return &body;
    return nullptr;
  }

  ExprPtr call(const Ast& a, Frame& f) {
    if (ExprBuilder::isFunction(a.text)) {
      std::vector<ExprPtr> args;
      for (const AstPtr& arg : a.args) args.push_back(value(*arg, f));
      b_.at(a.at);
      return b_.function(a.text, args);
    }
    std::string unsupported;
    const std::string kinds = libraryArguments(a.text, &unsupported);
    if (!unsupported.empty()) b_.fail(unsupported);
    if (!kinds.empty()) return library(a, kinds, f);
    if (const Body* callee = findBody(a.text)) return callBody(a, *callee, f);
    b_.fail("unknown function '" + a.text + "'");
  }

  ExprPtr library(const Ast& a, const std::string& kinds, Frame& f) {
    if (a.args.size() != kinds.size())
      b_.fail(a.text + " takes " + std::to_string(kinds.size()) + " arguments, not " +
              std::to_string(a.args.size()));
    std::vector<LibraryArgument> args(kinds.size());
    for (std::size_t i = 0; i < kinds.size(); ++i) {
      const Ast& arg = *a.args[i];
      if (kinds[i] == 'A') {
        b_.at(arg.at);
        if (arg.kind != Ast::Kind::Name)
          b_.fail("argument " + std::to_string(i + 1) + " of " + a.text + " is an array name");
        if (arg.text == "a")
          b_.fail(
              "a holds parameters given to HyperFun from outside; FRepCAD is given none: "
              "pass an array of your own");
        args[i].array = &arrayNamed(arg.text, f).items;
        args[i].name = arg.text;
      } else {
        args[i].value = value(arg, f);
      }
    }
    b_.at(a.at);
    return callLibrary(a.text, args, b_);
  }

  ExprPtr callBody(const Ast& a, const Body& callee, Frame& f) {
    if (&callee == f.body || &callee > f.body)
      b_.fail(a.text + " is called before it is defined (a body may call the bodies above it)");
    if (a.args.size() < 2 || a.args.size() > 3)
      b_.fail(a.text + " is called with its arrays: " + a.text + "(x, a)");
    std::vector<ExprPtr> arrays[2];
    for (int k = 0; k < 2; ++k) {
      const Ast& arg = *a.args[static_cast<std::size_t>(k)];
      b_.at(arg.at);
      if (arg.kind != Ast::Kind::Name)
        b_.fail("argument " + std::to_string(k + 1) + " of " + a.text + " is an array name");
      arrays[k] = arrayNamed(arg.text, f).items;
    }
    b_.at(a.at);
    if (arrays[0].size() != static_cast<std::size_t>(callee.coordinates))
      b_.fail(a.text + " takes a point of " + std::to_string(callee.coordinates) +
              " coordinates; the array given has " + std::to_string(arrays[0].size()));
    for (std::size_t i = 0; i < arrays[0].size(); ++i)
      if (!arrays[0][i]) b_.fail("the point given to " + a.text + " has items without a value");
    const Location back = b_.where();
    ExprPtr result = run(callee, arrays[0], arrays[1]);
    b_.at(back);
    return result;
  }

  const Program& program_;
  ExprBuilder& b_;
  std::size_t steps_ = 0;
};

// Symbolic values as FRep nodes.
class Emitter {
 public:
  Emitter(ExprBuilder& b, std::string path, const std::map<const Expr*, std::string>& names,
          std::map<const Node*, std::string>& labels)
      : b_(b), path_(std::move(path)), names_(names), labels_(labels) {}

  NodePtr solid(const ExprPtr& e) {
    const auto found = made_.find(e.get());
    if (found != made_.end()) return found->second;
    NodePtr n;
    switch (e->kind) {
      case Expr::Kind::Union:
      case Expr::Kind::Intersection:
      case Expr::Kind::Difference:
        n = setOperation(e);
        break;
      case Expr::Kind::Complement:
        n = makeNode("complement", {}, {solid(e->args[0])}, path_);
        break;
      case Expr::Kind::BlendUnion:
      case Expr::Kind::BlendIntersection:
        n = blend(e);
        break;
      case Expr::Kind::Primitive:
        n = formula(e->args[0]);
        break;
      default:
        n = formula(e);
        break;
    }
    made_[e.get()] = n;
    const auto name = names_.find(e.get());
    if (name != names_.end())
      labels_.emplace(n.get(), name->second);
    else if (e->kind == Expr::Kind::Primitive)
      labels_.emplace(n.get(), e->label);
    return n;
  }

 private:
  // A chain a | b | c (from the left) is one variadic node: HyperFun's left-to-right order is
  // the node's fold (node_types_setops.cpp).
  NodePtr setOperation(const ExprPtr& e) {
    std::vector<ExprPtr> operands;
    ExprPtr at = e;
    while (at->kind == e->kind && made_.find(at.get()) == made_.end()) {
      operands.push_back(at->args[1]);
      at = at->args[0];
    }
    operands.push_back(at);
    std::vector<NodePtr> inputs;
    for (auto it = operands.rbegin(); it != operands.rend(); ++it) inputs.push_back(solid(*it));
    const char* type = e->kind == Expr::Kind::Union          ? "union"
                       : e->kind == Expr::Kind::Intersection ? "intersection"
                                                             : "difference";
    return makeNode(type, {{"alpha", realValue(0.0)}}, std::move(inputs), path_);
  }

  NodePtr blend(const ExprPtr& e) {
    const char* type = e->kind == Expr::Kind::BlendUnion ? "blend_union" : "blend_intersection";
    return makeNode(type,
                    {{"a0", realValue(e->blend[0])},
                     {"a1", realValue(std::fabs(e->blend[1]))},
                     {"a2", realValue(std::fabs(e->blend[2]))},
                     {"alpha", realValue(0.0)}},
                    {solid(e->args[0]), solid(e->args[1])}, path_);
  }

  NodePtr formula(const ExprPtr& e) {
    Rendering r;
    int precedence = 0;
    const std::string text = render(e, r, precedence);
    return makeNode("formula", {{"formula", textValue(text)}, {"parameters", textValue("")}},
                    std::move(r.inputs), path_);
  }

  struct Rendering {
    std::vector<NodePtr> inputs;
    std::map<const Expr*, std::size_t> inputOf;
    std::size_t length = 0;
  };

  // The shortest text that reads back as the same double.
  static std::string number(double v) {
    char buffer[40];
    for (int digits = 15; digits <= 17; ++digits) {
      std::snprintf(buffer, sizeof buffer, "%.*g", digits, v);
      if (std::strtod(buffer, nullptr) == v) break;
    }
    return buffer;
  }

  // Text of `e` in the formula language with as few parentheses as its parser needs;
  // `precedence` says how it binds: 1 sum, 2 product, 3 sign, 4 power, 5 a single value.
  // r.length: the characters of the formula written so far (a node's text replaces its
  // parts', which counted while they were written), checked as it grows so that a tree
  // whose text would explode is refused before it is built.
  std::string render(const ExprPtr& e, Rendering& r, int& precedence) {
    const std::size_t before = r.length;
    std::string out = renderOnce(e, r, precedence);
    r.length = before + out.size();
    if (r.length > kMostFormulaChars)
      b_.fail("a formula of the model is longer than " + std::to_string(kMostFormulaChars) +
              " characters (many nested transformations?)");
    return out;
  }
  std::string operand(const ExprPtr& e, Rendering& r, int atLeast) {
    int p = 0;
    std::string s = render(e, r, p);
    return p < atLeast ? "(" + s + ")" : s;
  }
  std::string renderOnce(const ExprPtr& e, Rendering& r, int& precedence) {
    precedence = 5;
    if (ExprBuilder::isSolid(e)) {  // a solid inside arithmetic: an input of the formula
      const auto found = r.inputOf.find(e.get());
      std::size_t k = 0;
      if (found != r.inputOf.end()) {
        k = found->second;
      } else {
        r.inputs.push_back(solid(e));
        k = r.inputs.size();
        r.inputOf[e.get()] = k;
      }
      return "f" + std::to_string(k);
    }
    switch (e->kind) {
      case Expr::Kind::Constant:
        if (e->value < 0.0) precedence = 3;
        return number(e->value);
      case Expr::Kind::Coordinate:
        return std::string(1, "xyz"[e->axis]);
      case Expr::Kind::Function: {
        std::string s = e->op + "(";
        for (std::size_t i = 0; i < e->args.size(); ++i) {
          int p = 0;
          s += (i ? ", " : "") + render(e->args[i], r, p);
        }
        return s + ")";
      }
      case Expr::Kind::Operator: {
        const std::string& op = e->op;
        if (op == "neg") {
          precedence = 3;
          return "-" + operand(e->args[0], r, 3);
        }
        if (op == "^") {
          precedence = 4;
          return operand(e->args[0], r, 5) + "^" + operand(e->args[1], r, 3);
        }
        const bool sum = op == "+" || op == "-";
        precedence = sum ? 1 : 2;
        const ExprPtr& right = e->args[1];
        if (sum && ExprBuilder::isConstant(right) && right->value < 0.0)  // x - -5 as x + 5
          return operand(e->args[0], r, 1) + (op == "+" ? " - " : " + ") + number(-right->value);
        return operand(e->args[0], r, precedence) + " " + op + " " +
               operand(e->args[1], r, precedence + 1);
      }
      default:
        break;
    }
    return "0";  // (solids are inputs, above)
  }

  ExprBuilder& b_;
  std::string path_;
  const std::map<const Expr*, std::string>& names_;
  std::map<const Node*, std::string>& labels_;
  std::map<const Expr*, NodePtr> made_;
};

const Body& modelBody(const Program& p) {
  for (const Body& b : p.bodies)
    if (b.name == "my_model") return b;
  return p.bodies.back();
}

}  // namespace

}  // namespace hyperfun

bool isHyperFunPath(const std::string& path) {
  return fileExtension(path) == "hf";
}

Model importHyperFun(const std::string& text, const std::string& source) {
  using namespace hyperfun;
  const hyperfun::Program program = parseProgram(text, source);
  const Body& body = modelBody(program);
  ExprBuilder b(source);
  Evaluator evaluator(program, b);
  std::vector<ExprPtr> point = {b.coordinate(0), b.coordinate(1), b.coordinate(2)};
  const ExprPtr result = evaluator.run(body, point, {});
  Model m;
  Emitter emitter(b, source, evaluator.names, m.labels);
  b.at(body.result->at);
  m.root = emitter.solid(result);
  m.description = "HyperFun model " + body.name + " from " + source;
  // HyperFun's polygonizer looks at -10..10 on each axis unless told otherwise: the box its
  // models are made for, used where the solid's extent cannot be proven (a cylinder without
  // ends; polynomial fields that overflow the interval search far away).
  m.fallbackBox = Box3{{-10.0, -10.0, -10.0}, {10.0, 10.0, 10.0}};
  return m;
}

}  // namespace frep
