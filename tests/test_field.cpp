// The Field seam: a field written only here (a capsule) meshes printable through the same
// mesher as compiled trees, sits in a tree through an external node in all four modes, and
// region specialisation shortens programs without changing a value.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "base/errors.h"
#include "check/mesh_check.h"
#include "frep/field.h"
#include "frep/interval.h"
#include "frep/model_json.h"
#include "frep/scalar_math.h"
#include "frep/tree.h"
#if defined(__x86_64__) && defined(__GLIBC__)
#include "frep/vector_trig.h"
#endif
#include "mesh/mesher.h"

namespace frep {
namespace {

// A ball of radius r swept along the segment a-b: F = r - distance to the segment. One
// template serves the point (double), interval and gradient (Dual) modes, as the evaluator's
// own instructions do; interval.h's rules make the interval mode rigorous.
class CapsuleField final : public Field {
 public:
  CapsuleField(Vec3 a, Vec3 b, double r) : a_(a), b_(b), r_(r) {}

  double eval(double x, double y, double z) const override { return value<double>(x, y, z); }
  Interval evalInterval(const Interval& x, const Interval& y, const Interval& z) const override {
    return value<Interval>(x, y, z);
  }
  Dual evalGradient(const Dual& x, const Dual& y, const Dual& z) const override {
    return value<Dual>(x, y, z);
  }
  using Field::evalGradient;
  Box3 bounds() const override {
    Box3 box;
    for (int i = 0; i < 3; ++i) {
      box.lo[i] = std::min(a_[i], b_[i]) - r_;
      box.hi[i] = std::max(a_[i], b_[i]) + r_;
    }
    return box;
  }

