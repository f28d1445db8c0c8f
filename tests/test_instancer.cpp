// The instancer: copies of a solid at many points through a k-d tree. Checked against the
// brute-force union of every copy, in every evaluator mode, and meshed with 10,000 copies.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "base/errors.h"
#include "check/mesh_check.h"
#include "frep/instances.h"
#include "frep/ops.h"
#include "frep/program.h"
#include "frep/structural_bounds.h"
#include "frep/tree.h"
#include "mesh/mesher.h"
#include "test_nodes.h"

namespace frep {
namespace {

using frep::testing::sphere;

ParamValue pointsValue(const std::vector<Vec3>& pts) {
  ParamValue v;
  for (const Vec3& p : pts) v.numbers.insert(v.numbers.end(), p.begin(), p.end());
  return v;
}

NodePtr instancer(const NodePtr& copy, const std::vector<Vec3>& at, const char* combine = "union",
                  double a0 = 0.1, double a1 = 0.1) {
  return makeNode("instancer",
                  {{"positions", pointsValue(at)},
                   {"combine", choiceValue(combine)},
                   {"blend_amount", realValue(a0)},
                   {"blend_range", realValue(a1)}},
                  {copy}, "copies");
}

// 10,000 points: a 100 x 100 plate of jittered positions 0.5 apart, so that spheres of radius
// 0.3 overlap into one piece.
std::vector<Vec3> plate() {
  std::mt19937 g(11);
  std::uniform_real_distribution<double> jitter(-0.04, 0.04);
  std::vector<Vec3> pts;
  for (int i = 0; i < 100; ++i)
    for (int j = 0; j < 100; ++j)
      pts.push_back({0.5 * i + jitter(g), 0.5 * j + jitter(g), jitter(g)});
  return pts;
}

TEST(Instancer, TenThousandCopiesAreTheUnionOfEveryCopy) {
  const NodePtr ball = sphere(0.3, {0.05, 0, 0.02});  // off the origin: copies keep the offset
  const std::vector<Vec3> at = plate();
  const Program p = compile(instancer(ball, at)), one = compile(ball);
  std::mt19937 g(3);
  std::uniform_real_distribution<double> u(-1, 51), w(-0.6, 0.6);
  int inside = 0;
  for (int i = 0; i < 1500; ++i) {
    const double x = u(g), y = u(g), z = w(g);
    double best = -1e300;
    for (const Vec3& c : at) best = std::max(best, one.eval(x - c[0], y - c[1], z - c[2]));
    const double v = p.eval(x, y, z);
    // exact where the solid is; elsewhere the sign is what matters (and is right)
    if (best >= 0) {
      EXPECT_EQ(v, best) << x << "," << y << "," << z;
      ++inside;
    } else {
      EXPECT_LT(v, 0.0) << x << "," << y << "," << z;
    }
  }
  EXPECT_GT(inside, 25);  // the brick fills about 1.3 % of the sampled cubes
}

TEST(InstancerAcceptance, TenThousandCopiesMeshPrintableInOnePiece) {
  const NodePtr part = instancer(sphere(0.3), plate());
  const Box3 b = structuralBounds(part);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(b.lo[a], a < 2 ? -0.34 : -0.34, 0.01);
    EXPECT_NEAR(b.hi[a], a < 2 ? 49.84 : 0.34, 0.01);
  }
  MeshingOptions o;
  o.bbox = b;
  for (int a = 0; a < 3; ++a) {
    o.bbox.lo[a] -= 0.2;
    o.bbox.hi[a] += 0.2;
  }
  o.resolution = 0.15;
  const CheckReport r = checkMesh(polygonize(compile(part), o));
  EXPECT_TRUE(r.printable()) << reportToText(r, "instancer");
  EXPECT_EQ(r.components, 1u);
  // between one big slab and 10,000 separate balls
  EXPECT_GT(r.volume, 0.5 * 10000 * 4.0 / 3.0 * 3.14159265 * 0.027);
  EXPECT_LT(r.volume, 10000 * 4.0 / 3.0 * 3.14159265 * 0.027);
}

TEST(Instancer, BlendOfTwoCopiesIsPaskosBlendUnion) {
  const NodePtr ball = sphere(0.4);
  const Program p = compile(instancer(ball, {{-0.3, 0, 0}, {0.35, 0.1, 0}}, "blend", 0.2, 0.3));
  const Program ref = compile(makeNode(
      "blend_union", {{"a0", realValue(0.2)}, {"a1", realValue(0.3)}, {"a2", realValue(0.3)}},
      {sphere(0.4, {-0.3, 0, 0}), sphere(0.4, {0.35, 0.1, 0})}));
  std::mt19937 g(4);
  std::uniform_real_distribution<double> u(-0.6, 0.6);
  int compared = 0;
  for (int i = 0; i < 2000; ++i) {
    const double x = u(g), y = u(g), z = u(g);
    if (std::hypot(x + 0.3, y, z) > 0.69 || std::hypot(x - 0.35, y - 0.1, z) > 0.69) continue;
    EXPECT_NEAR(p.eval(x, y, z), ref.eval(x, y, z), 1e-12);  // both copies within reach
    ++compared;
  }
  EXPECT_GT(compared, 100);
}

TEST(Instancer, IntervalsEncloseOnLargeBoxesAndGradientsFollowATransform) {
  const std::vector<Vec3> at = plate();
  const NodePtr part = instancer(sphere(0.3), at, "blend", 0.05, 0.1);
  const Program p = compile(part);
  std::mt19937 g(8);
  std::uniform_real_distribution<double> u(-2, 52), s(0.2, 20);
  for (int i = 0; i < 60; ++i) {  // boxes holding from a few to thousands of copies
    const double cx = u(g), cy = u(g), h = s(g);
    const Interval X(cx - h, cx + h), Y(cy - h, cy + h), Z(-0.5, 0.5);
    const Interval range = p.evalInterval(X, Y, Z);
    std::uniform_real_distribution<double> px(X.lo, X.hi), py(Y.lo, Y.hi), pz(Z.lo, Z.hi);
    for (int k = 0; k < 50; ++k) {
      const double v = p.eval(px(g), py(g), pz(g));
      ASSERT_GE(v, range.lo);
      ASSERT_LE(v, range.hi);
    }
  }
  // under a rotation the gradient is the chain rule through the copies
  const Program turned = compile(
      makeNode("rotate", {{"axis", vec3Value({1, 1, 0})}, {"angle", realValue(30)}}, {part}));
  for (int i = 0; i < 200; ++i) {
    const double x = u(g), y = u(g), z = 0.3 * std::sin(x);
    const Dual d = turned.evalGradient(x, y, z);
    const double e = 1e-6;
    const double fd[3] = {(turned.eval(x + e, y, z) - turned.eval(x - e, y, z)) / (2 * e),
                          (turned.eval(x, y + e, z) - turned.eval(x, y - e, z)) / (2 * e),
                          (turned.eval(x, y, z + e) - turned.eval(x, y, z - e)) / (2 * e)};
    const double fd2 = (turned.eval(x + 1e-5, y, z) - turned.eval(x - 1e-5, y, z)) / 2e-5;
    if (std::abs(fd2 - fd[0]) > 1e-5) continue;  // a kink of the max within reach
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(d.d[a], fd[a], 1e-5);
  }
}

TEST(Instancer, TurnedCopiesAreTheInputRotatedThenMoved) {
  // a box off its origin, so that a turn shows; each copy is rotate-then-translate of it
  const NodePtr brick = makeNode(
      "box", {{"corner", vec3Value({0.1, -0.1, -0.2})}, {"size", vec3Value({0.6, 0.2, 0.3})}}, {});
  const std::vector<Vec3> at = {{0, 0, 0}, {2, 0, 0}, {0, 2, 1}};
  const std::vector<Vec3> turns = {{0, 0, 90}, {0, 0, 0}, {30, 40, 0}};  // axis * degrees
  const NodePtr copies =
      makeNode("instancer", {{"positions", pointsValue(at)}, {"rotations", pointsValue(turns)}},
               {brick}, "copies");
  std::vector<Program> each;
  for (std::size_t i = 0; i < at.size(); ++i) {
    const double angle = std::sqrt(turns[i][0] * turns[i][0] + turns[i][1] * turns[i][1] +
                                   turns[i][2] * turns[i][2]);
    NodePtr turned = brick;
    if (angle > 0)
      turned =
          makeNode("rotate", {{"axis", vec3Value(turns[i])}, {"angle", realValue(angle)}}, {brick});
    each.push_back(compile(makeNode("translate", {{"offset", vec3Value(at[i])}}, {turned})));
  }
  const Program p = compile(copies);
  std::mt19937 g(9);
  int inside = 0;
  std::uniform_real_distribution<double> near(-0.7, 0.7);
  for (int k = 0; k < 3000; ++k) {  // around each copy in turn
    const Vec3& c = at[k % at.size()];
    const double x = c[0] + near(g), y = c[1] + near(g), z = c[2] + near(g);
    double best = -1e300;
    for (const Program& e : each) best = std::max(best, e.eval(x, y, z));
    if (best >= 0) {
      EXPECT_NEAR(p.eval(x, y, z), best, 1e-12);
      ++inside;
    } else {
      EXPECT_LT(p.eval(x, y, z), 0.0);
    }
    // gradient: the chain rule through the turn, against the reference where smooth
    const Dual d = p.evalGradient(x, y, z);
    const double h = 1e-6;
    const double fx = (p.eval(x + h, y, z) - p.eval(x - h, y, z)) / (2 * h);
    const double fx2 = (p.eval(x + 1e-5, y, z) - p.eval(x - 1e-5, y, z)) / 2e-5;
    if (std::abs(fx - fx2) < 1e-6) {
      EXPECT_NEAR(d.d[0], fx, 1e-5);
    }
  }
  EXPECT_GT(inside, 25);  // the brick fills about 1.3 % of the sampled cubes
  // the structural box holds every turned copy
  const Box3 b = structuralBounds(copies);
  std::uniform_real_distribution<double> w(-2, 4);
  for (int k = 0; k < 20000; ++k) {
    const double x = w(g), y = w(g), z = w(g);
    if (p.eval(x, y, z) >= 0) {
      ASSERT_TRUE(x >= b.lo[0] && x <= b.hi[0] && y >= b.lo[1] && y <= b.hi[1] && z >= b.lo[2] &&
                  z <= b.hi[2]);
    }
  }
  // one rotation per position, or none
  try {
    makeNode("instancer", {{"positions", pointsValue(at)}, {"rotations", pointsValue({{0, 0, 9}})}},
             {brick}, "copies");
    FAIL() << "accepted";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("1 rotations for 3 positions"), std::string::npos);
  }
}

