// The checker finds each defect class on small hand-made meshes.
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <random>

#include "check/cgal_surface.h"
#include "check/face_pair_test.h"
#include "check/mesh_check.h"
#include "check/partitioned_check.h"
#include "check/self_intersections.h"
#include "check/volume_nesting.h"
#include "frep/model_json.h"
#include "frep/program.h"
#include "frep/tree.h"
#include "mesh/mesher.h"

namespace frep {
namespace {

TriangleMesh tetra(float dx = 0, float dy = 0, float dz = 0) {
  TriangleMesh m;
  m.positions = {{dx, dy, dz}, {dx + 1, dy, dz}, {dx, dy + 1, dz}, {dx, dy, dz + 1}};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};  // outward
  return m;
}

TriangleMesh merged(const TriangleMesh& a, const TriangleMesh& b) {
  TriangleMesh m = a;
  appendMesh(m, b);
  return m;
}

TEST(Check, ClosedOutwardTetrahedronIsPrintable) {
  const CheckReport r = checkMesh(tetra());
  EXPECT_TRUE(r.printable());
  EXPECT_NEAR(r.volume, 1.0 / 6, 1e-9);
  EXPECT_EQ(r.components, 1u);
  EXPECT_TRUE(r.outward);
}

TEST(Check, HoleIsReported) {
  TriangleMesh m = tetra();
  m.triangles.pop_back();
  const CheckReport r = checkMesh(m);
  EXPECT_FALSE(r.printable());
  EXPECT_FALSE(r.closed);
  EXPECT_EQ(r.borderEdges, 3u);
}

TEST(Check, InsideOutIsNotOutward) {
  TriangleMesh m = tetra();
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
  const CheckReport r = checkMesh(m);
  EXPECT_FALSE(r.printable());
  EXPECT_TRUE(r.closed);
  EXPECT_FALSE(r.outward);
  EXPECT_LT(r.volume, 0);
}

TEST(Check, OneFlippedTriangleBreaksOrientation) {
  TriangleMesh m = tetra();
  std::swap(m.triangles[0][1], m.triangles[0][2]);
  const CheckReport r = checkMesh(m);
  EXPECT_EQ(r.misorientedEdges, 3u);
  EXPECT_FALSE(r.printable());
}

TEST(Check, SharedEdgeIsNonManifold) {
  // Two tetrahedra sharing the edge (0,0,0)-(1,0,0) only.
  TriangleMesh b;
  b.positions = {{0, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 0, -1}};
  b.triangles = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
  const CheckReport r = checkMesh(merged(tetra(), b));
  EXPECT_GE(r.nonManifoldEdges, 1u);
  EXPECT_FALSE(r.printable());
}

TEST(Check, TouchingVertexIsNonManifold) {
  // A mirrored tetrahedron meeting the first one at the origin only.
  TriangleMesh b;
  b.positions = {{0, 0, 0}, {-1, 0, 0}, {0, -1, 0}, {0, 0, -1}};
  b.triangles = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
  const CheckReport r = checkMesh(merged(tetra(), b));
  EXPECT_EQ(r.nonManifoldVertices, 1u);
  EXPECT_FALSE(r.printable());
}

TEST(Check, InterpenetratingSolidsSelfIntersect) {
  const CheckReport r = checkMesh(merged(tetra(), tetra(0.2f, 0.2f, 0.2f)));
  EXPECT_GT(r.selfIntersections, 0u);
  EXPECT_EQ(r.components, 2u);
  EXPECT_FALSE(r.printable());
}

TEST(Check, DegenerateTrianglesAreReported) {
  TriangleMesh m = tetra();
  m.positions.push_back({2, 0, 0});
  m.positions.push_back({3, 0, 0});
  m.triangles.push_back({1, 4, 5});  // collinear
  m.triangles.push_back({1, 1, 2});  // repeated vertex
  const CheckReport r = checkMesh(m);
  EXPECT_EQ(r.degenerateFaces, 2u);
  EXPECT_FALSE(r.printable());
}

TEST(Check, IdenticalCoordinatesWeldButNearDuplicatesDoNot) {
  // STL-style: every triangle with its own copy of the vertices.
  const TriangleMesh t = tetra();
  TriangleMesh soup;
  for (const auto& tri : t.triangles) {
    const auto b = static_cast<std::uint32_t>(soup.positions.size());
    for (auto v : tri) soup.positions.push_back(t.positions[v]);
    soup.triangles.push_back({b, b + 1, b + 2});
  }
  EXPECT_TRUE(checkMesh(soup).printable());
  EXPECT_EQ(checkMesh(soup).vertices, 4u);
  soup.positions[0][0] += 1e-6f;  // looks closed, is not
  const CheckReport r = checkMesh(soup);
  EXPECT_FALSE(r.printable());
  EXPECT_GT(r.borderEdges, 0u);
}

// Distinct points are numbered in parallel; the numbering must be the one a serial pass
// gives (in order of first occurrence, equal as floats: -0 and +0 alike, a NaN never), on
// soups of many blocks with twins near and far, and on points all distinct (the identity).
TEST(Check, DistinctPointsAreNumberedAsASerialPassNumbersThem) {
  std::mt19937 g(5);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t n : {std::size_t(7), std::size_t(5000), std::size_t(300000)}) {
    for (int twinsEvery : {0, 3, 50}) {
      std::vector<Vec3f> points(n);
      std::uniform_int_distribution<int> coord(-40, 40), pick(0, 1 << 30);
      for (std::size_t i = 0; i < n; ++i) {
        points[i] = {coord(g) * 0.25f, coord(g) * 0.5f, float(i)};  // distinct by z
        if (twinsEvery && i > 0 && pick(g) % twinsEvery == 0)
          points[i] = points[static_cast<std::size_t>(pick(g)) % i];  // a twin, near or far
        if (i % 997 == 5) points[i][0] = (i % 2 ? -0.0f : 0.0f);      // -0 and +0
        if (i % 1999 == 7) points[i][1] = nan;                        // never equal
      }
      // the reference: a serial pass with a map
      std::map<std::array<float, 3>, std::uint32_t> seen;
      std::vector<std::uint32_t> expectMap(n), expectFirst;
      for (std::size_t i = 0; i < n; ++i) {
        std::array<float, 3> key = points[i];
        for (float& x : key)
          if (x == 0.0f) x = 0.0f;
        if (std::isnan(key[1])) {  // (a map cannot hold NaN as a key: its own number)
          expectMap[i] = static_cast<std::uint32_t>(expectFirst.size());
          expectFirst.push_back(static_cast<std::uint32_t>(i));
          continue;
        }
        const auto found = seen.find(key);
        if (found != seen.end()) {
          expectMap[i] = found->second;
          continue;
        }
        seen[key] = expectMap[i] = static_cast<std::uint32_t>(expectFirst.size());
        expectFirst.push_back(static_cast<std::uint32_t>(i));
      }
      std::vector<std::uint32_t> first;
      const std::vector<std::uint32_t> map = distinctPoints(points, &first);
      ASSERT_EQ(map, expectMap) << n << " points, twins every " << twinsEvery;
      ASSERT_EQ(first, expectFirst) << n << " points, twins every " << twinsEvery;
      if (twinsEvery == 0) {
        EXPECT_EQ(first.size(), n);
      }
    }
  }
}

