// The mesher's guarantee, with CGAL as the judge: closed, manifold, outward, no
// self-intersections, no degenerate triangles, for the examples and for random trees.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "base/errors.h"
#include "base/mesh_invariants.h"
#include "base/triangle_geometry.h"
#include "check/cgal_surface.h"
#include "check/mesh_check.h"
#include "frep/model_json.h"
#include "mesh/centred_cube.h"
#include "mesh/crease_flips.h"
#include "mesh/cube_loops.h"
#include "mesh/flat_vertex_removal.h"
#include "mesh/mesher.h"
#include "random_trees.h"
#include "sorted_triangles.h"

namespace frep {
namespace {

constexpr double kPi = 3.14159265358979323846;

Model example(const std::string& name) {
  return loadModel(std::string(FREP_SOURCE_DIR) + "/examples/" + name + ".json");
}

TriangleMesh meshModel(const Model& m, double resolution, int brick = 16, bool sharp = true,
                       Extraction extraction = Extraction::Cubes, bool flatVertices = false) {
  MeshingOptions o;
  o.settings.dropFlatVertices = flatVertices;
  o.bbox = *m.bbox;
  o.resolution = resolution;
  o.brickCells = brick;
  o.settings.sharpFeatures = sharp;
  o.settings.mesher = extraction;
  return polygonize(compile(m.root), o);
}

std::string reasons(const CheckReport& r) {
  std::string s;
  for (const auto& x : r.reasons) s += x + "; ";
  return s;
}

// The check before the fast one (CGAL's own self-intersection routine and its
// does_bound_a_volume with a positive volume) must agree with checkMesh's verdicts, on the
// mesh welded as the check welds it. Up to a million triangles: beyond, CGAL's general box
// tree takes minutes (the fast check's own tests compare the two on broken meshes).
void expectOldCheckAgrees(const TriangleMesh& mesh, const CheckReport& r,
                          const std::string& label) {
  if (mesh.triangleCount() > 1000000 || r.nonManifoldEdges || r.misorientedEdges ||
      r.nonManifoldVertices)
    return;
  std::vector<Vec3f> welded;
  const std::vector<std::uint32_t> map = weldIdenticalVertices(mesh.positions, welded);
  std::vector<FaceIndices> faces;
  for (const Triangle& t : mesh.triangles) faces.push_back({map[t[0]], map[t[1]], map[t[2]]});
  EXPECT_EQ(countSelfIntersectionsWithCgal(welded, faces), r.selfIntersections) << label;
  if (r.closed && r.selfIntersections == 0) {
    EXPECT_EQ(boundsAVolume(welded, faces) && r.volume > 0, r.outward) << label;
  }
}

struct ExampleCase {
  std::string model;
  int cellsPerUnit;
};

class ExamplesPrintable : public ::testing::TestWithParam<ExampleCase> {};

// Each by cubes with sharp features (the default), without, and with the flat vertices dropped;
// the coarse cases by marching tetrahedra too (still selectable).
TEST_P(ExamplesPrintable, CgalSaysPrintable) {
  const ExampleCase c = GetParam();
  // modes: 0 cubes, 1 without sharp features, 2 tetrahedra (coarse only), 3 flat vertices dropped
  for (int mode : {0, 1, 2, 3}) {
    if (mode == 2 && c.cellsPerUnit > 64) continue;
    const TriangleMesh mesh =
        meshModel(example(c.model), 1.0 / c.cellsPerUnit, 16, mode != 1,
                  mode == 2 ? Extraction::Tetrahedra : Extraction::Cubes, mode == 3);
    const CheckReport r = checkMesh(mesh);
    EXPECT_TRUE(r.printable()) << c.model << " at 1/" << c.cellsPerUnit << " mode " << mode << ": "
                               << reasons(r);
    expectOldCheckAgrees(mesh, r, c.model + " mode " + std::to_string(mode));
    // The gyroid shell cut by the ball leaves small separate pieces at the ball's surface.
    if (c.model != "gyroid") {
      EXPECT_EQ(r.components, 1u);
    }
    EXPECT_GT(r.volume, 0.0);
    EXPECT_TRUE(r.outward);
  }
}

std::vector<ExampleCase> exampleCases() {
  std::vector<ExampleCase> cases;
  for (const char* m : {"sphere", "csg"})
    for (int res : {16, 32, 64}) cases.push_back({m, res});
  // The reference models of the modelling set at a coarse grid (finer ones in the acceptance
  // tier below).
  for (const char* m : {"twist", "helix", "gyroid"}) cases.push_back({m, 16});
  return cases;
}

INSTANTIATE_TEST_SUITE_P(Resolutions, ExamplesPrintable, ::testing::ValuesIn(exampleCases()),
                         [](const ::testing::TestParamInfo<ExampleCase>& i) {
                           return i.param.model + "_1_" + std::to_string(i.param.cellsPerUnit);
                         });
// The finest resolutions of the acceptance ranges: millions of triangles, its own test binary
// label so ctest can schedule it early.
INSTANTIATE_TEST_SUITE_P(FineAcceptance, ExamplesPrintable,
                         ::testing::Values(ExampleCase{"sphere", 128}, ExampleCase{"csg", 128},
                                           ExampleCase{"twist", 64}, ExampleCase{"helix", 64},
                                           ExampleCase{"gyroid", 64}, ExampleCase{"sphere", 256},
                                           ExampleCase{"csg", 256}, ExampleCase{"twist", 128},
                                           ExampleCase{"helix", 128}, ExampleCase{"gyroid", 128}),
                         [](const ::testing::TestParamInfo<ExampleCase>& i) {
                           return i.param.model + "_1_" + std::to_string(i.param.cellsPerUnit);
                         });

// Seed 000's showcase shapes (examples/showcase, written by examples/make_showcase.py), each at
// its own export resolution: one printable part apiece.
class ShowcasePrintable : public ::testing::TestWithParam<std::string> {};

TEST_P(ShowcasePrintable, CgalSaysPrintable) {
  const Model m =
      loadModel(std::string(FREP_SOURCE_DIR) + "/examples/showcase/" + GetParam() + ".json");
  ASSERT_TRUE(m.bbox && m.resolution);
  MeshingOptions o;
  o.bbox = *m.bbox;
  o.resolution = *m.resolution;
  const CheckReport r = checkMesh(polygonize(compile(m.root), o));
  EXPECT_TRUE(r.printable()) << GetParam() << ": " << reasons(r);
  EXPECT_EQ(r.components, 1u) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(Seed000, ShowcasePrintable,
                         ::testing::Values("blend_narrow", "blend_wide", "blend_uneven",
                                           "bounded_blend", "taper", "bend", "twist",
                                           "deform_point", "sweep", "offset_in", "offset_out",
                                           "metamorphosis", "instancer_grid", "instancer_torus"),
                         [](const ::testing::TestParamInfo<std::string>& i) { return i.param; });

TEST(MesherAcceptance, SphereVolumeWithinHalfPercentAt128) {
  const CheckReport r = checkMesh(meshModel(example("sphere"), 1.0 / 128));
  const double exact = 4.0 / 3.0 * kPi;
  EXPECT_LT(std::abs(r.volume - exact) / exact, 0.005) << r.volume;
  EXPECT_NEAR(r.area, 4 * kPi, 0.01 * 4 * kPi);
}

TEST(MesherAcceptance, CsgVolumeMatchesInclusionExclusion) {
  // Box [-1,1]^3 with the rounding sphere r=1.3, minus three r=0.5 cylinders; the mesh volume
  // converges as the grid refines: 1/64 and 1/128 agree to 0.2 %.
  const double v64 = checkMesh(meshModel(example("csg"), 1.0 / 64)).volume;
  const double v128 = checkMesh(meshModel(example("csg"), 1.0 / 128)).volume;
  EXPECT_LT(std::abs(v64 - v128) / v128, 0.002) << v64 << " vs " << v128;
}

TEST(Mesher, NormalsComeFromTheGradient) {
  // Each brick computes the normals of the vertices it owns; a vertex on a face two bricks
  // share has its owner's (bricks of 5 cells: many shared faces, some bricks clipped).
  for (int brick : {16, 5}) {
    const TriangleMesh m = meshModel(example("sphere"), 1.0 / 16, brick);
    ASSERT_EQ(m.normals.size(), m.positions.size());
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
      const auto& p = m.positions[i];
      const double len = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
      const double dot =
          (p[0] * m.normals[i][0] + p[1] * m.normals[i][1] + p[2] * m.normals[i][2]) / len;
      ASSERT_GT(dot, 0.9999) << "vertex " << i << ", bricks of " << brick;
    }
  }
}

using testing::sortedTriangles;

TEST(Mesher, SameMeshWhateverTheBrickSize) {
  // Bricks only split the work: vertices on brick faces weld exactly.
  const Model m = example("csg");
  const TriangleMesh a = meshModel(m, 1.0 / 24, 4), b = meshModel(m, 1.0 / 24, 16);
  const TriangleMesh odd = meshModel(m, 1.0 / 24, 7);  // bricks that do not divide the grid
  EXPECT_EQ(sortedTriangles(odd), sortedTriangles(b));
  EXPECT_EQ(a.positions.size(), b.positions.size());
  EXPECT_EQ(sortedTriangles(a), sortedTriangles(b));
  const TriangleMesh c = meshModel(m, 1.0 / 24, 16);
  EXPECT_EQ(b.triangles, c.triangles);  // deterministic across runs and thread schedules
  // Where faces are split by their centres' values, cubes split round their centres and
  // feature vertices reach into a uniform neighbour (the twist at 112 cells, the gyroid at
  // 64 have all three), a brick's face still meets its neighbour's exactly: those decisions
  // use the whole field's values past the brick's faces.
  for (const auto& [name, cells] : {std::make_pair("twist", 112), std::make_pair("gyroid", 64)}) {
    const Model e = example(name);
    const double h = (e.bbox->hi[0] - e.bbox->lo[0]) / cells;
    const auto whole = sortedTriangles(meshModel(e, h, 16));
    for (int brick : {4, 7}) EXPECT_EQ(sortedTriangles(meshModel(e, h, brick)), whole) << name;
  }
}

// Flat vertices: two triangles fewer for each vertex dropped, only vertices of the full mesh
// kept (none moved), the surface moved by at most a fiftieth of a cell, the same mesh for
// every even brick size, and a brick size that would split a block refused.
TEST(FlatVertices, FewerTrianglesTheSameVerticesAndSurface) {
  for (const auto& [name, cells] :
       {std::make_pair("csg", 48), std::make_pair("twist", 56), std::make_pair("sphere", 40)}) {
    const Model m = example(name);
    const double h = (m.bbox->hi[0] - m.bbox->lo[0]) / cells;
    MeshingOptions o;
    o.bbox = *m.bbox;
    o.resolution = h;
    const Program program = compile(m.root);
    o.settings.dropFlatVertices = false;
    const TriangleMesh full = polygonize(program, o);
    o.settings.dropFlatVertices = true;  // (the default)
    EXPECT_TRUE(MeshingOptions{}.settings.dropFlatVertices);
    const TriangleMesh fewer = polygonize(program, o);
    const CheckReport r = checkMesh(fewer);
    EXPECT_TRUE(r.printable()) << name << ": " << reasons(r);
    const std::size_t dropped = full.positions.size() - fewer.positions.size();
    EXPECT_GT(dropped, full.positions.size() / 40) << name;  // (at least a fortieth)
    EXPECT_EQ(full.triangleCount() - fewer.triangleCount(), 2 * dropped) << name;
    std::vector<Vec3f> before = full.positions, after = fewer.positions;
    std::sort(before.begin(), before.end());
    std::sort(after.begin(), after.end());
    EXPECT_TRUE(std::includes(before.begin(), before.end(), after.begin(), after.end())) << name;
    // every dropped vertex lies within the bound of the new surface
    double worst = 0.0;
    std::vector<Vec3f> gone;
    std::set_difference(before.begin(), before.end(), after.begin(), after.end(),
                        std::back_inserter(gone));
    for (const Vec3f& p : gone) {
      double nearest = std::numeric_limits<double>::infinity();
      const Vec3d q{p[0], p[1], p[2]};
      for (const Triangle& t : fewer.triangles) {
        const Vec3f &a = fewer.positions[t[0]], &b = fewer.positions[t[1]],
                    &c = fewer.positions[t[2]];
        if (std::fabs(a[0] - p[0]) > 2 * h || std::fabs(a[1] - p[1]) > 2 * h ||
            std::fabs(a[2] - p[2]) > 2 * h)
          continue;
        nearest = std::min(nearest, pointTriangleDistance(q, {a[0], a[1], a[2]}, {b[0], b[1], b[2]},
                                                          {c[0], c[1], c[2]}));
      }
      worst = std::max(worst, nearest);
    }
    EXPECT_LE(worst, 0.0201 * h) << name;
    for (int brick : {4, 8}) {
      o.brickCells = brick;
      EXPECT_EQ(sortedTriangles(polygonize(program, o)), sortedTriangles(fewer))
          << name << " bricks of " << brick;
    }
    o.brickCells = 7;
    EXPECT_THROW(polygonize(program, o), ModelError);
  }
}

// The planner alone, on a square of four quads round a vertex (the mesher's case): it drops
// a flat vertex, keeps one raised by more than the bound, refuses a star that folds over, and
// a triangle of the region that reaches over the polygon stops it.
TEST(FlatVertices, ThePlannerRefusesWhatCouldFoldOrCross) {
  // vertex 0 at the centre, 1..8 round it (counter-clockwise seen from +z)
  std::vector<Vec3f> p = {{0, 0, 0},  {1, 0, 0},   {1, 1, 0},  {0, 1, 0}, {-1, 1, 0},
                          {-1, 0, 0}, {-1, -1, 0}, {0, -1, 0}, {1, -1, 0}};
  std::vector<Triangle> star;
  for (std::uint32_t i = 1; i <= 8; ++i) star.push_back({0, i, i % 8 + 1});
  const double lo[3] = {-1, -1, -0.5}, hi[3] = {1, 1, 0.5};
  FlatVertexRemoval plan;
  ASSERT_TRUE(planFlatVertexRemoval(0, p, star, lo, hi, 0.01, 0.02, &plan));
  EXPECT_EQ(plan.size, 8u);
  EXPECT_DOUBLE_EQ(plan.deviation, 0.0);
  EXPECT_TRUE(flatVertexRemovalIsClear(plan, p, star));
  // the new fan covers the square once, facing +z
  double area = 0.0;
  for (std::size_t t = 0; t + 2 < plan.size; ++t) {
    const Vec3d c = triangleCross(p[plan.replacement[t][0]], p[plan.replacement[t][1]],
                                  p[plan.replacement[t][2]]);
    EXPECT_GT(c[2], 0.0);
    area += 0.5 * c[2];
  }
  EXPECT_NEAR(area, 4.0, 1e-12);
  // raised above the bound: kept; within it: dropped, the deviation measured
  p[0][2] = 0.05f;
  EXPECT_FALSE(planFlatVertexRemoval(0, p, star, lo, hi, 0.01, 0.02, &plan));
  p[0][2] = 0.005f;
  ASSERT_TRUE(planFlatVertexRemoval(0, p, star, lo, hi, 0.01, 0.02, &plan));
  EXPECT_NEAR(plan.deviation, 0.005, 1e-6);
  p[0][2] = 0.0f;
  // a star that winds twice (its ring visits each direction twice) is refused
  std::vector<Vec3f> twice = p;
  std::vector<Triangle> folded;
  for (std::uint32_t i = 1; i <= 8; ++i) {
    const double a = 4.0 * kPi * (i - 1) / 8.0;
    twice[i] = {float(std::cos(a) * (1 + 0.1 * i)), float(std::sin(a) * (1 + 0.1 * i)), 0.f};
    folded.push_back({0, i, i % 8 + 1});
  }
  EXPECT_FALSE(planFlatVertexRemoval(0, twice, folded, lo, hi, 0.01, 0.02, &plan));
  // another sheet's triangle over the polygon, just above it: the fan would cross it
  std::vector<Vec3f> q = p;
  q.push_back({0.2f, 0.2f, 0.001f});
  q.push_back({0.5f, 0.2f, 0.001f});
  q.push_back({0.2f, 0.5f, 0.001f});
  std::vector<Triangle> region = star;
  region.push_back({9, 10, 11});
  ASSERT_TRUE(planFlatVertexRemoval(0, q, region, lo, hi, 0.01, 0.02, &plan));
  EXPECT_FALSE(flatVertexRemovalIsClear(plan, q, region));
  // ... and a neighbour's triangle that only shares the polygon's edge is no obstacle
  q[9] = {1.5f, 0.5f, 0.f};
  region.back() = {1, 9, 2};
  ASSERT_TRUE(planFlatVertexRemoval(0, q, region, lo, hi, 0.01, 0.02, &plan));
  EXPECT_TRUE(flatVertexRemovalIsClear(plan, q, region));
  // no new edge may lie in a face of the box: with the box's face at y = 1, the fans whose
  // diagonals run along y = 1 (from vertex 2 or 4 to 3) are not taken
  ASSERT_TRUE(planFlatVertexRemoval(0, p, star, lo, hi, 0.01, 0.02, &plan));
  for (std::size_t t = 0; t + 2 < plan.size; ++t)
    for (int c = 0; c < 3; ++c) {
      const Vec3f &a = p[plan.replacement[t][c]], &b = p[plan.replacement[t][(c + 1) % 3]];
      const int d = std::abs(int(plan.replacement[t][c]) - int(plan.replacement[t][(c + 1) % 3]));
      const bool ringEdge = d == 1 || d == 7;
      if (!ringEdge) {
        EXPECT_FALSE(a[1] == 1.f && b[1] == 1.f);
      }
    }
}

// The clear test's shortcut: on a convex polygon (a hexagon round the vertex), a triangle that
// one edge's line leaves outside, but for that edge's ends, is clear at once; one that reaches
// in, from a shared corner or across the polygon between its corners, is still refused.
TEST(FlatVertices, TheClearTestsShortcutTakesOnlyWhatAnEdgeSeparates) {
  std::vector<Vec3f> p = {{0, 0, 0}};
  std::vector<Triangle> star;
  for (std::uint32_t i = 0; i < 6; ++i) {
    const double a = kPi / 3 * i;
    p.push_back({float(std::cos(a)), float(std::sin(a)), 0.f});
    star.push_back({0, i + 1, (i + 1) % 6 + 1});
  }
  const double lo[3] = {-2, -2, -0.5}, hi[3] = {2, 2, 0.5};
  FlatVertexRemoval plan;
  auto clearWith = [&](std::vector<Vec3f> extra, Triangle t) {
    std::vector<Vec3f> q = p;
    q.insert(q.end(), extra.begin(), extra.end());
    std::vector<Triangle> region = star;
    region.push_back(t);
    EXPECT_TRUE(planFlatVertexRemoval(0, q, region, lo, hi, 0.01, 0.02, &plan));
    return flatVertexRemovalIsClear(plan, q, region);
  };
  // the neighbour across the edge 1-2, and one meeting the polygon at corner 1 only
  EXPECT_TRUE(clearWith({{1.2f, 0.7f, 0.f}}, {2, 1, 7}));
  EXPECT_TRUE(clearWith({{1.5f, 0.1f, 0.f}, {1.5f, -0.4f, 0.f}}, {1, 8, 7}));
  // from corner 1 with a corner inside the polygon (just above it): refused
  EXPECT_FALSE(clearWith({{1.5f, 0.3f, 0.f}, {0.3f, 0.2f, 0.01f}}, {1, 7, 8}));
  // every corner outside the polygon, beyond different edges, the triangle across it
  EXPECT_FALSE(clearWith({{2.f, -0.2f, 0.01f}, {-2.f, 0.6f, 0.01f}, {0.f, 3.f, 0.01f}}, {7, 8, 9}));
  // corners beyond the lines of different edges, the triangle over corner 1: refused; all
  // three beyond the line of edge 6-1 (sharing nothing, close by): clear
  EXPECT_FALSE(
      clearWith({{0.6f, -1.5f, 0.01f}, {3.f, 0.f, 0.01f}, {0.6f, 1.5f, 0.01f}}, {7, 8, 9}));
  EXPECT_TRUE(
      clearWith({{0.6f, -1.5f, 0.01f}, {1.6f, 0.5f, 0.01f}, {1.4f, -1.4f, 0.01f}}, {7, 9, 8}));
}

TEST(Mesher, BoxCutsTheSolidWithACap) {
  // A half-space filling the lower half: the box closes it into a block.
  const NodePtr h = makeNode("halfspace", {{"point", vec3Value({0, 0, 0.25})}}, {});
  MeshingOptions o;
  o.bbox = {{-1, -1, -1}, {1, 1, 1}};
  o.resolution = 0.1;
  const CheckReport r = checkMesh(polygonize(compile(h), o));
  EXPECT_TRUE(r.printable()) << reasons(r);
  // Cap faces lie exactly on the box (root finding stops at an exact zero); its 21 units of
  // edges get vertices on them (sharp features). The top plane lies on grid points (value
  // exactly 0: inside), so its vertices sit on the 1 % edge margin above it: 0.004 of volume.
  EXPECT_NEAR(r.volume, 2 * 2 * 1.25, 0.011);
  EXPECT_LE(r.volume, 5.0 + 4 * 0.01 * o.resolution + 1e-6);
  EXPECT_NEAR(r.bbox.lo[0], -1.0, 1e-6);
  EXPECT_NEAR(r.bbox.hi[0], 1.0, 1e-6);
  EXPECT_NEAR(r.bbox.hi[2], 0.25, 1e-3);
}

TEST(Mesher, ExactZeroAtGridPointsStaysValid) {
  // Faces of this box lie exactly on grid planes (field 0 at grid points).
  const NodePtr b = makeNode(
      "box", {{"corner", vec3Value({-0.5, -0.5, -0.5})}, {"size", vec3Value({1, 1, 1})}}, {});
  MeshingOptions o;
  o.bbox = {{-1.05, -1.05, -1.05}, {1.05, 1.05, 1.05}};
  o.resolution = 0.1;  // grid points at -1.05 + (j - 0.5) 0.1: ..., -0.5, ..., 0.5
  const CheckReport r = checkMesh(polygonize(compile(b), o));
  EXPECT_TRUE(r.printable()) << reasons(r);
  EXPECT_NEAR(r.volume, 1.0, 0.05);
}

TEST(Mesher, EmptyModelGivesNoTriangles) {
  const NodePtr s = makeNode("sphere", {{"center", vec3Value({5, 5, 5})}}, {});
  MeshingOptions o;
  o.bbox = {{-1, -1, -1}, {1, 1, 1}};
  o.resolution = 0.1;
  MeshingStats stats;
  EXPECT_EQ(polygonize(compile(s), o, &stats).triangleCount(), 0u);
  EXPECT_EQ(stats.bricksActive, 0u);  // proven empty by intervals, nothing evaluated
}

// The promise every stage checks at its end in debug builds (base/mesh_invariants.h): the
// test holds it to the reference models in release builds too, and shows it refuses what
// breaks it.
TEST(MeshInvariant, TheReferenceModelsKeepItAndBrokenMeshesAreNamed) {
  for (const char* name : {"csg", "twist", "gyroid"}) {
    const Model m = loadModel(std::string(FREP_SOURCE_DIR) + "/examples/" + name + ".json");
    MeshingOptions o;
    o.bbox = *m.bbox;
    o.resolution = 2.4 / 40;
    const TriangleMesh mesh = polygonize(compile(m.root), o);
    ASSERT_GT(mesh.triangleCount(), 100u);
    EXPECT_EQ(meshInvariantBroken(mesh), "") << name;
    TriangleMesh flipped = mesh;
    std::swap(flipped.triangles[7][0], flipped.triangles[7][1]);
    EXPECT_NE(meshInvariantBroken(flipped).find("runs the same way"), std::string::npos);
    TriangleMesh open = mesh;
    open.triangles.pop_back();
    EXPECT_NE(meshInvariantBroken(open).find("is a border"), std::string::npos);
    TriangleMesh degenerate = mesh;
    degenerate.triangles[3][2] = degenerate.triangles[3][0];
    EXPECT_NE(meshInvariantBroken(degenerate).find("triangle 3 repeats a vertex"),
              std::string::npos);
    EXPECT_THROW(assertMeshInvariant(open, "a test"), std::logic_error);
  }
}

TEST(Mesher, IntervalPruningSkipsMostBricks) {
  MeshingStats stats;
  const Model m = example("sphere");
  MeshingOptions o;
  o.bbox = *m.bbox;
  o.resolution = 1.0 / 64;
  polygonize(compile(m.root), o, &stats);
  EXPECT_LT(stats.bricksActive * 2, stats.bricksTotal);
}

TEST(Mesher, CancelStopsWithCancelled) {
  const Model m = example("csg");
  MeshingOptions o;
  o.bbox = *m.bbox;
  o.resolution = 1.0 / 64;
  int calls = 0;
  o.progress = [&](double) { return ++calls < 3; };
  EXPECT_THROW(polygonize(compile(m.root), o), Cancelled);
}

TEST(Mesher, BadOptionsAreRefused) {
  const Program p = compile(makeNode("sphere", {}, {}));
  MeshingOptions o;
  o.bbox = {{0, 0, 0}, {0, 1, 1}};
  EXPECT_THROW(polygonize(p, o), ModelError);
  o.bbox = {{-1, -1, -1}, {1, 1, 1}};
  o.resolution = 0;
  EXPECT_THROW(polygonize(p, o), ModelError);
  o.resolution = 1e-9;
  try {
    polygonize(p, o);
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("larger cell size"), std::string::npos);
  }
}

// >= 1,000 random trees (8 shards of 125), each meshed by cubes with sharp features on and
// off (and one in four by tetrahedra too), and with the flat vertices kept and (with an even
// brick size) dropped, every mesh checked by CGAL, and the check before the fast one
// agreeing.
class RandomTreeShard : public ::testing::TestWithParam<int> {};

TEST_P(RandomTreeShard, EveryMeshIsPrintable) {
  testing::RandomTrees rng(1000 + GetParam());
  const double resolutions[] = {1.0 / 8, 1.0 / 12, 1.0 / 16, 1.0 / 20};
  int nonEmpty = 0;
  for (int i = 0; i < 125; ++i) {
    const NodePtr tree = rng.tree(rng.integer(1, 4));
    const Program program = compile(tree);
    MeshingOptions o;
    o.bbox = {{-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2}};
    o.resolution = resolutions[rng.integer(0, 3)];
    o.brickCells = rng.integer(0, 1) ? 16 : 5;  // bricks that do not divide the grid, too
    o.settings.dropFlatVertices = false;  // (odd bricks cannot have them; they are tried below)
    const bool tetra = rng.integer(0, 3) == 0, bricksAgain = rng.integer(0, 7) == 0;
    std::size_t cubeTriangles = 0;
    for (int mode = 0; mode < (tetra ? 3 : 2); ++mode) {
      o.settings.sharpFeatures = mode == 0;
      o.settings.mesher = mode == 2 ? Extraction::Tetrahedra : Extraction::Cubes;
      MeshingStats stats;
      const TriangleMesh mesh = polygonize(program, o, &stats);
      // every vertex a brick shares was found in its owner's list
      ASSERT_FALSE(stats.weldedBySorting) << "tree " << i << " mode " << mode;
      if (mesh.triangleCount() == 0) continue;
      nonEmpty += mode == 0;
      const CheckReport r = checkMesh(mesh);
      ASSERT_TRUE(r.printable()) << "tree " << i << " at " << o.resolution << " mode " << mode
                                 << ": " << reasons(r) << "\n"
                                 << modelToJson(Model{tree, o.bbox, o.resolution, "", {}, {}});
      expectOldCheckAgrees(mesh, r, "tree " + std::to_string(i) + " mode " + std::to_string(mode));
      if (mode == 1) cubeTriangles = mesh.triangleCount();
      if (mode == 2) {
        EXPECT_LT(cubeTriangles, mesh.triangleCount()) << "tree " << i;
      }
      if (mode < 2 && o.brickCells == 16) {  // and with the flat vertices dropped
        MeshingOptions flat = o;
        flat.settings.dropFlatVertices = true;
        const TriangleMesh fewer = polygonize(program, flat);
        const CheckReport f = checkMesh(fewer);
        ASSERT_TRUE(f.printable())
            << "tree " << i << " flat, mode " << mode << ": " << reasons(f) << "\n"
            << modelToJson(Model{tree, o.bbox, o.resolution, "", {}, {}});
        expectOldCheckAgrees(fewer, f,
                             "tree " + std::to_string(i) + " flat, mode " + std::to_string(mode));
        // each vertex dropped takes two triangles with it
        EXPECT_EQ(mesh.triangleCount() - fewer.triangleCount(),
                  2 * (mesh.positions.size() - fewer.positions.size()))
            << "tree " << i;
      }
      if (mode == 0 && bricksAgain) {  // the bricks decide their shared faces alike
        MeshingOptions other = o;
        other.brickCells = o.brickCells == 16 ? 7 : 16;
        EXPECT_EQ(sortedTriangles(polygonize(program, other)), sortedTriangles(mesh))
            << "tree " << i;
      }
    }
  }
  EXPECT_GT(nonEmpty, 80);  // the generator makes real shapes, not mostly empty boxes
}

INSTANTIATE_TEST_SUITE_P(Shards, RandomTreeShard, ::testing::Range(0, 8));

}  // namespace
}  // namespace frep

