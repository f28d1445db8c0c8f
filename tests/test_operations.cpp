// The defining property of each deformation, field operation and microstructure node: what
// the node means, checked on shapes whose answer is known exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "base/errors.h"
#include "check/mesh_check.h"
#include "frep/structural_bounds.h"
#include "frep/tree.h"
#include "mesh/mesher.h"
#include "test_nodes.h"

namespace frep {
namespace {

using frep::testing::box;
using frep::testing::sphere;

constexpr double kPi = 3.14159265358979323846;

std::vector<Vec3> randomPoints(int n, double reach, unsigned seed = 3) {
  std::mt19937 g(seed);
  std::uniform_real_distribution<double> u(-reach, reach);
  std::vector<Vec3> pts(n);
  for (auto& p : pts) p = {u(g), u(g), u(g)};
  return pts;
}

double eval(const Program& p, const Vec3& q) {
  return p.eval(q[0], q[1], q[2]);
}
double norm3(const Vec3& p) {
  return std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
}

double meshVolume(const NodePtr& n, double reach, double h) {
  MeshingOptions o;
  o.bbox = {{-reach, -reach, -reach}, {reach, reach, reach}};
  o.resolution = h;
  return checkMesh(polygonize(compile(n), o)).volume;
}

TEST(BoundedBlend, FullInsideTheBoundNoneOutside) {
  const NodePtr a = box({-1, -1, -1}, {2, 2, 1}), b = box({-0.25, -1, -0.5}, {0.5, 2, 1.5});
  const NodePtr bound = sphere(0.6, {0, -1, 0});
  const NodePtr bounded =
      makeNode("bounded_blend", {{"a0", realValue(0.3)}, {"a3", realValue(0.2)}}, {a, b, bound});
  const Program pb = compile(bounded), pbound = compile(bound);
  const Program plain = compile(makeNode("union", {}, {a, b}));
  const Program blend = compile(makeNode("blend_union", {{"a0", realValue(0.3)}}, {a, b}));
  int outside = 0, deep = 0;
  for (const Vec3& q : randomPoints(2000, 1.5)) {
    const double f3 = eval(pbound, q);
    if (f3 <= 0) {
      EXPECT_EQ(eval(pb, q), eval(plain, q));  // sharp where the bound is not
      ++outside;
    } else if (f3 >= 0.2) {
      EXPECT_NEAR(eval(pb, q), eval(blend, q), 1e-12);  // the ordinary blend inside
      ++deep;
    }
  }
  EXPECT_GT(outside, 100);
  EXPECT_GT(deep, 10);
}

TEST(Superellipsoid, ExponentsOneMakeTheEllipsoidAndSmallOnesTheBox) {
  auto superell = [](double e1, double e2) {
    return compile(makeNode("superellipsoid",
                            {{"radii", vec3Value({1, 0.5, 0.8})},
                             {"exponent1", realValue(e1)},
                             {"exponent2", realValue(e2)}},
                            {}));
  };
  const Program round = superell(1, 1);
  for (const Vec3& q : randomPoints(300, 1.2)) {
    const double s = q[0] * q[0] + q[1] * q[1] / 0.25 + q[2] * q[2] / 0.64;
    EXPECT_NEAR(eval(round, q), 0.25 * (1 - s), 1e-12);  // min radius / 2 * (1 - S)
  }
  // Small exponents approach the box [-1,1] x [-0.5,0.5] x [-0.8,0.8]: its corner region fills.
  EXPECT_GT(superell(0.1, 0.1).eval(0.9, 0.45, 0.7), 0.0);
  EXPECT_LT(round.eval(0.9, 0.45, 0.7), 0.0);
  // A rounded box meshes printable (flat faces, cusp-free field away from the axes).
  MeshingOptions o;
  o.bbox = {{-1.1, -1.1, -1.1}, {1.1, 1.1, 1.1}};
  o.resolution = 1.0 / 32;
  const NodePtr rounded = makeNode("superellipsoid",
                                   {{"radii", vec3Value({1, 0.5, 0.8})},
                                    {"exponent1", realValue(0.3)},
                                    {"exponent2", realValue(0.3)}},
                                   {});
  EXPECT_TRUE(checkMesh(polygonize(compile(rounded), o)).printable());
  // The poles and the equator stay on the radii for every exponent.
  for (double e : {0.2, 1.0, 2.0, 3.0}) {
    EXPECT_NEAR(superell(e, e).eval(1, 0, 0), 0.0, 1e-12) << e;
    EXPECT_NEAR(superell(e, e).eval(0, 0, 0.8), 0.0, 1e-12) << e;
  }
}

ParamValue pointsValue(const std::vector<Vec3>& pts) {
  ParamValue v;
  for (const Vec3& q : pts) v.numbers.insert(v.numbers.end(), q.begin(), q.end());
  return v;
}

double segmentDistance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 e = {b[0] - a[0], b[1] - a[1], b[2] - a[2]},
             d = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
  const double t = std::clamp(
      (d[0] * e[0] + d[1] * e[1] + d[2] * e[2]) / (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]), 0.0,
      1.0);
  return norm3({d[0] - t * e[0], d[1] - t * e[1], d[2] - t * e[2]});
}

TEST(Sweep, ExactDistanceToAStraightSegment) {
  const Vec3 a = {-0.5, 0.2, 0.1}, b = {0.7, -0.3, 0.4};
  const Program p = compile(makeNode(
      "sweep",
      {{"points", pointsValue({a, b})}, {"radius1", realValue(0.3)}, {"radius2", realValue(0.3)}},
      {}));
  for (const Vec3& q : randomPoints(500, 1.5))
    EXPECT_NEAR(eval(p, q), 0.3 - segmentDistance(q, a, b), 1e-12);
}

