// The guarded simplifier (simplify/simplify.h): far fewer triangles, creases placed, and every
// mesh still printable by the check and by CGAL's own self-intersection test.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>

#include "base/errors.h"
#include "base/qef.h"
#include "check/cgal_surface.h"
#include "check/mesh_check.h"
#include "frep/model_json.h"
#include "frep/program.h"
#include "frep/tree.h"
#include "mesh/mesher.h"
#include "pipeline/accuracy.h"
#include "random_trees.h"
#include "simplify/simplify.h"
#include "simplify/straighten_creases.h"
#include "simplify/work_zone.h"
#include "sorted_triangles.h"
#include "test_nodes.h"

namespace frep {
namespace {

using frep::testing::sphere;

std::string reasons(const CheckReport& r) {
  std::string s;
  for (const std::string& x : r.reasons) s += x + "; ";
  return s;
}

TriangleMesh meshOf(const Field& f, const Box3& box, double cell, bool normals = false,
                    Extraction extraction = Extraction::Cubes) {
  MeshingOptions o;
  o.settings.mesher = extraction;
  o.bbox = box;
  o.resolution = cell;
  o.normals = normals;
  return polygonize(f, o);
}

SimplifyOptions optionsFor(const Box3& box, double cell, double tolerance, bool sharp = true) {
  SimplifyOptions o;
  o.bbox = box;
  o.cell = cell;
  o.tolerance = tolerance;
  o.sharpFeatures = sharp;
  return o;
}

// |G| / |grad G| for G = min(F, distance to the box): the estimate the simplifier bounds.
double distanceEstimate(const Field& f, const Box3& box, const Vec3& p) {
  double box_distance = HUGE_VAL;
  for (int a = 0; a < 3; ++a)
    box_distance = std::min({box_distance, p[a] - box.lo[a], box.hi[a] - p[a]});
  const Dual d = f.evalGradient(p[0], p[1], p[2]);
  if (box_distance < d.v) return std::abs(box_distance);
  return std::abs(d.v) / std::sqrt(d.d[0] * d.d[0] + d.d[1] * d.d[1] + d.d[2] * d.d[2]);
}

// A cube turned off the grid's axes: its edges and corners fall inside cells, where marching
// tetrahedra cut them off.
NodePtr turnedCube() {
  const NodePtr cube = makeNode(
      "box", {{"corner", vec3Value({-0.5, -0.5, -0.5})}, {"size", vec3Value({1, 1, 1})}}, {});
  const NodePtr a =
      makeNode("rotate", {{"axis", vec3Value({0, 0, 1})}, {"angle", realValue(30)}}, {cube});
  return makeNode("rotate", {{"axis", vec3Value({1, 0, 0})}, {"angle", realValue(20)}}, {a});
}

// The cube's corners, turned as turnedCube turns them.
std::vector<Vec3> turnedCorners() {
  std::vector<Vec3> out;
  const double c30 = std::cos(M_PI / 6), s30 = std::sin(M_PI / 6);
  const double c20 = std::cos(M_PI / 9), s20 = std::sin(M_PI / 9);
  for (double x : {-0.5, 0.5})
    for (double y : {-0.5, 0.5})
      for (double z : {-0.5, 0.5}) {
        const double x1 = c30 * x - s30 * y, y1 = s30 * x + c30 * y, z1 = z;
        out.push_back({x1, c20 * y1 - s20 * z1, s20 * y1 + c20 * z1});
      }
  return out;
}

double nearestVertex(const TriangleMesh& m, const Vec3& p) {
  double best = HUGE_VAL;
  for (const Vec3f& v : m.positions)
    best = std::min(best, std::hypot(v[0] - p[0], v[1] - p[1], v[2] - p[2]));
  return best;
}

TEST(Simplify, SphereKeepsItsShapeWithAFractionOfTheTriangles) {
  const Program p = compile(sphere(1));
  const Box3 box{{-1.1, -1.1, -1.1}, {1.1, 1.1, 1.1}};
  const double cell = 2.2 / 40;
  const TriangleMesh mesh = meshOf(p, box, cell, true);
  SimplifyStats stats;
  const TriangleMesh s = simplifyMesh(mesh, p, optionsFor(box, cell, 0.1 * cell), &stats);
  const CheckReport before = checkMesh(mesh), after = checkMesh(s);
  ASSERT_TRUE(after.printable()) << reasons(after);
  EXPECT_EQ(stats.trianglesBefore, mesh.triangleCount());
  EXPECT_EQ(stats.trianglesAfter, s.triangleCount());
  EXPECT_LT(5 * s.triangleCount(), mesh.triangleCount());  // measured: about 12x fewer
  EXPECT_LE(stats.largestDistance, 0.1 * cell);
  EXPECT_EQ(after.components, 1u);
  // chords of a convex surface cut inside it: the volume changes by at most the area times
  // the tolerance
  EXPECT_NEAR(after.volume, before.volume, after.area * 0.1 * cell);
  // every vertex and every face centre within the tolerance of the surface
  for (const Vec3f& v : s.positions)
    ASSERT_LE(distanceEstimate(p, box, {v[0], v[1], v[2]}), 0.1 * cell * (1 + 1e-6));
  for (const Triangle& t : s.triangles) {
    Vec3 c{0, 0, 0};
    for (std::uint32_t v : t)
      for (int a = 0; a < 3; ++a) c[a] += s.positions[v][a] / 3.0;
    ASSERT_LE(distanceEstimate(p, box, c), 0.1 * cell * (1 + 1e-6));
  }
  // normals kept, unit length, pointing out
  ASSERT_EQ(s.normals.size(), s.positions.size());
  for (std::size_t v = 0; v < s.positions.size(); ++v) {
    const Vec3f& n = s.normals[v];
    const Vec3f& q = s.positions[v];
    EXPECT_NEAR(std::hypot(n[0], n[1], n[2]), 1.0, 1e-5);
    EXPECT_GT(n[0] * q[0] + n[1] * q[1] + n[2] * q[2], 0.9);
  }
}

// With sharp features the merged vertices go onto the cube's corners (the quadric of the
// three faces' planes meets there); without, every vertex stays where the grid put one, a
// cut-off corner.
TEST(Simplify, SharpFeaturesPutVerticesOnTheCorners) {
  const Program p = compile(turnedCube());
  const Box3 box{{-1, -1, -1}, {1, 1, 1}};
  const double cell = 2.0 / 24;
  // marching tetrahedra: the mesher's cubes would put vertices on the corners themselves
  const TriangleMesh mesh = meshOf(p, box, cell, false, Extraction::Tetrahedra);
  const TriangleMesh sharp = simplifyMesh(mesh, p, optionsFor(box, cell, 0.2 * cell, true));
  const TriangleMesh smooth = simplifyMesh(mesh, p, optionsFor(box, cell, 0.2 * cell, false));
  for (const TriangleMesh* m : {&sharp, &smooth}) {
    const CheckReport r = checkMesh(*m);
    ASSERT_TRUE(r.printable()) << reasons(r);
  }
  double worstSharp = 0, worstSmooth = 0, worstGrid = 0;
  for (const Vec3& c : turnedCorners()) {
    worstSharp = std::max(worstSharp, nearestVertex(sharp, c));
    worstSmooth = std::max(worstSmooth, nearestVertex(smooth, c));
    worstGrid = std::max(worstGrid, nearestVertex(mesh, c));
  }
  EXPECT_LT(worstSharp, 0.05 * cell) << "grid " << worstGrid / cell << " cells";
  EXPECT_GT(worstSmooth, 0.05 * cell);
  EXPECT_LT(sharp.triangleCount(), smooth.triangleCount());
}

// Random trees (sharp CSG, thin walls, tangent contacts, values exactly zero on grid points,
// surfaces cut by the box), simplified with sharp features on and off: every mesh is
// printable by the check, CGAL's own self-intersection test finds nothing either, and no
// component is lost or split.
void simplifyRandomTrees(unsigned seed, int trees) {
  testing::RandomTrees rng(seed);
  const double cells[] = {1.0 / 6, 1.0 / 8, 1.0 / 10};
  int nonEmpty = 0, fewer = 0;
  for (int i = 0; i < trees; ++i) {
    const NodePtr tree = rng.tree(rng.integer(1, 4));
    const Box3 box{{-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2}};
    const double cell = cells[rng.integer(0, 2)];
    const Program p = compile(tree);
    // both extractions: the default's cubes, and marching tetrahedra's three times as many
    const bool tetra = rng.integer(0, 1) == 1;
    const TriangleMesh mesh =
        meshOf(p, box, cell, false, tetra ? Extraction::Tetrahedra : Extraction::Cubes);
    if (mesh.triangleCount() == 0) continue;
    ++nonEmpty;
    const std::size_t components = checkMesh(mesh).components;
    for (bool sharp : {true, false}) {
      SimplifyOptions o = optionsFor(box, cell, rng.uniform(0.05, 0.5) * cell, sharp);
      o.regionCells = rng.integer(0, 1) ? 16 : 4;  // small regions: many frozen faces
      const TriangleMesh s = simplifyMesh(mesh, p, o);
      const CheckReport r = checkMesh(s);
      ASSERT_TRUE(r.printable()) << "tree " << i << " sharp " << sharp << " tolerance "
                                 << o.tolerance << " regions " << o.regionCells << ": "
                                 << reasons(r) << "\n"
                                 << modelToJson(Model{tree, box, cell, "", {}, {}});
      ASSERT_EQ(countSelfIntersectionsWithCgal(s.positions, s.triangles, true), 0u) << "tree " << i;
      EXPECT_EQ(r.components, components) << "tree " << i;
      fewer += (tetra ? 2 : 1) * s.triangleCount() < mesh.triangleCount();
    }
  }
  EXPECT_GT(nonEmpty, trees * 2 / 3);
  // most meshes lose triangles (a tetrahedra mesh more than half)
  EXPECT_GT(fewer, nonEmpty);
}

// 128 trees in make test; the acceptance tier simplifies 1,008 more.
class SimplifyRandomTrees : public ::testing::TestWithParam<int> {};
TEST_P(SimplifyRandomTrees, EveryMeshStaysPrintable) {
  simplifyRandomTrees(7000 + GetParam(), 32);
}
INSTANTIATE_TEST_SUITE_P(Shards, SimplifyRandomTrees, ::testing::Range(0, 4));

class SimplifyRandomTreesAcceptance : public ::testing::TestWithParam<int> {};
TEST_P(SimplifyRandomTreesAcceptance, EveryMeshStaysPrintable) {
  simplifyRandomTrees(8000 + GetParam(), 63);
}
INSTANTIATE_TEST_SUITE_P(Shards, SimplifyRandomTreesAcceptance, ::testing::Range(0, 16));

// A regression the random trees found: a face removed only for the collapse under test was
// dropped from the search grid as the grid was scanned, so a later collapse did not see it
// and made 3 self-intersecting pairs.
TEST(Simplify, AFaceRemovedOnlyForATestStaysSearched) {
  const Model m = loadModel(std::string(FREP_SOURCE_DIR) + "/tests/data/simplify_search_grid.json");
  const Program p = compile(m.root);
  // the marching-tetrahedra mesh it was found on
  const TriangleMesh mesh = meshOf(p, *m.bbox, *m.resolution, false, Extraction::Tetrahedra);
  const TriangleMesh s =
      simplifyMesh(mesh, p, optionsFor(*m.bbox, *m.resolution, 0.033642576569059716, false));
  const CheckReport r = checkMesh(s);
  EXPECT_TRUE(r.printable()) << reasons(r);
  EXPECT_LT(10 * s.triangleCount(), mesh.triangleCount());
}

// The accuracy report measures both ways: a sphere mesh blown up by 1 % is 0.01 from the
// unit sphere both ways, and its volume grows by 3 %.
TEST(Accuracy, MeasuresAMeshMovedOffTheSurfaceBothWays) {
  const Program p = compile(sphere(1));
  const Box3 box{{-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2}};
  const double cell = 2.4 / 48;
  TriangleMesh mesh = meshOf(p, box, cell);
  AccuracyOptions o;
  o.bbox = box;
  o.cell = cell;
  const AccuracyReport exact = measureAccuracy(mesh, p, o);
  EXPECT_LT(exact.hausdorff, 0.1 * cell);  // the mesher's own: chords of a cell
  EXPECT_NEAR(exact.volume, 4.0 / 3.0 * M_PI, 0.01);
  for (Vec3f& v : mesh.positions)
    for (float& c : v) c *= 1.01f;
  const AccuracyReport moved = measureAccuracy(mesh, p, o);
  EXPECT_NEAR(moved.meshToSurface, 0.01, 0.002);
  EXPECT_NEAR(moved.surfaceToMesh, 0.01, 0.002);
  EXPECT_NEAR(moved.volume, exact.volume * 1.01 * 1.01 * 1.01, 1e-3);
  EXPECT_EQ(moved.creaseLength, 0.0);  // a smooth sphere has none
  EXPECT_GT(moved.samples, mesh.vertexCount());
  // where the mesh is worst: one vertex pulled out is the mesh's farthest point, and one
  // pushed in leaves the surface above it the farthest from the mesh
  TriangleMesh dented = meshOf(p, box, cell);
  std::size_t out = 0, in = 0;
  for (std::size_t v = 0; v < dented.positions.size(); ++v) {
    if (dented.positions[v][0] > dented.positions[out][0]) out = v;
    if (dented.positions[v][1] > dented.positions[in][1]) in = v;
  }
  const Vec3f wasIn = dented.positions[in];
  for (float& c : dented.positions[out]) c *= 1.3f;
  for (float& c : dented.positions[in]) c *= 0.7f;
  const AccuracyReport worst = measureAccuracy(dented, p, o);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(worst.meshToSurfaceAt[a], dented.positions[out][a], 1e-6);
    EXPECT_NEAR(worst.surfaceToMeshAt[a], wasIn[a], cell);
  }
  EXPECT_NEAR(worst.meshToSurface, 0.3, 0.02);
}

// The grid cuts a turned cube's corners and edges off by most of a cell; simplified with
// sharp features its corners and edges come back: the Hausdorff distance falls below half a
// cell and the crease length comes near the cube's 12 edges (the staircase of the grid's
// mesh counts almost twice that).
TEST(Accuracy, SharpFeaturesBringTheCubesEdgesBack) {
  const Program p = compile(turnedCube());
  const Box3 box{{-1, -1, -1}, {1, 1, 1}};
  const double cell = 2.0 / 32;
  const TriangleMesh mesh = meshOf(p, box, cell, false, Extraction::Tetrahedra);
  const TriangleMesh sharp = simplifyMesh(mesh, p, optionsFor(box, cell, 0.1 * cell));
  AccuracyOptions o;
  o.bbox = box;
  o.cell = cell;
  const AccuracyReport grid = measureAccuracy(mesh, p, o), placed = measureAccuracy(sharp, p, o);
  EXPECT_GT(grid.surfaceToMesh, 0.5 * cell);
  EXPECT_LT(placed.hausdorff, 0.5 * cell) << "grid's " << grid.hausdorff / cell << " cells";
  // (measured 12.5, 14.2 without crease flips: some crease edges still zigzag by a fraction
  // of a cell; the grid's 21.4)
  EXPECT_NEAR(placed.creaseLength, 12.0, 2.5) << "grid's " << grid.creaseLength;
  EXPECT_GT(grid.creaseLength, 18.0);
  EXPECT_NEAR(placed.volume, 1.0, 0.01);
}

// The mesher's own sharp features (cubes with a vertex on the crease or corner, joined by
// flips): the same turned cube comes within half a cell without any simplification, and
// with them off its edges are chamfered by more.
TEST(Accuracy, TheMeshersSharpFeaturesPlaceTheCubesEdges) {
  const Program p = compile(turnedCube());
  const Box3 box{{-1, -1, -1}, {1, 1, 1}};
  const double cell = 2.0 / 32;
  MeshingOptions m;
  m.bbox = box;
  m.resolution = cell;
  m.normals = false;
  const TriangleMesh sharp = polygonize(p, m);
  m.settings.sharpFeatures = false;
  const TriangleMesh chamfered = polygonize(p, m);
  AccuracyOptions o;
  o.bbox = box;
  o.cell = cell;
  const AccuracyReport s = measureAccuracy(sharp, p, o), c = measureAccuracy(chamfered, p, o);
  EXPECT_TRUE(checkMesh(sharp).printable());
  EXPECT_LT(s.hausdorff, 0.5 * cell) << "without: " << c.hausdorff / cell << " cells";
  EXPECT_GT(c.hausdorff, 0.5 * cell);
  EXPECT_LT(std::abs(s.volume - 1.0), std::abs(c.volume - 1.0));
  EXPECT_LT(std::abs(s.creaseLength - 12.0), std::abs(c.creaseLength - 12.0))
      << s.creaseLength << " against " << c.creaseLength;
}

// The distance from the mesh to the surface is an upper bound that stays tight where the
// gradient does not point at the nearest surface: on the gyroid's thin sheets, Newton's steps
// from a point near one side can cross to the far side (they overstated the distance 4 times
// over). Measured against a brute-force one: each vertex's and face centre's distance (the
// points the measure takes) to the nearest vertex of a mesh six times finer (whose vertices
// lie on the surface).
// At a kink of a min, Newton's steps follow the piece whose value is least and reach its
// surface, missing a nearer piece whose value is larger only because it is steep: a wall
// (|y + 0.005| <= 0.005, scaled by 100) cut by the unit sphere, measured from a point 0.1
// inside the sphere and 0.002 from the wall's face. The wall lies between the points of the
// finer mesh's grid (-0.0125, 0.0125), which sees none of it. The search through the field's
// intervals finds the face (without it: 0.1, the sphere).
TEST(Accuracy, MeshToSurfaceFindsANearerPieceThanNewtonsSteps) {
  const Model m = parseModel(R"json({"frepcad": 1, "root": {"type": "intersection", "inputs": [
      {"type": "sphere", "params": {"radius": 1}},
      {"type": "formula", "params": {"formula": "100 * (0.005 - abs(y + 0.005))"}}]}})json",
                             "kink", ".");
  const Program p = compile(m.root);
  TriangleMesh mesh;
  mesh.positions = {{0.9f, -0.002f, 0.f}, {0.9001f, -0.002f, 0.f}, {0.9f, -0.002f, 0.0001f}};
  mesh.triangles = {{0, 1, 2}};
  AccuracyOptions o;
  o.bbox = {{0.7, -0.2, -0.2}, {1.1, 0.2, 0.2}};  // (its faces 0.2 from the point)
  o.cell = 0.05;
  const AccuracyReport r = measureAccuracy(mesh, p, o);
  EXPECT_GT(r.meshToSurface, 0.00199);  // an upper bound: never below the true distance
  EXPECT_LT(r.meshToSurface, 0.0025);   // (to within the search's smallest cubes)
}

