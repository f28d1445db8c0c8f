// The checker finds each defect class on small hand-made meshes.
#include <gtest/gtest.h>

#include "check/mesh_check.h"

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
  const auto base = static_cast<std::uint32_t>(a.positions.size());
  m.positions.insert(m.positions.end(), b.positions.begin(), b.positions.end());
  for (auto t : b.triangles) m.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
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

}  // namespace
}  // namespace frep