TEST(Instancer, NestedInstancersEvaluateAlikeInPointAndBatch) {
  // copies of copies: the inner program runs inside an instruction of the outer one
  const NodePtr pair = instancer(sphere(0.2), {{0, 0, 0}, {0.3, 0, 0}});
  const Program p = compile(instancer(pair, {{0, 0, 0}, {0, 0.5, 0}, {0, 0, 0.5}, {1, 1, 1}}));
  std::mt19937 g(6);
  std::uniform_real_distribution<double> u(-0.5, 1.5);
  std::vector<double> x(700), y(700), z(700), out(700);
  for (std::size_t i = 0; i < x.size(); ++i) {
    x[i] = u(g);
    y[i] = u(g);
    z[i] = u(g);
  }
  p.evalBatch(x.data(), y.data(), z.data(), x.size(), out.data());
  int inside = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    ASSERT_EQ(out[i], p.eval(x[i], y[i], z[i]));
    inside += out[i] > 0;
  }
  EXPECT_GT(inside, 5);
  EXPECT_GT(p.eval(1.3, 1, 1), 0.0);  // the last pair's second ball
}

// Specialised to a box, the instancer keeps only the copies within reach of it; points no
// copy reaches, and intervals, are answered by the whole set. Every mode gives the same values
// as the whole program, near the copies, between them and far from all of them.
TEST(Instancer, SpecialisedToABoxGivesTheSameValues) {
  const NodePtr ball = makeNode("sphere", {{"radius", realValue(0.3)}}, {});
  for (const char* combine : {"union", "blend"}) {
    const Program whole = compile(instancer(ball, plate(), combine));
    std::mt19937 g(5);
    std::uniform_real_distribution<double> u(-3.0, 53.0), w(-2.0, 2.0), size(0.05, 4.0);
    for (int b = 0; b < 40; ++b) {
      const double c[3] = {u(g), u(g), w(g)}, h = size(g);
      const Box3 box{{c[0] - h, c[1] - h, c[2] - h}, {c[0] + h, c[1] + h, c[2] + h}};
      const Program part = whole.specialised(box);
      std::uniform_real_distribution<double> in(-h, h);
      for (int i = 0; i < 50; ++i) {
        const double x = c[0] + in(g), y = c[1] + in(g), z = c[2] + in(g);
        ASSERT_EQ(part.eval(x, y, z), whole.eval(x, y, z)) << combine << " box " << b;
        double batch = 0;
        part.evalBatch(&x, &y, &z, 1, &batch);
        ASSERT_EQ(batch, whole.eval(x, y, z));
        ASSERT_EQ(part.evalGradient(x, y, z).d[0], whole.evalGradient(x, y, z).d[0]);
      }
      const Interval a =
          part.evalInterval({c[0] - h / 2, c[0]}, {c[1], c[1] + h / 3}, {c[2], c[2]});
      const Interval e =
          whole.evalInterval({c[0] - h / 2, c[0]}, {c[1], c[1] + h / 3}, {c[2], c[2]});
      ASSERT_TRUE(a.lo == e.lo && a.hi == e.hi && a.nan == e.nan);
    }
  }
}

