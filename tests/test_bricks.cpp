// Brick jobs: a model meshed as 1, 8 or 64 jobs and welded by key is the mesh
// polygonize makes in one process (the same triangles, the same coordinates after sorting),
// on the reference models and on random trees; piece files refuse what is not a piece; the
// merge refuses foreign, repeated and missing pieces.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "base/errors.h"
#include "check/mesh_check.h"
#include "frep/model_json.h"
#include "frep/program.h"
#include "io/mesh_3mf.h"
#include "io/mesh_io.h"
#include "io/mesh_piece_file.h"
#include "mesh/piece_merge.h"
#include "pipeline/brick_jobs.h"
#include "random_trees.h"

namespace frep {
namespace {

namespace fs = std::filesystem;

MeshSettings settingsOf(bool sharp, Extraction mesher) {
  MeshSettings s;
  s.sharpFeatures = sharp;
  s.mesher = mesher;
  return s;
}

// The mesh's triangles as coordinates, each turned to start at its smallest corner (its
// orientation kept), sorted: equal for two meshes with the same triangles in any order.
std::vector<std::array<Vec3f, 3>> sortedTriangles(const TriangleMesh& m) {
  std::vector<std::array<Vec3f, 3>> out;
  out.reserve(m.triangles.size());
  for (const Triangle& t : m.triangles) {
    std::array<Vec3f, 3> c = {m.positions[t[0]], m.positions[t[1]], m.positions[t[2]]};
    const int first = static_cast<int>(std::min_element(c.begin(), c.end()) - c.begin());
    std::rotate(c.begin(), c.begin() + first, c.end());
    out.push_back(c);
  }
  std::sort(out.begin(), out.end());
  return out;
}

TriangleMesh inJobs(const Field& f, const BrickJobPlan& plan) {
  std::vector<MeshPiece> pieces;
  for (std::uint32_t j = 0; j < plan.jobs; ++j) pieces.push_back(runBrickJob(f, plan, j));
  std::reverse(pieces.begin(), pieces.end());  // the merge takes them in any order
  return mergePieces(pieces);
}

void expectSameMesh(const TriangleMesh& a, const TriangleMesh& b, const std::string& what) {
  ASSERT_EQ(a.triangleCount(), b.triangleCount()) << what;
  EXPECT_EQ(a.vertexCount(), b.vertexCount()) << what;
  EXPECT_TRUE(sortedTriangles(a) == sortedTriangles(b)) << what << ": triangles differ";
}

TEST(BrickJobs, ReferenceModelsInOneEightAndSixtyFourJobsAreTheOneProcessMesh) {
  for (const char* name : {"csg", "twist", "gyroid", "helix"}) {
    const Model m = loadModel(std::string(FREP_SOURCE_DIR) + "/examples/" + name + ".json");
    const Program p = compile(m.root);
    const MeshingBox box{*m.bbox, 2.4 / 72};  // 5 bricks of 16 cells per axis
    for (bool sharp : {true, false}) {
      const TriangleMesh whole = polygonize(
          p, brickMeshingOptions(planBrickJobs(box, settingsOf(sharp, Extraction::Cubes), 1, 0)));
      ASSERT_GT(whole.triangleCount(), 1000u);
      for (std::uint32_t jobs : {1u, 8u, 64u}) {
        const BrickJobPlan plan = planBrickJobs(box, settingsOf(sharp, Extraction::Cubes), jobs, 7);
        const TriangleMesh merged = inJobs(p, plan);
        expectSameMesh(merged, whole,
                       std::string(name) + " in " + std::to_string(jobs) + " jobs, sharp " +
                           std::to_string(sharp));
        EXPECT_TRUE(checkMesh(merged).printable()) << name << " in " << jobs << " jobs";
      }
    }
  }
}

// Random trees (sharp CSG, thin walls, surfaces on grid planes and on the box), both
// extractions, jobs that split the bricks unevenly.
TEST(BrickJobs, RandomTreesInJobsAreTheOneProcessMesh) {
  testing::RandomTrees rng(4242);
  int nonEmpty = 0;
  for (int i = 0; i < 60; ++i) {
    const NodePtr tree = rng.tree(rng.integer(1, 4));
    const Program p = compile(tree);
    const MeshingBox box{{{-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2}}, 2.4 / (40 + rng.integer(0, 30))};
    const Extraction how = rng.integer(0, 3) == 0 ? Extraction::Tetrahedra : Extraction::Cubes;
    const bool sharp = rng.integer(0, 1) == 0;
    const TriangleMesh whole =
        polygonize(p, brickMeshingOptions(planBrickJobs(box, settingsOf(sharp, how), 1, 0)));
    if (whole.triangleCount() > 0) ++nonEmpty;
    const std::uint32_t jobs = std::vector<std::uint32_t>{2, 6, 8, 12, 27}[rng.integer(0, 4)];
    const BrickJobPlan plan = planBrickJobs(box, settingsOf(sharp, how), jobs, 1);
    expectSameMesh(inJobs(p, plan), whole,
                   "tree " + std::to_string(i) + " in " + std::to_string(jobs) + " jobs:\n" +
                       modelToJson(Model{tree, box.box, box.resolution, "", {}, {}}));
  }
  EXPECT_GT(nonEmpty, 40);
}

TEST(BrickJobs, PlansSplitTheBricksEvenly) {
  const MeshingBox box{{{0, 0, 0}, {4, 2, 1}}, 1.0 / 16};  // 5 x 3 x 2 bricks
  const BrickJobPlan p = planBrickJobs(box, settingsOf(true, Extraction::Cubes), 6, 0);
  EXPECT_EQ(p.split[0] * p.split[1] * p.split[2], 6);
  EXPECT_EQ(p.bricks[0], 5);
  // every brick in exactly one job
  std::vector<int> covered(5 * 3 * 2, 0);
  for (std::uint32_t j = 0; j < p.jobs; ++j) {
    std::int64_t lo[3], hi[3];
    jobBricks(p, j, lo, hi);
    for (std::int64_t z = lo[2]; z < hi[2]; ++z)
      for (std::int64_t y = lo[1]; y < hi[1]; ++y)
        for (std::int64_t x = lo[0]; x < hi[0]; ++x) ++covered[x + 5 * (y + 3 * z)];
  }
  EXPECT_TRUE(std::all_of(covered.begin(), covered.end(), [](int c) { return c == 1; }));
  // another model, box or option is another run
  EXPECT_NE(planBrickJobs(box, settingsOf(false, Extraction::Cubes), 6, 0).runId, p.runId);
  EXPECT_NE(planBrickJobs(box, settingsOf(true, Extraction::Cubes), 6, 1).runId, p.runId);
  try {
    planBrickJobs(box, settingsOf(true, Extraction::Cubes), 7, 0);  // no axis has 7 bricks
    FAIL() << "7 jobs accepted";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("5 x 3 x 2 bricks"), std::string::npos) << e.what();
  }
  EXPECT_THROW(planBrickJobs(box, settingsOf(true, Extraction::Cubes), 0, 0), ModelError);
  // what a job cannot take is refused naming the option
  MeshSettings refined = settingsOf(true, Extraction::Cubes);
  refined.refine = Refinement::ThinParts;
  try {
    planBrickJobs(box, refined, 6, 0);
    FAIL() << "a refinement accepted";
  } catch (const SettingError& e) {
    EXPECT_EQ(e.option, "refine");
  }
  EXPECT_THROW(jobBricks(p, 6, nullptr, nullptr), ModelError);
}

class PieceFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("frep-bricks-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
  std::size_t others() const {
    return static_cast<std::size_t>(
        std::distance(fs::directory_iterator(dir_), fs::directory_iterator()));
  }
  static std::string bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  static void put(const std::string& path, const std::string& data) {
    std::ofstream(path, std::ios::binary) << data;
  }
  fs::path dir_;
};

TEST_F(PieceFiles, RoundTripAndExportAsOneProcess) {
  const Model m = loadModel(std::string(FREP_SOURCE_DIR) + "/examples/csg.json");
  const Program p = compile(m.root);
  const MeshingBox box{*m.bbox, 2.4 / 64};
  const BrickJobPlan plan =
      planBrickJobs(box, settingsOf(true, Extraction::Cubes), 8, textFingerprint("csg"));
  std::vector<std::string> files;
  for (std::uint32_t j = 0; j < plan.jobs; ++j) {
    const MeshPiece piece = runBrickJob(p, plan, j);
    files.push_back(file("piece" + std::to_string(j)));
    writePieceFile(piece, files.back());
    const MeshPiece back = readPieceFile(files.back());
    EXPECT_EQ(back.keys, piece.keys);
    EXPECT_EQ(back.positions, piece.positions);
    EXPECT_EQ(back.triangles, piece.triangles);
    EXPECT_EQ(back.pendingFlips, piece.pendingFlips);
    EXPECT_EQ(back.runId, plan.runId);
  }
  ExportRequest request;
  const ExportResult r = exportPieces(plan, files, request, file("csg.stl"));
  ASSERT_TRUE(r.written);
  EXPECT_TRUE(r.report.printable());
  ExportRequest single;
  single.box.bbox = box.box;
  single.box.resolution = box.resolution;
  exportField(p, single, file("one.stl"), "csg");
  const TriangleMesh a = readMesh(file("csg.stl")), b = readMesh(file("one.stl"));
  EXPECT_TRUE(sortedTriangles(a) == sortedTriangles(b));
  EXPECT_TRUE(r.checkedInParts);
  // a 3MF streams too (vertices as they are numbered, triangles spilled until the last
  // vertex): the same triangles, every coordinate exact, one object named as asked
  const std::size_t before = others();
  ExportRequest threeMf;
  threeMf.objectName = "csg part";
  threeMf.threeMf.unit = LengthUnit::Centimeter;
  const ExportResult r3 = exportPieces(plan, files, threeMf, file("csg.3mf"));
  ASSERT_TRUE(r3.written);
  EXPECT_TRUE(r3.checkedInParts);
  EXPECT_EQ(reportToText(r3.report, "x"), reportToText(r.report, "x"));
  const ThreeMfContents c = read3mf(file("csg.3mf"));
  ASSERT_EQ(c.objects.size(), 1u);
  EXPECT_EQ(c.objects[0].name, "csg part");
  EXPECT_EQ(c.unit, LengthUnit::Centimeter);
  EXPECT_EQ(c.objects[0].mesh.triangles.size(), r3.triangles);
  EXPECT_TRUE(sortedTriangles(c.objects[0].mesh) == sortedTriangles(b));
  EXPECT_EQ(others(), before + 1) << "a temporary or the spill was left";
  // a piece of another run is refused, and nothing is written
  const BrickJobPlan other =
      planBrickJobs(box, settingsOf(false, Extraction::Cubes), 8, textFingerprint("csg"));
  writePieceFile(runBrickJob(p, other, 3), files[3]);
  EXPECT_THROW(exportPieces(plan, files, request, file("mixed.stl")), FileError);
  EXPECT_FALSE(fs::exists(file("mixed.stl")));
}

// A binary STL export of pieces streams the file while merging and checks the pieces one
// at a time: the report is the whole mesh's (the gyroid: several components, nested boxes,
// rays counted piece by piece), and a piece with a hole is refused, nothing written.
TEST_F(PieceFiles, TheCheckPieceByPieceIsTheWholeChecksReport) {
  for (const char* name : {"gyroid", "helix"}) {
    const Model m = loadModel(std::string(FREP_SOURCE_DIR) + "/examples/" + name + ".json");
    const Program p = compile(m.root);
    const MeshingBox box{*m.bbox, (m.bbox->hi[0] - m.bbox->lo[0]) / 80};
    for (std::uint32_t jobs : {8u, 27u}) {
      const BrickJobPlan plan = planBrickJobs(box, settingsOf(true, Extraction::Cubes), jobs, 5);
      std::vector<std::string> files;
      std::vector<MeshPiece> pieces;
      for (std::uint32_t j = 0; j < plan.jobs; ++j) {
        pieces.push_back(runBrickJob(p, plan, j));
        files.push_back(file(std::string(name) + std::to_string(j)));
        writePieceFile(pieces.back(), files.back());
      }
      const std::string out = file(std::string(name) + ".stl");
      const ExportResult r = exportPieces(plan, files, ExportRequest(), out);
      ASSERT_TRUE(r.written) << name;
      // the same with each piece judged by its job (a summary file beside it)
      std::vector<std::string> summaries;
      for (const MeshPiece& piece : pieces) {
        summaries.push_back(files[piece.job] + ".check");
        const std::vector<char> bytes = judgeBrickPiece(plan, piece);
        std::ofstream(summaries.back(), std::ios::binary)
            .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
      }
      const ExportResult byJobs = exportPieces(plan, files, ExportRequest(), out, summaries);
      EXPECT_TRUE(byJobs.checkedInParts);
      EXPECT_EQ(reportToText(byJobs.report, "x"), reportToText(r.report, "x"));
      // a summary of another job is refused, nothing written
      std::vector<std::string> swapped = summaries;
      std::swap(swapped[0], swapped[1]);
      EXPECT_THROW(exportPieces(plan, files, ExportRequest(), file("swapped.stl"), swapped),
                   FileError);
      EXPECT_FALSE(fs::exists(file("swapped.stl")));
      EXPECT_TRUE(r.checkedInParts) << name;
      const CheckReport whole = checkMesh(mergePieces(pieces));
      EXPECT_EQ(r.report.vertices, whole.vertices);
      EXPECT_EQ(r.report.inputVertices, whole.inputVertices);
      EXPECT_EQ(r.report.components, whole.components);
      EXPECT_EQ(r.report.selfIntersections, 0u);
      EXPECT_TRUE(r.report.outward);
      EXPECT_NEAR(r.report.volume, whole.volume, 1e-9 * whole.volume);
      EXPECT_NEAR(r.report.area, whole.area, 1e-9 * whole.area);  // (the flips across jobs too)
      EXPECT_EQ(r.report.reasons, whole.reasons);
      EXPECT_GT(whole.components, std::string(name) == "gyroid" ? 4u : 0u);
      EXPECT_TRUE(sortedTriangles(readMesh(out)) == sortedTriangles(mergePieces(pieces)));
      // a hole in one piece: refused, nothing written
      MeshPiece holed = pieces[jobs / 2];
      ASSERT_GT(holed.triangles.size(), 10u);
      holed.triangles.erase(holed.triangles.begin() + 5);
      holed.pendingFlips.clear();  // (its numbers moved)
      writePieceFile(holed, files[jobs / 2]);
      const std::size_t before = others();
      const ExportResult refused = exportPieces(plan, files, ExportRequest(), file("holed.stl"));
      EXPECT_FALSE(refused.written);
      EXPECT_TRUE(refused.checkedInParts);
      EXPECT_EQ(refused.report.borderEdges, 3u);
      EXPECT_FALSE(fs::exists(file("holed.stl")));
      EXPECT_EQ(others(), before) << "a temporary was left";
      const ExportResult refused3 = exportPieces(plan, files, ExportRequest(), file("holed.3mf"));
      EXPECT_FALSE(refused3.written);
      EXPECT_EQ(refused3.report.borderEdges, 3u);
      EXPECT_EQ(others(), before) << "a temporary or the spill was left";
    }
  }
}

TEST_F(PieceFiles, HostileFilesAreRefusedBeforeTheyCostMemory) {
  const Program p = compile(loadModel(std::string(FREP_SOURCE_DIR) + "/examples/sphere.json").root);
  const BrickJobPlan plan = planBrickJobs({{{-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2}}, 0.1},
                                          settingsOf(true, Extraction::Cubes), 1, 0);
  writePieceFile(runBrickJob(p, plan, 0), file("good"));
  const std::string good = bytes(file("good"));
  auto refused = [&](const std::string& data, const std::string& words) {
    put(file("bad"), data);
    try {
      readPieceFile(file("bad"));
      return ::testing::AssertionFailure() << "accepted";
    } catch (const FileError& e) {
      if (std::string(e.what()).find(words) == std::string::npos)
        return ::testing::AssertionFailure() << e.what();
      return ::testing::AssertionSuccess();
    }
  };
  EXPECT_TRUE(refused("", "header"));
  EXPECT_TRUE(refused("STL binary" + good.substr(10), "header"));
  EXPECT_TRUE(refused(good.substr(0, good.size() - 1), "size"));
  std::string huge = good;
  const std::uint64_t count = 1ull << 62;  // the vertex count: 8 + 8 + 4 + 4 + 72 bytes in
  std::memcpy(&huge[8 + 96], &count, 8);
  EXPECT_TRUE(refused(huge, "size"));
  std::string wrongVertex = good;  // the first triangle's first vertex, past the last
  const std::uint32_t far = 0xFFFFFFF0u;
  const std::size_t vertices = runBrickJob(p, plan, 0).keys.size();
  std::memcpy(&wrongVertex[8 + 120 + vertices * 20], &far, 4);
  EXPECT_TRUE(refused(wrongVertex, "vertex"));
  EXPECT_THROW(readPieceFile(file("missing")), FileError);
}

TEST(PieceMerge, RefusesRepeatedForeignAndMissingJobs) {
  const Program p = compile(loadModel(std::string(FREP_SOURCE_DIR) + "/examples/sphere.json").root);
  const MeshingBox box{{{-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2}}, 2.4 / 40};
  const BrickJobPlan plan = planBrickJobs(box, settingsOf(true, Extraction::Cubes), 8, 0);
  std::vector<MeshPiece> pieces;
  for (std::uint32_t j = 0; j < 8; ++j) pieces.push_back(runBrickJob(p, plan, j));
  auto refusal = [&](std::vector<MeshPiece> list) {
    try {
      mergePieces(list);
    } catch (const ModelError& e) {
      return std::string(e.what());
    }
    return std::string("merged");
  };
  std::vector<MeshPiece> twice = pieces;
  twice.push_back(pieces[2]);
  EXPECT_NE(refusal(twice).find("job 2: the job came twice"), std::string::npos);
  std::vector<MeshPiece> short_ = pieces;
  short_.erase(short_.begin() + 5);
  EXPECT_NE(refusal(short_).find("1 of 8 jobs have no piece (jobs 5)"), std::string::npos);
  std::vector<MeshPiece> foreign = pieces;
  foreign[4] = runBrickJob(p, planBrickJobs(box, settingsOf(true, Extraction::Cubes), 8, 99), 4);
  EXPECT_NE(refusal(foreign).find("another run"), std::string::npos);
  EXPECT_EQ(refusal(pieces), "merged");
}

}  // namespace
}  // namespace frep