TEST(Sweep, ArcPolylineAndTaperedRadius) {
  // A quarter arc of radius 1 as 64 segments: the field is 0.2 minus the distance to the arc,
  // up to the polyline's sagitta (1 - cos(pi/256) = 7.5e-5).
  std::vector<Vec3> arc;
  for (int i = 0; i <= 64; ++i) {
    const double th = kPi / 2 * i / 64;
    arc.push_back({std::cos(th), std::sin(th), 0});
  }
  const Program p = compile(makeNode(
      "sweep",
      {{"points", pointsValue(arc)}, {"radius1", realValue(0.2)}, {"radius2", realValue(0.2)}},
      {}));
  for (const Vec3& q : randomPoints(500, 1.3)) {
    const double rho = std::hypot(q[0], q[1]);
    if (q[0] <= 0 || q[1] <= 0 || rho < 0.1) continue;  // the arc's angular range
    const double exact = 0.2 - std::hypot(rho - 1, q[2]);
    EXPECT_NEAR(eval(p, q), exact, 1e-4);
  }
  // The radius goes linearly along the length: r1 at the start, r2 at the end.
  const Program taper = compile(makeNode(
      "sweep",
      {{"points", pointsValue(arc)}, {"radius1", realValue(0.3)}, {"radius2", realValue(0.1)}},
      {}));
  EXPECT_NEAR(taper.eval(1, 0, 0), 0.3, 1e-12);
  EXPECT_NEAR(taper.eval(0, 1, 0), 0.1, 1e-9);
  const double mid = kPi / 4;
  EXPECT_NEAR(taper.eval(std::cos(mid), std::sin(mid), 0), 0.2, 1e-4);
}

TEST(Sweep, ExactOnAnArcWithLinesAround) {
  // segments "arcs": a line (three collinear points), a quarter arc of radius 1 about the
  // origin through its middle, and a line again; exact everywhere, not within sampling.
  const double c = std::cos(kPi / 4), s = std::sin(kPi / 4);
  const std::vector<Vec3> path = {{1, -1, 0}, {1, -0.5, 0}, {1, 0, 0}, {c, s, 0},
                                  {0, 1, 0},  {-0.5, 1, 0}, {-1, 1, 0}};
  const NodePtr n = makeNode("sweep",
                             {{"points", pointsValue(path)},
                              {"radius1", realValue(0.2)},
                              {"radius2", realValue(0.2)},
                              {"segments", choiceValue("arcs")}},
                             {});
  const Program p = compile(n);
  int onArc = 0;
  for (const Vec3& q : randomPoints(4000, 1.6)) {
    const double rho = std::hypot(q[0], q[1]);
    const double toArc = q[0] >= 0 && q[1] >= 0 ? std::hypot(rho - 1, q[2]) : 1e300;
    const double exact = 0.2 - std::min({toArc, segmentDistance(q, {1, -1, 0}, {1, 0, 0}),
                                         segmentDistance(q, {0, 1, 0}, {-1, 1, 0})});
    ASSERT_NEAR(eval(p, q), exact, 1e-12) << q[0] << "," << q[1] << "," << q[2];
    onArc += toArc < 0.5;
  }
  EXPECT_GT(onArc, 100);
  // the radius goes along the arc length of lines and arcs alike
  const Program taper = compile(makeNode("sweep",
                                         {{"points", pointsValue(path)},
                                          {"radius1", realValue(0.3)},
                                          {"radius2", realValue(0.1)},
                                          {"segments", choiceValue("arcs")}},
                                         {}));
  EXPECT_NEAR(taper.eval(c, s, 0), 0.2, 1e-12);  // the middle of the length
  EXPECT_NEAR(taper.eval(1, 0, 0), 0.3 - 0.2 * 1 / (2 + kPi / 2), 1e-12);
  // the structural box holds the arc's bulge
  const Box3 b = structuralBounds(n);
  EXPECT_LE(b.hi[0], 1.2 + 1e-12);
  EXPECT_GE(b.hi[0], 1.2 - 1e-12);
  // an even count or a closed arc is refused with the reason
  for (const auto& bad : {std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}},
                          std::vector<Vec3>{{0, 0, 0}, {1, 1, 0}, {0, 0, 0}}}) {
    try {
      makeNode("sweep", {{"points", pointsValue(bad)}, {"segments", choiceValue("arcs")}}, {},
               "path");
      FAIL() << "accepted";
    } catch (const ModelError& e) {
      const std::string m = e.what();
      EXPECT_TRUE(m.find("odd number") != std::string::npos ||
                  m.find("split a full circle") != std::string::npos)
          << m;
    }
  }
}

TEST(Sweep, FollowsABsplineFromItsControlPoints) {
  // four control points: the clamped cubic is the Bezier curve of them
  const std::vector<Vec3> ctrl = {{0, 0, 0}, {0.5, 1, 0}, {1.5, -1, 0}, {2, 0, 0}};
  const Program p = compile(makeNode("sweep",
                                     {{"points", pointsValue(ctrl)},
                                      {"radius1", realValue(0.2)},
                                      {"radius2", realValue(0.2)},
                                      {"segments", choiceValue("bspline")}},
                                     {}));
  const double tol = 1e-4 * std::sqrt(4.0 + 4.0);  // of the control polygon's diagonal
  for (int i = 0; i <= 200; ++i) {
    const double t = i / 200.0, u = 1 - t;
    Vec3 b;
    for (int c = 0; c < 3; ++c)
      b[c] = u * u * u * ctrl[0][c] + 3 * u * u * t * ctrl[1][c] + 3 * u * t * t * ctrl[2][c] +
             t * t * t * ctrl[3][c];
    EXPECT_NEAR(p.eval(b[0], b[1], b[2]), 0.2, tol);   // on the curve
    EXPECT_NEAR(p.eval(b[0], b[1], 0.15), 0.05, tol);  // above it, in its plane's normal
  }
  // several spans: collinear control points keep the curve on their line, ends clamped
  const Program line = compile(makeNode(
      "sweep",
      {{"points",
        pointsValue({{0, 0, 0}, {0.3, 0, 0}, {1, 0, 0}, {1.2, 0, 0}, {2, 0, 0}, {3, 0, 0}})},
       {"segments", choiceValue("bspline")},
       {"radius1", realValue(0.1)},
       {"radius2", realValue(0.1)}},
      {}));
  EXPECT_NEAR(line.eval(0, 0, 0), 0.1, 1e-12);
  EXPECT_NEAR(line.eval(3, 0, 0), 0.1, 1e-12);
  EXPECT_NEAR(line.eval(-0.05, 0, 0), 0.05, 1e-12);
  EXPECT_NEAR(line.eval(1.7, 0.05, 0), 0.05, 1e-12);
}

TEST(Sweep, NeedsTwoPoints) {
  try {
    makeNode("sweep", {{"points", pointsValue({{0, 0, 0}})}}, {}, "root");
    FAIL() << "no error";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("at least 2 points"), std::string::npos) << e.what();
  }
}

