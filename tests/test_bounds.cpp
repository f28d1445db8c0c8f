// Automatic bounds: the box findBounds reports encloses the solid, is tight to within the
// tolerance (plus interval slack), and tells empty and unbounded solids apart.
#include <gtest/gtest.h>

#include <cmath>

#include "base/triangle_geometry.h"
#include "frep/bounds.h"
#include "frep/structural_bounds.h"
#include "frep/tree.h"
#include "mesh/mesher.h"
#include "random_trees.h"
#include "test_nodes.h"

namespace frep {
namespace {

using frep::testing::box;
using frep::testing::sphere;

SolidBounds boundsOf(const NodePtr& n) {
  return findBounds(compile(n));
}

TEST(Bounds, SphereIsTight) {
  SolidBounds b = boundsOf(sphere(0.5, {1, -2, 3}));
  ASSERT_TRUE(b.bounded());
  const Vec3 lo{0.5, -2.5, 2.5}, hi{1.5, -1.5, 3.5};
  for (int a = 0; a < 3; ++a) {
    EXPECT_LE(b.box.lo[a], lo[a]);  // never inside the solid
    EXPECT_GE(b.box.hi[a], hi[a]);
    EXPECT_NEAR(b.box.lo[a], lo[a], 1e-3);
    EXPECT_NEAR(b.box.hi[a], hi[a], 1e-3);
  }
}

// The box encloses the solid's mesh (cell `resolution` over `extent`) and is within `slack`
// of it on every side: mesh vertices lie on the surface up to root-finding error.
void expectTightToMesh(const Program& p, const SolidBounds& b, double extent, double resolution,
                       double slack) {
  ASSERT_TRUE(b.bounded());
  MeshingOptions o;
  o.bbox = Box3{{-extent, -extent, -extent}, {extent, extent, extent}};
  o.resolution = resolution;
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
    EXPECT_NEAR(b.box.lo[a], lo[a], slack);
    EXPECT_NEAR(b.box.hi[a], hi[a], slack);
  }
}

TEST(Bounds, RotatedBoxEnclosesItsMesh) {
  NodePtr box = makeNode("box", {{"size", vec3Value({1, 2, 0.5})}}, {});
  NodePtr rotated =
      makeNode("rotate", {{"axis", vec3Value({1, 1, 0})}, {"angle", realValue(37)}}, {box});
  Program p = compile(rotated);
  expectTightToMesh(p, findBounds(p), 5, 0.05, 0.05);  // within a cell
}

// A rotated torus has no flat face: the search ends on cells thin across the direction, whose
// intervals are loose while they are wide sideways. The box must still be tight.
TEST(Bounds, RotatedTorusIsTightToItsMesh) {
  NodePtr torus =
      makeNode("torus", {{"major_radius", realValue(1.0)}, {"minor_radius", realValue(0.25)}}, {});
  NodePtr rotated =
      makeNode("rotate", {{"axis", vec3Value({1, 1, 0})}, {"angle", realValue(37)}}, {torus});
  Program p = compile(rotated);
  BoundsOptions options;  // as the export and the workbench call it
  options.known = structuralBounds(rotated);
  // within 2 % of the torus's size (2.5): a looser box is a coarser preview
  expectTightToMesh(p, findBounds(p, options), 2, 0.02, 0.05);
}

TEST(Bounds, DisjointIntersectionIsEmpty) {
  NodePtr n = makeNode("intersection", {}, {sphere(1, {0, 0, 0}), sphere(1, {5, 0, 0})});
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
  SolidBounds b = boundsOf(makeNode("complement", {}, {sphere(1, {0, 0, 0})}));
  EXPECT_FALSE(b.bounded());
  EXPECT_FALSE(b.empty);
}

SolidBounds boundsWithStructure(const NodePtr& n) {
  BoundsOptions o;
  o.known = structuralBounds(n);
  return findBounds(compile(n), o);
}

TEST(StructuralBounds, TwistedBoxIsBoundedByItsCylinder) {
  // Intervals alone cannot bound a twist (sin and cos of z mix x and y); the structure can.
  const NodePtr t =
      makeNode("twist", {{"rate", realValue(90)}}, {box({-0.5, -0.5, -1}, {1, 1, 2})});
  EXPECT_FALSE(boundsOf(t).bounded());
  const SolidBounds b = boundsWithStructure(t);
  ASSERT_TRUE(b.bounded());
  const double r = std::sqrt(0.5);
  for (int a = 0; a < 2; ++a) {
    EXPECT_NEAR(b.box.lo[a], -r, 0.01);
    EXPECT_NEAR(b.box.hi[a], r, 0.01);
  }
  EXPECT_NEAR(b.box.hi[2], 1.0, 0.01);
}

TEST(StructuralBounds, LatticeInsideASphereAndDisjointBoxes) {
  const NodePtr lattice = makeNode("gyroid", {{"cell", realValue(0.3)}}, {});
  const Box3 open = structuralBounds(lattice);
  EXPECT_TRUE(std::isinf(open.lo[0]) && std::isinf(open.hi[2]));
  const Box3 b = structuralBounds(makeNode("intersection", {}, {lattice, sphere(0.5, {1, 0, 0})}));
  EXPECT_EQ(b.lo[0], 0.5);
  EXPECT_EQ(b.hi[0], 1.5);
  const NodePtr apart =
      makeNode("intersection", {}, {box({0, 0, 0}, {1, 1, 1}), box({2, 0, 0}, {1, 1, 1})});
  EXPECT_TRUE(boundsWithStructure(apart).empty);
  // An infinite cylinder along z: bounded across, unbounded along.
  const Box3 c = structuralBounds(
      makeNode("cylinder", {{"length", realValue(0)}, {"radius", realValue(2)}}, {}));
  EXPECT_EQ(c.hi[0], 2.0);
  EXPECT_TRUE(std::isinf(c.hi[2]));
}

TEST(StructuralBounds, EncloseEveryInsidePointOfRandomTrees) {
  // Random trees, some wrapped in the deformations and field operations that have rules:
  // every sampled point with F > 0 lies in the structural box and in the found box.
  testing::RandomTrees r(77);
  int insideChecked = 0;
  for (int t = 0; t < 60; ++t) {
    NodePtr n = r.tree(3);
    switch (t % 5) {
      case 0:
        n = makeNode("twist",
                     {{"rate", realValue(r.uniform(-120, 120))},
                      {"axis", vec3Value(r.direction())},
                      {"center", vec3Value(r.point(0.3))}},
                     {n});
        break;
      case 1:
        n = makeNode("taper",
                     {{"axis", vec3Value(r.direction())},
                      {"scale1", realValue(r.uniform(0.3, 2))},
                      {"scale2", realValue(r.uniform(0.3, 2))},
                      {"length", realValue(r.uniform(0.2, 2))}},
                     {n});
        break;
      case 2:
        n = makeNode("shell", {{"thickness", realValue(0.1)}}, {n});
        break;
      case 3:
        n = makeNode("metamorphosis", {{"t", realValue(r.uniform(0, 1))}}, {n, r.tree(2)});
        break;
      default:
        break;
    }
    const Program p = compile(n);
    const Box3 known = structuralBounds(n);
    BoundsOptions o;
    o.known = known;
    const SolidBounds found = findBounds(p, o);
    for (int s = 0; s < 4000; ++s) {
      const Vec3 q = {r.uniform(-3, 3), r.uniform(-3, 3), r.uniform(-3, 3)};
      if (p.eval(q[0], q[1], q[2]) <= 0) continue;
      ++insideChecked;
      ASSERT_FALSE(found.empty) << "tree " << t;
      for (int a = 0; a < 3; ++a) {
        ASSERT_GE(q[a], known.lo[a] - 1e-9) << "tree " << t << " axis " << a;
        ASSERT_LE(q[a], known.hi[a] + 1e-9) << "tree " << t << " axis " << a;
        ASSERT_GE(q[a], found.box.lo[a] - 1e-9) << "tree " << t << " axis " << a;
        ASSERT_LE(q[a], found.box.hi[a] + 1e-9) << "tree " << t << " axis " << a;
      }
    }
  }
  EXPECT_GT(insideChecked, 10000);
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
