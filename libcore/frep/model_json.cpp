#include "frep/model_json.h"

#include <cerrno>
#include <cstring>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "base/errors.h"
#include "base/file_names.h"
#include "frep/hyperfun_import.h"

namespace frep {

using nlohmann::json;

namespace {

std::string typeOf(const json& j) {
  switch (j.type()) {
    case json::value_t::null:
      return "null";
    case json::value_t::boolean:
      return "a boolean";
    case json::value_t::string:
      return "a string";
    case json::value_t::array:
      return "an array";
    case json::value_t::object:
      return "an object";
    default:
      return "a number";
  }
}

ParamValue paramFromJson(const ParamTemplate& t, const json& j, const std::string& where) {
  auto fail = [&](const std::string& got) {
    return ModelError(where + ": parameter '" + t.name + "' expects " + t.rangeText() + ", got " +
                      got);
  };
  ParamValue v;
  switch (t.type) {
    case ParamType::Choice:
    case ParamType::Text:
      if (!j.is_string()) throw fail(typeOf(j));
      v.text = j.get<std::string>();
      return v;
    case ParamType::Boolean:
      if (!j.is_boolean()) throw fail(typeOf(j));
      v.numbers = {j.get<bool>() ? 1.0 : 0.0};
      return v;
    case ParamType::Real:
    case ParamType::Integer:
      if (!j.is_number()) throw fail(typeOf(j));
      v.numbers = {j.get<double>()};
      return v;
    case ParamType::Points: {
      if (!j.is_array()) throw fail(typeOf(j));
      for (const auto& q : j) {
        if (!q.is_array() || q.size() != 3) throw fail("an array holding " + typeOf(q));
        for (const auto& e : q) {
          if (!e.is_number()) throw fail("a point holding " + typeOf(e));
          v.numbers.push_back(e.get<double>());
        }
      }
      return v;
    }
    case ParamType::Vector3:
    case ParamType::Matrix3x4: {
      const std::size_t n = t.type == ParamType::Vector3 ? 3 : 12;
      if (!j.is_array() || j.size() != n)
        throw fail(j.is_array() ? "an array of " + std::to_string(j.size()) : typeOf(j));
      for (const auto& e : j) {
        if (!e.is_number()) throw fail("an array holding " + typeOf(e));
        v.numbers.push_back(e.get<double>());
      }
      return v;
    }
  }
  return v;
}

json paramToJson(const ParamTemplate& t, const ParamValue& v) {
  switch (t.type) {
    case ParamType::Choice:
    case ParamType::Text:
      return v.text;
    case ParamType::Boolean:
      return v.numbers.at(0) != 0.0;
    case ParamType::Real:
      return v.numbers.at(0);
    case ParamType::Integer:
      return static_cast<long long>(v.numbers.at(0));
    case ParamType::Points: {
      json points = json::array();
      for (const Vec3& q : pointsOf(v)) points.push_back({q[0], q[1], q[2]});
      return points;
    }
    default:
      return v.numbers;
  }
}

class Parser {
 public:
  Parser(const json& doc, std::string source, std::string baseDirectory)
      : doc_(doc), source_(std::move(source)), baseDirectory_(std::move(baseDirectory)) {}

  NodePtr node(const json& j, const std::string& path) {
    // Nested nodes and chains of refs recurse here; makeNode refuses deep trees too, but
    // only after the recursion: count it on the way down.
    struct Depth {
      explicit Depth(int& d) : d_(d) { ++d_; }
      ~Depth() { --d_; }
      int& d_;
    } depth(depth_);
    if (depth_ > kMaxTreeDepth)
      throw ModelError(source_ + ": nodes nested deeper than " + std::to_string(kMaxTreeDepth) +
                       " (inputs within inputs, or a chain of refs); combine wide rather "
                       "than deep");
    // The path names the node in messages; deep down only its end is kept (a path of every
    // level would cost memory growing with the square of the depth).
    const std::string where = source_ + ": " + path;
    if (!j.is_object()) throw ModelError(where + ": a node must be an object, got " + typeOf(j));
    if (j.contains("ref")) return reference(j, path);
    if (!j.contains("type") || !j["type"].is_string())
      throw ModelError(where + ": a node needs a \"type\" string (see `frepcad info`)");
    for (auto it = j.begin(); it != j.end(); ++it)
      if (it.key() != "type" && it.key() != "params" && it.key() != "inputs" && it.key() != "name")
        throw ModelError(where + ": unknown key \"" + it.key() +
                         "\"; a node has \"type\", \"params\", \"inputs\" and \"name\"");
    const std::string typeId = j["type"].get<std::string>();
    const NodeType* type = registry().find(typeId);
    if (!type) {
      try {
        registry().get(typeId);
      } catch (const ModelError& e) {
        throw ModelError(where + ": " + e.what());
      }
    }
    const std::string nodeWhere = where + " (" + typeId + ")";

    std::map<std::string, ParamValue> params;
    if (j.contains("params")) {
      if (!j["params"].is_object()) throw ModelError(nodeWhere + ": \"params\" must be an object");
      for (auto it = j["params"].begin(); it != j["params"].end(); ++it) {
        const ParamTemplate* t = type->findParam(it.key());
        if (!t) throw ModelError(nodeWhere + ": " + type->unknownParamText(it.key()));
        ParamValue v = paramFromJson(*t, it.value(), nodeWhere);
        // A relative file path is read from the model file's folder, wherever frepcad runs.
        if (t->filePath && !baseDirectory_.empty() && !v.text.empty() && v.text[0] != '/')
          v.text = baseDirectory_ + "/" + v.text;
        params[it.key()] = std::move(v);
      }
    }
    std::vector<NodePtr> inputs;
    if (j.contains("inputs")) {
      if (!j["inputs"].is_array())
        throw ModelError(nodeWhere + ": \"inputs\" must be an array of nodes");
      for (std::size_t i = 0; i < j["inputs"].size(); ++i)
        inputs.push_back(
            node(j["inputs"][i], shortPath(path) + ".inputs[" + std::to_string(i) + "]"));
    }
    return makeNode(typeId, std::move(params), std::move(inputs), source_ + ": " + path);
  }

