// Automatic bounds: the box findBounds reports encloses the solid, is tight to within the
// tolerance (plus interval slack), and tells empty and unbounded solids apart.
#include <gtest/gtest.h>

#include <cmath>

#include "frep/bounds.h"
#include "frep/tree.h"
#include "mesh/mesher.h"
#include "mesh/triangle_geometry.h"

namespace frep {
namespace {

NodePtr sphere(Vec3 c, double r) {
  return makeNode("sphere", {{"center", vec3Value(c)}, {"radius", realValue(r)}}, {});
}

SolidBounds boundsOf(const NodePtr& n) {
  return findBounds(compile(n));
}

TEST(Bounds, SphereIsTight) {
  SolidBounds b = boundsOf(sphere({1, -2, 3}, 0.5));
  ASSERT_TRUE(b.bounded());
  const Vec3 lo{0.5, -2.5, 2.5}, hi{1.5, -1.5, 3.5};
  for (int a = 0; a < 3; ++a) {
    EXPECT_LE(b.box.lo[a], lo[a]);  // never inside the solid
    EXPECT_GE(b.box.hi[a], hi[a]);
    EXPECT_NEAR(b.box.lo[a], lo[a], 1e-3);
    EXPECT_NEAR(b.box.hi[a], hi[a], 1e-3);
  }
}

TEST(Bounds, RotatedBoxEnclosesItsMesh) {
  NodePtr box = makeNode("box", {{"size", vec3Value({1, 2, 0.5})}}, {});
  NodePtr rotated =
      makeNode("rotate", {{"axis", vec3Value({1, 1, 0})}, {"angle", realValue(37)}}, {box});
  Program p = compile(rotated);
  SolidBounds b = findBounds(p);
  ASSERT_TRUE(b.bounded());
  MeshingOptions o;
  o.bbox = Box3{{-5, -5, -5}, {5, 5, 5}};
  o.resolution = 0.05;
  TriangleMesh m = polygonize(p, o);
  ASSERT_GT(m.triangleCount(), 0u);
  Vec3 lo{1e9, 1e9, 1e9}, hi{-1e9, -1e9, -1e9};
  for (const Vec3f& v : m.positions)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], double(v[a]));
      hi[a] = std::max(hi[a], double(v[a]));
    }
  for (int a = 0; a < 3; ++a) {
    EXPECT_LE(b.box.lo[a], lo[a] + 1e-6);
    EXPECT_GE(b.box.hi[a], hi[a] - 1e-6);
    // Mesh vertices lie on the surface up to root-finding error; the box is within a cell.
    EXPECT_NEAR(b.box.lo[a], lo[a], 0.05);
    EXPECT_NEAR(b.box.hi[a], hi[a], 0.05);
  }
}

TEST(Bounds, DisjointIntersectionIsEmpty) {
  NodePtr n = makeNode("intersection", {}, {sphere({0, 0, 0}, 1), sphere({5, 0, 0}, 1)});
  SolidBounds b = boundsOf(n);
  EXPECT_TRUE(b.empty);
  EXPECT_FALSE(b.bounded());
}

TEST(Bounds, HalfspaceIsUnboundedOnFiveSides) {
  NodePtr h = makeNode("halfspace",
                       {{"point", vec3Value({0, 0, 2})}, {"normal", vec3Value({0, 0, 1})}}, {});
  SolidBounds b = boundsOf(h);
  ASSERT_FALSE(b.empty);
  EXPECT_FALSE(b.bounded());
  // Inside is z <= 2 (F = dot(point - p, normal)); only +z is bounded.
  EXPECT_TRUE(b.unbounded[0][0] && b.unbounded[0][1] && b.unbounded[1][0] && b.unbounded[1][1] &&
              b.unbounded[2][0]);
  EXPECT_FALSE(b.unbounded[2][1]);
  EXPECT_NEAR(b.box.hi[2], 2.0, 1e-3);
}

TEST(Bounds, ComplementOfSphereIsUnbounded) {
  SolidBounds b = boundsOf(makeNode("complement", {}, {sphere({0, 0, 0}, 1)}));
  EXPECT_FALSE(b.bounded());
  EXPECT_FALSE(b.empty);
}

TEST(MeshMeasures, CubeVolumeAndArea) {
  // Unit cube from the mesher: volume 1 and area 6 up to the chamfer at its edges.
  NodePtr box = makeNode("box", {{"size", vec3Value({1, 1, 1})}}, {});
  MeshingOptions o;
  o.bbox = Box3{{-0.5, -0.5, -0.5}, {1.5, 1.5, 1.5}};
  o.resolution = 0.02;
  TriangleMesh m = polygonize(compile(box), o);
  EXPECT_NEAR(meshVolume(m), 1.0, 0.01);
  EXPECT_NEAR(meshArea(m), 6.0, 0.05);
  // Reversing every triangle negates the volume.
  for (Triangle& t : m.triangles) std::swap(t[1], t[2]);
  EXPECT_NEAR(meshVolume(m), -1.0, 0.01);
}

}  // namespace
}  // namespace frep
