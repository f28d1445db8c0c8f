// Repair of meshes broken on purpose: each defect repaired, and a corpus of the cases a
// repair must not destroy (open sheets, fans, thin panels, scans with holes, many pieces),
// each either accepted faithful to its input, measured here independently, or refused with
// its reason and figures.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "base/errors.h"
#include "check/mesh_check.h"
#include "check/mesh_deviation.h"
#include "repair/repair.h"
#include "repair_samples.h"

namespace frep {
namespace {

std::string reasons(const RepairResult& r) {
  std::string s;
  for (const std::string& x : r.after.reasons) s += x + "; ";
  for (const std::string& x : r.departures) s += x + "; ";
  return s;
}

bool saysSomewhere(const std::vector<std::string>& lines, const std::string& words) {
  return std::any_of(lines.begin(), lines.end(),
                     [&](const std::string& l) { return l.find(words) != std::string::npos; });
}

// The diagonal of the box of the vertices the triangles use.
double diagonalOf(const TriangleMesh& m) {
  Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (const Triangle& t : m.triangles)
    for (std::uint32_t v : t)
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], double(m.positions[v][a]));
        hi[a] = std::max(hi[a], double(m.positions[v][a]));
      }
  return std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                   (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

RepairResult repaired(const TriangleMesh& m, RebuildPolicy rebuild = RebuildPolicy::Auto,
                      double voxel = 0.0) {
  RepairOptions o;
  o.rebuild = rebuild;
  o.voxel = voxel;
  return repairMesh(m, o, "test mesh");
}

TEST(Repair, HolesAreFilled) {
  const TriangleMesh good = sphereMesh();
  TriangleMesh m = good;
  for (std::size_t k = 0; k < 6; ++k) m.triangles.erase(m.triangles.begin() + 97 * k * 5);
  ASSERT_FALSE(checkMesh(m).printable());
  const RepairResult r = repaired(m);
  EXPECT_TRUE(r.accepted()) << reasons(r);
  EXPECT_FALSE(r.rebuilt);
  EXPECT_LT(meshDeviation(r.mesh, good).hausdorff(), 0.05);
  EXPECT_NEAR(r.after.volume, checkMesh(good).volume, 0.01 * checkMesh(good).volume);
}

TEST(Repair, FlippedTrianglesAndAnInsideOutShellAreTurnedOutward) {
  const TriangleMesh good = sphereMesh();
  TriangleMesh flipped = good, inside = good;
  std::mt19937 rng(7);
  for (auto& t : flipped.triangles)
    if (rng() % 10 == 0) std::swap(t[1], t[2]);
  for (auto& t : inside.triangles) std::swap(t[1], t[2]);
  for (const TriangleMesh* m : {&flipped, &inside}) {
    ASSERT_FALSE(checkMesh(*m).printable());
    const RepairResult r = repaired(*m);
    EXPECT_TRUE(r.printable()) << reasons(r);
    EXPECT_TRUE(r.after.outward);
    EXPECT_GT(r.after.volume, 0);
    EXPECT_LT(r.deviation.hausdorff(), 1e-6);  // nothing moved
  }
}

TEST(Repair, DuplicateTrianglesDegenerateOnesAndNearlyCoincidentVerticesAreCleanedUp) {
  const TriangleMesh good = sphereMesh();
  TriangleMesh m = good;
  // Every triangle its own three vertices (as STL stores them), some nudged by a float ulp or
  // two (cracks of CAD exports), 40 triangles twice, and 30 zero-area triangles.
  TriangleMesh soup;
  for (const auto& t : m.triangles) {
    const auto base = static_cast<std::uint32_t>(soup.positions.size());
    for (std::uint32_t v : t) {
      Vec3f p = m.positions[v];
      if ((base + v) % 17 == 0) p[0] = std::nextafter(p[0], 10.0f);
      soup.positions.push_back(p);
    }
    soup.triangles.push_back({base, base + 1, base + 2});
  }
  for (int k = 0; k < 40; ++k) soup.triangles.push_back(soup.triangles[k * 11]);
  for (int k = 0; k < 30; ++k) {
    const Triangle t = soup.triangles[k * 13];
    soup.triangles.push_back({t[0], t[1], t[1]});
  }
  const CheckReport before = checkMesh(soup);
  ASSERT_FALSE(before.printable());
  EXPECT_GT(before.degenerateFaces, 0u);
  const RepairResult r = repaired(soup);
  EXPECT_TRUE(r.printable()) << reasons(r);
  EXPECT_FALSE(r.rebuilt);
  EXPECT_EQ(r.after.faces, good.triangles.size());
  EXPECT_LT(r.deviation.hausdorff(), 1e-5);
}

// Cracks wider than the first weld (a hundredth of the median edge): the weld widens while
// that closes borders, so the mesh keeps its own triangles, no hole filled, no rebuild.
TEST(Repair, WiderCracksAreWeldedNotRebuilt) {
  const TriangleMesh good = sphereMesh();
  double sum = 0;
  for (const Triangle& t : good.triangles) {
    const Vec3f& a = good.positions[t[0]];
    const Vec3f& b = good.positions[t[1]];
    sum += std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                     (a[2] - b[2]) * (a[2] - b[2]));
  }
  const double jitter = 0.004 * sum / double(good.triangles.size());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-jitter, jitter);
  TriangleMesh soup;  // every triangle its own corners, each corner moved a little
  for (const Triangle& t : good.triangles) {
    const auto base = static_cast<std::uint32_t>(soup.positions.size());
    for (std::uint32_t v : t) {
      Vec3f p = good.positions[v];
      for (float& x : p) x += float(u(rng));
      soup.positions.push_back(p);
    }
    soup.triangles.push_back({base, base + 1, base + 2});
  }
  const RepairResult r = repaired(soup);
  EXPECT_TRUE(r.printable()) << reasons(r);
  EXPECT_FALSE(r.rebuilt);
  for (const auto& a : r.actions) EXPECT_EQ(a.find("filled"), std::string::npos) << a;
  EXPECT_EQ(r.after.faces, good.triangles.size());
  EXPECT_LT(r.deviation.hausdorff(), 4 * jitter);
}