 private:
  template <class T>
  T value(const T& x, const T& y, const T& z) const {
    const double d[3] = {b_[0] - a_[0], b_[1] - a_[1], b_[2] - a_[2]};
    const double dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    const T px = x - T(a_[0]), py = y - T(a_[1]), pz = z - T(a_[2]);
    const T t = min(max((px * T(d[0]) + py * T(d[1]) + pz * T(d[2])) * T(1.0 / dd), T(0.0)),
                    T(1.0));
    const T qx = px - t * T(d[0]), qy = py - t * T(d[1]), qz = pz - t * T(d[2]);
    return T(r_) - sqrt(sqr(qx) + sqr(qy) + sqr(qz));
  }
  Vec3 a_, b_;
  double r_;
};

std::shared_ptr<const Field> capsule() {
  return std::make_shared<const CapsuleField>(Vec3{-0.6, -0.2, 0.1}, Vec3{0.7, 0.3, -0.2}, 0.35);
}

// sin and cos as the modes evaluate them (glibc's vector library, scalar_math.h): within 5
// ulps of the scalar library (4 from the exact value, plus its own 1), never outside [-1, 1],
// the same bits two at a time (batch) as one at a time (point, gradient), and inside the
// interval rules' bounds, on arguments small, large and next to the extrema and zeros.
TEST(Trig, VectorSinAndCosAreNearTheLibraryTheSameInEveryModeAndInsideTheirIntervals) {
  std::mt19937_64 g(11);
  std::vector<double> x;
  for (double range : {1.0, 10.0, 1e4, 1e6})
    for (int i = 0; i < 50000; ++i)
      x.push_back(std::uniform_real_distribution<double>(-range, range)(g));
  for (int k = -2000; k <= 2000; ++k)  // next to k pi / 2
    for (double d : {0.0, 1e-300, 1e-12, -1e-9})
      x.push_back(k * 1.5707963267948966 + d);
  x.push_back(0.0);
  x.push_back(-0.0);
  auto ulps = [](double ours, double lib) {
    if (ours == lib) return 0.0;
    const double unit = std::nextafter(std::abs(lib), INFINITY) - std::abs(lib);
    return std::abs(ours - lib) / unit;
  };
  double worst = 0.0;
  for (double v : x) {
    for (const auto& [ours, lib] : {std::pair<double, double>{frep::sin(v), std::sin(v)},
                                   std::pair<double, double>{frep::cos(v), std::cos(v)}}) {
      ASSERT_LE(std::abs(ours), 1.0) << v;
      if (std::abs(lib) > 1e-300) worst = std::max(worst, ulps(ours, lib));
    }
  }
  EXPECT_LE(worst, 5.0);
  std::vector<double> s(x.size()), c(x.size());
  sinCosMany(x.data(), x.size(), s.data(), nullptr);  // one of the two
  sinCosMany(x.data(), x.size(), nullptr, c.data());
  std::vector<double> s1(x.size()), c1(x.size());  // the lattices' one pass for both
  sinCosMany(x.data(), x.size(), s1.data(), c1.data());
  ASSERT_EQ(std::memcmp(s.data(), s1.data(), x.size() * sizeof(double)), 0);
  ASSERT_EQ(std::memcmp(c.data(), c1.data(), x.size() * sizeof(double)), 0);
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double one[2] = {frep::sin(x[i]), frep::cos(x[i])};
    double both[2];
    frep::sinCos(x[i], &both[0], &both[1]);  // the gradient mode's
    ASSERT_EQ(std::memcmp(&one[0], &s[i], sizeof(double)), 0) << x[i];
    ASSERT_EQ(std::memcmp(&one[1], &c[i], sizeof(double)), 0) << x[i];
    ASSERT_EQ(std::memcmp(one, both, sizeof(both)), 0) << x[i];
  }
  // every value at a point of an interval lies in the interval rule's bounds
  std::uniform_real_distribution<double> start(-20.0, 20.0), width(0.0, 3.0), at(0.0, 1.0);
  for (int i = 0; i < 20000; ++i) {
    const double lo = i % 2 ? start(g) : std::round(start(g)) * 1.5707963267948966;
    const Interval box{lo, lo + (i % 3 ? width(g) : 1e-9 * at(g))};
    const Interval bs = frep::sin(box), bc = frep::cos(box);
    for (int k = 0; k < 20; ++k) {
      const double t = k == 0 ? box.lo : k == 1 ? box.hi : box.lo + at(g) * (box.hi - box.lo);
      ASSERT_TRUE(bs.contains(frep::sin(t))) << t << " in [" << box.lo << ", " << box.hi << "]";
      ASSERT_TRUE(bc.contains(frep::cos(t))) << t << " in [" << box.lo << ", " << box.hi << "]";
    }
  }
}

#if defined(__x86_64__) && defined(__GLIBC__)
// The lanes give the same bits two at a time (every x86-64 processor) as four at a time (AVX2),
// so a model evaluates alike on every processor; and they stay within 3 ulps of the exact
// value (long double's sinl and cosl as the reference) up to the direct limit. A mistake in
// either width's quadrant logic, sign, polynomial or fallback mask fails one of the two.
TEST(Trig, TwoAndFourLanesGiveTheSameBitsNearTheExactValue) {
  namespace vt = frep::vector_trig;
  ASSERT_GE(vt::widestLanes(), 4) << "this test needs a processor with AVX2 (every CI machine)";
  std::mt19937_64 g(19);
  std::vector<double> x;
  for (double range : {0.8, 10.0, 100.0, vt::kDirectLimit})
    for (int i = 0; i < 500000; ++i)
      x.push_back(std::uniform_real_distribution<double>(-range, range)(g));
  for (int k = -20000; k <= 20000; ++k)  // next to k pi / 4 (quadrant changes, zeros, extrema)
    for (double d : {0.0, 1e-300, 4e-16, -4e-16, 1e-9}) x.push_back(k * 0.78539816339744831 + d);
  for (double v :
       {0.0, -0.0, 1e-310, -1e-310, 1e-20, vt::kDirectLimit, 2e5, 1e300,
        std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
        std::numeric_limits<double>::quiet_NaN()})
    x.push_back(v);
  const auto fallback = [](double v) { return v == v ? 7.0 : 9.0; };  // marks the lanes left
  std::vector<double> s2(x.size()), s4(x.size()), c2(x.size()), c4(x.size());
  // the whole array, short ones (a padded block only), and ones that end past a fallback
  for (std::size_t n :
       {x.size(), std::size_t{1}, std::size_t{3}, std::size_t{6}, std::size_t{11}, x.size() - 3}) {
    vt::sinCosLanes(2, x.data(), n, s2.data(), c2.data(), fallback, fallback);
    vt::sinCosLanes(4, x.data(), n, s4.data(), nullptr, fallback, nullptr);  // one wanted
    vt::sinCosLanes(4, x.data(), n, nullptr, c4.data(), nullptr, fallback);
    ASSERT_EQ(std::memcmp(s2.data(), s4.data(), n * sizeof(double)), 0) << n;
    ASSERT_EQ(std::memcmp(c2.data(), c4.data(), n * sizeof(double)), 0) << n;
  }
  vt::sinCosLanes(2, x.data(), x.size(), s2.data(), c2.data(), fallback, fallback);
  double worst = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double v = x[i];
    if (!(std::abs(v) <= vt::kDirectLimit)) {
      EXPECT_EQ(s2[i], v == v ? 7.0 : 9.0) << v;  // left to the fallback
      continue;
    }
    for (const auto& [ours, exact] : {std::pair<double, long double>{s2[i], sinl(v)},
                                      std::pair<double, long double>{c2[i], cosl(v)}}) {
      ASSERT_LE(std::abs(ours), 1.0) << v;
      const double rounded = static_cast<double>(exact);
      if (std::abs(rounded) < 1e-300) continue;
      const double unit = std::nextafter(std::abs(rounded), INFINITY) - std::abs(rounded);
      const double e = static_cast<double>(std::abs(ours - exact) / unit);
      worst = std::max(worst, e);
    }
  }
  EXPECT_LE(worst, 3.0);  // measured 2.32 (cos near 22,329); scalar_math.h promises 4
  EXPECT_EQ(std::signbit(s2[x.size() - 10]), true);  // sin(-0) = -0
}
#endif