TEST(Accuracy, MeshToSurfaceIsTightOnThinSheets) {
  const Model m = loadModel(std::string(FREP_SOURCE_DIR) + "/examples/gyroid.json");
  const Program p = compile(m.root);
  const Box3 box{{0.35, 0.35, 0.0}, {1.05, 1.05, 0.7}};
  const double cell = 0.7 / 40;
  const TriangleMesh mesh = meshOf(p, box, cell);
  const TriangleMesh fine = meshOf(p, box, cell / 6);
  ASSERT_GT(mesh.triangleCount(), 1000u);
  // the fine vertices bucketed by coarse cell, searched in the 5^3 cells around a vertex
  auto cellOf = [&](const Vec3f& v, int a) {
    return static_cast<long>(std::floor((v[a] - box.lo[a]) / cell));
  };
  std::map<std::array<long, 3>, std::vector<Vec3f>> buckets;
  for (const Vec3f& v : fine.positions)
    buckets[{cellOf(v, 0), cellOf(v, 1), cellOf(v, 2)}].push_back(v);
  double brute = 0.0;
  std::vector<Vec3f> points = mesh.positions;
  for (const Triangle& t : mesh.triangles) {
    Vec3f c;
    for (int a = 0; a < 3; ++a)
      c[a] = (mesh.positions[t[0]][a] + mesh.positions[t[1]][a] + mesh.positions[t[2]][a]) / 3;
    points.push_back(c);
  }
  for (const Vec3f& v : points) {
    double best = 1e9;
    for (long i = -2; i <= 2; ++i)
      for (long j = -2; j <= 2; ++j)
        for (long k = -2; k <= 2; ++k) {
          const auto it = buckets.find({cellOf(v, 0) + i, cellOf(v, 1) + j, cellOf(v, 2) + k});
          if (it == buckets.end()) continue;
          for (const Vec3f& f : it->second) {
            const double dx = v[0] - f[0], dy = v[1] - f[1], dz = v[2] - f[2];
            best = std::min(best, std::sqrt(dx * dx + dy * dy + dz * dz));
          }
        }
    brute = std::max(brute, best);
  }
  AccuracyOptions o;
  o.bbox = box;
  o.cell = cell;
  const AccuracyReport r = measureAccuracy(mesh, p, o);
  // nearest fine vertex: at most the true distance plus a fine cell's spacing
  EXPECT_GT(r.meshToSurface, brute - cell / 6) << "brute force " << brute / cell << " cells";
  EXPECT_LT(r.meshToSurface, brute + 0.2 * cell)
      << r.meshToSurface / cell << " cells, brute force " << brute / cell;
}

