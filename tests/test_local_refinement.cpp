// Local refinement (mesh/local_refinement.h, MeshSettings::refine): parts thinner
// than a cell that the grid passes between are meshed at half a cell, and every mesh stays
// printable (CGAL's check), the same whatever the bricks.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "base/errors.h"
#include "base/triangle_geometry.h"
#include "check/mesh_check.h"
#include "frep/model_json.h"
#include "mesh/mesher.h"
#include "random_trees.h"
#include "sorted_triangles.h"

namespace frep {
namespace {

std::string reasonsOf(const CheckReport& r) {
  std::string s;
  for (const auto& x : r.reasons) s += x + "; ";
  return s;
}

using testing::sortedTriangles;

TriangleMesh meshModel(const std::string& json, bool refine, int brick, MeshingStats* stats) {
  const Model m = parseModel(json, "refine", ".");
  MeshingOptions o;
  o.bbox = *m.bbox;
  o.resolution = *m.resolution;
  o.brickCells = brick;
  o.settings.dropFlatVertices = brick % 2 == 0;
  o.settings.refine = refine ? Refinement::ThinParts : Refinement::Off;
  return polygonize(compile(m.root), o, stats);
}

// A wall 0.3 cell thick between two layers of grid points: the grid never sees it, so the
// mesh is empty; refined, the half-cell points in the middle of its cubes see it, and it is
// meshed, closed, with about its volume (0.03).
const char* kWall = R"({"frepcad": 1, "root": {"type": "box", "params":
  {"corner": [-0.015, -0.5, -0.5], "size": [0.03, 1, 1]}},
  "export": {"bbox": [-1, -1, -1, 1, 1, 1], "resolution": 0.1}})";

TEST(LocalRefinement, AWallBetweenTheGridsPointsIsMeshedAtHalfACell) {
  MeshingStats plain;
  EXPECT_EQ(meshModel(kWall, false, 16, &plain).triangleCount(), 0u);
  EXPECT_EQ(plain.refinedCubes, 0u);
  EXPECT_GT(plain.thinSolidEdges, 0u);
  MeshingStats stats;
  const TriangleMesh mesh = meshModel(kWall, true, 16, &stats);
  ASSERT_GT(mesh.triangleCount(), 0u) << stats.refinementSkipped;
  EXPECT_TRUE(stats.refinementSkipped.empty()) << stats.refinementSkipped;
  EXPECT_GE(stats.refinedCubes, 100u);  // the 10 x 10 cubes on either side at least
  const CheckReport r = checkMesh(mesh);
  EXPECT_TRUE(r.printable()) << reasonsOf(r);
  EXPECT_EQ(r.components, 1u);
  EXPECT_NEAR(r.volume, 0.03, 0.003);
  // the same mesh whatever the bricks (the refinement works on the welded mesh)
  for (int brick : {4, 10}) {
    MeshingStats other;
    EXPECT_EQ(sortedTriangles(meshModel(kWall, true, brick, &other)), sortedTriangles(mesh))
        << brick;
  }
}

// Deeper levels (MeshingOptions::refinementLevels): a wall 0.3 cell thick between two
// layers of the half-cell grid's points, around a point of the quarter-cell grid. One level
// of refinement sees nothing; two mesh it, closed, with about its volume (0.03).
TEST(LocalRefinement, AWallBetweenTheHalfCellPointsIsMeshedAtAQuarterCell) {
  const char* wall = R"({"frepcad": 1, "root": {"type": "box", "params":
    {"corner": [0.01, -0.5, -0.5], "size": [0.03, 1, 1]}},
    "export": {"bbox": [-1, -1, -1, 1, 1, 1], "resolution": 0.1}})";
  const Model m = parseModel(wall, "refine", ".");
  MeshingOptions o;
  o.bbox = *m.bbox;
  o.resolution = *m.resolution;
  o.settings.refine = Refinement::ThinParts;
  MeshingStats one, two;
  EXPECT_EQ(polygonize(compile(m.root), o, &one).triangleCount(), 0u);
  EXPECT_EQ(one.refinedDeeperCubes, 0u);
  o.settings.refineLevels = 2;
  const TriangleMesh mesh = polygonize(compile(m.root), o, &two);
  ASSERT_GT(mesh.triangleCount(), 0u) << two.refinementSkipped << two.refinementDeeperSkipped;
  EXPECT_EQ(two.refinementLevelsReached, 2);
  EXPECT_GE(two.refinedDeeperCubes, 400u);  // 10 x 10 cubes' half cubes on either side
  const CheckReport r = checkMesh(mesh);
  EXPECT_TRUE(r.printable()) << reasonsOf(r);
  EXPECT_EQ(r.components, 1u);
  EXPECT_NEAR(r.volume, 0.03, 0.003);
}