TEST(Repair, IntersectingShellsAreRebuiltIntoTheirUnion) {
  const TriangleMesh a = sphereMesh(1.0, {0, 0, 0}), b = sphereMesh(1.0, {1.0, 0.2, 0});
  const TriangleMesh m = merged(a, b);
  const CheckReport before = checkMesh(m);
  ASSERT_GT(before.selfIntersections, 0u);
  // Local repairs alone cannot make one solid of two crossing shells: the command says why.
  const RepairResult r = repaired(m, RebuildPolicy::Auto, 0.03);
  EXPECT_TRUE(r.printable()) << reasons(r);
  EXPECT_TRUE(r.rebuilt);
  EXPECT_EQ(r.after.components, 1u);
  // The union of two unit spheres sqrt(1.04) apart: twice the sphere less the lens between.
  const double d = std::sqrt(1.04);
  const double lens = M_PI / 12 * (4 + d) * (2 - d) * (2 - d);
  const double exact = 2 * 4.0 / 3 * M_PI - lens;
  EXPECT_NEAR(r.after.volume, exact, 0.01 * exact);
  // Every point of the result lies on the input's surface, within a voxel (the input's
  // inner caps are gone from the result, as they must be).
  EXPECT_LT(r.deviation.bToA, r.voxel) << r.voxel;
  EXPECT_GT(r.deviation.aToB, 0.5);
}

// An open sheet has no inside: hole filling closes it flat, and neither CGAL nor the level
// set can make a solid of that. The repair says why instead of writing something.
TEST(Repair, ASheetCannotBecomeASolidAndTheRepairSaysWhy) {
  TriangleMesh sheet = gridBox({0, 0, 0}, {1, 1, 1}, 3);
  sheet.triangles.resize(18);  // one face of the box
  const RepairResult r = repaired(sheet);
  EXPECT_FALSE(r.printable());
  EXPECT_FALSE(r.after.reasons.empty());
  bool none = false;
  for (const auto& a : r.actions) none = none || a.find("encloses no volume") != std::string::npos;
  EXPECT_TRUE(none);
  RepairOptions o;
  o.fillHoles = false;
  const RepairResult open = repairMesh(sheet, o, "sheet");
  EXPECT_FALSE(open.printable());
  EXPECT_GT(open.after.borderEdges, 0u);
  bool said = false;
  for (const auto& a : open.actions) said = said || a.find("no rebuild") != std::string::npos;
  EXPECT_TRUE(said);
}