TEST(Check, EmptyAndNonFinite) {
  EXPECT_FALSE(checkMesh(TriangleMesh{}).printable());
  TriangleMesh m = tetra();
  m.positions[0][0] = std::numeric_limits<float>::quiet_NaN();
  const CheckReport r = checkMesh(m);
  EXPECT_EQ(r.nonFiniteVertices, 1u);
  EXPECT_FALSE(r.printable());
}

TEST(Check, ReportFormats) {
  const CheckReport good = checkMesh(tetra());
  EXPECT_NE(reportToText(good, "t.stl").find("verdict: printable"), std::string::npos);
  TriangleMesh open = tetra();
  open.triangles.pop_back();
  const CheckReport bad = checkMesh(open);
  const std::string text = reportToText(bad, "t.stl");
  EXPECT_NE(text.find("NOT printable"), std::string::npos);
  EXPECT_NE(text.find("3 border edges"), std::string::npos);
  EXPECT_NE(reportToJson(bad, "t.stl").find("\"printable\": false"), std::string::npos);
}

// Found by the test below: a vertex no triangle uses made CGAL's orientation test crash
// (SIGSEGV), and mesh files may list such vertices.
TEST(Check, UnusedVerticesDoNotMatter) {
  TriangleMesh m = tetra();
  m.positions.push_back({5, 5, 5});
  m.positions.push_back({-3, 2, 1});
  const CheckReport r = checkMesh(m);
  EXPECT_TRUE(r.printable()) << r.reasons.size();
  EXPECT_TRUE(r.outward);
  EXPECT_EQ(r.components, 1u);
}