// The blend takes a point's two largest copies among those within reach, so a copy missed or
// wrongly taken at the edge of its reach changes the value. Copies scattered in 3D (the
// bucket grid's 3D neighbourhoods), points just inside and just outside each copy's reach:
// the value is that of the brute-force rule over every copy.
TEST(Instancer, BlendFindsExactlyTheCopiesWithinReach) {
  std::mt19937 g(21);
  std::uniform_real_distribution<double> u(0, 6), dir(-1, 1);
  std::vector<Vec3> at(200);  // sparse: a copy at the edge of reach is often one of the two
  for (Vec3& c : at) c = {u(g), u(g), u(g)};
  const NodePtr ball = sphere(0.4);
  const double a0 = 0.3, a1 = 0.5;
  const Program p = compile(instancer(ball, at, "blend", a0, a1)), one = compile(ball);
  const auto* set = dynamic_cast<const InstanceSet*>(p.externals().at(0).get());
  ASSERT_NE(set, nullptr);
  const double reach = set->reach();
  auto expected = [&](double x, double y, double z, bool* anyInReach) {
    // copies strictly within reach (squared distances summed in x, y, z order), in index
    // order; the first largest and the next largest
    int first = -1, second = -1;
    double v1 = 0, v2 = 0;
    for (std::size_t i = 0; i < at.size(); ++i) {
      const double dx = x - at[i][0], dy = y - at[i][1], dz = z - at[i][2];
      if (!(dx * dx + dy * dy + dz * dz < reach * reach)) continue;
      const double v = one.eval(dx, dy, dz);
      if (first < 0 || v > v1) {
        second = first;
        v2 = v1;
        first = static_cast<int>(i);
        v1 = v;
      } else if (second < 0 || v > v2) {
        second = static_cast<int>(i);
        v2 = v;
      }
    }
    *anyInReach = first >= 0;
    if (second < 0) return v1;
    const double k[3] = {a0, a1, a1};
    return v1 + blendBump(v1, v2, k);
  };
  int compared = 0;
  for (int i = 0; i < 3000; ++i) {
    double x, y, z;
    if (i % 2) {
      x = u(g), y = u(g), z = u(g);
    } else {  // on the edge of a copy's reach, inside or outside by a hair
      const Vec3& c = at[static_cast<std::size_t>(i / 2) % at.size()];
      double d[3] = {dir(g), dir(g), dir(g)};
      const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      const double r = reach * (i % 4 ? 1 - 1e-12 : 1 + 1e-12) / len;
      x = c[0] + d[0] * r, y = c[1] + d[1] * r, z = c[2] + d[2] * r;
    }
    bool reached = false;
    const double e = expected(x, y, z, &reached);
    if (!reached) continue;
    ASSERT_EQ(p.eval(x, y, z), e) << i << " at " << x << "," << y << "," << z;
    ++compared;
  }
  EXPECT_GT(compared, 1000);
}

