// The export pipeline writes the file while its check runs, under a temporary name: only a
// mesh the check accepts (or --force) is renamed into place; a refusal, a cancel during the
// check and a cancel at the write leave no file, no temporary, and an older file untouched.
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace frep