// A model's own box and cell, its crease tips refined two levels deep.
MeshingOptions tipsTwoLevelsDeep(const Model& m) {
  MeshingOptions o;
  o.bbox = *m.bbox;
  o.resolution = *m.resolution;
  o.settings.refine = Refinement::Tips;
  o.settings.refineLevels = 2;
  return o;
}

// The reference gyroid at 512 cells, in a box of 40 cells round a sliver of sheet about
// an eighth of a cell thick that runs aslant across a cube from an inside corner to the
// opposite edge. Its quarter-cell points see it only as points touching at their corners
// (faces whose sides lie on the diagonals), no edge or face with both ends on one side and
// the other between; the quarter-cell crossings lie near enough to the mesh one level
// makes. Two levels now refine that cube's half cubes: every point of the surface round the
// sliver's tip lies within 0.3 cell of the mesh (it was 0.56 cell when only sign tests
// chose the half cubes).
TEST(LocalRefinement, ASliverAslantAcrossTheQuarterCellsIsRefinedAtTheTip) {
  const double cell = 2.4 / 512;
  const char* gyroid = R"({"frepcad": 1, "root": {"type": "intersection", "inputs": [
    {"type": "gyroid", "params": {"cell": 0.33333333333333333, "level": 0.3, "kind": "sheet",
     "origin": [0, 0, 0]}},
    {"type": "sphere", "params": {"center": [0, 0, 0], "radius": 1}}]},
    "export": {"bbox": [-0.534375, 0.759375, -0.3703125, -0.346875, 0.946875, -0.1828125],
               "resolution": 0.0046875}})";
  const Model m = parseModel(gyroid, "refine", ".");
  const Program field = compile(m.root);
  MeshingOptions o = tipsTwoLevelsDeep(m);
  MeshingStats stats;
  const TriangleMesh mesh = polygonize(field, o, &stats);
  EXPECT_EQ(stats.refinementLevelsReached, 2) << stats.refinementDeeperSkipped;
  const CheckReport r = checkMesh(mesh);
  ASSERT_TRUE(r.printable()) << reasonsOf(r);
  // the surface round the tip: crossings of a lattice of eighth cells, three cells each way
  const Vec3d tip{-0.4386, 0.8552, -0.2758};
  const int n = 49;
  auto at = [&](int i, int j, int k) {
    return Vec3d{tip[0] + (i - 24) * cell / 8, tip[1] + (j - 24) * cell / 8,
                 tip[2] + (k - 24) * cell / 8};
  };
  std::vector<std::array<Vec3d, 3>> near;
  for (const Triangle& t : mesh.triangles) {
    std::array<Vec3d, 3> v;
    bool close = true;
    for (int c = 0; c < 3; ++c) {
      const Vec3f& p = mesh.positions[t[c]];
      v[c] = Vec3d{p[0], p[1], p[2]};
      for (int a = 0; a < 3; ++a) close = close && std::abs(v[c][a] - tip[a]) < 6 * cell;
    }
    if (close) near.push_back(v);
  }
  ASSERT_GT(near.size(), 20u);
  double worst = 0.0;
  std::size_t crossings = 0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const Vec3d p = at(i, j, k);
        const double fp = field.eval(p[0], p[1], p[2]);
        for (int a = 0; a < 3; ++a) {
          int d[3] = {i, j, k};
          if (++d[a] >= n) continue;
          const Vec3d q = at(d[0], d[1], d[2]);
          const double fq = field.eval(q[0], q[1], q[2]);
          if ((fp >= 0) == (fq >= 0)) continue;
          ++crossings;
          const double t = fp / (fp - fq);
          const Vec3d s{p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1]),
                        p[2] + t * (q[2] - p[2])};
          double best = 1e9;
          for (const auto& v : near) {
            const Vec3d c = closestPointOnTriangle(s, v[0], v[1], v[2]);
            best = std::min(
                best, std::sqrt((c[0] - s[0]) * (c[0] - s[0]) + (c[1] - s[1]) * (c[1] - s[1]) +
                                (c[2] - s[2]) * (c[2] - s[2])));
          }
          worst = std::max(worst, best);
        }
      }
  EXPECT_GT(crossings, 1000u);
  EXPECT_LT(worst / cell, 0.3);
}