NodePtr blob(const std::string& id, const std::vector<Vec3>& centers,
             std::map<std::string, ParamValue> params = {}) {
  params["centers"] = pointsValue(centers);
  return makeNode(id, params, {});
}

TEST(Blobs, KernelsAtTheirCentresAndSummedNearby) {
  const Vec3 c = {0.1, 0.2, 0.3};
  EXPECT_NEAR(compile(blob("blobby", {c})).eval(0.1, 0.2, 0.3), 1.0 - 0.5, 1e-12);
  EXPECT_NEAR(compile(blob("soft_objects", {c})).eval(0.1, 0.2, 0.3), 1.0 - 0.5, 1e-12);
  EXPECT_NEAR(compile(blob("convolution", {c})).eval(0.1, 0.2, 0.3), 1.0 - 0.5, 1e-12);
  // Blobby at distance d from each of two centres: the two bumps add up.
  const Program two = compile(blob("blobby", {{-0.3, 0, 0}, {0.3, 0, 0}}));
  EXPECT_NEAR(two.eval(0, 0, 0), 2 * std::exp(-8 * 0.09) - 0.5, 1e-12);
  EXPECT_GT(two.eval(0, 0, 0), 0.0);  // melted together in the middle
}

TEST(Blobs, SoftObjectsStopExactlyAtTheirRadius) {
  const Program far =
      compile(blob("soft_objects", {{-1, 0, 0}, {1, 0, 0}}, {{"radius", realValue(0.6)}}));
  EXPECT_EQ(far.eval(-1, 0, 0), 1.0 - 0.5);  // the other centre adds exactly nothing
  EXPECT_EQ(far.eval(0, 0, 0), -0.5);
  EXPECT_EQ(far.eval(0, 0.61, 0), -0.5);
}

TEST(Blobs, BoundsEncloseTheSolidAndTheMeshIsOnePart) {
  for (const char* id : {"blobby", "soft_objects", "convolution", "metaballs"}) {
    const NodePtr n = blob(id, {{-0.4, 0, 0}, {0.3, 0.2, 0}, {0, -0.3, 0.3}});
    const Program p = compile(n);
    const Box3 b = structuralBounds(n);
    for (const Vec3& q : randomPoints(20000, 2)) {
      if (eval(p, q) <= 0) continue;
      for (int a = 0; a < 3; ++a) {
        ASSERT_GE(q[a], b.lo[a]) << id;
        ASSERT_LE(q[a], b.hi[a]) << id;
      }
    }
    MeshingOptions o;
    o.bbox = b;
    for (int a = 0; a < 3; ++a) {
      o.bbox.lo[a] -= 0.1;
      o.bbox.hi[a] += 0.1;
    }
    o.resolution = 1.0 / 32;
    const CheckReport r = checkMesh(polygonize(p, o));
    EXPECT_TRUE(r.printable()) << id;
    EXPECT_EQ(r.components, 1u) << id;
  }
}

// From 16 centres on, the kernels of compact support are summed through the instancer's
// spatial index. The values are those of the written-out sum: each centre's kernel alone,
// added in order, minus the threshold; batches agree with points and
// intervals enclose the samples.
TEST(Blobs, ManyCentresGoThroughTheIndexWithTheSameValues) {
  std::mt19937 g(17);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Vec3> centres(300);
  for (Vec3& c : centres) c = {u(g), u(g), u(g)};
  for (const char* id : {"soft_objects", "metaballs"}) {
    std::map<std::string, ParamValue> params = {{"radius", realValue(0.25)},
                                                {"threshold", realValue(0.4)}};
    const Program p = compile(blob(id, centres, params));
    ASSERT_EQ(p.externals().size(), 1u) << id << ": not through the index";
    // Each centre alone with a threshold far below every kernel value that is not 0 (the
    // kernels' smallest such values are about 1e-32): eval + 1e-300 is its kernel exactly.
    params["threshold"] = realValue(1e-300);
    std::vector<Program> each;
    for (const Vec3& c : centres) each.push_back(compile(blob(id, {c}, params)));
    std::vector<double> x, y, z;
    int inside = 0;
    for (int i = 0; i < 3000; ++i) {
      // near a centre (often within several kernels) or anywhere
      const Vec3& c = centres[static_cast<std::size_t>(i) % centres.size()];
      const double s = i % 2 ? 0.3 : 1.2;
      x.push_back(c[0] + s * u(g));
      y.push_back(c[1] + s * u(g));
      z.push_back(c[2] + s * u(g));
      double sum = 0;
      for (std::size_t k = 0; k < each.size(); ++k) {
        const double v = each[k].eval(x.back(), y.back(), z.back()) + 1e-300;
        sum = k == 0 ? v : sum + v;
      }
      const double expect = sum - 0.4;
      ASSERT_EQ(p.eval(x.back(), y.back(), z.back()), expect) << id << " point " << i;
      inside += expect >= 0;
    }
    EXPECT_GT(inside, 300) << id;
    std::vector<double> out(x.size());
    p.evalBatch(x.data(), y.data(), z.data(), x.size(), out.data());
    for (std::size_t i = 0; i < x.size(); ++i) ASSERT_EQ(out[i], p.eval(x[i], y[i], z[i])) << id;
    std::uniform_real_distribution<double> size(0.01, 0.8);
    for (int b = 0; b < 200; ++b) {
      const double cx = u(g), cy = u(g), cz = u(g), h = size(g);
      const Interval range = p.evalInterval({cx - h, cx + h}, {cy - h, cy + h}, {cz - h, cz + h});
      std::uniform_real_distribution<double> in(-h, h);
      for (int k = 0; k < 40; ++k) {
        const double v = p.eval(cx + in(g), cy + in(g), cz + in(g));
        ASSERT_TRUE(range.contains(v))
            << id << ": " << v << " outside [" << range.lo << ", " << range.hi << "]";
      }
    }
  }
}

