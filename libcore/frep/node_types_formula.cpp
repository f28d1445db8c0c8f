// The formula node: a solid (or an operation on its inputs) written as a user formula.
#include <string>
#include <vector>

#include "base/errors.h"
#include "frep/formula.h"
#include "frep/registry.h"
#include "frep/tree.h"

namespace frep {

namespace {

std::vector<std::string> inputNames(std::size_t count) {
  std::vector<std::string> names;
  for (std::size_t i = 1; i <= count; ++i) names.push_back("f" + std::to_string(i));
  return names;
}

std::string located(const std::string& param, const std::string& text, const FormulaError& e) {
  return "parameter '" + param + "' column " + std::to_string(e.column) + ": " + e.what() + "\n" +
         formulaCaret(text, e.column);
}

struct ParsedFormula {
  std::vector<FormulaParameter> parameters;
  Formula formula;
};

// Parses both texts of a formula node; throws ModelError with the located message.
ParsedFormula parseNode(const Node& n) {
  ParsedFormula out;
  const std::string& paramText = n.param("parameters").text;
  try {
    out.parameters = parseFormulaParameters(paramText);
  } catch (const FormulaError& e) {
    throw ModelError(located("parameters", paramText, e));
  }
  std::vector<std::string> names;
  for (const auto& p : out.parameters) {
    if (p.name.size() > 1 && p.name[0] == 'f' &&
        p.name.find_first_not_of("0123456789", 1) == std::string::npos)
      throw ModelError("parameter 'parameters': '" + p.name +
                       "' is reserved for the inputs (f1, f2, ...)");
    names.push_back(p.name);
  }
  const std::vector<std::string> inputs = inputNames(n.inputs.size());
  names.insert(names.end(), inputs.begin(), inputs.end());
  const std::string& text = n.param("formula").text;
  try {
    out.formula = Formula::parse(text, names);
  } catch (const FormulaError& e) {
    std::string message = located("formula", text, e);
    if (std::string(e.what()).find("unknown name 'f") != std::string::npos)
      message +=
          "\n  (f1, f2, ... are the inputs; this node has " + std::to_string(n.inputs.size()) + ")";
    throw ModelError(message);
  }
  return out;
}

}  // namespace

void registerFormula(Registry& r) {
  r.add({"formula",
         "formula",
         "A solid written as a formula in x, y, z: F >= 0 inside. Named parameters are set in "
         "`parameters` (\"r = 1, k = 2 pi\"); the node's inputs are the fields f1, f2, ... so a "
         "formula can also combine solids (max(f1, f2) is their union). Functions: " +
             formulaFunctionList() +
             "; operators + - * / ^ (also **). Parsed once and compiled like every node, so it "
             "meshes at full speed with interval pruning and exact normals. A parse error names "
             "the column.",
         "F = the formula",
         0,
         kVariadic,
         {textParam("formula", "r - sqrt(x^2 + y^2 + z^2) + a*sin(k*x)*sin(k*y)*sin(k*z)",
                    "The function of x, y, z (and of the parameters and inputs f1, f2, ...); "
                    "positive inside."),
          textParam("parameters", "r = 1, a = 0.08, k = 8",
                    "Named constants, 'name = value' separated by commas; a value may use pi "
                    "and earlier parameters.")},
         [](CompileContext& c) {
           const ParsedFormula f = parseNode(c.node());
           return f.formula.emit(c.b, c.p.x, c.p.y, c.p.z, [&](const std::string& name) -> Slot {
             for (const auto& p : f.parameters)
               if (p.name == name) return c.b.constant(p.value);
             return c.input(std::stoi(name.substr(1)) - 1);  // f1, f2, ...
           });
         },
         nullptr,
         [](const Node& n) -> std::string {
           try {
             parseNode(n);
           } catch (const ModelError& e) {
             return e.what();
           }
           return "";
         }});
}

}  // namespace frep