// Gradients of many points at once are those of each point, under a transform, with turned
// copies and with copies of copies.
TEST(Instancer, GradientBatchEqualsGradientAtEachPoint) {
  const NodePtr brick = makeNode(
      "box", {{"corner", vec3Value({0.1, -0.1, -0.2})}, {"size", vec3Value({0.6, 0.2, 0.3})}}, {});
  const NodePtr turned =
      makeNode("instancer",
               {{"positions", pointsValue({{0, 0, 0}, {0.5, 0, 0}, {0, 0.5, 0.2}})},
                {"rotations", pointsValue({{0, 0, 90}, {0, 0, 0}, {30, 40, 0}})},
                {"combine", choiceValue("blend")}},
               {brick}, "copies");
  const NodePtr nested = instancer(turned, {{0, 0, 0}, {0.4, 0.4, 0}, {2, 2, 2}});
  const Program p = compile(
      makeNode("rotate", {{"axis", vec3Value({1, 2, 0})}, {"angle", realValue(25)}}, {nested}));
  std::mt19937 g(12);
  std::uniform_real_distribution<double> u(-0.4, 1.0);
  const std::size_t n = 3000;
  std::vector<Dual> x(n), y(n), z(n), out(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = Dual(u(g), 1, 0, 0);
    y[i] = Dual(u(g), 0, 1, 0);
    z[i] = Dual(u(g), 0, 0, 1);
  }
  p.evalGradientBatch(x.data(), y.data(), z.data(), n, out.data());
  int inside = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Dual d = p.evalGradient(x[i].v, y[i].v, z[i].v);
    ASSERT_EQ(out[i].v, d.v) << i;
    for (int a = 0; a < 3; ++a) ASSERT_EQ(out[i].d[a], d.d[a]) << i << " axis " << a;
    inside += d.v >= 0;
  }
  EXPECT_GT(inside, 50);
}