// The check decides "is this soup a polygon mesh?" from its own edge and fan counts instead
// of CGAL's is_polygon_soup_a_polygon_mesh (a large part of its time). The two must agree:
// soups made from two octahedra sharing vertices, with faces removed, flipped, repeated and
// added at random.
TEST(Check, PolygonMeshTestAgreesWithCgals) {
  const std::vector<Vec3f> octahedron = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                         {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
  const std::vector<Triangle> faces = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                       {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  std::mt19937 g(7);
  int meshes = 0, soups = 0;
  for (int i = 0; i < 3000; ++i) {
    TriangleMesh m;
    m.positions = octahedron;
    // a second octahedron beside the first, sharing 0, 1 or 2 of its vertices
    const int shared = std::uniform_int_distribution<int>(0, 2)(g);
    for (const Vec3f& p : octahedron) m.positions.push_back({p[0] + 2, p[1], p[2]});
    if (shared >= 1) m.positions[6 + 1] = m.positions[0];  // its -x vertex is our +x vertex
    if (shared >= 2) m.positions[6 + 2] = m.positions[2];  // and its +y our +y... moved
    const bool second = g() % 2;
    for (int copy = 0; copy < (second ? 2 : 1); ++copy)
      for (Triangle t : faces) {
        const int what = std::uniform_int_distribution<int>(0, 19)(g);
        if (what == 0) continue;               // removed
        if (what == 1) std::swap(t[1], t[2]);  // flipped
        for (auto& v : t) v += 6 * copy;
        m.triangles.push_back(t);
        if (what == 2) m.triangles.push_back(t);  // repeated
      }
    const int extra = std::uniform_int_distribution<int>(0, 3)(g) == 0 ? 1 : 0;
    for (int e = 0; e < extra; ++e) {  // a random face over the first octahedron's vertices
      std::uint32_t a = g() % 6, b = g() % 6, c = g() % 6;
      if (a == b || b == c || a == c) continue;
      m.triangles.push_back({a, b, c});
    }
    if (m.triangles.empty()) continue;
    const CheckReport r = checkMesh(m);
    const bool ours =
        r.nonManifoldEdges == 0 && r.misorientedEdges == 0 && r.nonManifoldVertices == 0;
    // CGAL's verdict on the same welded soup (unused points do not matter to it)
    std::vector<std::array<float, 3>> unique;
    std::vector<std::vector<std::size_t>> soup;
    auto id = [&](const Vec3f& p) {
      for (std::size_t k = 0; k < unique.size(); ++k)
        if (unique[k] == std::array<float, 3>{p[0], p[1], p[2]}) return k;
      unique.push_back({p[0], p[1], p[2]});
      return unique.size() - 1;
    };
    for (const Triangle& t : m.triangles)
      soup.push_back({id(m.positions[t[0]]), id(m.positions[t[1]]), id(m.positions[t[2]])});
    const bool cgal = CGAL::Polygon_mesh_processing::is_polygon_soup_a_polygon_mesh(soup);
    ASSERT_EQ(ours, cgal) << "soup " << i;
    (cgal ? meshes : soups) += 1;
  }
  EXPECT_GT(meshes, 300);  // both verdicts are exercised
  EXPECT_GT(soups, 300);
}

// The surface of the cube [0, n]^3 as lattice triangles, two per unit square, outward.
void latticeCube(int n, std::vector<Vec3f>& points, std::vector<FaceIndices>& faces) {
  std::map<std::array<int, 3>, std::uint32_t> ids;
  auto id = [&](int x, int y, int z) {
    const auto it = ids.find({x, y, z});
    if (it != ids.end()) return it->second;
    points.push_back({float(x), float(y), float(z)});
    return ids[{x, y, z}] = static_cast<std::uint32_t>(points.size() - 1);
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side)
      for (int u = 0; u < n; ++u)
        for (int v = 0; v < n; ++v) {
          auto at = [&](int du, int dv) {
            int c[3];
            c[axis] = side * n;
            c[(axis + 1) % 3] = u + du;
            c[(axis + 2) % 3] = v + dv;
            return id(c[0], c[1], c[2]);
          };
          const std::uint32_t a = at(0, 0), b = at(1, 0), c = at(1, 1), d = at(0, 1);
          if (side == 1) {
            faces.push_back({a, b, c});
            faces.push_back({a, c, d});
          } else {
            faces.push_back({a, c, b});
            faces.push_back({a, d, c});
          }
        }
}

// Broken meshes for the self-intersection tests: a lattice cube (3 to 5 units a side, by i)
// with 1 to 4 vertices moved to other lattice points (exactly coplanar folds over shared
// edges, shared-vertex crossings, collinear faces, piercings)...
void movedLatticeCube(int i, std::mt19937& g, std::vector<Vec3f>& points,
                      std::vector<FaceIndices>& faces) {
  latticeCube(3 + i % 3, points, faces);
  std::uniform_int_distribution<int> lattice(-1, 6), which(0, static_cast<int>(points.size()) - 1);
  for (int k = 0; k < 1 + i % 4; ++k)
    points[static_cast<std::size_t>(which(g))] = {float(lattice(g)), float(lattice(g)),
                                                  float(lattice(g))};
}

// ... and a meshed ball's vertices with 1 to 20 of them (by i) jittered by up to `jitter`.
std::vector<Vec3f> jitteredBall(const TriangleMesh& ball, int i, float jitter, std::mt19937& g) {
  std::vector<Vec3f> points = ball.positions;
  std::uniform_int_distribution<std::size_t> which(0, points.size() - 1);
  std::uniform_real_distribution<float> shift(-jitter, jitter);
  for (int k = 0; k < 1 + i % 20; ++k) {
    Vec3f& q = points[which(g)];
    for (float& c : q) c += shift(g);
  }
  return points;
}

TriangleMesh meshedBall(double cell) {
  MeshingOptions o;
  o.bbox = {{-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2}};
  o.resolution = cell;
  return polygonize(compile(makeNode("sphere", {}, {})), o);
}

// The grid count must be CGAL's count exactly: lattice cubes with vertices moved to other
// lattice points (exactly coplanar folds over shared edges, shared-vertex crossings,
// collinear faces, piercings), and a meshed ball with vertices jittered by a cell.
TEST(Check, GridSelfIntersectionCountIsCgals) {
  std::mt19937 g(31);
  int withIntersections = 0;
  for (int i = 0; i < 400; ++i) {
    std::vector<Vec3f> points;
    std::vector<FaceIndices> faces;
    movedLatticeCube(i, g, points, faces);
    const std::size_t ours = countSelfIntersections(points, faces);
    ASSERT_EQ(ours, countSelfIntersectionsWithCgal(points, faces)) << "cube " << i;
    withIntersections += ours > 0;
  }
  EXPECT_GT(withIntersections, 150);
  const TriangleMesh ball = meshedBall(0.2);
  std::vector<FaceIndices> faces(ball.triangles.begin(), ball.triangles.end());
  for (int i = 0; i < 60; ++i) {
    const std::vector<Vec3f> points = jitteredBall(ball, i, 0.2f, g);
    ASSERT_EQ(countSelfIntersections(points, faces), countSelfIntersectionsWithCgal(points, faces))
        << "ball " << i;
  }
  EXPECT_EQ(countSelfIntersections(ball.positions, faces), 0u);
}

// The grid is searched in slabs of z layers. With slabs of a few dozen entries, nearly
// every pair lies on or across a slab boundary: the count must still be CGAL's, each pair
// counted once, on jittered balls and on two interpenetrating meshed balls (their crossing
// circle runs through every slab).
TEST(Check, SlabsOfTheGridCountAsCgal) {
  std::mt19937 g(77);
  const TriangleMesh ball = meshedBall(0.2);
  std::vector<FaceIndices> faces(ball.triangles.begin(), ball.triangles.end());
  int withIntersections = 0;
  for (int i = 0; i < 60; ++i) {
    const std::vector<Vec3f> points = jitteredBall(ball, i, 0.2f, g);
    const std::size_t cgal = countSelfIntersectionsWithCgal(points, faces);
    for (std::size_t slab : {1, 40, 400})
      ASSERT_EQ(countSelfIntersections(points, faces, nullptr, SIZE_MAX, {}, slab), cgal)
          << "ball " << i << ", slabs of " << slab << " entries";
    withIntersections += cgal > 0;
  }
  EXPECT_GT(withIntersections, 15);
  std::vector<Vec3f> points = ball.positions;
  const std::size_t half = points.size();
  for (std::size_t v = 0; v < half; ++v)
    points.push_back({points[v][0] + 0.7f, points[v][1] + 0.3f, points[v][2] + 0.5f});
  for (std::size_t f = 0, n = faces.size(); f < n; ++f)
    faces.push_back({faces[f][0] + static_cast<std::uint32_t>(half),
                     faces[f][1] + static_cast<std::uint32_t>(half),
                     faces[f][2] + static_cast<std::uint32_t>(half)});
  const std::size_t cgal = countSelfIntersectionsWithCgal(points, faces);
  ASSERT_GT(cgal, 50u);
  for (std::size_t slab : {1, 40, 400, 0})
    EXPECT_EQ(countSelfIntersections(points, faces, nullptr, SIZE_MAX, {}, slab), cgal)
        << "slabs of " << slab << " entries";
}

// Faces crowding one place (a fan of hundreds of slivers round one vertex, a pile of
// copies) make the grid pay too many pairs a face: CGAL's box tree finds the pairs then, and
// the count is still CGAL's, folded fans (crossings) and piles alike.
TEST(Check, CrowdedFacesAreCountedThroughTheBoxTreeAsCgal) {
  std::mt19937 g(11);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int i = 0; i < 6; ++i) {
    const int n = 300 + 50 * i;
    std::vector<Vec3f> points = {{0, 0, 0}};
    for (int k = 0; k < n; ++k) {
      float a = 6.2831853f * (static_cast<float>(k) + 0.5f * unit(g)) / n;
      if (i % 2 == 1 && k % 37 == 0) a += 0.3f;  // folded over its neighbours: crossings
      points.push_back({std::cos(a), std::sin(a), 0.2f * (unit(g) - 0.5f)});
    }
    std::vector<FaceIndices> faces;
    for (int k = 0; k < n; ++k)
      faces.push_back(
          {0, static_cast<std::uint32_t>(1 + k), static_cast<std::uint32_t>(1 + (k + 1) % n)});
    const std::size_t cgal = countSelfIntersectionsWithCgal(points, faces);
    EXPECT_EQ(countSelfIntersections(points, faces), cgal) << "fan " << i;
    if (i % 2 == 1) {
      EXPECT_GT(cgal, 0u) << "fan " << i;
    }
  }
}

// A fan proved embedded (face_pair_test.h) has no intersecting pair of faces by CGAL's own
// count, on random fans round a vertex: neighbours in order or shuffled, winding once or
// twice, flat, bent, folded over, and on integer lattice points (exact coplanar overlaps).
TEST(Check, AFanIsProvedEmbeddedOnlyWhereCgalFindsNoIntersection) {
  std::mt19937 g(5);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  int proved = 0, refusedWithIntersections = 0;
  for (int i = 0; i < 20000; ++i) {
    const int n = 3 + static_cast<int>(g() % 7);
    const bool lattice = i % 3 == 0;
    const int winding = i % 11 == 0 ? 2 : 1;
    std::vector<float> angles;
    for (int k = 0; k < n; ++k)
      angles.push_back(6.2831853f * winding * (static_cast<float>(k) + 0.8f * unit(g)) / n);
    if (i % 7 == 0) std::swap(angles[0], angles[g() % n]);  // out of order: folds
    std::vector<Vec3f> points = {{0, 0, 0}};
    const float bend = i % 5 == 0 ? 2.0f : 0.3f;
    for (int k = 0; k < n; ++k) {
      const float r = 0.5f + unit(g);
      Vec3f q = {r * std::cos(angles[k]), r * std::sin(angles[k]), bend * (unit(g) - 0.5f)};
      if (lattice)
        for (float& c : q) c = std::round(c * 2.0f);
      points.push_back(q);
    }
    std::vector<FaceIndices> faces;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> sectors;
    for (int k = 0; k < n; ++k) {
      const std::uint32_t a = 1 + k, b = 1 + (k + 1) % n;
      faces.push_back({0, a, b});
      sectors.emplace_back(a, b);
    }
    // (a repeated lattice point makes a face repeat a vertex: not a fan of a polygon mesh)
    std::vector<Vec3f> sorted(points.begin(), points.end());
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) continue;
    const bool embedded = fanProvedEmbedded(points, 0, sectors.data(), sectors.size());
    const std::size_t cgal = countSelfIntersectionsWithCgal(points, faces);
    if (embedded) {
      ASSERT_EQ(cgal, 0u) << "fan " << i;
      ++proved;
    } else if (cgal > 0) {
      ++refusedWithIntersections;
    }
  }
  EXPECT_GT(proved, 5000);
  EXPECT_GT(refusedWithIntersections, 500);
}

