// The node registry: the single table of FRep node types. Each type declares its id,
// category, inputs and parameter templates (name, type, default, range, unit, doc) and how
// it compiles into program instructions. The JSON model format, `frepcad info`, the docs'
// node reference, frepcore's functions and the workbench's features and commands are all
// derived from this table.
// Types are always looked up by id, never by an instance's name.
#pragma once

#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "base/vec.h"
#include "frep/program_builder.h"

namespace frep {

enum class ParamType { Real, Integer, Boolean, Vector3, Matrix3x4, Choice, Points, Text };
const char* paramTypeName(ParamType t);

// A parameter value. Numbers hold 1 (Real, Integer, Boolean), 3 (Vector3), 12 (Matrix3x4) or
// 3 per point (Points: x, y, z of each in turn) values; Choice and Text use text.
struct ParamValue {
  std::vector<double> numbers;
  std::string text;
  bool operator==(const ParamValue& o) const { return numbers == o.numbers && text == o.text; }
};

struct ParamTemplate {
  std::string name;
  ParamType type = ParamType::Real;
  ParamValue defaultValue;
  // Allowed range of each number (Real, Integer, Vector3 components).
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool minExclusive = false;
  bool maxExclusive = false;
  bool nonZeroVector = false;  // Vector3 that must not be (0, 0, 0), e.g. an axis
  std::size_t minPoints = 0;   // Points: at least this many
  // Points: at most this many (a limit that keeps the field's program small)
  std::size_t maxPoints = std::numeric_limits<std::size_t>::max();
  bool path = false;  // Points: an ordered path (a sweep's), else a set of positions
  // Points taken from the same object as the named parameter in FreeCAD (the instancer's
  // rotations follow its positions' source); "" for a list of its own.
  std::string follows;
  std::vector<std::string> choices;
  bool filePath = false;  // Text: a file's path; a model file's relative paths are read
                          // relative to the model file's folder
  std::string unit;       // "length", "angle" (degrees) or "" (dimensionless)
  std::string doc;
  // The label a user reads where the name is a formula's letter ("Strength (A0)" for a0);
  // empty: the name says it.
  std::string title = {};

  // Returns an empty string when v is allowed, else what is wrong and what is allowed.
  std::string check(const ParamValue& v) const;
  std::string rangeText() const;
  std::string valueText(const ParamValue& v) const;
};

// A number as a user typed it (1.5, not 1.500000; inf): what messages about values show.
std::string numberText(double v);

// Parameter template constructors, chained with the setters below.
ParamTemplate realParam(std::string name, double def, std::string unit, std::string doc);
ParamTemplate intParam(std::string name, int def, std::string doc);
ParamTemplate boolParam(std::string name, bool def, std::string doc);
ParamTemplate vec3Param(std::string name, Vec3 def, std::string unit, std::string doc);
ParamTemplate matrixParam(std::string name, std::string doc);
ParamTemplate choiceParam(std::string name, std::vector<std::string> choices, std::string doc);
ParamTemplate textParam(std::string name, std::string def, std::string doc);
// A file's path (Text, not empty).
ParamTemplate fileParam(std::string name, std::string doc);
ParamTemplate pointsParam(std::string name, std::vector<Vec3> def, std::size_t minPoints,
                          std::string unit, std::string doc);
// The points of a Points value.
std::vector<Vec3> pointsOf(const ParamValue& v);
ParamTemplate& range(ParamTemplate& p, double lo, double hi, bool loOpen = false,
                     bool hiOpen = false);

struct Point3Slots {
  Slot x, y, z;
};

class CompileContext;
struct Node;
using CompileFn = std::function<Slot(CompileContext&)>;
// Where the node's solid can be, given the boxes of its inputs' solids (infinite sides where
// unknown); see structural_bounds.h. Optional: a type without one is "anywhere".
using BoundsFn = std::function<Box3(const Node&, const std::vector<Box3>& inputs)>;

constexpr int kVariadic = -1;

struct NodeType {
  std::string id;        // "sphere", "union", ...
  std::string category;  // "primitive", "transform", "set operation", "blend", ...
  std::string doc;       // one paragraph
  std::string formula;   // the defining function, in plain text
  int minInputs = 0;
  int maxInputs = 0;  // kVariadic for no upper limit
  std::vector<ParamTemplate> params;
  CompileFn compile;
  BoundsFn bounds = nullptr;  // none: the solid may be anywhere
  // Checks that need the whole node (e.g. a formula naming its parameters and inputs);
  // returns "" or the problem, naming the parameter. Optional.
  std::function<std::string(const Node&)> check = nullptr;
  // The name a user reads in menus and the node reference ("Free-form deformation"). Left
  // empty, Registry::add takes it from the registry's table of titles, else from the id
  // ("blend_union" -> "Blend union").
  std::string title = {};

  const ParamTemplate* findParam(const std::string& name) const;
  // "unknown parameter 'x'; parameters of T: a, b" for error messages
  std::string unknownParamText(const std::string& name) const;
  std::string inputsText() const;
};

class Registry {
 public:
  void add(NodeType type);
  const NodeType* find(const std::string& id) const;
  const NodeType& get(const std::string& id) const;  // throws ModelError naming the id
  std::vector<const NodeType*> all() const;          // in registration order

 private:
  std::vector<std::unique_ptr<NodeType>> types_;
  std::map<std::string, const NodeType*> byId_;
};

// The registry with every built-in node type.
const Registry& registry();

// Registration functions, one per family (node_types_*.cpp).
void registerPrimitives(Registry& r);
void registerTransforms(Registry& r);
void registerSetOperations(Registry& r);
void registerBoundedBlend(Registry& r);
void registerSweeps(Registry& r);
void registerBlobs(Registry& r);
void registerArrays(Registry& r);
void registerStrutLattices(Registry& r);
void registerDeformations(Registry& r);
void registerFieldOperations(Registry& r);
void registerMicrostructures(Registry& r);
void registerFormula(Registry& r);
void registerFieldSources(Registry& r);
void registerLattices(Registry& r);

}  // namespace frep