// The twist's helical creases poke their tips through cube faces the grid never sees
// crossed, and pass cubes with two diagonal corners inside that Kuhn's split would cut apart
// (docs/mesher.md, "Ambiguous faces" and "Sharp features"): the issue's bound, half a cell,
// holds at cell counts that put the tips at different depths. Its crease (exact length
// 19.956) is followed by crease flips wherever a fan cuts across it at a face: within a tenth
// of its length (29.5 to 30.7 at these cells before they were).
AccuracyReport twistAccuracy(int cells) {
  const Model m = loadModel(std::string(FREP_SOURCE_DIR) + "/examples/twist.json");
  const Program p = compile(m.root);
  const double cell = (m.bbox->hi[0] - m.bbox->lo[0]) / cells;
  AccuracyOptions o;
  o.bbox = *m.bbox;
  o.cell = cell;
  const TriangleMesh mesh = meshOf(p, *m.bbox, cell);
  EXPECT_TRUE(checkMesh(mesh).printable()) << cells << " cells";
  AccuracyReport r = measureAccuracy(mesh, p, o);
  r.hausdorff /= cell;
  return r;
}

constexpr double kTwistCreaseLength = 19.956;

TEST(Accuracy, TwistWithinHalfACell) {
  for (int cells : {64, 112}) {
    const AccuracyReport r = twistAccuracy(cells);
    EXPECT_LT(r.hausdorff, 0.5) << cells << " cells";
    EXPECT_NEAR(r.creaseLength, kTwistCreaseLength, 0.1 * kTwistCreaseLength) << cells << " cells";
  }
}