// Holes beside flipped triangles leave, after the local repairs, a watertight mesh with
// non-manifold edges (the soup's split points fall together again in float coordinates):
// the level set's flood fill does not mind them, so the rebuild runs and passes.
TEST(Repair, AWatertightButNonManifoldResultIsRebuilt) {
  const TriangleMesh good = sphereMesh(1.0, {0, 0, 0}, 0.1);
  TriangleMesh m = good;
  for (std::size_t i = 0; i < m.triangles.size(); ++i)
    if (i % 3 == 0) std::swap(m.triangles[i][1], m.triangles[i][2]);
  std::vector<Triangle> kept;
  for (std::size_t i = 0; i < m.triangles.size(); ++i)
    if (i % 53 != 7) kept.push_back(m.triangles[i]);
  m.triangles = kept;
  const RepairResult r = repaired(m, RebuildPolicy::Auto, 0.04);
  EXPECT_TRUE(r.printable()) << reasons(r);
  EXPECT_LT(meshDeviation(r.mesh, good).hausdorff(), 0.1);
  // the rebuild's mesh is simplified: about as many triangles as the input, not a few per voxel
  if (r.rebuilt) {
    EXPECT_LT(r.mesh.triangles.size(), 4 * good.triangles.size());
  }
}

TEST(Repair, APrintableMeshIsLeftAsItIs) {
  const TriangleMesh good = sphereMesh();
  const RepairResult r = repaired(good);
  EXPECT_TRUE(r.before.printable());
  EXPECT_TRUE(r.printable());
  EXPECT_EQ(r.after.faces, good.triangles.size());
  EXPECT_LT(r.deviation.hausdorff(), 1e-9);
}

TEST(Repair, WeldingKeepsTheFirstVertexAndNeverChains) {
  TriangleMesh m;
  // A row of vertices 0.6 apart, welded within 1: only pairs within 1 of a kept vertex merge.
  for (int i = 0; i < 5; ++i) m.positions.push_back({0.6f * i, 0, 0});
  m.positions.push_back({0, 2, 0});
  m.triangles = {{0, 1, 5}, {2, 3, 5}, {3, 4, 5}};
  std::size_t removed = 0;
  const std::size_t moved = weldNearbyVertices(m, 1.0, removed);
  EXPECT_EQ(moved, 2u);  // 1 -> 0 and 3 -> 2; 2 (1.2 from 0) and 4 (1.2 from 2) are kept
  EXPECT_EQ(removed, 2u);
  ASSERT_EQ(m.triangles.size(), 1u);
  EXPECT_EQ(m.triangles[0], (Triangle{2, 4, 5}));
}

TEST(Repair, BadOptionsAreRefusedNamingTheMesh) {
  RepairOptions o;
  o.voxel = -1;
  try {
    repairMesh(sphereMesh(), o, "part.stl");
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("part.stl"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("voxel"), std::string::npos);
  }
  EXPECT_THROW(parseRebuildPolicy("sometimes"), ModelError);
}

TEST(Repair, CancelStopsIt) {
  RepairOptions o;
  int calls = 0;
  o.progress = [&](double) { return ++calls < 3; };
  TriangleMesh m = sphereMesh();
  m.triangles.pop_back();
  EXPECT_THROW(repairMesh(m, o, "m"), Cancelled);
}

// ---- the corpus: nothing destroyed ----------------------------------------------------------

// Each case of the corpus, judged here without the repair's own figures: an accepted result
// is printable, has no more pieces than the input and lies within the bound of it both ways
// (measured plainly: none of these inputs has inner walls a union may absorb); a refused
// one says why.
void expectKeptOrRefused(const TriangleMesh& input, const RepairResult& r, const char* label) {
  SCOPED_TRACE(label);
  const double bound = kDefaultDeviationFraction * diagonalOf(input);
  EXPECT_NEAR(r.deviationBound, bound, 1e-6 * bound);
  if (r.accepted()) {
    const CheckReport c = checkMesh(r.mesh);
    EXPECT_TRUE(c.printable());
    EXPECT_LE(c.components, checkMesh(input).components);
    const DeviationReport d = meshDeviation(input, r.mesh);
    EXPECT_LE(d.bToA, bound);
    EXPECT_LE(d.aToB, bound);
  } else {
    EXPECT_FALSE(r.after.reasons.empty() && r.departures.empty()) << "refused without a reason";
  }
}