TEST(FieldSeam, AFieldWrittenOnlyInTestsMeshesPrintable) {
  const auto f = capsule();
  MeshingOptions o;
  o.bbox = f->bounds();
  for (int a = 0; a < 3; ++a) o.bbox.lo[a] -= 0.05, o.bbox.hi[a] += 0.05;
  o.resolution = 0.02;
  const CheckReport r = checkMesh(polygonize(*f, o));
  EXPECT_TRUE(r.printable()) << reportToText(r, "capsule");
  EXPECT_EQ(r.components, 1u);
  const double len = std::sqrt(1.3 * 1.3 + 0.5 * 0.5 + 0.3 * 0.3), rr = 0.35;
  const double exact = M_PI * rr * rr * len + 4.0 / 3.0 * M_PI * rr * rr * rr;
  EXPECT_NEAR(r.volume, exact, 0.01 * exact);
}

TEST(FieldSeam, AnExternalNodeIsEvaluatedInAllFourModesInsideATree) {
  const NodePtr ball = makeNode("sphere", {{"center", vec3Value({0.8, 0, 0})}, {"radius", realValue(0.4)}}, {});
  const NodePtr ext = makeFieldNode(capsule(), "capsule");
  const NodePtr moved = makeNode("rotate", {{"axis", vec3Value({0, 0, 1})}, {"angle", realValue(30)}}, {ext});
  const Program both = compile(makeNode("union", {}, {moved, ball}));
  const Program alone = compile(ball);
  const CapsuleField cap({-0.6, -0.2, 0.1}, {0.7, 0.3, -0.2}, 0.35);
  const double c = std::cos(-M_PI / 6), s = std::sin(-M_PI / 6);
  for (int i = 0; i < 200; ++i) {
    const double x = -1 + 0.01 * i, y = 0.3 * std::sin(i), z = 0.2 * std::cos(i);
    // rotate by 30 degrees about z: the capsule is evaluated at the point turned back
    const double lx = c * x - s * y, ly = s * x + c * y;
    const double expect = std::max(cap.eval(lx, ly, z), alone.eval(x, y, z));
    EXPECT_NEAR(both.eval(x, y, z), expect, 1e-12);
    double batch = 0;
    both.evalBatch(&x, &y, &z, 1, &batch);
    EXPECT_EQ(batch, both.eval(x, y, z));
    // gradient through the chain rule: compare with central differences
    const Dual g = both.evalGradient(x, y, z);
    const double h = 1e-6;
    const double fx = (both.eval(x + h, y, z) - both.eval(x - h, y, z)) / (2 * h);
    if (std::abs(cap.eval(lx, ly, z) - alone.eval(x, y, z)) > 1e-3) {  // away from the crease
      EXPECT_NEAR(g.d[0], fx, 1e-5);
    }
    const Interval iv = both.evalInterval({x - 0.01, x + 0.01}, {y, y + 0.01}, {z, z});
    EXPECT_TRUE(iv.contains(both.eval(x, y, z)));
  }
  MeshingOptions o;
  o.bbox = {{-1.2, -1.2, -1}, {1.4, 1.2, 1}};
  o.resolution = 0.03;
  const CheckReport r = checkMesh(polygonize(both, o));
  EXPECT_TRUE(r.printable()) << reportToText(r, "capsule and ball");
}