// blobby's Gaussian bumps never reach 0: with many centres a point sums those within the
// radius beyond which all the others add less than 1e-9 of the threshold. The values stay
// within that of the full sum; batches agree with points; intervals enclose.
TEST(Blobs, ManyGaussianBumpsAreTruncatedWithinTheTolerance) {
  std::mt19937 g(23);
  std::uniform_real_distribution<double> u(-3, 3);
  std::vector<Vec3> centres(400);
  for (Vec3& c : centres) c = {u(g), u(g), 0.3 * u(g)};
  const double threshold = 0.5;
  std::map<std::string, ParamValue> params = {{"falloff", realValue(20.0)},
                                              {"threshold", realValue(threshold)}};
  const Program p = compile(blob("blobby", centres, params));
  ASSERT_EQ(p.externals().size(), 1u) << "not through the index";
  params["threshold"] = realValue(1e-300);
  std::vector<Program> each;
  for (const Vec3& c : centres) each.push_back(compile(blob("blobby", {c}, params)));
  std::vector<double> x, y, z;
  double worst = 0;
  int inside = 0;
  for (int i = 0; i < 2000; ++i) {
    x.push_back(u(g));
    y.push_back(u(g));
    z.push_back(0.3 * u(g));
    double sum = 0;
    for (const Program& e : each) sum += e.eval(x.back(), y.back(), z.back()) + 1e-300;
    const double v = p.eval(x.back(), y.back(), z.back());
    worst = std::max(worst, std::abs(v - (sum - threshold)));
    inside += v >= 0;
  }
  EXPECT_LT(worst, 1e-9 * threshold + 1e-12);
  EXPECT_GT(inside, 100);
  std::vector<double> out(x.size());
  p.evalBatch(x.data(), y.data(), z.data(), x.size(), out.data());
  for (std::size_t i = 0; i < x.size(); ++i) ASSERT_EQ(out[i], p.eval(x[i], y[i], z[i]));
  std::uniform_real_distribution<double> size(0.01, 1.0);
  for (int b = 0; b < 200; ++b) {
    const double cx = u(g), cy = u(g), cz = 0.3 * u(g), h = size(g);
    const Interval range = p.evalInterval({cx - h, cx + h}, {cy - h, cy + h}, {cz - h, cz + h});
    std::uniform_real_distribution<double> in(-h, h);
    for (int k = 0; k < 40; ++k) {
      const double v = p.eval(cx + in(g), cy + in(g), cz + in(g));
      ASSERT_TRUE(range.contains(v)) << v << " outside [" << range.lo << ", " << range.hi << "]";
    }
  }
}

// 100,000 centres: a point costs the centres within reach, so a coarse mesh takes seconds
// (every centre per point, as before the index, would not finish a coarse export in 60 s).
TEST(Blobs, HundredThousandMetaballsMeshPrintable) {
  std::mt19937 g(5);
  std::uniform_real_distribution<double> jitter(-0.02, 0.02);
  std::vector<Vec3> centres;
  for (int i = 0; i < 100; ++i)
    for (int j = 0; j < 100; ++j)
      for (int k = 0; k < 10; ++k)
        centres.push_back({0.1 * i + jitter(g), 0.1 * j + jitter(g), 0.1 * k + jitter(g)});
  const NodePtr n =
      blob("metaballs", centres, {{"radius", realValue(0.15)}, {"threshold", realValue(0.5)}});
  MeshingOptions o;
  o.bbox = structuralBounds(n);
  o.resolution = 0.1;
  const TriangleMesh mesh = polygonize(compile(n), o);
  const CheckReport r = checkMesh(mesh);
  EXPECT_TRUE(r.printable());
  EXPECT_EQ(r.components, 1u);
  // a slab of about 10 x 10 x 1 units
  EXPECT_GT(r.volume, 70.0);
  EXPECT_LT(r.volume, 130.0);
}

TEST(Blobs, MetaballsArePiecewiseQuadraticC1AndZeroBeyondTheRadius) {
  const NodePtr n = blob(
      "metaballs", {{0, 0, 0}},
      {{"strength", realValue(2.0)}, {"radius", realValue(0.9)}, {"threshold", realValue(0.5)}});
  const Program p = compile(n);
  auto kernel = [&](double r) { return p.eval(r, 0, 0) + 0.5; };
  EXPECT_NEAR(kernel(0), 2.0, 1e-15);
  EXPECT_NEAR(kernel(0.3), 2.0 * 2 / 3, 1e-14);            // t = 1/3: both pieces agree
  EXPECT_NEAR(kernel(0.45), 1.5 * 2.0 * 0.25, 1e-14);      // t = 1/2 on the outer piece
  EXPECT_NEAR(kernel(0.15), 2.0 * (1 - 3.0 / 36), 1e-14);  // t = 1/6 on the inner piece
  EXPECT_EQ(kernel(0.9), 0.0);
  EXPECT_EQ(kernel(1.7), 0.0);
  // C1 at t = 1/3: the slopes on either side agree (-2 strength / radius)
  const double h = 1e-6, left = (kernel(0.3) - kernel(0.3 - h)) / h,
               right = (kernel(0.3 + h) - kernel(0.3)) / h;
  EXPECT_NEAR(left, -2 * 2.0 / 0.9, 1e-4);
  EXPECT_NEAR(right, -2 * 2.0 / 0.9, 1e-4);
}

TEST(Blobs, SegmentConvolutionIsTheKernelIntegratedAlongTheSkeleton) {
  const std::vector<Vec3> path = {{-0.5, 0, 0}, {0.4, 0.1, 0}, {0.5, 0.7, 0.3}};
  const double s = 3.0, strength = 1.3;
  for (const char* skeleton : {"polyline", "pairs"}) {
    std::vector<Vec3> pts = path;
    if (std::string(skeleton) == "pairs") pts = {path[0], path[1], path[1], path[2]};
    const NodePtr n = makeNode("convolution_segments",
                               {{"points", pointsValue(pts)},
                                {"skeleton", choiceValue(skeleton)},
                                {"strength", realValue(strength)},
                                {"sharpness", realValue(s)},
                                {"threshold", realValue(0.3)}},
                               {});
    const Program p = compile(n);
    for (const Vec3& q : randomPoints(40, 1.2)) {
      // midpoint rule along each segment, 4000 steps each
      double integral = 0;
      for (std::size_t k = 0; k + 1 < path.size(); ++k) {
        const Vec3 a = path[k],
                   e = {path[k + 1][0] - a[0], path[k + 1][1] - a[1], path[k + 1][2] - a[2]};
        const double l = norm3(e);
        const int steps = 4000;
        for (int i = 0; i < steps; ++i) {
          const double t = (i + 0.5) / steps;
          const Vec3 d = {q[0] - a[0] - t * e[0], q[1] - a[1] - t * e[1], q[2] - a[2] - t * e[2]};
          const double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
          integral += l / steps / ((1 + s * s * r2) * (1 + s * s * r2));
        }
      }
      EXPECT_NEAR(eval(p, q), strength * integral - 0.3, 1e-6) << skeleton;
    }
    // the bounds hold the solid, which meshes as one printable part
    const Box3 b = structuralBounds(n);
    for (const Vec3& q : randomPoints(20000, 3))
      if (eval(p, q) > 0) {
        for (int a = 0; a < 3; ++a) ASSERT_TRUE(q[a] >= b.lo[a] && q[a] <= b.hi[a]);
      }
    MeshingOptions o;
    o.bbox = paddedBox(b, 0.05);
    o.resolution = 1.0 / 40;
    const CheckReport r = checkMesh(polygonize(p, o));
    EXPECT_TRUE(r.printable());
    EXPECT_EQ(r.components, 1u);
  }
  try {
    makeNode("convolution_segments",
             {{"points", pointsValue(path)}, {"skeleton", choiceValue("pairs")}}, {}, "tube");
    FAIL() << "three points accepted as pairs";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("needs an even number"), std::string::npos);
  }
}

