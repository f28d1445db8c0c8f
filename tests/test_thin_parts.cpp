// Parts thinner than a cell (mesh/hidden_parts.h, MeshingStats): the tent test and its sieve,
// and the mesher's counts on walls and gaps that fall between the grid's points, on crease
// tips, and on models with none, the same whatever the bricks.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "frep/model_json.h"
#include "mesh/hidden_parts.h"
#include "mesh/mesher.h"

namespace frep {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(ThinParts, ATentThatReachesZeroIsFoundWhereItsLinesMeet) {
  double t = -1.0;
  // outside at both ends, rising by 0.1 a cell towards the edge from both sides: the lines
  // meet at the middle at -0.035 + 0.05 = 0.015 > 0
  ASSERT_TRUE(tentCrossesZero(-0.135, -0.035, -0.035, -0.135, &t));
  EXPECT_DOUBLE_EQ(t, 0.5);
  // lopsided: -0.1 + 0.3 t = -0.05 + 0.1 (1 - t) -> t = 0.15 / 0.4, the peak 0.0125
  ASSERT_TRUE(tentCrossesZero(-0.4, -0.1, -0.05, -0.15, &t));
  EXPECT_NEAR(t, 0.375, 1e-12);
  // the mirror image: a gap between two inside points
  ASSERT_TRUE(tentCrossesZero(0.135, 0.035, 0.035, 0.135, &t));
  EXPECT_DOUBLE_EQ(t, 0.5);
}

TEST(ThinParts, NoTentWhereTheLinesMeetShortOfZeroOrTheFieldIsMonotone) {
  double t = -1.0;
  EXPECT_FALSE(tentCrossesZero(-0.2, -0.1, -0.1, -0.2, &t));      // peak -0.05
  EXPECT_FALSE(tentCrossesZero(-0.4, -0.3, -0.2, -0.1, &t));      // rising all along
  EXPECT_FALSE(tentCrossesZero(-0.1, -0.2, -0.2, -0.1, &t));      // a valley seen from outside
  EXPECT_FALSE(tentCrossesZero(-0.135, -0.035, 0.01, -0.1, &t));  // ends on two sides
  EXPECT_FALSE(tentCrossesZero(0.2, 0.1, 0.1, 0.2, &t));          // valley at 0.05: still inside
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(tentCrossesZero(-0.135, nan, -0.035, -0.135, &t));
  EXPECT_FALSE(tentCrossesZero(nan, -0.035, -0.035, -0.135, &t));
  EXPECT_DOUBLE_EQ(t, -1.0);  // untouched when there is none
}

// The sieve is a necessary condition: it never drops an edge the tent test takes, on random
// rows (values on a coarse lattice, so ties and exact zeros occur), with infinite stand-ins.
TEST(ThinParts, TheSieveKeepsEveryTent) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> step(-8, 8);
  std::vector<double> before(64), a(64), b(64), after(64), flags(64);
  int tents = 0, flagged = 0;
  for (int round = 0; round < 2000; ++round) {
    for (int i = 0; i < 64; ++i) {
      before[i] = step(rng) / 16.0;
      a[i] = step(rng) / 16.0;
      b[i] = step(rng) / 16.0;
      after[i] = step(rng) / 16.0;
    }
    const bool any =
        sieveTentRow(before.data(), a.data(), b.data(), after.data(), 64, flags.data());
    bool seen = false;
    for (int i = 0; i < 64; ++i) {
      double t;
      const bool tent = tentCrossesZero(before[i], a[i], b[i], after[i], &t);
      tents += tent;
      flagged += flags[i] != 0.0;
      seen = seen || flags[i] != 0.0;
      if (tent) {
        ASSERT_EQ(flags[i], 1.0) << before[i] << " " << a[i] << " " << b[i] << " " << after[i];
      }
    }
    ASSERT_EQ(any, seen);
  }
  EXPECT_GT(tents, 100);              // the rows hold tents
  EXPECT_LT(flagged, 2000 * 64 / 4);  // and the sieve passes few of the rest
  // Stand-ins: of the ends' side they pass as neighbours; as ends, or of the other side, not.
  const double bf[4] = {-kInf, -0.2, -0.135, kInf}, af[4] = {-0.035, -0.035, -kInf, -0.035},
               bb[4] = {-0.035, -0.035, -0.035, -0.035}, aa[4] = {-kInf, -kInf, -0.135, -0.135};
  double f4[4];
  sieveTentRow(bf, af, bb, aa, 4, f4);
  EXPECT_EQ(f4[0], 1.0);
  EXPECT_EQ(f4[1], 1.0);
  EXPECT_EQ(f4[2], 0.0);  // an end proven outside: no tent rises to it
  EXPECT_EQ(f4[3], 0.0);  // a neighbour proven inside: none falls from it
}

