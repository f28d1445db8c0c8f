#include "frep/registry_docs.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>

namespace frep {

namespace {

nlohmann::json defaultJson(const ParamTemplate& p) {
  switch (p.type) {
    case ParamType::Choice:
    case ParamType::Text:
      return p.defaultValue.text;
    case ParamType::Boolean:
      return p.defaultValue.numbers.at(0) != 0.0;
    case ParamType::Real:
    case ParamType::Integer:
      return p.defaultValue.numbers.at(0);
    case ParamType::Points: {
      nlohmann::json points = nlohmann::json::array();
      for (const Vec3& q : pointsOf(p.defaultValue)) points.push_back({q[0], q[1], q[2]});
      return points;
    }
    default:
      return p.defaultValue.numbers;
  }
}

nlohmann::json toJson(const NodeType& t) {
  nlohmann::json j;
  j["type"] = t.id;
  j["title"] = t.title;
  j["category"] = t.category;
  j["doc"] = t.doc;
  j["formula"] = t.formula;
  j["inputs"] = {
      {"min", t.minInputs},
      {"max", t.maxInputs == kVariadic ? nlohmann::json(nullptr) : nlohmann::json(t.maxInputs)}};
  j["params"] = nlohmann::json::array();
  for (const auto& p : t.params) {
    nlohmann::json pj;
    pj["name"] = p.name;
    pj["title"] = p.title;
    pj["type"] = paramTypeName(p.type);
    pj["default"] = defaultJson(p);
    pj["allowed"] = p.rangeText();
    // The same range as numbers, for programs (null: unbounded on that side).
    auto bound = [](double v) {
      return std::isinf(v) ? nlohmann::json(nullptr) : nlohmann::json(v);
    };
    pj["min"] = bound(p.min);
    pj["max"] = bound(p.max);
    pj["min_exclusive"] = p.minExclusive;
    pj["max_exclusive"] = p.maxExclusive;
    pj["nonzero"] = p.nonZeroVector;
    pj["unit"] = p.unit;
    pj["doc"] = p.doc;
    if (!p.choices.empty()) pj["choices"] = p.choices;
    if (p.type == ParamType::Text) pj["file"] = p.filePath;
    if (p.type == ParamType::Points) {
      pj["path"] = p.path;
      pj["min_points"] = p.minPoints;
      pj["max_points"] = p.maxPoints == std::numeric_limits<std::size_t>::max()
                             ? nlohmann::json(nullptr)
                             : nlohmann::json(p.maxPoints);
      pj["follows"] = p.follows;
    }
    j["params"].push_back(pj);
  }
  return j;
}

}  // namespace

std::string nodeTypeText(const NodeType& t) {
  std::ostringstream os;
  os << t.id << " (" << t.category << ", inputs: " << t.inputsText() << ")\n";
  os << "  " << t.doc << "\n";
  os << "  formula: " << t.formula << "\n";
  for (const auto& p : t.params) {
    os << "  " << p.name << " : " << paramTypeName(p.type) << " = " << p.valueText(p.defaultValue);
    if (!p.unit.empty()) os << " [" << p.unit << "]";
    os << "  allowed: " << p.rangeText() << "\n      " << p.doc << "\n";
  }
  return os.str();
}

std::string nodeTypeJson(const NodeType& t) {
  return toJson(t).dump(2) + "\n";
}

std::string registryJson() {
  nlohmann::json all = nlohmann::json::array();
  for (const NodeType* t : registry().all()) all.push_back(toJson(*t));
  return all.dump(2) + "\n";
}

std::string registryMarkdown() {
  std::ostringstream os;
  os << "# Node reference\n\n"
     << "Generated from the node registry by `frepcad info --markdown`; do not edit by hand "
        "(a test checks it is current).\n\n"
     << "Fields are positive inside the solid: F(p) >= 0. Angles are in degrees.\n\n";
  std::string category;
  for (const NodeType* t : registry().all()) {
    if (t->category != category) {
      category = t->category;
      os << "## " << category << "\n\n";
    }
    os << "### `" << t->id << "`\n\n**" << t->title << ".** " << t->doc << "\n\n";
    os << "Inputs: " << t->inputsText() << ".\n\n";
    os << "```\n" << t->formula << "\n```\n\n";
    if (!t->params.empty()) {
      os << "| parameter | type | default | allowed | unit | meaning |\n"
         << "|---|---|---|---|---|---|\n";
      for (const auto& p : t->params)
        os << "| `" << p.name << "` | " << paramTypeName(p.type) << " | `"
           << p.valueText(p.defaultValue) << "` | " << p.rangeText() << " | "
           << (p.unit.empty() ? "-" : p.unit) << " | "
           << (p.title.empty() ? "" : "**" + p.title + ".** ") << p.doc << " |\n";
      os << "\n";
    }
  }
  return os.str();
}

}  // namespace frep