// At 151 cells the twist's bottom rim runs 0.04 cell from a grid line: the feature points
// there may reach only a few hundredths of a cell into the uniform cubes beyond it, which
// would cost their fans the crease flips (crease length 28.7). They stay in their cubes.
TEST(Accuracy, TwistsRimAlongAGridLineKeepsItsFlips) {
  const AccuracyReport r = twistAccuracy(151);
  EXPECT_LT(r.hausdorff, 0.55);
  EXPECT_NEAR(r.creaseLength, kTwistCreaseLength, 0.15 * kTwistCreaseLength);
}

TEST(AccuracyAcceptance, TwistWithinHalfACellAtTheIssuesResolutions) {
  for (int cells : {128, 256, 512}) {
    const AccuracyReport r = twistAccuracy(cells);
    EXPECT_LT(r.hausdorff, 0.5) << cells << " cells";
    EXPECT_NEAR(r.creaseLength, kTwistCreaseLength, 0.1 * kTwistCreaseLength) << cells << " cells";
  }
}

// The issue's bound on the other reference models, measured as `frepcad export --stats`
// does: within half a cell of the exact surface, by default for sphere, csg and helix, and
// for the gyroid with the tips refined two levels deep (its sheets graze the ball in
// slivers narrower than a cell: 1.0 to 2.2 cells by default; docs/mesher.md, "Deeper
// levels"). 512 cells for the gyroid are in docs/performance.md (0.48 cell; minutes).
double hausdorffCells(const std::string& model, int cells, int refinementLevels) {
  const Model m = loadModel(std::string(FREP_SOURCE_DIR) + "/examples/" + model + ".json");
  const Program p = compile(m.root);
  double longest = 0.0;
  for (int a = 0; a < 3; ++a) longest = std::max(longest, m.bbox->hi[a] - m.bbox->lo[a]);
  MeshingOptions o;
  o.bbox = *m.bbox;
  o.resolution = longest / cells;
  o.settings.refine = refinementLevels > 0 ? Refinement::Tips : Refinement::Off;
  o.settings.refineLevels = std::max(1, refinementLevels);
  const TriangleMesh mesh = polygonize(p, o);
  EXPECT_TRUE(checkMesh(mesh).printable()) << model << " at " << cells << " cells";
  AccuracyOptions a;
  a.bbox = o.bbox;
  a.cell = o.resolution;
  return measureAccuracy(mesh, p, a).hausdorff / o.resolution;
}