namespace frep {
namespace {

// Cheap adversarial cases for the mesher's guarantee; the fine grids that confirm it on the
// reference models are in the acceptance tier (FineAcceptance above).
CheckReport meshAndCheck(const NodePtr& tree, const Box3& box, double resolution) {
  MeshingOptions o;
  o.bbox = box;
  o.resolution = resolution;
  return checkMesh(polygonize(compile(tree), o));
}

TEST(MesherAdversarial, FarFromTheOriginWhereFloatSpacingIsCoarse) {
  // At 3e4 a float32 coordinate steps by 2^-9 (0.002). Cells of 0.5 span 256 steps: the
  // mesh is valid; cells of 0.05 (25 steps) would collapse triangles, and are refused with
  // the smallest cell allowed there.
  const Vec3 c{3e4, -3e4, 3e4};
  const NodePtr ball = makeNode("sphere", {{"center", vec3Value(c)}, {"radius", realValue(4)}}, {});
  const Box3 box{{c[0] - 5, c[1] - 5, c[2] - 5}, {c[0] + 5, c[1] + 5, c[2] + 5}};
  const CheckReport r = meshAndCheck(ball, box, 0.5);
  EXPECT_TRUE(r.printable()) << reasons(r);
  EXPECT_NEAR(r.volume, 4.0 / 3.0 * M_PI * 64, 0.03 * 4.0 / 3.0 * M_PI * 64);
  try {
    meshAndCheck(ball, box, 0.05);
    FAIL() << "a grid too fine for float32 was accepted";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("allowed here: cells of at least 0.5"), std::string::npos)
        << e.what();
  }
}

TEST(MesherAdversarial, TinyBallInTinyCells) {
  const NodePtr ball =
      makeNode("sphere", {{"center", vec3Value({0.3, 0.1, 0})}, {"radius", realValue(1e-4)}}, {});
  const CheckReport r =
      meshAndCheck(ball, {{0.3 - 2e-4, 0.1 - 2e-4, -2e-4}, {0.3 + 2e-4, 0.1 + 2e-4, 2e-4}}, 1e-5);
  EXPECT_TRUE(r.printable()) << reasons(r);
  EXPECT_EQ(r.components, 1u);
}

TEST(MesherAdversarial, WallsThinnerThanACell) {
  // A spherical shell 0.03 thick meshed with 0.05 cells: pieces of wall fall between grid
  // points, and what is meshed must still be closed and manifold.
  const NodePtr outer = makeNode("sphere", {{"radius", realValue(1.0)}}, {});
  const NodePtr inner = makeNode("sphere", {{"radius", realValue(0.97)}}, {});
  const CheckReport r = meshAndCheck(makeNode("difference", {}, {outer, inner}),
                                     {{-1.1, -1.1, -1.1}, {1.1, 1.1, 1.1}}, 0.05);
  EXPECT_TRUE(r.printable()) << reasons(r);
}

void expectSameLoops(const CubeLoopCase& got, const CubeLoopCase& want, const std::string& what) {
  ASSERT_EQ(got.loops, want.loops) << what;
  ASSERT_EQ(got.length, want.length) << what;
  for (int i = 0; i < got.length; ++i) ASSERT_EQ(got.ids[i], want.ids[i]) << what << " at " << i;
}

TEST(CubeLoops, KuhnsSplitGivesTheLoopsOfKuhnsTetrahedra) {
  // The tables draw each face's lines from its two triangles, oriented by a rule (u x m,
  // mesh/cube_loops.cpp). With no face flipped that must be exactly what Kuhn's six
  // tetrahedra draw on the faces, derived here from their oriented polygons instead.
  const CubeLoopTables& cl = cubeLoopTables();
  const KuhnTables& kt = kuhnTables();
  for (int mask = 1; mask < 255; ++mask) {
    std::map<int, int> nextOf;
    for (int tet = 0; tet < 6; ++tet) {
      int m = 0;
      for (int v = 0; v < 4; ++v) m |= ((mask >> kt.tets[tet][v]) & 1) << v;
      const TetPolygon& p = kt.polygons[tet][m];
      for (int i = 0; i < p.count; ++i) {
        const TetEdge &e = p.edges[i], &f = p.edges[(i + 1) % p.count];
        const int a = cl.idOf[e.low][e.dir], b = cl.idOf[f.low][f.dir];
        if (cl.faces[a] & cl.faces[b]) nextOf[a] = b;
      }
    }
    expectSameLoops(cl.caseOf(mask, 0), loopsFromLines(nextOf), "mask " + std::to_string(mask));
  }
}

TEST(CubeLoops, CentredTetrahedraCloseTheLoopsOfAnySplit) {
  // For every sign pattern, every split of its ambiguous faces and either sign at the
  // centre: the twelve tetrahedra's polygons form a closed oriented surface inside the cube
  // (every inner edge once each way) whose boundary on the faces is the tables' loops, so a
  // cube split round its centre meets its fanned neighbours' lines exactly.
  const CubeLoopTables& cl = cubeLoopTables();
  int flippedCases = 0;
  for (int mask = 1; mask < 255; ++mask) {
    const int ambiguous = cl.ambiguous[mask];
    for (int flips = 0; flips < 64; ++flips) {
      if ((flips & ambiguous) != flips) continue;
      flippedCases += flips != 0;
      for (bool centre : {false, true}) {
        std::vector<TetCrossing> polys;
        centredCubeCrossings(mask, centre, flips, polys);
        std::map<std::pair<int, int>, int> inner;  // directed edge between crossed edges
        std::map<int, int> nextOf;
        for (const TetCrossing& p : polys)
          for (int i = 0; i < p.count; ++i) {
            const int j = (i + 1) % p.count;
            auto vertex = [&](int k) {  // crossed edge as (low, high) vertex ids, 0..8
              return std::make_pair(std::min(p.from[k], p.to[k]), std::max(p.from[k], p.to[k]));
            };
            const auto u = vertex(i), w = vertex(j);
            const bool onFaces = u.second != kCubeCentre && w.second != kCubeCentre;
            const int a = onFaces ? cl.idOf[u.first][u.first ^ u.second] : -1;
            const int b = onFaces ? cl.idOf[w.first][w.first ^ w.second] : -1;
            ASSERT_TRUE(!onFaces || (a != 255 && b != 255)) << "a flipped diagonal crossed";
            if (onFaces && (cl.faces[a] & cl.faces[b])) {
              ASSERT_EQ(nextOf.count(a), 0u) << "mask " << mask << " flips " << flips;
              nextOf[a] = b;
            } else {
              ++inner[{u.first * 9 + u.second, w.first * 9 + w.second}];
            }
          }
        for (const auto& [edge, times] : inner) {
          EXPECT_EQ(times, 1) << "mask " << mask << " flips " << flips;
          const auto back = inner.find({edge.second, edge.first});
          EXPECT_TRUE(back != inner.end() && back->second == 1)
              << "mask " << mask << " flips " << flips << ": an open or twisted inner edge";
        }
        expectSameLoops(loopsFromLines(nextOf), cl.caseOf(mask, flips),
                        "mask " + std::to_string(mask) + " flips " + std::to_string(flips));
      }
    }
  }
  EXPECT_GT(flippedCases, 100);
}

// A crease flip decides from four positions: fan triangles (v1, a, b) and (v2, b, a) across a
// cube face become (v1, a, v2), (v1, v2, b).
bool flips(const Vec3f& v1, const Vec3f& a, const Vec3f& b, const Vec3f& v2) {
  const std::vector<Vec3f> P = {v1, a, b, v2};
  Triangle t1, t2;
  const bool flipped = flipCrease({0, 1, 2}, {3, 2, 1}, P, &t1, &t2);
  if (flipped) {
    EXPECT_EQ(t1, (Triangle{0, 1, 3}));
    EXPECT_EQ(t2, (Triangle{0, 3, 2}));
  }
  return flipped;
}

TEST(CreaseFlips, ACreaseCutAcrossIsJoinedAndNothingFoldsBack) {
  // The face x = 0; a crease near the x axis between the top side (z = 0, a on it) and the
  // front side (y = 0, b on it). Apexes a little off the crease: the old pair folds by more
  // than 90 degrees along a-b, and the new triangles turn away from the old pair's mean
  // normal, which alone used to refuse the flip; it is taken now.
  EXPECT_TRUE(flips({-0.17f, 0.07f, -0.09f}, {0, -0.22f, -0.04f}, {0, -0.04f, -0.13f},
                    {0.08f, 0.11f, 0.02f}));
  // Apexes on the crease: both new triangles face as the old pair did (taken before too).
  EXPECT_TRUE(flips({-0.3f, 0, 0}, {0, -0.2f, 0}, {0, 0, -0.15f}, {0.2f, 0, 0}));
  // v1-v2 crossing the face on the line through a and b beyond b: the new triangles would
  // lie in one plane, overlapping (folded back by 180 degrees). Never taken.
  const Vec3f a{0, -0.2f, 0}, b{0, 0, -0.15f}, x{0, 0.1f, -0.225f}, d{0.2f, 0.03f, 0.04f};
  EXPECT_FALSE(flips({x[0] - d[0], x[1] - d[1], x[2] - d[2]}, a, b,
                     {x[0] + d[0], x[1] + d[1], x[2] + d[2]}));
  // A nearly flat pair (turning by 11 degrees along a-b) whose flip would fold the surface
  // by 112 degrees where there is no crease. Not taken.
  EXPECT_FALSE(flips({-0.2f, 0.07f, -0.13f}, {0, -0.2f, 0}, {0, 0.2f, 0}, {0.2f, 0.37f, 0.19f}));
}

// A rod of radius 0.3 cell along a face diagonal, through a line of grid points: only the
// points on its axis are inside, and the faces between them are ambiguous, their centres
// on the axis. Kuhn's split cuts the rod into beads (one per point); the cubes join them.
NodePtr diagonalRod(const Vec3& through, double cell, const Vec3& axis = {-1, 0, 1}) {
  return makeNode("cylinder",
                  {{"center", vec3Value(through)},
                   {"axis", vec3Value(axis)},
                   {"radius", realValue(0.3 * cell)},
                   {"length", realValue(0)}},
                  {});
}

TEST(MesherAmbiguousFaces, AFaceSplitsAsItsCentreSays) {
  const double h = 0.125;
  const Box3 box{{-1, -1, -1}, {1, 1, 1}};  // grid points at -1 + (j - 0.5) h
  const Vec3 point{0.0625, 0.0625, 0.0625};
  MeshingOptions o;
  o.bbox = box;
  o.resolution = h;
  const TriangleMesh cubes = polygonize(compile(diagonalRod(point, h)), o);
  const CheckReport r = checkMesh(cubes);
  EXPECT_TRUE(r.printable()) << reasons(r);
  EXPECT_EQ(r.components, 1u);
  o.settings.mesher = Extraction::Tetrahedra;
  const CheckReport beads = checkMesh(polygonize(compile(diagonalRod(point, h)), o));
  EXPECT_TRUE(beads.printable()) << reasons(beads);
  EXPECT_GT(beads.components, 10u);  // the case is ambiguous for Kuhn's split
  // With a second rod a cell above, across the first, through the other two corners of the
  // cubes between them: those cubes have a flipped face and two loops, and are split round
  // their centres (mesh/centred_cube.h). No grid edge joins the rods' points.
  const NodePtr two = makeNode(
      "union", {},
      {diagonalRod(point, h), diagonalRod({point[0] - h, point[1] + h, point[2]}, h, {1, 0, 1})});
  o.settings.mesher = Extraction::Cubes;
  for (int brick : {4, 16}) {
    o.brickCells = brick;
    const CheckReport pair = checkMesh(polygonize(compile(two), o));
    EXPECT_TRUE(pair.printable()) << reasons(pair);
    EXPECT_EQ(pair.components, 2u) << "brick " << brick;
  }
}

TEST(MesherAdversarial, SmoothUnionsOfSteepFields) {
  // The outside fuzz run's kind of tree: an R-union with alpha = 0.5 of a superellipsoid with
  // a tiny exponent (values beyond 1e100 a little way out) and a convolution surface. With
  // round-to-nearest intervals pruning skipped bricks the surface crossed.
  ParamValue pts;
  pts.numbers = {-0.5, 0.2, 0.0, 0.6, -0.1, 0.3};
  for (double alpha : {0.5, -0.5, 0.9}) {
    const NodePtr se = makeNode("superellipsoid",
                                {{"radii", vec3Value({0.6, 0.5, 0.4})},
                                 {"exponent1", realValue(0.084)},
                                 {"exponent2", realValue(0.3)}},
                                {});
    const NodePtr conv = makeNode("convolution_segments", {{"points", pts}}, {});
    const CheckReport r = meshAndCheck(makeNode("union", {{"alpha", realValue(alpha)}}, {se, conv}),
                                       {{-1.3, -1.3, -1.3}, {1.3, 1.3, 1.3}}, 1.0 / 24);
    EXPECT_TRUE(r.printable()) << "alpha " << alpha << ": " << reasons(r);
  }
}

}  // namespace
}  // namespace frep

namespace frep {
namespace {

TEST(MesherMemoryGuard, AGridTooLargeForTheMemoryIsRefusedWithTheFigures) {
  // The case: a unit sphere at cell 1e-3 would need tens of GB. With a 1 GB budget
  // it is refused before any brick is meshed, naming the cell size that fits.
  const NodePtr ball = makeNode("sphere", {}, {});
  MeshingOptions o;
  o.bbox = {{-1.1, -1.1, -1.1}, {1.1, 1.1, 1.1}};
  o.resolution = 1e-3;
  o.memoryBudget = std::size_t(1) << 30;
  o.bytesPerTriangle = 820;
  try {
    polygonize(compile(ball), o);
    FAIL() << "not refused";
  } catch (const ModelError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("million triangles"), std::string::npos) << m;
    EXPECT_NE(m.find("use a cell size of at least"), std::string::npos) << m;
    // and the suggested cell size does fit
    const double suggested = std::stod(m.substr(m.find("at least ") + 9));
    o.resolution = suggested;
    o.normals = false;
    EXPECT_NO_THROW(polygonize(compile(ball), o)) << suggested;
  }
}

}  // namespace
}  // namespace frep