// Hundreds of turned copies go through the bucket grid, where a batch gathers its (point,
// copy) pairs in one pass over each cell's candidates. Every batch mode must still give each
// point's value and gradient bit for bit, for a union and a blend, near the copies, between
// them and beyond every copy's reach (where the nearest copy answers).
TEST(Instancer, ManyTurnedCopiesEvaluateAlikeInPointAndBatch) {
  std::mt19937 g(21);
  std::uniform_real_distribution<double> u(0, 4), angle(-180, 180);
  std::vector<Vec3> at, turns;
  for (int i = 0; i < 400; ++i) {
    at.push_back({u(g), u(g), u(g)});
    turns.push_back({angle(g), angle(g), angle(g)});
  }
  const NodePtr brick = makeNode(
      "box", {{"corner", vec3Value({-0.1, -0.2, -0.15})}, {"size", vec3Value({0.4, 0.3, 0.2})}},
      {});
  for (const char* combine : {"union", "blend"}) {
    const Program p = compile(makeNode("instancer",
                                       {{"positions", pointsValue(at)},
                                        {"rotations", pointsValue(turns)},
                                        {"combine", choiceValue(combine)}},
                                       {brick}, "copies"));
    std::uniform_real_distribution<double> w(-1.5, 5.5);
    const std::size_t n = 4000;
    std::vector<double> x(n), y(n), z(n), out(n);
    std::vector<Dual> dx(n), dy(n), dz(n), dout(n);
    for (std::size_t i = 0; i < n; ++i) {
      x[i] = w(g);
      y[i] = w(g);
      z[i] = w(g);
      dx[i] = Dual(x[i], 1, 0, 0);
      dy[i] = Dual(y[i], 0, 1, 0);
      dz[i] = Dual(z[i], 0, 0, 1);
    }
    p.evalBatch(x.data(), y.data(), z.data(), n, out.data());
    p.evalGradientBatch(dx.data(), dy.data(), dz.data(), n, dout.data());
    int inside = 0, far = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double v = p.eval(x[i], y[i], z[i]);
      ASSERT_EQ(out[i], v) << combine << " point " << i;
      const Dual d = p.evalGradient(x[i], y[i], z[i]);
      ASSERT_EQ(dout[i].v, d.v) << combine << " point " << i;
      for (int a = 0; a < 3; ++a) ASSERT_EQ(dout[i].d[a], d.d[a]) << combine << " point " << i;
      inside += v >= 0;
      far += x[i] < -1 || x[i] > 5;
    }
    EXPECT_GT(inside, 40) << combine;
    EXPECT_GT(far, 400) << combine;  // beyond every copy's reach
  }
}

