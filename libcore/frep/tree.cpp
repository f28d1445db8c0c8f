#include "frep/tree.h"

#include <algorithm>
#include <tuple>
#include <utility>

#include "base/errors.h"

namespace frep {

const ParamValue& Node::param(const std::string& name) const {
  auto it = params.find(name);
  if (it == params.end())
    throw ModelError("node type '" + type->id + "' has no parameter '" + name + "'");
  return it->second;
}

Vec3 Node::vec3(const std::string& name) const {
  const auto& n = param(name).numbers;
  return {n.at(0), n.at(1), n.at(2)};
}

ParamValue realValue(double v) { return ParamValue{{v}, ""}; }
ParamValue vec3Value(const Vec3& v) { return ParamValue{{v[0], v[1], v[2]}, ""}; }
ParamValue choiceValue(const std::string& s) { return ParamValue{{}, s}; }
ParamValue textValue(const std::string& s) { return ParamValue{{}, s}; }

NodePtr makeNode(const std::string& typeId, std::map<std::string, ParamValue> params,
                 std::vector<NodePtr> inputs, const std::string& path) {
  const NodeType* type = registry().find(typeId);
  if (!type) {
    try {
      registry().get(typeId);
    } catch (const ModelError& e) {
      throw ModelError(path + ": " + e.what());
    }
  }
  const std::string where = path + " (" + type->id + ")";
  for (const auto& kv : params) {
    if (!type->findParam(kv.first)) throw ModelError(where + ": " + type->unknownParamText(kv.first));
  }
  auto node = std::make_shared<Node>();
  node->type = type;
  for (const auto& tmpl : type->params) {
    auto it = params.find(tmpl.name);
    ParamValue v = it == params.end() ? tmpl.defaultValue : it->second;
    const std::string problem = tmpl.check(v);
    if (!problem.empty())
      throw ModelError(where + ": parameter '" + tmpl.name + "' " + problem);
    node->params[tmpl.name] = std::move(v);
  }
  const int n = static_cast<int>(inputs.size());
  if (n < type->minInputs || (type->maxInputs != kVariadic && n > type->maxInputs))
    throw ModelError(where + ": takes " + type->inputsText() + " input(s), got " +
                     std::to_string(n));
  int depth = 0;
  for (int i = 0; i < n; ++i) {
    if (!inputs[i])
      throw ModelError(where + ": input " + std::to_string(i) + " is missing");
    depth = std::max(depth, inputs[i]->depth);
  }
  if (depth + 1 > kMaxTreeDepth)
    throw ModelError(where + ": the tree is nested deeper than " + std::to_string(kMaxTreeDepth) +
                     " nodes; combine wide (one union of many inputs) rather than deep");
  node->depth = depth + 1;
  node->inputs = std::move(inputs);
  if (type->check) {
    const std::string problem = type->check(*node);
    if (!problem.empty()) throw ModelError(where + ": " + problem);
  }
  return node;
}

namespace {
const NodeType& fieldNodeType() {
  static const NodeType type = [] {
    NodeType t;
    t.id = "external";
    t.category = "field";
    t.doc = "Another field (a grid, a mesh distance, ...) as a leaf of the tree.";
    t.formula = "F = the field's value";
    t.compile = [](CompileContext& c) {
      return c.b.external(c.node().field, c.p.x, c.p.y, c.p.z);
    };
    t.bounds = [](const Node& n, const std::vector<Box3>&) { return n.field->bounds(); };
    return t;
  }();
  return type;
}
}  // namespace

NodePtr makeFieldNode(std::shared_ptr<const Field> field, const std::string& name) {
  if (!field) throw ModelError(name + ": an external node needs a field");
  auto node = std::make_shared<Node>();
  node->type = &fieldNodeType();
  node->field = std::move(field);
  return node;
}

bool isFieldNode(const Node& node) { return node.type == &fieldNodeType(); }

Program compile(const NodePtr& root) {
  ProgramBuilder builder;
  // Memo per (node, point): a node shared by several parents at the same coordinates is
  // compiled once; structurally equal sub-trees also merge through the builder.
  std::map<std::tuple<const Node*, Slot, Slot, Slot>, Slot> memo;
  std::function<Slot(const NodePtr&, Point3Slots)> compileNode = [&](const NodePtr& node,
                                                                     Point3Slots p) -> Slot {
    const auto key = std::make_tuple(node.get(), p.x, p.y, p.z);
    auto it = memo.find(key);
    if (it != memo.end()) return it->second;
    CompileContext ctx(builder, *node, p, compileNode);
    const Slot s = node->type->compile(ctx);
    memo.emplace(key, s);
    return s;
  };
  const Slot result = compileNode(root, {builder.x(), builder.y(), builder.z()});
  return builder.finish(result);
}

}  // namespace frep