// The whole check (which skips the pairs proved apart by embedded fans) counts what CGAL
// counts on meshes broken by moved vertices: the lattice cubes and the jittered ball above.
TEST(Check, CheckWithEmbeddedFansCountsAsCgal) {
  std::mt19937 g(77);
  int broken = 0;
  auto compare = [&](const std::vector<Vec3f>& points, const std::vector<FaceIndices>& faces,
                     int i) {
    TriangleMesh m;
    m.positions = points;
    m.triangles.assign(faces.begin(), faces.end());
    const CheckReport r = checkMesh(m);
    if (r.nonManifoldEdges || r.misorientedEdges || r.nonManifoldVertices || r.degenerateFaces)
      return;  // (the grid and the fans serve polygon meshes only)
    std::vector<Vec3f> welded;
    const std::vector<std::uint32_t> map = weldIdenticalVertices(points, welded);
    std::vector<FaceIndices> indexed;
    for (const FaceIndices& f : faces) indexed.push_back({map[f[0]], map[f[1]], map[f[2]]});
    ASSERT_EQ(r.selfIntersections, countSelfIntersectionsWithCgal(welded, indexed)) << "mesh " << i;
    broken += r.selfIntersections > 0;
  };
  for (int i = 0; i < 300; ++i) {
    std::vector<Vec3f> points;
    std::vector<FaceIndices> faces;
    movedLatticeCube(i, g, points, faces);
    compare(points, faces, i);
  }
  const TriangleMesh ball = meshedBall(0.15);
  const std::vector<FaceIndices> faces(ball.triangles.begin(), ball.triangles.end());
  for (int i = 0; i < 100; ++i) compare(jitteredBall(ball, i, 0.15f, g), faces, 1000 + i);
  EXPECT_GT(broken, 100);
}

