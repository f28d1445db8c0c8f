// The registry and the JSON model format: every type reachable, every bad-input class gives
// a message naming the node path, the parameter and what is allowed.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "base/affine.h"
#include "base/errors.h"
#include "frep/model_json.h"
#include "frep/registry_docs.h"

namespace frep {
namespace {

std::string errorOf(const std::string& json) {
  try {
    parseModel(json, "m.json");
  } catch (const ModelError& e) {
    return e.what();
  }
  return "";
}

// A JSON node of the given type with default parameters and sphere inputs.
nlohmann::json defaultNode(const NodeType& t) {
  nlohmann::json j;
  j["type"] = t.id;
  nlohmann::json inputs = nlohmann::json::array();
  for (int i = 0; i < std::max(t.minInputs, 0); ++i)
    inputs.push_back({{"type", "sphere"}, {"params", {{"radius", 0.5 + 0.1 * i}}}});
  if (!inputs.empty()) j["inputs"] = inputs;
  // A file has no default: parsing only needs a name (the file is read when compiling).
  for (const auto& p : t.params)
    if (p.filePath) j["params"][p.name] = "part.stl";
  return j;
}

TEST(Registry, EveryTypeIsReachableFromJsonAndInfo) {
  const auto types = registry().all();
  ASSERT_GE(types.size(), 17u);
  const auto info = nlohmann::json::parse(registryJson());
  ASSERT_EQ(info.size(), types.size());
  for (std::size_t i = 0; i < types.size(); ++i) {
    const NodeType& t = *types[i];
    EXPECT_EQ(info[i]["type"], t.id);
    EXPECT_EQ(info[i]["params"].size(), t.params.size()) << t.id;
    EXPECT_FALSE(t.doc.empty()) << t.id;
    EXPECT_FALSE(t.formula.empty()) << t.id;
    for (const auto& p : t.params) EXPECT_FALSE(p.doc.empty()) << t.id << "." << p.name;
    nlohmann::json doc = {{"root", defaultNode(t)}};
    const Model m = parseModel(doc.dump(), "m.json");
    EXPECT_EQ(m.root->type, &t);
    // every parameter set explicitly to its default also parses
    nlohmann::json withParams = defaultNode(t);
    const auto defaults = nlohmann::json::parse(nodeTypeJson(t))["params"];
    for (const auto& p : defaults)
      if (!t.findParam(p["name"].get<std::string>())->filePath)
        withParams["params"][p["name"].get<std::string>()] = p["default"];
    EXPECT_NO_THROW(parseModel(nlohmann::json{{"root", withParams}}.dump(), "m.json")) << t.id;
    EXPECT_NE(nodeTypeText(t).find(t.id), std::string::npos);
  }
}

TEST(Registry, TypesAreFoundByIdNotInstanceName) {
  // the optional "name" is documentation only; renaming never changes the type
  const Model m = parseModel(R"({"root": {"type": "sphere", "name": "frep_bend_arm"}})");
  EXPECT_EQ(m.root->type->id, "sphere");
}

TEST(ModelErrors, UnknownType) {
  const std::string e = errorOf(R"({"root": {"type": "spere"}})");
  EXPECT_NE(e.find("m.json: root"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown node type 'spere'"), std::string::npos) << e;
  EXPECT_NE(e.find("sphere"), std::string::npos) << e;  // lists the known types
}

TEST(ModelErrors, OutOfRangeNamesPathParameterAndRange) {
  const std::string e = errorOf(
      R"({"root": {"type": "union", "inputs": [{"type": "box"}, {"type": "sphere", "params": {"radius": -1}}]}})");
  EXPECT_NE(e.find("root.inputs[1] (sphere)"), std::string::npos) << e;
  EXPECT_NE(e.find("'radius'"), std::string::npos) << e;
  EXPECT_NE(e.find("(0, inf)"), std::string::npos) << e;
}

TEST(ModelErrors, UnknownParameterListsKnownOnes) {
  const std::string e = errorOf(R"({"root": {"type": "sphere", "params": {"radus": 1}}})");
  EXPECT_NE(e.find("unknown parameter 'radus'"), std::string::npos) << e;
  EXPECT_NE(e.find("center, radius"), std::string::npos) << e;
}

TEST(ModelErrors, WrongValueType) {
  EXPECT_NE(errorOf(R"({"root": {"type": "sphere", "params": {"center": 3}}})").find("expects 3 numbers"),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"root": {"type": "sphere", "params": {"radius": "big"}}})").find("got a string"),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"root": {"type": "cylinder", "params": {"axis": [0, 0, 0]}}})").find("not all zero"),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"root": {"type": "union", "params": {"alpha": -1}, "inputs": [{"type": "box"}, {"type": "box"}]}})")
                .find("(-1, 1]"),
            std::string::npos);
}

TEST(ModelErrors, InputCount) {
  const std::string e = errorOf(R"({"root": {"type": "difference", "inputs": [{"type": "box"}]}})");
  EXPECT_NE(e.find("takes 2 or more input(s), got 1"), std::string::npos) << e;
  EXPECT_NE(errorOf(R"({"root": {"type": "sphere", "inputs": [{"type": "box"}]}})").find("takes 0 input(s)"),
            std::string::npos);
}