TEST(Stretch, ScalesAlongOneDirectionOnly) {
  const Vec3 c = {0.1, -0.2, 0.3};
  const NodePtr ball = sphere(0.5, c);
  EXPECT_EQ(compile(makeNode("stretch", {{"factor", realValue(1.0)}}, {ball})).eval(0.3, 0.2, 0.1),
            compile(ball).eval(0.3, 0.2, 0.1));
  const Vec3 d = {1 / std::sqrt(2.0), 1 / std::sqrt(2.0), 0};
  for (double k : {2.0, 0.5}) {
    const NodePtr n = makeNode(
        "stretch",
        {{"factor", realValue(k)}, {"direction", vec3Value({1, 1, 0})}, {"center", vec3Value(c)}},
        {ball});
    const Program p = compile(n);
    auto at = [&](const Vec3& dir, double r) {
      return p.eval(c[0] + r * dir[0], c[1] + r * dir[1], c[2] + r * dir[2]);
    };
    EXPECT_GT(at(d, 0.5 * k * 0.999), 0) << k;  // the semi-axis along d is k r
    EXPECT_LT(at(d, 0.5 * k * 1.001), 0) << k;
    EXPECT_GT(at({0, 0, 1}, 0.499), 0) << k;  // across d nothing changes
    EXPECT_LT(at({0, 0, 1}, 0.501), 0) << k;
    const Box3 b = structuralBounds(n);
    EXPECT_NEAR(b.hi[2], c[2] + 0.5, 1e-12);
    EXPECT_GE(b.hi[0], c[0] + 0.5 * k * d[0]);
  }
}

TEST(Arrays, LinearArrayIsTheUnionOfAllCopiesAtThreeEvaluations) {
  // 10,000 overlapping spheres (radius 0.8, step 1): the field is the union of every copy,
  // while the program holds the sphere only three times.
  const NodePtr ball = sphere(0.8, {0.2, 0, 0});
  const NodePtr row = makeNode(
      "linear_array", {{"count", realValue(10000)}, {"step", vec3Value({1, 0, 0})}}, {ball});
  const Program p = compile(row), one = compile(ball);
  EXPECT_LT(p.instructionCount(), 4 * one.instructionCount() + 40);
  std::mt19937 g(5);
  std::uniform_real_distribution<double> along(-3, 10003), across(-1, 1);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 q = {along(g), across(g), across(g)};
    double best = -1e300;
    for (int j = std::max(0, int(q[0]) - 3); j <= std::min(9999, int(q[0]) + 3); ++j)
      best = std::max(best, one.eval(q[0] - j, q[1], q[2]));
    if (q[0] < -2) best = one.eval(q[0], q[1], q[2]);
    EXPECT_NEAR(eval(p, q), best, 1e-12) << q[0];
  }
}

TEST(Arrays, BlendedCopiesArePaskosBlendUnionOfTheirNeighbours) {
  // Two copies: the blended array is exactly the blend union of the two, everywhere; with two
  // copies all round a polar array must not blend a copy with itself.
  const NodePtr ball = sphere(0.4, {0.6, 0, 0});
  auto blendOf = [&](const NodePtr& a, const NodePtr& b) {
    return compile(
        makeNode("blend_union",
                 {{"a0", realValue(0.2)}, {"a1", realValue(0.3)}, {"a2", realValue(0.3)}}, {a, b}));
  };
  const std::map<std::string, ParamValue> blend = {{"combine", choiceValue("blend")},
                                                   {"blend_amount", realValue(0.2)},
                                                   {"blend_range", realValue(0.3)}};
  auto with = [&](std::map<std::string, ParamValue> p) {
    p.insert(blend.begin(), blend.end());
    return p;
  };
  const NodePtr row = makeNode(
      "linear_array", with({{"count", realValue(2)}, {"step", vec3Value({0.7, 0, 0})}}), {ball});
  const NodePtr ring = makeNode("polar_array", with({{"count", realValue(2)}}), {ball});
  const Program pr = compile(row), pp = compile(ring);
  const Program rowRef = blendOf(ball, sphere(0.4, {1.3, 0, 0}));
  const Program ringRef = blendOf(ball, sphere(0.4, {-0.6, 0, 0}));
  for (const Vec3& q : randomPoints(3000, 2)) {
    EXPECT_NEAR(eval(pr, q), rowRef.eval(q[0] - 0.0, q[1], q[2]), 1e-12);
    EXPECT_NEAR(eval(pp, q), ringRef.eval(q[0], q[1], q[2]), 1e-9);
  }
  // the blend's material stays inside the structural box
  for (const NodePtr& n : {row, ring}) {
    const Program p = compile(n);
    const Box3 b = structuralBounds(n);
    for (const Vec3& q : randomPoints(20000, 2.5))
      if (eval(p, q) >= 0) {
        for (int a = 0; a < 3; ++a) ASSERT_TRUE(q[a] >= b.lo[a] && q[a] <= b.hi[a]);
      }
  }
}