TEST(FieldSeam, StructuralBoundsAndModelFilesKnowExternalNodes) {
  const NodePtr ext = makeFieldNode(capsule(), "capsule");
  Model m;
  m.root = ext;
  EXPECT_THROW(modelToJson(m), ModelError);
  EXPECT_THROW(makeFieldNode(nullptr, "nothing"), ModelError);
}

TEST(RegionSpecialisation, DropsTheFarSideOfAUnion) {
  // Two balls far apart: inside a box round the first, the second's branch is dead.
  const NodePtr a = makeNode("sphere", {{"center", vec3Value({-2, 0, 0})}}, {});
  const NodePtr b = makeNode("sphere", {{"center", vec3Value({2, 0, 0})}}, {});
  const NodePtr c = makeNode("box", {{"corner", vec3Value({-0.3, -3, -0.3})}, {"size", vec3Value({0.6, 6, 0.6})}}, {});
  const Program p = compile(makeNode("difference", {}, {makeNode("union", {}, {a, b}), c}));
  bool changed = false;
  const Box3 near{{-3.2, -1.2, -1.2}, {-0.8, 1.2, 1.2}};
  const Program s = p.specialised(near, &changed);
  EXPECT_TRUE(changed);
  // no longer than the program of the near ball minus the bar, compiled alone
  const Program nearOnly = compile(makeNode("difference", {}, {a, c}));
  EXPECT_LE(s.instructionCount(), nearOnly.instructionCount()) << s.disassemble();
  EXPECT_LT(s.instructionCount(), p.instructionCount());
  for (int i = 0; i < 500; ++i) {
    const double x = -3.2 + 2.4 * (i % 10) / 9.0, y = -1.2 + 2.4 * ((i / 10) % 10) / 9.0,
                 z = -1.2 + 2.4 * (i / 100) / 4.0;
    EXPECT_EQ(s.eval(x, y, z), p.eval(x, y, z));
  }
  // Where every branch can matter nothing is dropped.
  const Program whole = p.specialised({{-10, -10, -10}, {10, 10, 10}}, &changed);
  EXPECT_EQ(whole.instructionCount(), p.instructionCount());
  EXPECT_FALSE(changed);
}

}  // namespace
}  // namespace frep