TEST(ModelErrors, SyntaxStructureReferences) {
  EXPECT_NE(errorOf("{not json").find("not valid JSON"), std::string::npos);
  EXPECT_NE(errorOf("[]").find("must hold a JSON object"), std::string::npos);
  EXPECT_NE(errorOf("{}").find("no \"root\""), std::string::npos);
  EXPECT_NE(errorOf(R"({"root": {"ref": "a"}})").find("names no entry"), std::string::npos);
  EXPECT_NE(errorOf(R"({"root": {"ref": "a"}, "definitions": {"a": {"type": "complement", "inputs": [{"ref": "a"}]}}})")
                .find("cycle"),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"root": {"type": "box", "colour": 1}})").find("unknown key \"colour\""), std::string::npos);
  EXPECT_NE(errorOf(R"({"root": {"type": "box"}, "export": {"bbox": [1, 0, 0, 0, 1, 1]}})").find("x0 < x1"),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"root": {"type": "box"}, "export": {"resolution": 0}})").find("cell size > 0"),
            std::string::npos);
}

TEST(ModelFile, RoundTripKeepsTreeSharingAndExportSettings) {
  const std::string text = R"({
    "root": {"type": "union", "inputs": [{"ref": "s"}, {"type": "translate", "params": {"offset": [1, 0, 0]}, "inputs": [{"ref": "s"}]}]},
    "definitions": {"s": {"type": "sphere", "params": {"radius": 0.75}}},
    "export": {"bbox": [-1, -1, -1, 2, 1, 1], "resolution": 0.05}})";
  const Model a = parseModel(text);
  EXPECT_EQ(a.root->inputs[0], a.root->inputs[1]->inputs[0]);  // shared, not copied
  const Model b = parseModel(modelToJson(a));
  EXPECT_EQ(b.root->inputs[0], b.root->inputs[1]->inputs[0]);
  EXPECT_EQ(*b.resolution, 0.05);
  EXPECT_EQ(b.bbox->hi[0], 2.0);
  const Program pa = compile(a.root), pb = compile(b.root);
  EXPECT_EQ(pa.eval(0.9, 0.1, 0.2), pb.eval(0.9, 0.1, 0.2));
}

TEST(ModelFile, ExamplesLoad) {
  for (const char* name : {"sphere", "csg", "twist", "helix", "gyroid"}) {
    const Model m = loadModel(std::string(FREP_SOURCE_DIR) + "/examples/" + name + ".json");
    EXPECT_TRUE(m.bbox.has_value()) << name;
  }
  EXPECT_THROW(loadModel("/nonexistent/model.json"), FileError);
}

TEST(Docs, NodeReferenceIsGeneratedFromTheRegistry) {
  std::ifstream in(std::string(FREP_SOURCE_DIR) + "/docs/node-reference.md");
  ASSERT_TRUE(in) << "docs/node-reference.md missing: run build/bin/frepcad info --markdown";
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_EQ(ss.str(), registryMarkdown())
      << "docs/node-reference.md is stale: build/bin/frepcad info --markdown > docs/node-reference.md";
}

// docs/workbench.md pictures every task panel: each node type's, and the workbench's own.
TEST(Docs, WorkbenchPicturesEveryTaskPanel) {
  const std::string docs = std::string(FREP_SOURCE_DIR) + "/docs/";
  std::ifstream in(docs + "workbench.md");
  ASSERT_TRUE(in);
  std::stringstream ss;
  ss << in.rdbuf();
  std::vector<std::string> panels = {"hspline", "lattice", "printability"};
  for (const NodeType* t : registry().all()) panels.push_back(t->id);
  for (const auto& panel : panels) {
    const std::string image = "images/panels/" + panel + ".png";
    EXPECT_NE(ss.str().find("(" + image + ")"), std::string::npos)
        << "docs/workbench.md does not show " << image;
    EXPECT_TRUE(std::ifstream(docs + image).good())
        << "docs/" << image << " missing: make screenshots (or make test-trixie for FreeCAD 1.0)";
  }
}

// The affine helpers the node types build on (Eigen behind base/affine.h).
TEST(Affine, RotationInverseDeterminant) {
  auto apply = [](const Mat34& m, const Vec3& p) {
    return Vec3{m[0] * p[0] + m[1] * p[1] + m[2] * p[2] + m[3],
                m[4] * p[0] + m[5] * p[1] + m[6] * p[2] + m[7],
                m[8] * p[0] + m[9] * p[1] + m[10] * p[2] + m[11]};
  };
  // a quarter turn about z through (1, 0, 0): (2, 0, 5) -> (1, 1, 5); the axis's length is
  // irrelevant
  const Mat34 r = rotationMatrix({0, 0, 7}, 90, {1, 0, 0});
  const Vec3 q = apply(r, {2, 0, 5});
  EXPECT_NEAR(q[0], 1, 1e-15);
  EXPECT_NEAR(q[1], 1, 1e-15);
  EXPECT_NEAR(q[2], 5, 1e-15);
  EXPECT_NEAR(linearDeterminant(r), 1.0, 1e-15);
  // an affine map and its inverse compose to the identity
  const Mat34 m = {2, 1, 0, 3, 0, 1, 4, -1, 1, 0, 0.5, 2};
  EXPECT_NEAR(linearDeterminant(m), 2 * 0.5 - 1 * (0 - 4) + 0, 1e-14);
  const Mat34 inv = invertAffine(m);
  for (const Vec3& p : {Vec3{0, 0, 0}, Vec3{1, -2, 3}, Vec3{-5, 0.5, 9}}) {
    const Vec3 back = apply(inv, apply(m, p));
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(back[a], p[a], 1e-12);
  }
  const Vec3 n = normalized({3, 0, 4});
  EXPECT_NEAR(n[0], 0.6, 1e-15);
  EXPECT_NEAR(n[2], 0.8, 1e-15);
  const Vec3 c = cross({1, 0, 0}, {0, 1, 0});
  EXPECT_EQ(c, (Vec3{0, 0, 1}));
}

}  // namespace
}  // namespace frep