TEST(Arrays, PolarArrayFullAndPartial) {
  const NodePtr ball = sphere(0.3, {1, 0, 0});
  const Program one = compile(ball);
  auto brute = [&](const Vec3& q, int n, double stepDeg) {
    double best = -1e300;
    for (int j = 0; j < n; ++j) {
      const double th = -j * stepDeg * kPi / 180, c = std::cos(th), s = std::sin(th);
      best = std::max(best, one.eval(c * q[0] - s * q[1], s * q[0] + c * q[1], q[2]));
    }
    return best;
  };
  const Program full = compile(makeNode("polar_array", {{"count", realValue(6)}}, {ball}));
  const Program part =
      compile(makeNode("polar_array", {{"count", realValue(3)}, {"angle", realValue(90)}}, {ball}));
  for (const Vec3& q : randomPoints(2000, 1.5)) {
    EXPECT_NEAR(eval(full, q), brute(q, 6, 60), 1e-12);
    EXPECT_NEAR(eval(part, q), brute(q, 3, 45), 1e-12);
  }
  MeshingOptions o;
  o.bbox = {{-1.5, -1.5, -0.5}, {1.5, 1.5, 0.5}};
  o.resolution = 1.0 / 32;
  const NodePtr ring =
      makeNode("polar_array", {{"count", realValue(12)}}, {sphere(0.3, {1, 0, 0})});
  const CheckReport r = checkMesh(polygonize(compile(ring), o));
  EXPECT_TRUE(r.printable());
  EXPECT_EQ(r.components, 1u);  // neighbours 0.52 apart, radius 0.3: one ring
}

TEST(Offset, MovesASphereSurfaceByTheDistance) {
  for (double d : {0.2, -0.3}) {
    const Program p = compile(makeNode("offset", {{"distance", realValue(d)}}, {sphere(1)}));
    for (const Vec3& q : randomPoints(200, 2)) EXPECT_NEAR(eval(p, q), 1 + d - norm3(q), 1e-12);
    EXPECT_NEAR(p.eval(1 + d, 0, 0), 0.0, 1e-12);
  }
}

TEST(ShellAcceptance, KeepsAWallOfTheThicknessInside) {
  const NodePtr s = makeNode("shell", {{"thickness", realValue(0.1)}}, {sphere(1)});
  const Program p = compile(s);
  EXPECT_GT(p.eval(0.95, 0, 0), 0.0);  // in the wall
  EXPECT_LT(p.eval(0.85, 0, 0), 0.0);  // hollow
  EXPECT_LT(p.eval(1.05, 0, 0), 0.0);  // outside
  const double exact = 4.0 / 3.0 * kPi * (1 - 0.9 * 0.9 * 0.9);
  EXPECT_NEAR(meshVolume(s, 1.2, 1.0 / 64), exact, 0.01 * exact);
}

TEST(Metamorphosis, EndsAreItsInputsAndTheMiddleIsTheAverage) {
  const NodePtr a = sphere(1), b = box({-0.5, -0.5, -0.5}, {1, 1, 1});
  const Program pa = compile(a), pb = compile(b);
  auto morph = [&](double t) {
    return compile(makeNode("metamorphosis", {{"t", realValue(t)}}, {a, b}));
  };
  const Program m0 = morph(0), m1 = morph(1), mh = morph(0.5);
  for (const Vec3& q : randomPoints(200, 1.5)) {
    EXPECT_EQ(eval(m0, q), eval(pa, q));
    EXPECT_EQ(eval(m1, q), eval(pb, q));
    EXPECT_NEAR(eval(mh, q), 0.5 * (eval(pa, q) + eval(pb, q)), 1e-12);
  }
}

TEST(Twist, ZeroIsTheIdentity) {
  const NodePtr b = box({-0.5, -0.5, -1}, {1, 1, 2});
  const Program plain = compile(b);
  const Program twisted = compile(makeNode("twist", {{"rate", realValue(0)}}, {b}));
  for (const Vec3& q : randomPoints(200, 1.5)) EXPECT_EQ(eval(twisted, q), eval(plain, q));
}

TEST(Twist, EachSliceTurnsByRateTimesHeight) {
  // About an axis through (0.3, 0, 0) along z, 40 degrees per unit: the slice at height h
  // is the input's slice turned by 40 h degrees about the axis.
  const NodePtr b = box({-0.2, -0.5, -1}, {1.1, 0.6, 2});
  const Program plain = compile(b);
  const Program twisted = compile(
      makeNode("twist", {{"rate", realValue(40)}, {"center", vec3Value({0.3, 0, 0})}}, {b}));
  for (const Vec3& q : randomPoints(300, 1.2)) {
    const double th = 40 * q[2] * kPi / 180, c = std::cos(th), s = std::sin(th);
    const double x = q[0] - 0.3, y = q[1];
    const Vec3 moved = {0.3 + c * x - s * y, s * x + c * y, q[2]};
    EXPECT_NEAR(eval(twisted, moved), eval(plain, q), 1e-12);
  }
}

TEST(Twist, ReferenceModelKeepsTheBoxVolume) {
  // A twist is volume-preserving: the twisted box of examples/twist.json has volume 2.
  const NodePtr t =
      makeNode("twist", {{"rate", realValue(90)}}, {box({-0.5, -0.5, -1}, {1, 1, 2})});
  EXPECT_NEAR(meshVolume(t, 1.2, 1.0 / 48), 2.0, 0.01 * 2.0);
}

TEST(Bend, TurnsTheLineIntoAnArcOfTheGivenAngle) {
  // x along the bend, bending towards +z, 90 degrees over length 2: R = 4 / pi. A point at
  // (a, y, b) of the input goes to the arc: (R - b) sin(a/R) along x, R - (R - b) cos(a/R)
  // along z.
  const NodePtr bar = box({-0.5, -0.3, -0.2}, {3, 0.6, 0.4});
  const Program plain = compile(bar);
  const Program bent =
      compile(makeNode("bend", {{"angle", realValue(90)}, {"length", realValue(2)}}, {bar}));
  const double R = 2 / (kPi / 2);
  for (const Vec3& q : randomPoints(300, 1.5)) {
    if (std::abs(q[2]) > R / 2) continue;  // beyond the arc's centre space folds (documented)
    const double th = q[0] / R;
    const Vec3 moved = {(R - q[2]) * std::sin(th), q[1], R - (R - q[2]) * std::cos(th)};
    EXPECT_NEAR(eval(bent, moved), eval(plain, q), 1e-9);
  }
  const Program none = compile(makeNode("bend", {{"angle", realValue(0)}}, {bar}));
  EXPECT_EQ(none.eval(0.3, 0.1, 0.05), plain.eval(0.3, 0.1, 0.05));
}