// A bowl (a sphere's lower half, open at the top): the hole filling closes it with a flat cap
// up to a radius from any input surface. That is invented surface: refused with the figure,
// and accepted only when the bound is raised to cover it.
TEST(RepairCorpus, AnOpenBowlIsRefusedForItsCapUnlessTheBoundCoversIt) {
  TriangleMesh bowl = sphereMesh(1.0, {0, 0, 0}, 0.1);
  std::vector<Triangle> lower;
  for (const Triangle& t : bowl.triangles)
    if (bowl.positions[t[0]][2] + bowl.positions[t[1]][2] + bowl.positions[t[2]][2] < 0)
      lower.push_back(t);
  bowl.triangles = lower;
  const RepairResult r = repaired(bowl);
  expectKeptOrRefused(bowl, r, "bowl");
  ASSERT_FALSE(r.accepted());
  EXPECT_TRUE(saysSomewhere(r.departures, "surface invented")) << reasons(r);
  EXPECT_GT(r.deviation.bToA, 0.5);  // the cap's middle is about a radius from the rim
  RepairOptions wide;
  wide.maxDeviation = 1.5;
  const RepairResult capped = repairMesh(bowl, wide, "bowl");
  EXPECT_TRUE(capped.accepted()) << reasons(capped);
  EXPECT_GT(capped.deviation.bToA, 0.5);
  EXPECT_LE(capped.deviation.bToA, 1.5);
  EXPECT_NE(repairToText(capped, capped.after, "bowl").find("bound 1.5"), std::string::npos);
}

// A flat fan of 24 slivers around a point, and a strip of 12 triangles bent at a right angle:
// sheets with no inside, which must not come back as slivers of no volume.
TEST(RepairCorpus, FansAndBentStripsAreRefusedNotShredded) {
  TriangleMesh fan;
  fan.positions.push_back({0, 0, 0});
  for (int i = 0; i < 24; ++i) {
    const double a = 2 * M_PI * i / 24;
    fan.positions.push_back({float(5 * std::cos(a)), float(5 * std::sin(a)), 0});
  }
  for (std::uint32_t i = 0; i < 24; ++i) fan.triangles.push_back({0, 1 + i, 1 + (i + 1) % 24});
  TriangleMesh strip;
  for (int i = 0; i <= 6; ++i) {
    const float x = float(i < 4 ? i : 3), z = float(i < 4 ? 0 : i - 3);
    strip.positions.push_back({x, 0, z});
    strip.positions.push_back({x, 1, z});
  }
  for (std::uint32_t i = 0; i < 6; ++i) {
    strip.triangles.push_back({2 * i, 2 * i + 2, 2 * i + 1});
    strip.triangles.push_back({2 * i + 1, 2 * i + 2, 2 * i + 3});
  }
  ASSERT_EQ(strip.triangles.size(), 12u);
  for (const auto* c : {&fan, &strip}) {
    const RepairResult r = repaired(*c);
    expectKeptOrRefused(*c, r, c == &fan ? "fan" : "strip");
    EXPECT_FALSE(r.accepted()) << r.mesh.triangles.size() << " triangles accepted";
  }
}

// A thin CAD panel, 6 x 6 x 0.025, crossed by a second one (a plus in section), rebuilt at
// the default voxel (6 / 192), wider than the panels are thick: whatever comes back is either
// faithful or refused with the figures.
TEST(RepairCorpus, ThinCrossedPanelsAreNeverShreddedIntoAPrintableResult) {
  const TriangleMesh a = gridBox({-3, -3, -0.0125}, {3, 3, 0.0125}, 6);
  const TriangleMesh b = gridBox({-3, -0.0125, -3}, {3, 0.0125, 3}, 6);
  const TriangleMesh panels = merged(a, b);
  ASSERT_GT(checkMesh(panels).selfIntersections, 0u);
  RepairOptions o;
  o.rebuild = RebuildPolicy::Always;
  const RepairResult coarse = repairMesh(panels, o, "panels");
  SCOPED_TRACE(reasons(coarse));
  if (coarse.rebuilt) {
    EXPECT_TRUE(coarse.accepted());
    EXPECT_LE(coarse.after.components, 2u);
    EXPECT_LE(meshDeviation(coarse.mesh, panels).aToB, coarse.deviationBound);
    EXPECT_LE(largestDistanceOutside(panels, coarse.mesh), coarse.deviationBound);
  } else {
    EXPECT_FALSE(coarse.accepted());
    EXPECT_FALSE(coarse.departures.empty());
    EXPECT_TRUE(saysSomewhere(coarse.actions, "rebuild was not kept"));
  }
}

