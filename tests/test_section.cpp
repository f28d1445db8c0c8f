// Plane sections (mesh/section.h): closed loops on the surface, the solid on their left,
// holes as loops of their own, the plane's own axes.
#include <gtest/gtest.h>

#include <cmath>

#include "base/errors.h"
#include "mesh/section.h"
#include "test_nodes.h"

namespace frep {
namespace {

using testing::box;
using testing::sphere;

// Signed area of a loop in plane coordinates (positive: counterclockwise seen against u x v).
double signedArea(const SectionLoop& loop, const SectionPlane& p) {
  double a = 0;
  const std::size_t n = loop.points.size();
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3& q0 = loop.points[k];
    const Vec3& q1 = loop.points[(k + 1) % n];
    auto uv = [&](const Vec3& q, double& u, double& v) {
      const double d[3] = {q[0] - p.origin[0], q[1] - p.origin[1], q[2] - p.origin[2]};
      u = d[0] * p.u[0] + d[1] * p.u[1] + d[2] * p.u[2];
      v = d[0] * p.v[0] + d[1] * p.v[1] + d[2] * p.v[2];
    };
    double u0, v0, u1, v1;
    uv(q0, u0, v0);
    uv(q1, u1, v1);
    a += u0 * v1 - u1 * v0;
  }
  return a / 2;
}

double perimeter(const SectionLoop& loop) {
  double l = 0;
  for (std::size_t k = 0; k < loop.points.size(); ++k) {
    const Vec3& a = loop.points[k];
    const Vec3& b = loop.points[(k + 1) % loop.points.size()];
    l += std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                   (a[2] - b[2]) * (a[2] - b[2]));
  }
  return l;
}

std::vector<SectionLoop> cut(const NodePtr& solid, const SectionPlane& plane, double cell,
                             Box3 around = {{-2, -2, -2}, {2, 2, 2}}) {
  double u0, u1, v0, v1;
  EXPECT_TRUE(sectionRectangle(plane, around, u0, u1, v0, v1));
  return sectionField(compile(solid), plane, u0, u1, v0, v1, cell);
}

TEST(Section, ASphereCutByATiltedPlaneIsOneCircleOnItsSurface) {
  SectionPlane p;
  p.origin = {0.1, 0.2, 0.3};
  const double s = std::sqrt(0.5);
  p.u = {s, 0, -s};  // a plane through (0.1, 0.2, 0.3) tilted about y
  p.v = {0, 1, 0};
  const auto loops = cut(sphere(1.0), p, 0.02);
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_TRUE(loops[0].closed);
  // every vertex is on the sphere (root finding on the field) and in the plane
  const Vec3 n = {s, 0, s};
  double distance = 0;  // the plane's distance from the centre
  for (int k = 0; k < 3; ++k) distance += -p.origin[k] * n[k];
  for (const Vec3& q : loops[0].points) {
    EXPECT_NEAR(std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]), 1.0, 1e-9);
    EXPECT_NEAR(
        (q[0] - p.origin[0]) * n[0] + (q[1] - p.origin[1]) * n[1] + (q[2] - p.origin[2]) * n[2],
        0.0, 1e-12);
  }
  const double r = std::sqrt(1 - distance * distance);
  EXPECT_NEAR(perimeter(loops[0]), 2 * M_PI * r, 2e-3 * 2 * M_PI * r);
  EXPECT_NEAR(signedArea(loops[0], p), M_PI * r * r, 2e-3 * M_PI * r * r);  // solid on the left
}

TEST(Section, AHoleIsALoopTurningTheOtherWay) {
  const NodePtr plate = makeNode("difference", {}, {box({-1, -1, -0.5}, {2, 2, 1}), sphere(0.6)});
  SectionPlane p;  // z = 0: a square with a round hole
  const auto loops = cut(plate, p, 0.01);
  ASSERT_EQ(loops.size(), 2u);
  double outer = 0, inner = 0;
  for (const SectionLoop& l : loops) {
    EXPECT_TRUE(l.closed);
    const double a = signedArea(l, p);
    (a > 0 ? outer : inner) = a;
  }
  EXPECT_NEAR(outer, 4.0, 0.01);
  EXPECT_NEAR(inner, -M_PI * 0.36, 0.01);
}

TEST(Section, SeparatePartsAndThinNecksAreLoopsOfTheirOwn) {
  // two balls almost touching: the saddle squares between them stay apart
  const NodePtr two =
      makeNode("union", {}, {sphere(0.5, {-0.505, 0, 0}), sphere(0.5, {0.505, 0, 0})});
  SectionPlane p;
  EXPECT_EQ(cut(two, p, 0.05).size(), 2u);
  EXPECT_EQ(cut(two, p, 0.003).size(), 2u);
}

TEST(Section, APlaneThatMissesAndNonsenseAreSaid) {
  SectionPlane p;
  p.origin = {0, 0, 5};
  double u0, u1, v0, v1;
  EXPECT_FALSE(sectionRectangle(p, Box3{{-1, -1, -1}, {1, 1, 1}}, u0, u1, v0, v1));
  const Program ball = compile(sphere(1.0));
  EXPECT_THROW(sectionField(ball, SectionPlane(), -1, 1, -1, 1, 0.0), ModelError);
  EXPECT_THROW(sectionField(ball, SectionPlane(), -1, 1, -1, 1, 1e-5), ModelError);
  EXPECT_THROW(sectionField(ball, SectionPlane(), 1, -1, -1, 1, 0.1), ModelError);
  // a solid running past the rectangle: its loop is open there
  const auto open = sectionField(ball, SectionPlane(), -0.5, 0.5, -2, 2, 0.02);
  ASSERT_EQ(open.size(), 2u);
  EXPECT_FALSE(open[0].closed);
}

}  // namespace
}  // namespace frep