// Progress comes through the self-intersection pass too (it is most of a large check), in
// order, up to 1; a progress callback that throws stops the check there.
TEST(Check, ProgressCoversTheSelfIntersectionPassAndCanStopIt) {
  MeshingOptions o;
  o.bbox = {{-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2}};
  o.resolution = 1.0 / 24;
  const TriangleMesh ball = polygonize(compile(makeNode("sphere", {}, {})), o);
  std::vector<double> ticks;
  EXPECT_TRUE(checkMesh(ball, [&](double f) { ticks.push_back(f); }).printable());
  ASSERT_FALSE(ticks.empty());
  EXPECT_TRUE(std::is_sorted(ticks.begin(), ticks.end()));
  EXPECT_EQ(ticks.back(), 1.0);
  const auto inPass =
      std::count_if(ticks.begin(), ticks.end(), [](double f) { return f > 0.45 && f < 0.95; });
  EXPECT_GE(inPass, 10);
  struct Stop {};
  double last = 0;
  EXPECT_THROW(checkMesh(ball,
                         [&](double f) {
                           last = f;
                           if (f > 0.6) throw Stop();
                         }),
               Stop);
  EXPECT_LT(last, 0.7);
}

}  // namespace
}  // namespace frep

namespace frep {
namespace {

// A pile of coincident triangles makes n(n-1)/2 intersecting pairs: 30,000 of them took CGAL
// over a minute to count. The count stops at the limit and says "at least"; below the limit
// it is exact, on both routes (CGAL's for soups, the grid for polygon meshes).
TEST(Check, SelfIntersectionCountStopsAtItsLimit) {
  TriangleMesh pile;
  pile.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  pile.triangles.assign(30000, Triangle{0, 1, 2});
  const CheckReport r = checkMesh(pile);  // (a second a few hundred ms)
  EXPECT_EQ(r.selfIntersections, kSelfIntersectionLimit);
  EXPECT_TRUE(r.selfIntersectionsAtLeast);
  EXPECT_FALSE(r.printable());
  EXPECT_NE(reportToText(r, "pile").find("at least 1000000 triangle pairs"), std::string::npos);
  EXPECT_NE(reportToJson(r, "pile").find("\"self_intersections_at_least\": true"),
            std::string::npos);
  pile.triangles.resize(300);  // 44,850 pairs: below the limit, counted exactly
  const CheckReport small = checkMesh(pile);
  EXPECT_EQ(small.selfIntersections, 300u * 299u / 2u);
  EXPECT_FALSE(small.selfIntersectionsAtLeast);
  EXPECT_EQ(checkMesh(pile, nullptr, 1000).selfIntersections, 1000u);
  // a polygon mesh (two interpenetrating lattice cubes) through the grid
  std::vector<Vec3f> points;
  std::vector<FaceIndices> faces;
  latticeCube(6, points, faces);
  const std::size_t half = points.size();
  std::vector<FaceIndices> second = faces;
  for (std::size_t i = 0; i < half; ++i)
    points.push_back({points[i][0] + 2.5f, points[i][1] + 2.5f, points[i][2] + 2.5f});
  for (FaceIndices f : second) {
    for (std::uint32_t& v : f) v += static_cast<std::uint32_t>(half);
    faces.push_back(f);
  }
  const std::size_t all = countSelfIntersections(points, faces);
  ASSERT_GT(all, 20u);
  EXPECT_EQ(all, countSelfIntersectionsWithCgal(points, faces));
  EXPECT_EQ(countSelfIntersections(points, faces, nullptr, 20), 20u);
  EXPECT_EQ(countSelfIntersections(points, faces, nullptr, all + 1), all);
}

}  // namespace
}  // namespace frep