// A panel 25 times thinner than the voxel asked for, rebuilt on request: the rebuild moves its
// surface beyond the bound, so the input (printable already, only welded) is what comes back,
// and the report says so.
TEST(RepairCorpus, ARebuildThatLosesAThinPanelIsNotKept) {
  const TriangleMesh panel = gridBox({-10, -10, -0.02}, {10, 10, 0.02}, 6);
  RepairOptions o;
  o.rebuild = RebuildPolicy::Always;
  o.voxel = 2.0;
  const RepairResult r = repairMesh(panel, o, "panel");
  EXPECT_FALSE(r.rebuilt);
  EXPECT_TRUE(saysSomewhere(r.actions, "rebuild was not kept")) << reasons(r);
  EXPECT_TRUE(r.accepted()) << reasons(r);
  EXPECT_LT(r.deviation.hausdorff(), 0.01);
  expectKeptOrRefused(panel, r, "panel");
}

// A scan with holes, and a print bed of 12 small balls each with a hole: filled, every piece
// kept, within the bound.
TEST(RepairCorpus, ScansWithHolesAndManySmallPiecesAreRepairedPieceForPiece) {
  TriangleMesh scan = sphereMesh(1.0, {0, 0, 0}, 0.08);
  for (std::size_t k = 0; k < 8; ++k) scan.triangles.erase(scan.triangles.begin() + 61 * k * 7);
  const RepairResult r = repaired(scan);
  expectKeptOrRefused(scan, r, "scan");
  EXPECT_TRUE(r.accepted()) << reasons(r);
  TriangleMesh bed;
  for (int i = 0; i < 12; ++i) {
    TriangleMesh ball = sphereMesh(0.4, {double(i % 4), double(i / 4), 0}, 0.1);
    ball.triangles.erase(ball.triangles.begin() + 5 * i);
    appendMesh(bed, ball);
  }
  const RepairResult many = repaired(bed);
  expectKeptOrRefused(bed, many, "bed");
  EXPECT_TRUE(many.accepted()) << reasons(many);
  EXPECT_EQ(many.after.components, 12u);
  EXPECT_EQ(many.piecesBefore, 12u);
}

// Two crossing balls become their union: the input's inner caps lie inside the result's
// solid, absorbed rather than lost, so the judgement accepts the union.
TEST(RepairCorpus, TheInnerWallsOfAUnionAreAbsorbedNotLost) {
  const TriangleMesh m = merged(sphereMesh(1.0, {0, 0, 0}), sphereMesh(1.0, {1.0, 0.2, 0}));
  const RepairResult r = repaired(m, RebuildPolicy::Auto, 0.03);
  EXPECT_TRUE(r.accepted()) << reasons(r);
  EXPECT_GT(meshDeviation(m, r.mesh).aToB, 0.5);  // the caps, measured plainly
  EXPECT_LT(r.lostDistance, r.deviationBound);
  EXPECT_LT(largestDistanceOutside(m, r.mesh), r.deviationBound);
}

TEST(RepairCorpus, TheBoundAndThePiecesCanBeWidenedAndBadBoundsAreRefused) {
  RepairOptions o;
  o.maxDeviation = std::nan("");
  EXPECT_THROW(repairMesh(sphereMesh(), o, "m"), ModelError);
  o.maxDeviation = std::numeric_limits<double>::infinity();
  EXPECT_THROW(repairMesh(sphereMesh(), o, "m"), ModelError);
}

// A rebuild whose voxels cannot fit is refused before anything is allocated, naming a voxel
// that fits; one just at that voxel is allowed through the estimate.
TEST(RepairCorpus, ARebuildTooLargeForTheMemoryIsRefusedNamingAVoxelThatFits) {
  const TriangleMesh cube = gridBox({0, 0, 0}, {1, 1, 1}, 1);
  RepairOptions o;
  o.rebuild = RebuildPolicy::Always;
  o.voxel = 1e-4;
  o.memoryBudget = std::size_t(1) << 30;
  try {
    repairMesh(cube, o, "cube.stl");
    FAIL() << "a rebuild of 600 million surface voxels was not refused";
  } catch (const TooLargeError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("cube.stl"), std::string::npos) << what;
    const auto at = what.find("at least ");
    ASSERT_NE(at, std::string::npos) << what;
    const double fits = std::stod(what.substr(at + 9));
    // 6 square units of surface at 600 bytes a voxel in 1 GiB: voxels of about 1.9e-3
    EXPECT_GT(fits, 1.5e-3);
    EXPECT_LT(fits, 3e-3);
  }
  o.voxel = 1e-6;  // also past the mesher's grid
  EXPECT_THROW(repairMesh(cube, o, "cube.stl"), TooLargeError);
  o.voxel = 0.05;
  EXPECT_TRUE(repairMesh(cube, o, "cube.stl").accepted());
}

}  // namespace
}  // namespace frep