 private:
  NodePtr reference(const json& j, const std::string& path) {
    const std::string where = source_ + ": " + path;
    if (!j["ref"].is_string()) throw ModelError(where + ": \"ref\" must be a string");
    const std::string name = j["ref"].get<std::string>();
    if (auto it = done_.find(name); it != done_.end()) return it->second;
    if (!doc_.contains("definitions") || !doc_["definitions"].contains(name))
      throw ModelError(where + ": \"ref\": \"" + name + "\" names no entry in \"definitions\"");
    if (active_.count(name))
      throw ModelError(where + ": definition \"" + name + "\" refers to itself (a cycle)");
    active_.insert(name);
    NodePtr n = node(doc_["definitions"][name], "definitions." + name);
    active_.erase(name);
    done_[name] = n;
    return n;
  }

  static std::string shortPath(const std::string& path) {
    constexpr std::size_t kKeep = 120;
    if (path.size() <= kKeep) return path;
    return "..." + path.substr(path.size() - kKeep);
  }

  const json& doc_;
  std::string source_;
  std::string baseDirectory_;
  std::map<std::string, NodePtr> done_;
  std::set<std::string> active_;
  int depth_ = 0;
};

// nlohmann's parse errors, in our words: where (line and column) and what, without the
// library's exception ids.
std::string jsonErrorText(const std::string& text, std::size_t byte, const std::string& what) {
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i + 1 < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  std::string reason = "a syntax error";
  if (what.find("invalid literal") != std::string::npos) {
    const std::size_t at = std::min(byte ? byte - 1 : 0, text.size());
    const std::string rest = text.substr(at > 8 ? at - 8 : 0, 16);
    if (rest.find("NaN") != std::string::npos || rest.find("nfinity") != std::string::npos)
      reason = "NaN and Infinity are not JSON numbers (numbers must be finite)";
    else
      reason =
          "an invalid literal (strings need double quotes; true, false and null are lower "
          "case)";
  } else if (what.find("unexpected end of input") != std::string::npos ||
             (what.find("missing closing quote") != std::string::npos && byte >= text.size())) {
    reason = "the text ends in the middle of a value (a truncated file?)";
  } else if (what.find("UTF-8") != std::string::npos || what.find("utf-8") != std::string::npos ||
             what.find("ill-formed") != std::string::npos) {
    reason = "the text is not UTF-8";
  } else if (what.find("number overflow") != std::string::npos) {
    reason = "a number beyond the range of double (about 1.8e308)";
  } else if (what.find("control character") != std::string::npos) {
    reason = "a control character inside a string";
  } else if (what.find("expected") != std::string::npos) {
    const std::size_t e = what.find("expected");
    reason = "a syntax error: " + what.substr(e);
  }
  return "not valid JSON at line " + std::to_string(line) + ", column " + std::to_string(column) +
         ": " + reason;
}

}  // namespace

Model parseModel(const std::string& text, const std::string& source,
                 const std::string& baseDirectory) {
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::parse_error& e) {
    throw ModelError(source + ": " + jsonErrorText(text, e.byte, e.what()));
  } catch (const json::exception& e) {  // out_of_range: a number beyond double
    throw ModelError(source + ": " + jsonErrorText(text, text.size(), e.what()));
  }
  if (!doc.is_object()) throw ModelError(source + ": a model file must hold a JSON object");
  for (auto it = doc.begin(); it != doc.end(); ++it) {
    static const std::set<std::string> keys = {"frepcad", "description", "root", "definitions",
                                               "export"};
    if (!keys.count(it.key()))
      throw ModelError(source + ": unknown key \"" + it.key() +
                       "\"; a model file has \"frepcad\", \"description\", \"root\", "
                       "\"definitions\" and \"export\"");
  }
  if (doc.contains("frepcad")) {
    const json& v = doc["frepcad"];
    if (!v.is_number_integer() || v.get<long long>() != kModelFormatVersion)
      throw ModelError(source + ": \"frepcad\": " + v.dump() +
                       " is not a format version this "
                       "frepcad reads; allowed: " +
                       std::to_string(kModelFormatVersion) + " (a newer frepcad wrote the file?)");
  }
  if (doc.contains("definitions") && !doc["definitions"].is_object())
    throw ModelError(source + ": \"definitions\" must be an object of named nodes");
  if (doc.contains("description") && !doc["description"].is_string())
    throw ModelError(source + ": \"description\" must be a string");
  if (!doc.contains("root"))
    throw ModelError(source + ": no \"root\" node (the tree to build); see docs/file-formats.md");
  Model m;
  Parser parser(doc, source, baseDirectory);
  m.root = parser.node(doc["root"], "root");
  if (doc.contains("description") && doc["description"].is_string())
    m.description = doc["description"].get<std::string>();
  if (doc.contains("export")) {
    const json& e = doc["export"];
    if (!e.is_object()) throw ModelError(source + ": \"export\" must be an object");
    for (auto it = e.begin(); it != e.end(); ++it)
      if (it.key() != "bbox" && it.key() != "resolution")
        throw ModelError(source + ": export: unknown key \"" + it.key() +
                         "\"; export has \"bbox\" and \"resolution\"");
    if (e.contains("bbox")) {
      const json& b = e["bbox"];
      bool ok = b.is_array() && b.size() == 6;
      for (std::size_t i = 0; ok && i < 6; ++i) ok = b[i].is_number();
      Box3 box;
      if (ok) {
        for (int i = 0; i < 3; ++i) {
          box.lo[i] = b[i].get<double>();
          box.hi[i] = b[i + 3].get<double>();
        }
      }
      if (!ok || !box.valid())
        throw ModelError(source +
                         ": export.bbox expects 6 numbers [x0, y0, z0, x1, y1, z1] "
                         "with x0 < x1, y0 < y1, z0 < z1");
      m.bbox = box;
    }
    if (e.contains("resolution")) {
      const json& r = e["resolution"];
      if (!r.is_number() || !(r.get<double>() > 0.0))
        throw ModelError(source + ": export.resolution expects a cell size > 0, got " + r.dump());
      m.resolution = r.get<double>();
    }
  }
  return m;
}

