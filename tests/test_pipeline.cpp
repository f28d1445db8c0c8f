// The export pipeline writes the file while its check runs, under a temporary name: only a
// mesh the check accepts (or --force) is renamed into place; a refusal, a cancel during the
// check and a cancel at the write leave no file, no temporary, and an older file untouched.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "base/errors.h"
#include "frep/tree.h"
#include "pipeline/export_pipeline.h"

namespace frep {
namespace {

namespace fs = std::filesystem;

class Pipeline : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("frep-pipeline-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  // The folder's files other than `keep`.
  std::vector<std::string> others(const std::string& keep = "") const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_))
      if (e.path().filename() != keep) names.push_back(e.path().filename().string());
    return names;
  }
  static std::string contents(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  static ExportRequest request() {
    ExportRequest r;
    r.box.bbox = Box3{{-1.5, -1.5, -1.5}, {1.5, 1.5, 1.5}};
    r.box.cells = 40;
    return r;
  }
  fs::path dir_;
};

TEST_F(Pipeline, APrintableMeshIsRenamedIntoPlaceAndMatchesAPlainWrite) {
  const Program ball = compile(makeNode("sphere", {}, {}));
  const fs::path a = dir_ / "a.stl", b = dir_ / "b.stl";
  ExportResult r = exportField(ball, request(), a.string(), "ball");
  ASSERT_TRUE(r.written && r.report.printable());
  ExportRequest unchecked = request();
  unchecked.check = false;  // (written after the meshing alone, the plain way)
  ASSERT_TRUE(exportField(ball, unchecked, b.string(), "ball").written);
  EXPECT_EQ(contents(a), contents(b));
  EXPECT_EQ(others("a.stl").size(), 1u);  // b.stl, no temporary
}

TEST_F(Pipeline, ARefusedMeshLeavesNoFileUnlessForced) {
  // a ball outside the box: no triangles, which the check refuses ("empty")
  const Program away = compile(makeNode("sphere", {{"center", vec3Value({9.0, 9.0, 9.0})}}, {}));
  ExportRequest r = request();
  const fs::path out = dir_ / "empty.stl";
  const ExportResult refused = exportField(away, r, out.string(), "away");
  EXPECT_FALSE(refused.report.printable());
  EXPECT_FALSE(refused.written);
  EXPECT_TRUE(others().empty()) << "left: " << (others().empty() ? "" : others()[0]);
  r.force = true;
  EXPECT_TRUE(exportField(away, r, out.string(), "away").written);
  EXPECT_TRUE(fs::exists(out));
  EXPECT_TRUE(others("empty.stl").empty());
}

TEST_F(Pipeline, ACancelDuringTheCheckOrTheWriteLeavesTheOldFileAlone) {
  const Program ball = compile(makeNode("sphere", {}, {}));
  const fs::path out = dir_ / "ball.stl";
  { std::ofstream(out) << "the old file"; }
  for (const ExportStage stop : {ExportStage::Check, ExportStage::Write}) {
    ExportRequest r = request();
    r.progress = [stop](ExportStage s, double) { return s != stop; };
    EXPECT_THROW(exportField(ball, r, out.string(), "ball"), Cancelled);
    EXPECT_EQ(contents(out), "the old file");
    EXPECT_TRUE(others("ball.stl").empty()) << "a temporary was left";
  }
}

// Meshing, straightening the creases and simplifying share the meshing stage's bar: it rises
// monotonically to its end; a cancel while the creases are straightened (past meshing's
// share) leaves no file; without sharp features straightening is refused, naming the solid.
TEST_F(Pipeline, StraighteningAndSimplifyingShareTheMeshingBar) {
  const NodePtr cube = makeNode(
      "box", {{"corner", vec3Value({-0.8, -0.8, -0.8})}, {"size", vec3Value({1.6, 1.6, 1.6})}}, {});
  const Program turned = compile(makeNode(
      "rotate", {{"axis", vec3Value({1.0, 1.0, 0.0})}, {"angle", realValue(25.0)}}, {cube}));
  const fs::path out = dir_ / "cube.stl";
  ExportRequest r = request();
  r.mesh.straightenCreases = true;
  r.mesh.tolerance = 0.01;
  std::vector<double> seen;
  r.progress = [&seen](ExportStage s, double f) {
    if (s == ExportStage::Mesh) seen.push_back(f);
    return true;
  };
  const ExportResult done = exportField(turned, r, out.string(), "cube");
  ASSERT_TRUE(done.written && done.straightened && done.simplified);
  EXPECT_GT(done.straighten.collapses, 0u);
  EXPECT_EQ(done.simplify.trianglesBefore, done.straighten.trianglesAfter);
  ASSERT_FALSE(seen.empty());
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
  EXPECT_DOUBLE_EQ(seen.back(), 1.0);
  fs::remove(out);
  // with both asked, meshing takes the bar to 0.25 and straightening to 0.5
  r.progress = [](ExportStage s, double f) { return !(s == ExportStage::Mesh && f > 0.3); };
  EXPECT_THROW(exportField(turned, r, out.string(), "cube"), Cancelled);
  EXPECT_TRUE(others().empty());
  r.progress = nullptr;
  r.mesh.sharpFeatures = false;
  try {
    exportField(turned, r, out.string(), "cube");
    FAIL() << "no error";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("cube: straighten_creases needs sharp_features"),
              std::string::npos)
        << e.what();
  }
  EXPECT_TRUE(others().empty());
}

// meshAndFinish (the export's and frepcore's mesh()): the mesher's own mesh is kept only when
// asked, and only where a step changed it; a bad tolerance is refused before any meshing.
TEST(MeshAndFinish, KeepsTheMeshersMeshOnlyWhenAskedAndRefusesBeforeMeshing) {
  const NodePtr cube = makeNode(
      "box", {{"corner", vec3Value({-0.8, -0.8, -0.8})}, {"size", vec3Value({1.6, 1.6, 1.6})}}, {});
  const Program turned = compile(makeNode(
      "rotate", {{"axis", vec3Value({1.0, 1.0, 0.0})}, {"angle", realValue(25.0)}}, {cube}));
  MeshingOptions o;
  o.bbox = Box3{{-1.5, -1.5, -1.5}, {1.5, 1.5, 1.5}};
  o.resolution = 3.0 / 40;
  const FinishedMesh plain = meshAndFinish(turned, o, nullptr, true);
  EXPECT_FALSE(plain.straightened || plain.simplified);
  EXPECT_EQ(plain.meshers.triangleCount(), 0u);  // nothing changed it: no copy
  o.settings.tolerance = 0.01;
  const FinishedMesh kept = meshAndFinish(turned, o, nullptr, true);
  ASSERT_TRUE(kept.simplified);
  EXPECT_EQ(kept.meshers.triangleCount(), plain.mesh.triangleCount());
  EXPECT_LT(kept.mesh.triangleCount(), plain.mesh.triangleCount());
  EXPECT_EQ(kept.simplify.trianglesBefore, plain.mesh.triangleCount());
  EXPECT_EQ(meshAndFinish(turned, o, nullptr, false).meshers.triangleCount(), 0u);
  for (double bad : {0.0, -1.0, std::nan("")}) {
    o.settings.tolerance = bad;
    bool called = false;
    try {
      meshAndFinish(
          turned, o, [&called](double) { return called = true; }, false);
      ADD_FAILURE() << bad;
    } catch (const ModelError& e) {
      EXPECT_NE(std::string(e.what()).find("tolerance must be a distance > 0"), std::string::npos)
          << e.what();
    }
    EXPECT_FALSE(called) << bad;
  }
}

}  // namespace
}  // namespace frep
