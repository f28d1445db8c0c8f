// An FRep tree (a DAG: a node may feed several parents): typed nodes with parameter values and
// inputs. Nodes are immutable once made; makeNode validates them against the registry.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "frep/registry.h"

namespace frep {

struct Node;
using NodePtr = std::shared_ptr<const Node>;

struct Node {
  const NodeType* type = nullptr;
  std::map<std::string, ParamValue> params;  // every parameter of the type, defaults filled in
  std::vector<NodePtr> inputs;
  // The field of an external node (makeFieldNode); null for every registry type.
  std::shared_ptr<const Field> field;
  // 1 for a leaf, else 1 + the deepest input (kept at most kMaxTreeDepth).
  int depth = 1;

  const ParamValue& param(const std::string& name) const;
  double real(const std::string& name) const { return param(name).numbers.at(0); }
  Vec3 vec3(const std::string& name) const;
};

// How deep a tree may be. Compiling, bounding and freeing a tree recurse over it: deeper trees
// (a hostile file, a runaway script) are refused with a message instead of overflowing the
// stack. Wide trees (a union of 100,000 inputs) are fine.
constexpr int kMaxTreeDepth = 1000;

// Makes a validated node. `params` may omit parameters (their defaults are used). `path` names
// the node in error messages (e.g. "root.inputs[1]"). Throws ModelError.
NodePtr makeNode(const std::string& typeId, std::map<std::string, ParamValue> params,
                 std::vector<NodePtr> inputs, const std::string& path = "node");

// An external node: any Field as a leaf of a tree, evaluated through an `external` instruction
// in all four modes (the generic seam for grids, mesh distances, lattice deformations). Not a
// registry type: it is made in code, never read from a model file. `name` names it in
// messages. Its structural bounds are the field's bounds().
NodePtr makeFieldNode(std::shared_ptr<const Field> field, const std::string& name = "external");
bool isFieldNode(const Node& node);

// Shorthands for building trees in code and tests.
ParamValue realValue(double v);
ParamValue vec3Value(const Vec3& v);
ParamValue choiceValue(const std::string& s);
ParamValue textValue(const std::string& s);

// Compiles a tree into a flat program (shared and repeated sub-trees computed once).
Program compile(const NodePtr& root);

// Compile-time view of one node: its parameters, its point, and a way to compile its inputs.
class CompileContext {
 public:
  CompileContext(ProgramBuilder& builder, const Node& node, Point3Slots point,
                 std::function<Slot(const NodePtr&, Point3Slots)> compileInput)
      : b(builder), p(point), node_(node), compileInput_(std::move(compileInput)) {}

  ProgramBuilder& b;
  Point3Slots p;

  double real(const std::string& name) const { return node_.real(name); }
  Vec3 vec3(const std::string& name) const { return node_.vec3(name); }
  const ParamValue& param(const std::string& name) const { return node_.param(name); }
  int inputCount() const { return static_cast<int>(node_.inputs.size()); }
  const Node& node() const { return node_; }
  Slot input(int i) { return input(i, p); }
  Slot input(int i, Point3Slots at) { return compileInput_(node_.inputs.at(i), at); }

 private:
  const Node& node_;
  std::function<Slot(const NodePtr&, Point3Slots)> compileInput_;
};

}  // namespace frep