MeshingStats meshJson(const std::string& json, int brick = 16, TriangleMesh* mesh = nullptr) {
  const Model m = parseModel(json, "thin", ".");
  MeshingOptions o;
  o.bbox = *m.bbox;
  o.resolution = 0.1;
  o.brickCells = brick;
  o.settings.dropFlatVertices = brick % 2 == 0;  // (flat vertices need an even brick size)
  MeshingStats stats;
  TriangleMesh t = polygonize(compile(m.root), o, &stats);
  if (mesh) *mesh = std::move(t);
  return stats;
}

// A wall 0.3 cell thick between two layers of grid points (x = -0.05 and 0.05 at 0.1 cells in
// [-1, 1]): no grid point is inside, the mesh is empty, and each of the 10 x 10 grid edges
// through the wall is counted, the same whatever the bricks.
const char* kWall = R"({"frepcad": 1, "root": {"type": "box", "params":
  {"corner": [-0.015, -0.5, -0.5], "size": [0.03, 1, 1]}},
  "export": {"bbox": [-1, -1, -1, 1, 1, 1], "resolution": 0.1}})";

TEST(ThinParts, AWallBetweenTheGridsPointsIsCountedEdgeByEdge) {
  // Bricks of 10 and 11 cells start and end at the wall: a point beside an edge lies in the
  // neighbour brick (6 does not divide the grid).
  for (int brick : {16, 4, 6, 10, 11}) {
    TriangleMesh mesh;
    const MeshingStats s = meshJson(kWall, brick, &mesh);
    EXPECT_EQ(mesh.triangleCount(), 0u);
    EXPECT_EQ(s.thinSolidEdges, 100u) << brick;
    EXPECT_EQ(s.thinGapEdges, 0u);
    EXPECT_EQ(s.tipEdges, 0u);
    // the first in grid order: the wall's middle on the edge at the lowest y and z
    EXPECT_NEAR(s.thinExample[0], 0.0, 1e-12) << brick;
    EXPECT_DOUBLE_EQ(s.thinExample[1], -0.45);
    EXPECT_DOUBLE_EQ(s.thinExample[2], -0.45);
  }
  // where looking is turned off, nothing is counted and the mesh is the same
  const Model m = parseModel(kWall, "thin", ".");
  MeshingOptions o;
  o.bbox = *m.bbox;
  o.resolution = 0.1;
  o.findThinParts = false;
  MeshingStats off;
  EXPECT_EQ(polygonize(compile(m.root), o, &off).triangleCount(), 0u);
  EXPECT_EQ(off.thinSolidEdges, 0u);
}

// A slit 0.3 cell wide through a unit cube: the cube is meshed whole, the slit closed. The
// 8 x 8 edges with the cube's inside all round them are gaps seen nowhere near (the rows next
// to the cube's faces see the box's own surface; there the box's field flattens the tent).
TEST(ThinParts, ASlitBetweenTheGridsPointsIsAGapTheMeshCloses) {
  const char* slit = R"({"frepcad": 1, "root": {"type": "difference", "inputs": [
    {"type": "box", "params": {"corner": [-0.5, -0.5, -0.5], "size": [1, 1, 1]}},
    {"type": "box", "params": {"corner": [-0.015, -1, -1], "size": [0.03, 2, 2]}}]},
    "export": {"bbox": [-1, -1, -1, 1, 1, 1], "resolution": 0.1}})";
  for (int brick : {16, 4, 10, 11}) {
    TriangleMesh mesh;
    const MeshingStats s = meshJson(slit, brick, &mesh);
    EXPECT_GT(mesh.triangleCount(), 0u);
    EXPECT_EQ(s.thinGapEdges, 64u) << brick;
    EXPECT_EQ(s.thinSolidEdges, 0u);
    EXPECT_NEAR(s.thinExample[0], 0.0, 1e-12);
    EXPECT_DOUBLE_EQ(s.thinExample[1], -0.35);
  }
}

// A sharp crease not along the grid: its tip passes between grid points beside the surface
// (tips, no warning), and a plain sphere has nothing thin at all.
TEST(ThinParts, CreaseTipsAreTipsAndASphereHasNone) {
  const Model twist = loadModel(std::string(FREP_SOURCE_DIR) + "/examples/twist.json");
  MeshingOptions o;
  o.bbox = *twist.bbox;
  o.resolution = 2.4 / 64;
  MeshingStats s;
  polygonize(compile(twist.root), o, &s);
  EXPECT_GT(s.tipEdges, 20u);
  EXPECT_EQ(s.thinSolidEdges + s.thinGapEdges, 0u);
  MeshingStats again;
  o.brickCells = 8;
  polygonize(compile(twist.root), o, &again);
  EXPECT_EQ(again.tipEdges, s.tipEdges);  // whatever the bricks

  const Model sphere = loadModel(std::string(FREP_SOURCE_DIR) + "/examples/sphere.json");
  o.bbox = *sphere.bbox;
  o.resolution = 2.4 / 64;
  MeshingStats none;
  polygonize(compile(sphere.root), o, &none);
  EXPECT_EQ(none.thinSolidEdges + none.thinGapEdges + none.tipEdges, 0u);
}

}  // namespace
}  // namespace frep