TEST(AccuracyAcceptance, SphereCsgAndHelixWithinHalfACell) {
  for (const char* model : {"sphere", "csg", "helix"})
    for (int cells : {128, 256, 512})
      EXPECT_LT(hausdorffCells(model, cells, 0), 0.5) << model << " at " << cells << " cells";
}

TEST(AccuracyAcceptance, GyroidWithinHalfACellWithTwoRefinementLevels) {
  for (int cells : {128, 256})
    EXPECT_LT(hausdorffCells("gyroid", cells, 2), 0.5) << cells << " cells";
}

// Collapses leave the long faces of a simplified crease cutting across it; the crease flips
// put edges along it instead. The twist at 128 cells and a tenth of a cell: the crease length
// (exact 19.956) comes at least a fifth nearer (25.0 -> 23.1 when written), and the mesh
// stays printable and within half a cell of the surface.
TEST(Simplify, CreaseFlipsStraightenTheTwistsSimplifiedCreases) {
  const Model m = loadModel(std::string(FREP_SOURCE_DIR) + "/examples/twist.json");
  const Program p = compile(m.root);
  const double cell = (m.bbox->hi[0] - m.bbox->lo[0]) / 128;
  const TriangleMesh mesh = meshOf(p, *m.bbox, cell);
  AccuracyOptions a;
  a.bbox = *m.bbox;
  a.cell = cell;
  double excess[2], hausdorff[2];
  for (bool flips : {false, true}) {
    SimplifyOptions o = optionsFor(*m.bbox, cell, 0.1 * cell);
    o.creaseFlips = flips;
    SimplifyStats stats;
    const TriangleMesh s = simplifyMesh(mesh, p, o, &stats);
    const CheckReport r = checkMesh(s);
    ASSERT_TRUE(r.printable()) << reasons(r);
    EXPECT_EQ(stats.flips > 0, flips);
    const AccuracyReport acc = measureAccuracy(s, p, a);
    excess[flips] = std::abs(acc.creaseLength - kTwistCreaseLength);
    hausdorff[flips] = acc.hausdorff / cell;
  }
  EXPECT_LT(excess[1], 0.8 * excess[0]) << "without flips " << excess[0] + kTwistCreaseLength
                                        << ", with " << excess[1] + kTwistCreaseLength;
  EXPECT_LT(hausdorff[1], 0.5) << "without flips " << hausdorff[0];
}