Model loadModel(const std::string& path) {
  const std::string text = readSmallFile(path, "model file", kMaxModelBytes);
  if (isHyperFunPath(path)) return importHyperFun(text, displayName(path));
  const std::size_t slash = path.rfind('/');
  const std::string folder = slash == std::string::npos ? "."
                             : slash == 0               ? "/"
                                                        : path.substr(0, slash);
  return parseModel(text, displayName(path), folder);
}

std::string modelToJson(const Model& model) {
  // Nodes used more than once go to "definitions" and are referenced by name.
  std::map<const Node*, int> uses;
  std::function<void(const NodePtr&)> count = [&](const NodePtr& n) {
    if (uses[n.get()]++ > 0) return;
    for (const auto& in : n->inputs) count(in);
  };
  count(model.root);
  json defs = json::object();
  std::map<const Node*, std::string> names;
  std::function<json(const NodePtr&, bool)> write = [&](const NodePtr& n, bool top) -> json {
    if (!top && uses[n.get()] > 1) {
      auto it = names.find(n.get());
      if (it == names.end()) {
        const std::string name = n->type->id + std::to_string(names.size() + 1);
        names[n.get()] = name;
        defs[name] = write(n, true);
        return json{{"ref", name}};
      }
      return json{{"ref", it->second}};
    }
    if (isFieldNode(*n))
      throw ModelError(
          "an external field node cannot be written to a model file; save the "
          "field in its own file and refer to it by a node that reads it");
    json j;
    j["type"] = n->type->id;
    json params = json::object();
    for (const auto& t : n->type->params) {
      const ParamValue& v = n->param(t.name);
      if (!(v == t.defaultValue)) params[t.name] = paramToJson(t, v);
    }
    if (!params.empty()) j["params"] = params;
    if (!n->inputs.empty()) {
      j["inputs"] = json::array();
      for (const auto& in : n->inputs) j["inputs"].push_back(write(in, false));
    }
    return j;
  };
  json doc;
  doc["frepcad"] = kModelFormatVersion;
  if (!model.description.empty()) doc["description"] = model.description;
  doc["root"] = write(model.root, true);
  if (!defs.empty()) doc["definitions"] = defs;
  if (model.bbox || model.resolution) {
    json e = json::object();
    if (model.bbox)
      e["bbox"] = {model.bbox->lo[0], model.bbox->lo[1], model.bbox->lo[2],
                   model.bbox->hi[0], model.bbox->hi[1], model.bbox->hi[2]};
    if (model.resolution) e["resolution"] = *model.resolution;
    doc["export"] = e;
  }
  return doc.dump(2) + "\n";
}

}  // namespace frep