// The refinement is most of the time where it runs (ten times the meshing's and more with
// deeper levels): it moves the bar on and can be cancelled, as the bricks can.
TEST(LocalRefinement, DeeperLevelsReportProgressAndCanBeCancelled) {
  const char* gyroid = R"({"frepcad": 1, "root": {"type": "intersection", "inputs": [
    {"type": "gyroid", "params": {"cell": 0.5, "level": 0.3, "kind": "sheet",
     "origin": [0, 0, 0]}},
    {"type": "sphere", "params": {"center": [0, 0, 0], "radius": 1}}]},
    "export": {"bbox": [-1.2, -1.2, -1.2, 1.2, 1.2, 1.2], "resolution": 0.08}})";
  const Model m = parseModel(gyroid, "refine", ".");
  const Program field = compile(m.root);
  MeshingOptions o = tipsTwoLevelsDeep(m);
  std::vector<double> seen;
  o.progress = [&seen](double f) {
    seen.push_back(f);
    return true;
  };
  MeshingStats stats;
  const TriangleMesh mesh = polygonize(field, o, &stats);
  ASSERT_EQ(stats.refinementLevelsReached, 2) << stats.refinementDeeperSkipped;
  ASSERT_FALSE(seen.empty());
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
  EXPECT_DOUBLE_EQ(seen.back(), 1.0);
  // the refinement's own steps: past the bricks' share (5 %), before the end
  const auto during =
      std::count_if(seen.begin(), seen.end(), [](double f) { return f > 0.05 && f < 0.95; });
  EXPECT_GE(during, 5) << seen.size() << " calls";
  // a cancel in the look, and one in the second level (past the look and the first), stop it
  EXPECT_TRUE(std::any_of(seen.begin(), seen.end(), [](double f) { return f > 0.7 && f < 0.9; }));
  for (double at : {0.2, 0.8}) {
    o.progress = [at](double f) { return f < at; };
    EXPECT_THROW(polygonize(field, o), Cancelled) << at;
  }
}

TEST(LocalRefinement, RefinementLevelsOutOfRangeAreRefused) {
  const Model m = parseModel(kWall, "refine", ".");
  MeshingOptions o;
  o.bbox = *m.bbox;
  o.resolution = *m.resolution;
  o.settings.refine = Refinement::ThinParts;
  for (int levels : {0, kMaxRefinementLevels + 1}) {
    o.settings.refineLevels = levels;
    try {
      polygonize(compile(m.root), o);
      ADD_FAILURE() << levels;
    } catch (const ModelError& e) {
      EXPECT_NE(std::string(e.what()).find("refine_levels must be a whole number from 1 to 3"),
                std::string::npos)
          << e.what();
    }
  }
}

// A slit 0.3 cell wide through a cube: the grid closes it; refined, it is cut open again and
// the volume falls by about the slit's (0.03).
TEST(LocalRefinement, ASlitTheGridClosesIsOpenedAgain) {
  const char* slit = R"({"frepcad": 1, "root": {"type": "difference", "inputs": [
    {"type": "box", "params": {"corner": [-0.5, -0.5, -0.5], "size": [1, 1, 1]}},
    {"type": "box", "params": {"corner": [-0.015, -1, -1], "size": [0.03, 2, 2]}}]},
    "export": {"bbox": [-1, -1, -1, 1, 1, 1], "resolution": 0.1}})";
  MeshingStats plain, stats;
  const CheckReport closed = checkMesh(meshModel(slit, false, 16, &plain));
  const TriangleMesh mesh = meshModel(slit, true, 16, &stats);
  const CheckReport open = checkMesh(mesh);
  ASSERT_TRUE(open.printable()) << reasonsOf(open);
  EXPECT_NEAR(closed.volume, 1.0, 0.01);
  EXPECT_NEAR(open.volume, 0.97, 0.01);
  EXPECT_EQ(open.components, 2u);  // the two halves
}