TEST(Simplify, RefusesBadOptions) {
  const Program p = compile(sphere(1));
  const Box3 box{{-1.1, -1.1, -1.1}, {1.1, 1.1, 1.1}};
  const TriangleMesh mesh = meshOf(p, box, 0.2);
  auto message = [&](SimplifyOptions o) {
    try {
      simplifyMesh(mesh, p, o);
    } catch (const ModelError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  SimplifyOptions o = optionsFor(box, 0.2, 0.02);
  o.tolerance = 0;
  EXPECT_NE(message(o).find("tolerance must be a positive distance"), std::string::npos);
  o.tolerance = NAN;
  EXPECT_NE(message(o).find("tolerance"), std::string::npos);
  o = optionsFor(box, 0.2, 0.02);
  o.cell = -1;
  EXPECT_NE(message(o).find("cell must be a positive number"), std::string::npos);
  o = optionsFor(box, 0.2, 0.02);
  o.regionCells = 2;
  EXPECT_NE(message(o).find("regionCells must be 4 to 256"), std::string::npos);
}

TEST(Simplify, ProgressRisesToTheEndAndCancelStops) {
  const Program p = compile(sphere(1));
  const Box3 box{{-1.1, -1.1, -1.1}, {1.1, 1.1, 1.1}};
  const TriangleMesh mesh = meshOf(p, box, 0.1);
  SimplifyOptions o = optionsFor(box, 0.1, 0.01);
  std::vector<double> seen;
  o.progress = [&](double f) {
    seen.push_back(f);
    return true;
  };
  simplifyMesh(mesh, p, o);
  ASSERT_GE(seen.size(), 2u);
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
  EXPECT_EQ(seen.back(), 1.0);
  o.progress = [](double f) { return f < 0.3; };
  EXPECT_THROW(simplifyMesh(mesh, p, o), Cancelled);
}

struct TwistMeshes {
  TriangleMesh mesh, straightened;
  SimplifyStats stats;
  AccuracyReport before, after;
};

// Straightened creases (simplify/straighten_creases.h): the mesher's twist, whose crease the
// grid chamfers and zig-zags (21.4 at 64 and 96 cells against the exact 19.956), comes within
// 1 % of it (19.91 and 20.06 when written), nearer the surface and with fewer triangles.
TwistMeshes straightenedTwist(int cells) {
  const Model m = loadModel(std::string(FREP_SOURCE_DIR) + "/examples/twist.json");
  const Program p = compile(m.root);
  const double cell = (m.bbox->hi[0] - m.bbox->lo[0]) / cells;
  TwistMeshes t;
  t.mesh = meshOf(p, *m.bbox, cell);
  t.straightened = straightenCreases(t.mesh, p, {*m.bbox, cell, {}}, &t.stats);
  AccuracyOptions o;
  o.bbox = *m.bbox;
  o.cell = cell;
  t.before = measureAccuracy(t.mesh, p, o);
  t.after = measureAccuracy(t.straightened, p, o);
  t.before.hausdorff /= cell;
  t.after.hausdorff /= cell;
  return t;
}

TEST(StraightenCreases, TheTwistsCreaseComesWithinOnePercent) {
  for (int cells : {64, 96}) {
    const TwistMeshes t = straightenedTwist(cells);
    const CheckReport r = checkMesh(t.straightened);
    ASSERT_TRUE(r.printable()) << cells << " cells: " << reasons(r);
    EXPECT_EQ(
        countSelfIntersectionsWithCgal(t.straightened.positions, t.straightened.triangles, true),
        0u);
    EXPECT_GT(t.before.creaseLength, 1.05 * kTwistCreaseLength) << cells << " cells";
    EXPECT_NEAR(t.after.creaseLength, kTwistCreaseLength, 0.01 * kTwistCreaseLength)
        << cells << " cells";
    EXPECT_LT(t.after.hausdorff, t.before.hausdorff) << cells << " cells";
    EXPECT_GT(t.stats.collapses, 0u);
    EXPECT_GT(t.stats.flips, 0u);
    EXPECT_LT(t.straightened.triangleCount(), t.mesh.triangleCount());
    EXPECT_NEAR(r.volume, 2.0, 0.002) << cells << " cells";
  }
}

// The issue's figure: within 0.5 % at 512 cells (19.99 when written), and within 1.5 % at
// its other resolutions (20.07 and 20.23 at 128 and 256), every mesh within half a cell.
TEST(StraightenCreasesAcceptance, TheTwistsCreaseWithinHalfAPercentAt512Cells) {
  for (int cells : {128, 256, 512}) {
    const TwistMeshes t = straightenedTwist(cells);
    const CheckReport r = checkMesh(t.straightened);
    ASSERT_TRUE(r.printable()) << cells << " cells: " << reasons(r);
    EXPECT_NEAR(t.after.creaseLength, kTwistCreaseLength,
                (cells == 512 ? 0.005 : 0.015) * kTwistCreaseLength)
        << cells << " cells";
    EXPECT_LT(t.after.hausdorff, 0.5) << cells << " cells";
  }
}

// Only collapses onto creases: a sphere is left exactly as it was, at 40 cells (no face turns
// by 12 degrees from the surface at its vertices) and at radii of 3.3 and 2.5 cells, where
// tangent planes a couple of cells apart differ by over 30 degrees but meet outside the
// surface (without that test both are merged: 284 -> 106 triangles at 2.5 cells).
TEST(StraightenCreases, ASmoothSurfaceIsLeftAsItWas) {
  const Program p = compile(sphere(1));
  const Box3 box{{-1.5, -1.5, -1.5}, {1.5, 1.5, 1.5}};
  for (double cell : {3.0 / 40, 0.3, 0.4}) {
    const TriangleMesh mesh = meshOf(p, box, cell);
    SimplifyStats stats;
    const TriangleMesh s = straightenCreases(mesh, p, {box, cell, {}}, &stats);
    EXPECT_EQ(stats.collapses, 0u) << "cell " << cell;
    EXPECT_EQ(testing::sortedTriangles(s), testing::sortedTriangles(mesh)) << "cell " << cell;
  }
}

// The straightening's work zone (simplify/work_zone.h) is what lets it leave faces far from a
// crease out of every region: a box the zone covers meets no box that meets none of the
// zone's blocks. On random boxes round a random zone, every box the zone covers and every box
// it does not meet are disjoint (closed boxes, coordinates on block boundaries included), a
// box added with a margin is covered, and a box far from every added one is not met.
TEST(StraightenCreases, TheWorkZonesBoxesNeverMeetThoseLeftOut) {
  const Box3 box{{-1, -2, -1}, {3, 1, 1}};
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> at(-1.2f, 3.2f), size(0.0f, 0.4f);
  // (coordinates on the blocks' boundaries too, where the rounding decides)
  std::uniform_int_distribution<int> snap(0, 3);
  auto randomBox = [&](float lo[3], float hi[3]) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = at(rng);
      if (snap(rng) == 0) lo[a] = std::round(lo[a] / 0.1f) * 0.1f;
      hi[a] = lo[a] + (snap(rng) == 0 ? 0.0f : size(rng));
    }
  };
  int covered = 0, apart = 0, farAway = 0;
  for (int round = 0; round < 20; ++round) {
    simplifying::WorkZone zone(box, 0.1);
    std::vector<std::array<float, 6>> added;
    for (int i = 0; i < 6; ++i) {
      std::array<float, 6> b;
      randomBox(b.data(), b.data() + 3);
      zone.add(b.data(), b.data() + 3, 0.15);
      EXPECT_TRUE(zone.covers(b.data(), b.data() + 3));
      added.push_back(b);
    }
    std::vector<std::array<float, 6>> boxes(400);
    for (auto& b : boxes) randomBox(b.data(), b.data() + 3);
    for (const auto& a : boxes) {
      if (!zone.covers(a.data(), a.data() + 3)) continue;
      ++covered;
      for (const auto& b : boxes) {
        if (zone.meets(b.data(), b.data() + 3)) continue;
        ++apart;
        bool overlap = true;
        for (int k = 0; k < 3; ++k) overlap = overlap && a[k] <= b[3 + k] && b[k] <= a[3 + k];
        ASSERT_FALSE(overlap) << "a covered box meets a box left out";
      }
    }
    // inside the meshing box and far from everything added (more than the margin and a
    // block): not met (beyond the box's padding, blocks are clamped to its last ones)
    for (const auto& b : boxes) {
      bool far = true;
      for (int k = 0; k < 3; ++k) far = far && box.lo[k] <= b[k] && b[3 + k] <= box.hi[k];
      for (const auto& c : added) {
        bool near = true;
        for (int k = 0; k < 3; ++k)
          near = near && b[k] <= c[3 + k] + 0.15f + 0.21f && c[k] - 0.15f - 0.21f <= b[3 + k];
        far = far && !near;
      }
      if (far) {
        ++farAway;
        EXPECT_FALSE(zone.meets(b.data(), b.data() + 3));
      }
    }
  }
  EXPECT_GT(covered, 100);
  EXPECT_GT(apart, 10000);
  EXPECT_GT(farAway, 1000);
}

