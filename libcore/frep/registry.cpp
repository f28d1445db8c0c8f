#include "frep/registry.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <sstream>
#include <utility>

#include "base/affine.h"
#include "base/errors.h"

namespace frep {

const char* paramTypeName(ParamType t) {
  switch (t) {
    case ParamType::Real:
      return "real";
    case ParamType::Integer:
      return "integer";
    case ParamType::Boolean:
      return "boolean";
    case ParamType::Vector3:
      return "vector3";
    case ParamType::Matrix3x4:
      return "matrix3x4";
    case ParamType::Choice:
      return "choice";
    case ParamType::Points:
      return "points";
    case ParamType::Text:
      return "text";
  }
  return "?";
}

std::string numberText(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}

namespace {

ParamTemplate base(std::string name, ParamType type, std::string unit, std::string doc) {
  ParamTemplate p;
  p.name = std::move(name);
  p.type = type;
  p.unit = std::move(unit);
  p.doc = std::move(doc);
  return p;
}

std::size_t expectedCount(ParamType t) {
  switch (t) {
    case ParamType::Vector3:
      return 3;
    case ParamType::Matrix3x4:
      return 12;
    case ParamType::Choice:
    case ParamType::Text:
      return 0;
    default:
      return 1;
  }
}
}  // namespace

ParamTemplate realParam(std::string name, double def, std::string unit, std::string doc) {
  ParamTemplate p = base(std::move(name), ParamType::Real, std::move(unit), std::move(doc));
  p.defaultValue.numbers = {def};
  return p;
}

ParamTemplate intParam(std::string name, int def, std::string doc) {
  ParamTemplate p = base(std::move(name), ParamType::Integer, "", std::move(doc));
  p.defaultValue.numbers = {static_cast<double>(def)};
  return p;
}

ParamTemplate boolParam(std::string name, bool def, std::string doc) {
  ParamTemplate p = base(std::move(name), ParamType::Boolean, "", std::move(doc));
  p.defaultValue.numbers = {def ? 1.0 : 0.0};
  return p;
}

ParamTemplate vec3Param(std::string name, Vec3 def, std::string unit, std::string doc) {
  ParamTemplate p = base(std::move(name), ParamType::Vector3, std::move(unit), std::move(doc));
  p.defaultValue.numbers = {def[0], def[1], def[2]};
  return p;
}

ParamTemplate matrixParam(std::string name, std::string doc) {
  ParamTemplate p = base(std::move(name), ParamType::Matrix3x4, "", std::move(doc));
  p.defaultValue.numbers = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  return p;
}

ParamTemplate choiceParam(std::string name, std::vector<std::string> choices, std::string doc) {
  ParamTemplate p = base(std::move(name), ParamType::Choice, "", std::move(doc));
  p.defaultValue.text = choices.front();
  p.choices = std::move(choices);
  return p;
}

ParamTemplate textParam(std::string name, std::string def, std::string doc) {
  ParamTemplate p = base(std::move(name), ParamType::Text, "", std::move(doc));
  p.defaultValue.text = std::move(def);
  return p;
}

ParamTemplate fileParam(std::string name, std::string doc) {
  ParamTemplate p = base(std::move(name), ParamType::Text, "", std::move(doc));
  p.filePath = true;
  return p;
}

ParamTemplate pointsParam(std::string name, std::vector<Vec3> def, std::size_t minPoints,
                          std::string unit, std::string doc) {
  ParamTemplate p = base(std::move(name), ParamType::Points, std::move(unit), std::move(doc));
  for (const Vec3& q : def)
    p.defaultValue.numbers.insert(p.defaultValue.numbers.end(), q.begin(), q.end());
  p.minPoints = minPoints;
  return p;
}

std::vector<Vec3> pointsOf(const ParamValue& v) {
  std::vector<Vec3> out(v.numbers.size() / 3);
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = {v.numbers[3 * i], v.numbers[3 * i + 1], v.numbers[3 * i + 2]};
  return out;
}

ParamTemplate& range(ParamTemplate& p, double lo, double hi, bool loOpen, bool hiOpen) {
  p.min = lo;
  p.max = hi;
  p.minExclusive = loOpen;
  p.maxExclusive = hiOpen;
  return p;
}

std::string ParamTemplate::rangeText() const {
  switch (type) {
    case ParamType::Boolean:
      return "true or false";
    case ParamType::Choice: {
      std::string s = "one of";
      for (std::size_t i = 0; i < choices.size(); ++i)
        s += (i ? ", \"" : " \"") + choices[i] + "\"";
      return s;
    }
    case ParamType::Text:
      return filePath ? "a file path (relative paths: from the model file's folder)" : "text";
    case ParamType::Matrix3x4:
      return "12 finite numbers (rows of a 3x4 affine matrix, invertible)";
    case ParamType::Points:
      return (maxPoints == std::numeric_limits<std::size_t>::max()
                  ? "a list of at least " + std::to_string(minPoints)
                  : "a list of " + std::to_string(minPoints) + " to " + std::to_string(maxPoints)) +
             " points [x, y, z] of finite numbers";
    default:
      break;
  }
  // an infinite bound is never attained: always shown open
  std::string s = (minExclusive || std::isinf(min) ? "(" : "[") + numberText(min) + ", " +
                  numberText(max) + (maxExclusive || std::isinf(max) ? ")" : "]");
  if (type == ParamType::Integer) s = "an integer in " + s;
  if (type == ParamType::Vector3) {
    s = "3 numbers, each in " + s;
    if (nonZeroVector) s += ", not all zero";
  }
  return s;
}

std::string ParamTemplate::valueText(const ParamValue& v) const {
  if (type == ParamType::Choice || type == ParamType::Text) return "\"" + v.text + "\"";
  if (type == ParamType::Boolean && v.numbers.size() == 1) return v.numbers[0] ? "true" : "false";
  if (v.numbers.size() == 1) return numberText(v.numbers[0]);
  std::string s = "[";
  for (std::size_t i = 0; i < v.numbers.size(); ++i)
    s += (i ? ", " : "") + numberText(v.numbers[i]);
  return s + "]";
}

std::string ParamTemplate::check(const ParamValue& v) const {
  if (type == ParamType::Choice) {
    for (const auto& c : choices)
      if (c == v.text) return "";
    return "\"" + v.text + "\" is not allowed; allowed: " + rangeText();
  }
  if (type == ParamType::Text) {
    if (!v.numbers.empty()) return "expects text, got numbers";
    if (filePath && v.text.empty()) return "is empty; allowed: " + rangeText();
    return "";
  }
  if (type == ParamType::Points) {
    if (v.numbers.size() % 3 != 0 || v.numbers.size() / 3 < minPoints ||
        v.numbers.size() / 3 > maxPoints)
      return "expects " + rangeText() + ", got " +
             (v.numbers.size() % 3 ? std::to_string(v.numbers.size()) + " numbers"
                                   : std::to_string(v.numbers.size() / 3) + " points");
  } else if (v.numbers.size() != expectedCount(type)) {
    return "expects " + rangeText() + ", got " + std::to_string(v.numbers.size()) + " numbers";
  }
  for (double x : v.numbers) {
    if (!std::isfinite(x)) return valueText(v) + " is not finite; allowed: " + rangeText();
    if (type == ParamType::Integer && x != std::floor(x))
      return valueText(v) + " is not an integer; allowed: " + rangeText();
    if (type == ParamType::Boolean && x != 0.0 && x != 1.0)
      return valueText(v) + " is not a boolean; allowed: true or false";
    if (type == ParamType::Real || type == ParamType::Integer || type == ParamType::Vector3) {
      const bool below = minExclusive ? !(x > min) : !(x >= min);
      const bool above = maxExclusive ? !(x < max) : !(x <= max);
      if (below || above) return valueText(v) + " is out of range; allowed: " + rangeText();
    }
  }
  if (nonZeroVector && v.numbers[0] == 0 && v.numbers[1] == 0 && v.numbers[2] == 0)
    return "[0, 0, 0] is not allowed; allowed: " + rangeText();
  if (type == ParamType::Matrix3x4) {
    Mat34 m{};
    std::copy(v.numbers.begin(), v.numbers.begin() + 12, m.begin());
    if (std::abs(linearDeterminant(m)) < 1e-12)
      return "the matrix is singular; allowed: " + rangeText();
  }
  return "";
}

const ParamTemplate* NodeType::findParam(const std::string& name) const {
  for (const auto& p : params)
    if (p.name == name) return &p;
  return nullptr;
}

std::string NodeType::unknownParamText(const std::string& name) const {
  std::string known;
  for (const auto& p : params) known += (known.empty() ? "" : ", ") + p.name;
  return "unknown parameter '" + name + "'; parameters of " + id + ": " +
         (known.empty() ? "none" : known);
}

std::string NodeType::inputsText() const {
  if (maxInputs == kVariadic) return std::to_string(minInputs) + " or more";
  if (minInputs == maxInputs) return std::to_string(minInputs);
  return std::to_string(minInputs) + " to " + std::to_string(maxInputs);
}

namespace {

// Titles that the id does not spell out: abbreviations, proper names, what a short id means.
const std::map<std::string, std::string>& titleTable() {
  static const std::map<std::string, std::string> titles = {
      {"halfspace", "Half-space"},           {"ffd", "Free-form deformation"},
      {"deform_point", "Point deformation"}, {"schwarz_p", "Schwarz P surface"},
      {"schwarz_d", "Schwarz D surface"},    {"gyroid", "Gyroid surface"},
      {"diamond", "Diamond surface"},        {"neovius", "Neovius surface"},
      {"lidinoid", "Lidinoid surface"},      {"mesh_sdf", "Mesh distance field"},
      {"vdb_grid", "OpenVDB grid"},          {"instancer", "Instances at points"},
      {"transform", "Affine transform"},
  };
  return titles;
}

std::string titleFromId(const std::string& id) {
  std::string title = id;
  for (char& c : title)
    if (c == '_') c = ' ';
  if (!title.empty())
    title[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(title[0])));
  return title;
}

}  // namespace