TEST(DeformPoint, RaisesABumpAndLeavesTheRestAlone) {
  const NodePtr ball = sphere(1);
  const Program plain = compile(ball);
  const Program bumped = compile(makeNode("deform_point",
                                          {{"point", vec3Value({0, 0, 1})},
                                           {"displacement", vec3Value({0, 0, 0.3})},
                                           {"radius", realValue(0.5)}},
                                          {ball}));
  EXPECT_LT(plain.eval(0, 0, 1.2), 0.0);
  EXPECT_GT(bumped.eval(0, 0, 1.2), 0.0);  // the top moved up
  for (const Vec3& q : randomPoints(500, 2)) {
    const double r = std::sqrt(q[0] * q[0] + q[1] * q[1] + (q[2] - 1) * (q[2] - 1));
    if (r >= 0.5) {
      EXPECT_EQ(eval(bumped, q), eval(plain, q));  // beyond the reach: unchanged
    }
  }
}

TEST(Taper, ScalesLinearlyAcrossTheAxis) {
  const NodePtr c = makeNode("cylinder", {{"radius", realValue(1)}, {"length", realValue(0)}}, {});
  const Program p = compile(makeNode(
      "taper", {{"scale1", realValue(1)}, {"scale2", realValue(0.5)}, {"length", realValue(2)}},
      {c}));
  // The radius goes from 1 at z = 0 to 0.5 at z = 2, and stays beyond.
  for (double z : {-1.0, 0.0, 0.5, 1.0, 2.0, 3.0}) {
    const double r = 1 - 0.25 * std::min(std::max(z, 0.0), 2.0);
    EXPECT_NEAR(p.eval(r, 0, z), 0.0, 1e-12) << z;
    EXPECT_GT(p.eval(0.9 * r, 0, z), 0.0) << z;
    EXPECT_LT(p.eval(1.1 * r, 0, z), 0.0) << z;
  }
  const Program identity =
      compile(makeNode("taper", {{"scale1", realValue(1)}, {"scale2", realValue(1)}}, {c}));
  EXPECT_EQ(identity.eval(0.3, 0.2, 0.7), compile(c).eval(0.3, 0.2, 0.7));
}

NodePtr tpms(const std::string& id, double cell, const std::string& kind = "sheet",
             double level = 0.3) {
  return makeNode(
      id, {{"cell", realValue(cell)}, {"level", realValue(level)}, {"kind", choiceValue(kind)}},
      {});
}

TEST(Tpms, PeriodicWithTheCellSize) {
  for (const char* id : {"gyroid", "schwarz_p", "schwarz_d", "diamond", "neovius", "lidinoid"}) {
    const Program p = compile(tpms(id, 0.4));
    for (const Vec3& q : randomPoints(50, 1)) {
      for (int a = 0; a < 3; ++a) {
        Vec3 shifted = q;
        shifted[a] += 0.4;
        EXPECT_NEAR(eval(p, shifted), eval(p, q), 1e-9) << id;
      }
    }
  }
}

TEST(Tpms, KnownValuesOfTheNodalForms) {
  // At the origin: gyroid g = 0, Schwarz P g = 3, Neovius g = 13, diamond g = 1, D g = 0,
  // lidinoid g = -1.5 + 0.15.
  EXPECT_DOUBLE_EQ(compile(tpms("gyroid", 1)).eval(0, 0, 0), 0.3);
  EXPECT_DOUBLE_EQ(compile(tpms("schwarz_p", 1)).eval(0, 0, 0), 0.3 - 3);
  EXPECT_DOUBLE_EQ(compile(tpms("neovius", 1)).eval(0, 0, 0), 0.3 - 13);
  EXPECT_DOUBLE_EQ(compile(tpms("diamond", 1)).eval(0, 0, 0), 0.3 - 1);
  EXPECT_DOUBLE_EQ(compile(tpms("schwarz_d", 1)).eval(0, 0, 0), 0.3);
  EXPECT_NEAR(compile(tpms("lidinoid", 1)).eval(0, 0, 0), 0.3 - 1.35, 1e-12);
  // A quarter cell along x: the gyroid is sin(pi/2) cos 0 = 1.
  EXPECT_NEAR(compile(tpms("gyroid", 1)).eval(0.25, 0, 0), 0.3 - 1, 1e-12);
  // network: the solid side g <= level, so the origin of Schwarz P (g = 3) is empty and the
  // cell's centre (g = -3) solid.
  EXPECT_DOUBLE_EQ(compile(tpms("schwarz_p", 1, "network")).eval(0, 0, 0), 0.3 - 3);
  EXPECT_DOUBLE_EQ(compile(tpms("schwarz_p", 1, "network")).eval(0.5, 0.5, 0.5), 0.3 + 3);
}

TEST(TpmsAcceptance, SheetVolumeFractionGrowsWithTheLevel) {
  // The gyroid wall |g| <= level fills a growing share of a cube of whole cells.
  double last = 0;
  for (double level : {0.2, 0.4, 0.8}) {
    const NodePtr cube =
        makeNode("intersection", {},
                 {tpms("gyroid", 0.5, "sheet", level), box({-0.5, -0.5, -0.5}, {1, 1, 1})});
    const double v = meshVolume(cube, 0.6, 1.0 / 64);
    EXPECT_GT(v, last + 0.05) << level;
    EXPECT_LT(v, 1.0);
    last = v;
  }
}

TEST(Tpms, AnInputFieldGradesTheLevel) {
  // level(p) = the input's value: here 0.5 - z from a half-space, so the walls thin out
  // upwards and vanish above z = 0.5.
  const NodePtr ramp = makeNode("halfspace", {{"point", vec3Value({0, 0, 0.5})}}, {});
  const Program graded = compile(makeNode("gyroid", {{"cell", realValue(1)}}, {ramp}));
  const Program g0 = compile(tpms("gyroid", 1, "sheet", 1e-9));  // 1e-9 - |g|
  for (const Vec3& q : randomPoints(200, 2)) {
    const double level = 0.5 - q[2];
    EXPECT_NEAR(eval(graded, q), level + (eval(g0, q) - 1e-9), 1e-9);
  }
}