TEST(StraightenCreases, NeedsSharpFeatures) {
  const Program p = compile(sphere(1));
  const Box3 box{{-1.1, -1.1, -1.1}, {1.1, 1.1, 1.1}};
  const TriangleMesh mesh = meshOf(p, box, 0.2);
  SimplifyOptions o = straightenOptions({box, 0.2, {}});
  o.sharpFeatures = false;
  try {
    simplifyMesh(mesh, p, o);
    FAIL() << "no error";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("need sharp features"), std::string::npos) << e.what();
  }
}

// The straightening's early-out (Quadric::mayBeSharp) never drops a quadric the eigen solve
// would call a crease or corner: on 20,000 random sets of up to six planes, wherever it says
// no, minimiser() solves one direction at most; and it does say no for two planes 5 degrees
// apart, not for two 40 degrees apart.
TEST(StraightenCreases, TheQuadricsEarlyOutDropsOnlyPlanes) {
  // the simplifier's cutoff and the crease rule's (planes over 30 degrees apart)
  for (const double cutoff : {0.02, 0.0718}) {
    std::mt19937 rng(42);
    std::normal_distribution<double> normal;
    std::uniform_real_distribution<double> spread(0.0, 1.0);
    int dropped = 0;
    for (int i = 0; i < 20000; ++i) {
      Quadric q;
      // planes round one direction, fanned out by a random amount (near-planes and creases)
      const Vec3 axis{normal(rng), normal(rng), normal(rng)};
      const double fan = spread(rng) * spread(rng);
      const int planes = 1 + static_cast<int>(spread(rng) * 6);
      for (int k = 0; k < planes; ++k) {
        Vec3 n{axis[0] + fan * normal(rng), axis[1] + fan * normal(rng),
               axis[2] + fan * normal(rng)};
        const double l = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (!(l > 0)) continue;
        for (double& c : n) c /= l;
        q.addPlane({normal(rng), normal(rng), normal(rng)}, n);
      }
      if (q.mayBeSharp(cutoff)) continue;
      ++dropped;
      int rank = 0;
      q.minimiser(cutoff, &rank);
      ASSERT_LE(rank, 1) << "quadric " << i << ", cutoff " << cutoff;
    }
    EXPECT_GT(dropped, 1000) << "cutoff " << cutoff;  // (a test of the bound, not of nothing)
  }
  auto pair = [](double degrees) {
    Quadric q;
    const double r = degrees * M_PI / 180;
    q.addPlane({0, 0, 0}, {0, 0, 1});
    q.addPlane({0, 0, 0}, {std::sin(r), 0, std::cos(r)});
    return q;
  };
  EXPECT_FALSE(pair(5).mayBeSharp(0.0718));
  EXPECT_TRUE(pair(40).mayBeSharp(0.0718));
}