namespace frep {
namespace {

// Orientation: one component is judged by the sign of its volume, several by CGAL's
// does_bound_a_volume (which knows nesting). A ball with a hollow inside (its inner surface
// facing into the hollow) is printable; the inner surface facing out is not; two balls apart,
// both outward, are printable, one of them inside out is not.
TEST(Check, OrientationOfOneAndOfNestedComponents) {
  MeshingOptions o;
  o.bbox = {{-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2}};
  o.resolution = 0.1;
  const TriangleMesh ball = polygonize(compile(makeNode("sphere", {}, {})), o);
  auto scaled = [](TriangleMesh m, float s, float dx) {
    for (Vec3f& p : m.positions) p = {p[0] * s + dx, p[1] * s, p[2] * s};
    return m;
  };
  auto flipped = [](TriangleMesh m) {
    for (Triangle& t : m.triangles) std::swap(t[1], t[2]);
    return m;
  };
  EXPECT_TRUE(checkMesh(ball).printable());
  const CheckReport inside = checkMesh(flipped(ball));
  EXPECT_FALSE(inside.outward);
  EXPECT_FALSE(inside.printable());
  const TriangleMesh hollow = merged(ball, flipped(scaled(ball, 0.5f, 0)));
  const CheckReport h = checkMesh(hollow);
  EXPECT_EQ(h.components, 2u);
  EXPECT_TRUE(h.printable()) << (h.reasons.empty() ? "" : h.reasons[0]);
  const CheckReport wrong = checkMesh(merged(ball, scaled(ball, 0.5f, 0)));
  EXPECT_FALSE(wrong.outward);  // the inner surface faces out: a volume counted twice
  EXPECT_TRUE(checkMesh(merged(ball, scaled(ball, 1.0f, 3))).printable());
  EXPECT_FALSE(checkMesh(merged(ball, flipped(scaled(ball, 1.0f, 3)))).outward);
  // Large enough that the components' facts are gathered by blocks of faces in parallel
  // (65,536 a block): a hollow of two fine balls and a third beside them, each spanning
  // blocks.
  o.resolution = 0.015;
  const TriangleMesh fine = polygonize(compile(makeNode("sphere", {}, {})), o);
  ASSERT_GT(fine.triangles.size(), 65536u);
  const TriangleMesh fineHollow =
      merged(merged(fine, flipped(scaled(fine, 0.5f, 0))), scaled(fine, 1.0f, 3));
  const CheckReport fh = checkMesh(fineHollow);
  EXPECT_EQ(fh.components, 3u);
  EXPECT_TRUE(fh.printable()) << (fh.reasons.empty() ? "" : fh.reasons[0]);
  EXPECT_FALSE(
      checkMesh(merged(merged(fine, scaled(fine, 0.5f, 0)), scaled(fine, 1.0f, 3))).outward);
  EXPECT_FALSE(checkMesh(merged(merged(fine, flipped(scaled(fine, 0.5f, 0))),
                                flipped(scaled(fine, 1.0f, 3))))
                   .outward);
  // the rays decide it (CGAL's fallback would hide facts gathered wrongly)
  const std::size_t n = fine.triangles.size();
  std::vector<std::uint32_t> component(3 * n);
  for (std::size_t f = 0; f < component.size(); ++f)
    component[f] = static_cast<std::uint32_t>(f / n);
  const std::vector<FaceIndices> hollowFaces(fineHollow.triangles.begin(),
                                             fineHollow.triangles.end());
  const std::optional<bool> byRays =
      boundsAVolumeByRays(fineHollow.positions, hollowFaces, component, 3);
  ASSERT_TRUE(byRays.has_value());
  EXPECT_TRUE(*byRays);
}

// The nesting test by rays (check/volume_nesting.h) against the rule the check had before
// (CGAL's does_bound_a_volume and a positive volume) on 200 random arrangements of balls and
// axis-aligned boxes (whose vertices share grid lines, where axis rays from vertices would
// graze), nested up to three deep, side by side, some turned inside out: the two agree on
// every one.
TEST(Check, NestingByRaysAgreesWithCgal) {
  MeshingOptions o;
  o.bbox = {{-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2}};
  o.resolution = 0.3;
  const TriangleMesh ball = polygonize(compile(makeNode("sphere", {}, {})), o);
  const TriangleMesh cube = polygonize(
      compile(makeNode(
          "box", {{"corner", vec3Value({-0.9, -0.9, -0.9})}, {"size", vec3Value({1.8, 1.8, 1.8})}},
          {})),
      o);
  std::mt19937 rng(12);
  std::uniform_real_distribution<float> u(0, 1);
  int outward = 0, not_outward = 0;
  for (int trial = 0; trial < 200; ++trial) {
    TriangleMesh all;
    const int groups = 1 + static_cast<int>(u(rng) * 3);
    for (int g = 0; g < groups; ++g) {
      const float dx = 5.0f * static_cast<float>(g), dy = u(rng) < 0.3f ? 0.0f : u(rng);
      const int depth = 1 + static_cast<int>(u(rng) * 3);
      for (int d = 0; d < depth; ++d) {
        TriangleMesh m = u(rng) < 0.5f ? ball : cube;
        const float s = std::pow(0.45f, static_cast<float>(d));
        for (Vec3f& p : m.positions) p = {p[0] * s + dx, p[1] * s + 0.2f * dy * (1 - s), p[2] * s};
        // the orientation a volume needs (outward at even depth), or now and then the other
        if ((d % 2 == 1) != (u(rng) < 0.1f))
          for (Triangle& t : m.triangles) std::swap(t[1], t[2]);
        all = all.triangles.empty() ? m : merged(all, m);
      }
    }
    const CheckReport r = checkMesh(all);
    ASSERT_TRUE(r.closed && r.selfIntersections == 0) << "trial " << trial;
    std::vector<Vec3f> welded;
    const std::vector<std::uint32_t> map = weldIdenticalVertices(all.positions, welded);
    std::vector<FaceIndices> faces;
    for (const Triangle& t : all.triangles) faces.push_back({map[t[0]], map[t[1]], map[t[2]]});
    const bool before = r.volume > 0 && (r.components == 1 || boundsAVolume(welded, faces));
    EXPECT_EQ(r.outward, before) << "trial " << trial << ", " << r.components << " components";
    (before ? outward : not_outward)++;
  }
  EXPECT_GT(outward, 40);
  EXPECT_GT(not_outward, 40);
}

// The mesh cut into splits^3 parts by its faces' centroids, each part with the box of its
// own vertices, checked part by part (partitioned_check.h); nothing where the parts cannot
// decide.
// mode 0: each part judged here (addPart); 1: judged as a summary (a worker's) and taken in;
// 2: summaries, with every triangle whose corners all lie where boxes overlap held back from
// its part and given late (addZoneFaces), as the brick merge gives its crease flips.
std::optional<CheckReport> checkInParts(const TriangleMesh& m, int splits, int mode = 0) {
  Box3 all;
  for (int a = 0; a < 3; ++a) {
    all.lo[a] = HUGE_VAL;
    all.hi[a] = -HUGE_VAL;
  }
  for (const Vec3f& p : m.positions)
    for (int a = 0; a < 3; ++a) {
      all.lo[a] = std::min(all.lo[a], double(p[a]));
      all.hi[a] = std::max(all.hi[a], double(p[a]));
    }
  const std::size_t n = static_cast<std::size_t>(splits * splits * splits);
  std::vector<TriangleMesh> parts(n);
  std::vector<std::map<std::uint32_t, std::uint32_t>> index(n);
  for (const Triangle& t : m.triangles) {
    std::size_t cell = 0;
    for (int a = 2; a >= 0; --a) {
      const double c =
          (double(m.positions[t[0]][a]) + m.positions[t[1]][a] + m.positions[t[2]][a]) / 3;
      const int i =
          std::clamp(static_cast<int>((c - all.lo[a]) / (all.hi[a] - all.lo[a] + 1e-30) * splits),
                     0, splits - 1);
      cell = cell * static_cast<std::size_t>(splits) + static_cast<std::size_t>(i);
    }
    Triangle local;
    for (int k = 0; k < 3; ++k) {
      const auto [at, fresh] =
          index[cell].try_emplace(t[k], static_cast<std::uint32_t>(parts[cell].positions.size()));
      if (fresh) parts[cell].positions.push_back(m.positions[t[k]]);
      local[k] = at->second;
    }
    parts[cell].triangles.push_back(local);
  }
  std::vector<Box3> boxes(n);
  for (std::size_t i = 0; i < n; ++i) {
    boxes[i] = Box3{{0, 0, 0}, {0, 0, 0}};  // an empty part: a point
    for (std::size_t v = 0; v < parts[i].positions.size(); ++v)
      for (int a = 0; a < 3; ++a) {
        const double x = parts[i].positions[v][a];
        boxes[i].lo[a] = v ? std::min(boxes[i].lo[a], x) : x;
        boxes[i].hi[a] = v ? std::max(boxes[i].hi[a], x) : x;
      }
  }
  PartitionedCheck check(boxes);
  std::vector<TriangleMesh> late(n);
  if (mode == 2)
    for (std::size_t i = 0; i < n; ++i) {
      auto inTwo = [&](const Vec3f& p) {
        int in = 0;
        for (const Box3& b : boxes) {
          bool holds = true;
          for (int a = 0; a < 3; ++a) holds = holds && p[a] >= b.lo[a] && p[a] <= b.hi[a];
          in += holds;
        }
        return in > 1;
      };
      std::vector<Triangle> keep;
      for (const Triangle& t : parts[i].triangles) {
        const Vec3f* c[3] = {&parts[i].positions[t[0]], &parts[i].positions[t[1]],
                             &parts[i].positions[t[2]]};
        if (inTwo(*c[0]) && inTwo(*c[1]) && inTwo(*c[2]) && keep.size() % 3 == 0) {
          const auto base = static_cast<std::uint32_t>(late[i].positions.size());
          for (const Vec3f* p : c) late[i].positions.push_back(*p);
          late[i].triangles.push_back({base, base + 1, base + 2});
        } else {
          keep.push_back(t);
        }
      }
      parts[i].triangles = keep;
    }
  for (std::size_t i = 0; i < n; ++i) {
    const bool inside = mode == 0
                            ? check.addPart(i, parts[i])
                            : check.addSummary(i, PartitionedCheck::judgePart(boxes, i, parts[i]));
    if (!inside) return std::nullopt;
    if (!late[i].triangles.empty()) check.addZoneFaces(late[i]);
  }
  return check.finish(m.positions.size(), [&](std::size_t i) { return parts[i]; });
}

void expectSameReport(const CheckReport& parts, const CheckReport& whole, const std::string& what) {
  EXPECT_EQ(parts.vertices, whole.vertices) << what;
  EXPECT_EQ(parts.faces, whole.faces) << what;
  EXPECT_EQ(parts.borderEdges, whole.borderEdges) << what;
  EXPECT_EQ(parts.nonManifoldEdges, whole.nonManifoldEdges) << what;
  EXPECT_EQ(parts.nonManifoldVertices, whole.nonManifoldVertices) << what;
  EXPECT_EQ(parts.misorientedEdges, whole.misorientedEdges) << what;
  EXPECT_EQ(parts.degenerateFaces, whole.degenerateFaces) << what;
  EXPECT_EQ(parts.selfIntersections, whole.selfIntersections) << what;
  EXPECT_EQ(parts.components, whole.components) << what;
  EXPECT_EQ(parts.closed, whole.closed) << what;
  EXPECT_EQ(parts.outward, whole.outward) << what;
  EXPECT_EQ(parts.reasons, whole.reasons) << what;
  EXPECT_NEAR(parts.volume, whole.volume, 1e-9 * (1 + std::abs(whole.volume))) << what;
  EXPECT_NEAR(parts.area, whole.area, 1e-9 * (1 + whole.area)) << what;
  for (int a = 0; a < 3; ++a) {
    EXPECT_EQ(parts.bbox.lo[a], whole.bbox.lo[a]) << what;
    EXPECT_EQ(parts.bbox.hi[a], whole.bbox.hi[a]) << what;
  }
}

// Checked in parts, a mesh gets the report checked whole gives: broken lattice cubes
// (crossings, folds, coplanar overlaps cut across parts), jittered balls, nests of solids
// (orientation by rays counted part by part) and the mesher's meshes.
TEST(Check, CheckInPartsAgreesWithTheWholeCheck) {
  std::mt19937 g(91);
  int decided = 0, polygonMeshes = 0, broken = 0;
  auto compare = [&](const TriangleMesh& m, const std::string& what) {
    const CheckReport whole = checkMesh(m);
    const bool polygonMesh =
        !whole.nonManifoldEdges && !whole.misorientedEdges && !whole.nonManifoldVertices;
    polygonMeshes += polygonMesh;
    for (int splits : {2, 3}) {
      const int mode = (splits + decided) % 3;  // each way of taking parts in, in turn
      const std::optional<CheckReport> parts = checkInParts(m, splits, mode);
      if (polygonMesh) {
        EXPECT_TRUE(parts.has_value()) << what << " in " << splits;
      }
      if (!parts) continue;
      ++decided;
      broken += !whole.printable();
      expectSameReport(*parts, whole,
                       what + " in " + std::to_string(splits * splits * splits) + " parts, mode " +
                           std::to_string(mode));
    }
  };
  for (int i = 0; i < 150; ++i) {
    TriangleMesh m;
    std::vector<FaceIndices> faces;
    movedLatticeCube(i, g, m.positions, faces);
    m.triangles.assign(faces.begin(), faces.end());
    compare(m, "lattice cube " + std::to_string(i));
  }
  const TriangleMesh ball = meshedBall(0.15);
  for (int i = 0; i < 40; ++i) {
    TriangleMesh m = ball;
    m.positions = jitteredBall(ball, i, 0.15f, g);
    compare(m, "ball " + std::to_string(i));
  }
  for (const char* name : {"csg", "gyroid", "twist"}) {
    const Model model = loadModel(std::string(FREP_SOURCE_DIR) + "/examples/" + name + ".json");
    MeshingOptions o;
    o.bbox = *model.bbox;
    o.resolution = 2.4 / 48;
    o.normals = false;
    const TriangleMesh m = polygonize(compile(model.root), o);
    compare(m, name);
    TriangleMesh inside = m;  // turned inside out
    for (Triangle& t : inside.triangles) std::swap(t[1], t[2]);
    compare(inside, std::string(name) + " inside out");
    for (int k = 0; k < 4; ++k) {  // holes, some across the parts' seams
      TriangleMesh holed = m;
      for (int j = 0; j < 30; ++j)
        holed.triangles.erase(holed.triangles.begin() +
                              static_cast<long>(g() % holed.triangles.size()));
      compare(holed, std::string(name) + " holed " + std::to_string(k));
    }
  }
  EXPECT_GT(polygonMeshes, 60);
  EXPECT_GT(broken, 60);
  EXPECT_GT(decided, 150);
}

}  // namespace
}  // namespace frep