// Found by the fuzz test: one copy 1e30 away made the bucket grid's cell count overflow. Far
// apart copies must still evaluate, as the union of every copy.
TEST(Instancer, CopiesFarApartStillEvaluate) {
  const NodePtr ball = makeNode("sphere", {{"radius", realValue(0.3)}}, {});
  std::vector<Vec3> at = plate();
  at.resize(100);
  at.push_back({1e30, 0, 0});
  const Program p = compile(instancer(ball, at));
  const Program one = compile(ball);
  for (int i = 0; i < 200; ++i) {
    const double x = 0.05 * i - 1, y = 0.3, z = 0.1;
    double expect = -std::numeric_limits<double>::infinity();
    for (const Vec3& c : at) expect = std::max(expect, one.eval(x - c[0], y - c[1], z - c[2]));
    if (expect >= 0) {
      EXPECT_EQ(p.eval(x, y, z), expect);
    } else {
      EXPECT_LT(p.eval(x, y, z), 0.0);
    }
  }
}

TEST(Instancer, UnboundedCopiesAreEveryCopyEverywhereAndMeshWithinABox) {
  // Copies of a gyroid reach every point: the union is the max over all of them, far from
  // every position too, and the mesher clips it to the box it is given.
  const NodePtr gyroid = makeNode("gyroid", {}, {});
  const std::vector<Vec3> at = {{0, 0, 0}, {0.3, 0.1, 0}, {-0.2, 0.4, 0.7}};
  const Program p = compile(instancer(gyroid, at));
  const Program one = compile(gyroid);
  std::mt19937 g(9);
  std::uniform_real_distribution<double> u(-50, 50);
  for (int i = 0; i < 500; ++i) {
    const double x = u(g), y = u(g), z = u(g);
    double expected = -std::numeric_limits<double>::infinity();
    for (const Vec3& c : at) expected = std::max(expected, one.eval(x - c[0], y - c[1], z - c[2]));
    EXPECT_NEAR(p.eval(x, y, z), expected, 1e-12) << x << " " << y << " " << z;
  }
  MeshingOptions o;
  o.bbox = Box3{{-1, -1, -1}, {1, 1, 1}};
  o.resolution = 0.05;
  const TriangleMesh mesh = polygonize(p, o);
  EXPECT_TRUE(checkMesh(mesh).printable());
  // More copies than every point can afford to evaluate: refused, naming the figure.
  std::vector<Vec3> many;
  for (int i = 0; i <= 1000; ++i) many.push_back({0.01 * i, 0, 0});
  try {
    compile(instancer(gyroid, many));
    FAIL() << "1001 unbounded copies compiled";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("at most 1000 copies of it are allowed, got 1001"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace frep