// Random trees as the simplifier's (a quarter meshed by marching tetrahedra): every
// straightened mesh is printable, CGAL finds no self-intersection, no component is lost or
// split.
void straightenRandomTrees(unsigned seed, int trees) {
  testing::RandomTrees rng(seed);
  const double cells[] = {1.0 / 6, 1.0 / 8, 1.0 / 10};
  int nonEmpty = 0, merged = 0;
  for (int i = 0; i < trees; ++i) {
    const NodePtr tree = rng.tree(rng.integer(1, 4));
    const Box3 box{{-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2}};
    const double cell = cells[rng.integer(0, 2)];
    const Program p = compile(tree);
    // both extractions: the cubes' creases placed, marching tetrahedra's chamfered
    const bool tetra = rng.integer(0, 3) == 0;
    const TriangleMesh mesh =
        meshOf(p, box, cell, false, tetra ? Extraction::Tetrahedra : Extraction::Cubes);
    if (mesh.triangleCount() == 0) continue;
    ++nonEmpty;
    SimplifyStats stats;
    const TriangleMesh s = straightenCreases(mesh, p, {box, cell, {}}, &stats);
    const CheckReport r = checkMesh(s);
    ASSERT_TRUE(r.printable()) << "tree " << i << ": " << reasons(r) << "\n"
                               << modelToJson(Model{tree, box, cell, "", {}, {}});
    ASSERT_EQ(countSelfIntersectionsWithCgal(s.positions, s.triangles, true), 0u) << "tree " << i;
    EXPECT_EQ(r.components, checkMesh(mesh).components) << "tree " << i;
    merged += stats.collapses > 0;
  }
  EXPECT_GT(nonEmpty, trees * 2 / 3);
  EXPECT_GT(merged, 0);  // (sharp CSG has creases to straighten)
}

// 128 trees in make test; the acceptance tier straightens 1,008 more.
class StraightenRandomTrees : public ::testing::TestWithParam<int> {};
TEST_P(StraightenRandomTrees, EveryMeshStaysPrintable) {
  straightenRandomTrees(9000 + GetParam(), 32);
}
INSTANTIATE_TEST_SUITE_P(Shards, StraightenRandomTrees, ::testing::Range(0, 4));

class StraightenRandomTreesAcceptance : public ::testing::TestWithParam<int> {};
TEST_P(StraightenRandomTreesAcceptance, EveryMeshStaysPrintable) {
  straightenRandomTrees(9100 + GetParam(), 63);
}
INSTANTIATE_TEST_SUITE_P(Shards, StraightenRandomTreesAcceptance, ::testing::Range(0, 16));

}  // namespace
}  // namespace frep