// Models with nothing hidden are left as they were.
TEST(LocalRefinement, ASphereIsLeftAsItWas) {
  const char* sphere = R"({"frepcad": 1, "root": {"type": "sphere", "params": {"radius": 0.8}},
    "export": {"bbox": [-1, -1, -1, 1, 1, 1], "resolution": 0.05}})";
  MeshingStats plain, stats;
  const TriangleMesh a = meshModel(sphere, false, 16, &plain);
  const TriangleMesh b = meshModel(sphere, true, 16, &stats);
  EXPECT_EQ(stats.refinedCubes, 0u);
  EXPECT_EQ(sortedTriangles(a), sortedTriangles(b));
}

// Random trees (thin walls, tangent contacts, sharp CSG, faces on grid planes) refined: every
// mesh printable by the check, whatever was refined, sharp features on and off; and the same
// mesh for two brick sizes. 96 trees here, 1,000 in the acceptance tier.
void refineRandomTrees(unsigned seed, int trees, int levels = 1) {
  testing::RandomTrees rng(seed);
  const double resolutions[] = {1.0 / 8, 1.0 / 12, 1.0 / 16, 1.0 / 20};
  int refined = 0;
  for (int i = 0; i < trees; ++i) {
    const NodePtr tree = rng.tree(rng.integer(1, 4));
    const Program program = compile(tree);
    MeshingOptions o;
    o.bbox = {{-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2}};
    o.resolution = resolutions[rng.integer(0, 3)];
    o.brickCells = 16;
    o.settings.dropFlatVertices = rng.integer(0, 1) == 1;
    o.settings.sharpFeatures = rng.integer(0, 3) != 0;
    o.settings.refine = rng.integer(0, 3) != 0 ? Refinement::Tips : Refinement::ThinParts;
    o.settings.refineLevels = levels;
    MeshingStats stats;
    const TriangleMesh mesh = polygonize(program, o, &stats);
    refined += levels > 1 ? stats.refinedDeeperCubes > 0 : stats.refinedCubes > 0;
    if (mesh.triangleCount() == 0) continue;
    const CheckReport r = checkMesh(mesh);
    ASSERT_TRUE(r.printable()) << "tree " << i << " at " << o.resolution << " ("
                               << stats.refinedCubes << " cubes refined): " << reasonsOf(r) << "\n"
                               << modelToJson(Model{tree, o.bbox, o.resolution, "", {}, {}});
    if (i % 8 == 0 && o.settings.dropFlatVertices) {
      MeshingOptions other = o;
      other.brickCells = 6;
      EXPECT_EQ(sortedTriangles(polygonize(program, other)), sortedTriangles(mesh)) << "tree " << i;
    }
  }
  EXPECT_GT(refined, trees / 10);  // the trees have thin parts to refine (deeper too)
}

TEST(LocalRefinement, RandomTreesStayPrintable) {
  refineRandomTrees(7100, 120);
}

class LocalRefinementShard : public ::testing::TestWithParam<int> {};

TEST_P(LocalRefinementShard, RandomTreesStayPrintableAcceptance) {
  refineRandomTrees(7200 + static_cast<unsigned>(GetParam()), 125);
}

INSTANTIATE_TEST_SUITE_P(Shards, LocalRefinementShard, ::testing::Range(0, 8));

// Two and three levels: the half cubes refined again, every mesh still printable.
TEST(LocalRefinement, RandomTreesStayPrintableTwoAndThreeLevelsDeep) {
  refineRandomTrees(7300, 40, 2);
  refineRandomTrees(7301, 16, 3);
}

TEST_P(LocalRefinementShard, RandomTreesStayPrintableTwoAndThreeLevelsDeepAcceptance) {
  refineRandomTrees(7400 + static_cast<unsigned>(GetParam()), 60, 2 + GetParam() % 2);
}

}  // namespace
}  // namespace frep