TEST(InfillAcceptance, SkinOutsideLatticeInsidePrintable) {
  const NodePtr s = makeNode("infill",
                             {{"lattice", choiceValue("gyroid")},
                              {"wall", realValue(0.1)},
                              {"cell", realValue(0.5)},
                              {"level", realValue(0.3)}},
                             {sphere(1)});
  const Program p = compile(s), lattice = compile(tpms("gyroid", 0.5));
  EXPECT_GT(p.eval(0.95, 0, 0), 0.0);  // in the skin
  EXPECT_LT(p.eval(1.05, 0, 0), 0.0);  // outside
  for (const Vec3& q : randomPoints(300, 0.8)) {
    if (norm3(q) > 0.85) continue;  // deep inside: the lattice decides
    EXPECT_EQ(eval(p, q) > 0, eval(lattice, q) > 0);
  }
  MeshingOptions o;
  o.bbox = {{-1.1, -1.1, -1.1}, {1.1, 1.1, 1.1}};
  o.resolution = 1.0 / 64;
  const CheckReport r = checkMesh(polygonize(compile(s), o));
  EXPECT_TRUE(r.printable());
  // The lattice walls close the hollow into sealed chambers: each is a shell of its own in
  // the check's component count, so that count is not 1 here.
  const double full = 4.0 / 3.0 * kPi, skin = full * (1 - 0.9 * 0.9 * 0.9);
  EXPECT_GT(r.volume, skin * 1.1);
  EXPECT_LT(r.volume, 0.7 * full);
}

TEST(Infill, DrainHolesOpenTheSkinWithinTheirCylindersOnly) {
  // A 10 mm cube with a 1 mm skin; holes of 2 mm on its bottom and on a side (drilled along
  // x), the lattice untouched.
  auto infill = [](std::vector<Vec3> holes, Vec3 axis) {
    return compile(makeNode(
        "infill",
        {{"lattice", choiceValue("gyroid")},
         {"wall", realValue(1.0)},
         {"cell", realValue(4.0)},
         {"level", realValue(0.3)},
         {"drain_holes", pointsValue(holes)},
         {"drain_diameter", realValue(2.0)},
         {"drain_axis", vec3Value(axis)}},
        {makeNode("box", {{"corner", vec3Value({0, 0, 0})}, {"size", vec3Value({10, 10, 10})}},
                  {})}));
  };
  const Program plain = infill({}, {0, 0, 1});
  const Program bottom = infill({{5, 5, 0}}, {0, 0, 1});
  const Program side = infill({{10, 3, 7}}, {1, 0, 0});
  const Program lattice = compile(tpms("gyroid", 4.0));
  // In the bottom skin: solid without the hole; in the hole the lattice alone decides.
  for (const Vec3& q : std::vector<Vec3>{{5, 5, 0.5}, {5.9, 5, 0.1}, {5, 4.2, 0.9}}) {
    EXPECT_GT(eval(plain, q), 0.0);
    EXPECT_EQ(eval(bottom, q) > 0, eval(lattice, q) > 0) << q[0] << " " << q[1] << " " << q[2];
  }
  EXPECT_EQ(eval(side, {9.5, 3, 7}) > 0, eval(lattice, {9.5, 3, 7}) > 0);
  EXPECT_GT(eval(side, {9.5, 3, 8.5}), 0.0);  // the side's skin beside its hole
  // Outside the cylinders (beside them, or beyond their reach of wall + diameter = 3 along
  // the axis: the top skin) the solid is as without holes.
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-0.5, 10.5);
  int compared = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 q = {u(rng), u(rng), u(rng)};
    if (std::hypot(q[0] - 5, q[1] - 5) < 1.0 && std::abs(q[2]) < 3.0) continue;
    EXPECT_EQ(eval(bottom, q) > 0, eval(plain, q) > 0) << q[0] << " " << q[1] << " " << q[2];
    ++compared;
  }
  EXPECT_GT(compared, 1500);
  EXPECT_GT(eval(bottom, {5, 5, 9.5}), 0.0);    // the top skin above the hole: beyond its reach
  EXPECT_GT(eval(bottom, {6.2, 5, 0.5}), 0.0);  // beside the hole
  // More than 100 holes are refused, naming the parameter.
  try {
    infill(std::vector<Vec3>(101, Vec3{1, 1, 0}), {0, 0, 1});
    FAIL() << "101 drain holes were accepted";
  } catch (const ModelError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("parameter 'drain_holes' expects a list of 0 to 100 points"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("got 101 points"), std::string::npos) << message;
  }
}

TEST(Infill, ThicknessIsTheSheetsWidthInModelUnits) {
  // The sheets' width, measured across them along the surface's normal at points of the
  // surface g = 0 deep inside the part, is the thickness asked for (to the accuracy of one
  // typical gradient per surface), and twice the thickness gives twice the width.
  auto meanWidth = [](double t) {
    const Program p = compile(makeNode("infill",
                                       {{"lattice", choiceValue("gyroid")},
                                        {"wall", realValue(0.1)},
                                        {"cell", realValue(0.5)},
                                        {"thickness", realValue(t)}},
                                       {sphere(1)}));
    const Program g = compile(tpms("gyroid", 0.5, "network", 1e-9));  // about -g
    double sum = 0.0;
    int count = 0;
    for (const Vec3& a : randomPoints(400, 0.55)) {
      Vec3 b = a;
      b[0] += 0.2;
      double ga = eval(g, a), gb = eval(g, b);
      if ((ga > 0) == (gb > 0)) continue;
      Vec3 lo = a, hi = b;  // bisection onto g = 0
      for (int i = 0; i < 50; ++i) {
        Vec3 mid = {(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
        ((eval(g, mid) > 0) == (ga > 0) ? lo : hi) = mid;
      }
      Vec3 n;
      const double e = 1e-6;
      for (int k = 0; k < 3; ++k) {
        Vec3 u = lo, v = lo;
        u[k] += e;
        v[k] -= e;
        n[k] = (eval(g, u) - eval(g, v)) / (2 * e);
      }
      const double len = norm3(n);
      double width = 0.0;
      for (double side : {-1.0, 1.0}) {
        double s = 0.0;
        while (s < 0.2) {
          const Vec3 q = {lo[0] + side * s * n[0] / len, lo[1] + side * s * n[1] / len,
                          lo[2] + side * s * n[2] / len};
          if (eval(p, q) < 0) break;
          s += 1e-4;
        }
        width += s;
      }
      sum += width;
      ++count;
    }
    EXPECT_GT(count, 50);
    return sum / count;
  };
  const double thin = meanWidth(0.04), thick = meanWidth(0.08);
  EXPECT_NEAR(thin, 0.04, 0.012);
  EXPECT_NEAR(thick, 0.08, 0.024);
  EXPECT_NEAR(thick / thin, 2.0, 0.1);
}

}  // namespace
}  // namespace frep