void Registry::add(NodeType type) {
  if (byId_.count(type.id)) throw ModelError("node type '" + type.id + "' registered twice");
  if (type.title.empty()) {
    const auto it = titleTable().find(type.id);
    type.title = it != titleTable().end() ? it->second : titleFromId(type.id);
  }
  types_.push_back(std::make_unique<NodeType>(std::move(type)));
  byId_[types_.back()->id] = types_.back().get();
}

const NodeType* Registry::find(const std::string& id) const {
  auto it = byId_.find(id);
  return it == byId_.end() ? nullptr : it->second;
}

const NodeType& Registry::get(const std::string& id) const {
  const NodeType* t = find(id);
  if (!t) {
    std::string known;
    for (const auto& ty : types_) known += (known.empty() ? "" : ", ") + ty->id;
    throw ModelError("unknown node type '" + id + "'; known types: " + known);
  }
  return *t;
}

std::vector<const NodeType*> Registry::all() const {
  std::vector<const NodeType*> out;
  for (const auto& t : types_) out.push_back(t.get());
  return out;
}

const Registry& registry() {
  static const Registry instance = [] {
    Registry r;
    registerPrimitives(r);
    registerSweeps(r);
    registerBlobs(r);
    registerTransforms(r);
    registerSetOperations(r);
    registerBoundedBlend(r);
    registerFieldOperations(r);
    registerDeformations(r);
    registerLattices(r);
    registerArrays(r);
    registerMicrostructures(r);
    registerStrutLattices(r);
    registerFormula(r);
    registerFieldSources(r);
    return r;
  }();
  return instance;
}

}  // namespace frep
