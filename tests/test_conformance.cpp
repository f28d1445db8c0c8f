// Every node type through all four evaluator modes, checked against each other:
// point vs batch bit-exact, gradient vs central finite differences, and the interval
// enclosing sampled values on random boxes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "frep/errors.h"
#include "frep/registry.h"
#include "random_trees.h"

namespace frep {
namespace {

using testing::RandomTrees;

ParamValue randomValue(const ParamTemplate& p, RandomTrees& r) {
  auto number = [&]() {
    double lo = std::isfinite(p.min) ? p.min : (p.unit == "angle" ? -180.0 : -1.5);
    double hi = std::isfinite(p.max) ? p.max : (p.unit == "angle" ? 180.0 : 1.5);
    if (p.min == 0.0 && !std::isfinite(p.max)) lo = 0.05;
    if (p.minExclusive) lo += 1e-3 * (hi - lo);
    double v = r.uniform(lo, hi);
    if (p.type == ParamType::Integer) v = std::round(v);
    return v;
  };
  ParamValue v;
  switch (p.type) {
    case ParamType::Choice:
      v.text = p.choices[r.integer(0, int(p.choices.size()) - 1)];
      break;
    case ParamType::Text:
      v = p.defaultValue;
      break;  // formulas: see FormulaConformance
    case ParamType::Boolean:
      v.numbers = {double(r.integer(0, 1))};
      break;
    case ParamType::Real:
    case ParamType::Integer:
      v.numbers = {number()};
      break;
    case ParamType::Points:
      for (std::size_t i = 0; i < p.minPoints + (p.minPoints % 2 ? 2 : 3); ++i)  // odd: arcs
        for (int c = 0; c < 3; ++c) v.numbers.push_back(number());
      break;
    case ParamType::Vector3:
      v.numbers = {number(), number(), number()};
      if (p.nonZeroVector && std::abs(v.numbers[0]) + std::abs(v.numbers[1]) < 1e-3)
        v.numbers[2] = 1;
      break;
    case ParamType::Matrix3x4: {
      // rotation about a random axis, non-uniform scale, translation: always invertible
      const Vec3 a = r.direction();
      const double th = r.uniform(-3, 3), c = std::cos(th), s = std::sin(th), C = 1 - c;
      const double n = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
      const double x = a[0] / n, y = a[1] / n, z = a[2] / n;
      const double R[9] = {c + x * x * C,     x * y * C - z * s, x * z * C + y * s,
                           y * x * C + z * s, c + y * y * C,     y * z * C - x * s,
                           z * x * C - y * s, z * y * C + x * s, c + z * z * C};
      for (int row = 0; row < 3; ++row) {
        const double sc = r.uniform(0.5, 1.5);
        for (int col = 0; col < 3; ++col) v.numbers.push_back(R[row * 3 + col] * sc);
        v.numbers.push_back(r.uniform(-0.5, 0.5));
      }
      break;
    }
  }
  return v;
}

// A random valid instance. Whole-node checks may refuse a draw (an even point count for
// arcs, an odd one for pairs, a half-space as the instancer's copy): such draws are redrawn,
// with bounded inputs on the second half of the attempts.
NodePtr randomInstance(const NodeType& type, RandomTrees& r) {
  for (int attempt = 0;; ++attempt) {
    std::map<std::string, ParamValue> params;
    for (const auto& p : type.params) params[p.name] = randomValue(p, r);
    std::vector<NodePtr> inputs;
    // Variadic types get one or two more than their least; optional inputs are tried both ways.
    const int most = type.maxInputs == kVariadic ? type.minInputs + 1 : type.maxInputs;
    const int n = r.integer(type.minInputs, most);
    for (int i = 0; i < n; ++i) inputs.push_back(attempt < 10 ? r.primitive() : r.boundedPrimitive());
    try {
      return makeNode(type.id, params, inputs, "conformance");
    } catch (const ModelError&) {
      if (attempt == 20) throw;
    }
  }
}

bool sameValue(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0 || (std::isnan(a) && std::isnan(b));
}

class Conformance : public ::testing::TestWithParam<std::string> {};

struct ModeChecks {
  int gradientChecks = 0, gradientPoints = 0, intervalChecks = 0;
};

// Point vs batch bit-exact, gradient vs finite differences, interval enclosing samples, for
// one compiled tree; `what` names it in failures.
void checkModesAgree(const Program& prog, const std::string& what, RandomTrees& r,
                     ModeChecks& count) {
  // point vs batch: bit-identical
  const std::size_t n = 300;  // more than one internal batch chunk
  std::vector<double> x(n), y(n), z(n), out(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = r.uniform(-2, 2);
    y[i] = r.uniform(-2, 2);
    z[i] = r.uniform(-2, 2);
  }
  prog.evalBatch(x.data(), y.data(), z.data(), n, out.data());
  for (std::size_t i = 0; i < n; ++i)
    ASSERT_TRUE(sameValue(out[i], prog.eval(x[i], y[i], z[i])))
        << what << " at " << x[i] << "," << y[i] << "," << z[i];

  // gradient: value equals the point value; derivatives match finite differences
  for (std::size_t i = 0; i < 40; ++i) {
    const Dual g = prog.evalGradient(x[i], y[i], z[i]);
    const double v = prog.eval(x[i], y[i], z[i]);
    ASSERT_NEAR(g.v, v, 1e-12 * (1 + std::abs(v))) << what;
    ++count.gradientPoints;
    bool smooth = true;
    double fd[3], fd2[3];
    for (int a = 0; a < 3; ++a) {
      for (int k = 0; k < 2; ++k) {
        const double h = k == 0 ? 1e-6 : 1e-5;
        double p[3] = {x[i], y[i], z[i]}, q[3] = {x[i], y[i], z[i]};
        p[a] += h;
        q[a] -= h;
        const double d = (prog.eval(p[0], p[1], p[2]) - prog.eval(q[0], q[1], q[2])) / (2 * h);
        (k == 0 ? fd : fd2)[a] = d;
      }
      // a kink (min/max, abs) within reach: the two step sizes disagree
      if (std::abs(fd[a] - fd2[a]) > 1e-4 * (1 + std::abs(fd[a]))) smooth = false;
    }
    if (!smooth) continue;
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(g.d[a], fd[a], 1e-4 * (1 + std::abs(fd[a])))
          << what << " d/d"
          << "xyz"[a] << " at " << x[i] << "," << y[i] << "," << z[i];
    ++count.gradientChecks;
  }

  // interval: encloses sampled values on random boxes
  for (int b = 0; b < 20; ++b) {
    Interval box[3];
    for (auto& iv : box) {
      const double c = r.uniform(-1.5, 1.5), h = r.uniform(0, 0.6);
      iv = {c - h, c + h};
    }
    const Interval range = prog.evalInterval(box[0], box[1], box[2]);
    for (int s = 0; s < 30; ++s) {
      const double px = s < 8 ? ((s & 1) ? box[0].hi : box[0].lo) : r.uniform(box[0].lo, box[0].hi);
      const double py = s < 8 ? ((s & 2) ? box[1].hi : box[1].lo) : r.uniform(box[1].lo, box[1].hi);
      const double pz = s < 8 ? ((s & 4) ? box[2].hi : box[2].lo) : r.uniform(box[2].lo, box[2].hi);
      const double v = prog.eval(px, py, pz);
      const double tol = 1e-9 * (1 + std::abs(v));
      ASSERT_TRUE(v >= range.lo - tol && v <= range.hi + tol)
          << what << ": " << v << " outside [" << range.lo << ", " << range.hi << "]";
      ++count.intervalChecks;
    }
  }
}

TEST_P(Conformance, AllFourModesAgree) {
  const NodeType& type = registry().get(GetParam());
  RandomTrees r(12345 + static_cast<unsigned>(std::hash<std::string>()(type.id) % 1000));
  ModeChecks count;
  for (int instance = 0; instance < 25; ++instance) {
    checkModesAgree(compile(randomInstance(type, r)), type.id, r, count);
    if (HasFatalFailure()) return;
  }
  // The finite-difference comparison must have run on most points, not been skipped.
  EXPECT_GT(count.gradientChecks, count.gradientPoints / 2) << type.id;
  EXPECT_GT(count.intervalChecks, 0);
}

// Every formula function and operator through the four modes (the formula node's own
// conformance run above uses its default formula). Domains are kept where the functions are
// finite on the sampled cube [-2, 2]^3.
TEST(FormulaConformance, EveryFunctionInAllFourModes) {
  const char* formulas[] = {
      "sin(x) * cos(y) + tan(0.5 * z)",
      "atan(3 * x) - atan2(y, z + 3)",
      "log(1 + x^2 + y^2) - exp(z / 2)",
      "pow(1.5 + sin(x), 2.5) - pow(y, 3) + pow(2.5 + z, -2) + sqrt(4.5 + x * y)",
      "pow(2 + x, 1 + 0.1 * y)",
      "(x - y) ** 4 - 2 ^ -z",
      "abs(x) - sqr(y) + floor(z) * 0.1 + ceil(x) * 0.1 + mod(y, 0.7)",
      "min(x, y, z) + max(x, 0.5 * y) - clamp(z, -0.5, 0.5)",
      "hypot(x, y) - hypot(x, y, z) + 0.3",
      "asin(x / 3) + acos(y / 3) - sinh(z) + cosh(x / 2) - tanh(3 * y)",
      "-x^2 - +y + -(-z)",
      "1 - f1 * f2 + max(f1, f2)",
  };
  RandomTrees r(777);
  ModeChecks count;
  for (const char* f : formulas) {
    std::vector<NodePtr> inputs;
    if (std::string(f).find("f1") != std::string::npos) inputs = {r.primitive(), r.primitive()};
    const NodePtr node = makeNode(
        "formula", {{"formula", textValue(f)}, {"parameters", textValue("")}}, inputs, "formula");
    checkModesAgree(compile(node), f, r, count);
    if (HasFatalFailure()) return;
  }
  EXPECT_GT(count.gradientChecks, count.gradientPoints / 2);
}

std::vector<std::string> allTypes() {
  std::vector<std::string> ids;
  for (const NodeType* t : registry().all()) ids.push_back(t->id);
  return ids;
}

INSTANTIATE_TEST_SUITE_P(EveryNodeType, Conformance, ::testing::ValuesIn(allTypes()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           return info.param;
                         });

// Interval arithmetic corner cases the pruning relies on.
TEST(IntervalMath, SqrSinCosDivision) {
  EXPECT_EQ(sqr(Interval(-1, 2)).lo, 0.0);
  EXPECT_EQ(sqr(Interval(-1, 2)).hi, 4.0);
  const Interval s = sin(Interval(0.0, 3.2));
  EXPECT_EQ(s.hi, 1.0);
  EXPECT_LT(s.lo, 0.0);
  EXPECT_GT(s.lo, -0.1);
  const Interval c = cos(Interval(3.0, 3.3));
  EXPECT_EQ(c.lo, -1.0);
  const Interval d = Interval(1, 2) / Interval(-1, 1);
  EXPECT_TRUE(std::isinf(d.lo) && std::isinf(d.hi));
}

TEST(Compiler, SharedAndRepeatedSubtreesAreComputedOnce) {
  const NodePtr s = makeNode("sphere", {{"radius", realValue(0.7)}}, {});
  const NodePtr same = makeNode("sphere", {{"radius", realValue(0.7)}}, {});
  const Program one = compile(makeNode("translate", {{"offset", vec3Value({0.1, 0, 0})}}, {s}));
  // union of the same shared node with itself and with an equal copy: no extra sphere code
  const Program shared =
      compile(makeNode("union", {},
                       {makeNode("translate", {{"offset", vec3Value({0.1, 0, 0})}}, {s}),
                        makeNode("translate", {{"offset", vec3Value({0.1, 0, 0})}}, {same})}));
  EXPECT_LE(shared.instructionCount(), one.instructionCount() + 1);
  EXPECT_DOUBLE_EQ(shared.eval(0.3, 0.2, 0.1), one.eval(0.3, 0.2, 0.1));
}

TEST(Compiler, SphereValuesAreDistances) {
  const Program p =
      compile(makeNode("sphere", {{"center", vec3Value({1, 2, 3})}, {"radius", realValue(2)}}, {}));
  EXPECT_DOUBLE_EQ(p.eval(1, 2, 3), 2.0);
  EXPECT_DOUBLE_EQ(p.eval(4, 2, 3), -1.0);
  const Dual g = p.evalGradient(2, 2, 3);
  EXPECT_DOUBLE_EQ(g.d[0], -1.0);  // F grows inward
}

TEST(SetOperations, AlphaOneIsExactMinMax) {
  RandomTrees r(7);
  const NodePtr a = r.primitive(), b = r.primitive();
  const Program u = compile(makeNode("union", {}, {a, b}));
  const Program i = compile(makeNode("intersection", {}, {a, b}));
  const Program d = compile(makeNode("difference", {}, {a, b}));
  const Program pa = compile(a), pb = compile(b);
  for (int k = 0; k < 200; ++k) {
    const double x = r.uniform(-2, 2), y = r.uniform(-2, 2), z = r.uniform(-2, 2);
    const double fa = pa.eval(x, y, z), fb = pb.eval(x, y, z);
    EXPECT_EQ(u.eval(x, y, z), std::max(fa, fb));
    EXPECT_EQ(i.eval(x, y, z), std::min(fa, fb));
    EXPECT_EQ(d.eval(x, y, z), std::min(fa, -fb));
  }
}

TEST(SetOperations, BlendAddsPaskoDisplacement) {
  const NodePtr a = makeNode("sphere", {{"center", vec3Value({-0.5, 0, 0})}}, {});
  const NodePtr b = makeNode("sphere", {{"center", vec3Value({0.5, 0, 0})}}, {});
  const Program blend = compile(
      makeNode("blend_union",
               {{"a0", realValue(0.3)}, {"a1", realValue(0.5)}, {"a2", realValue(2)}}, {a, b}));
  const Program pa = compile(a), pb = compile(b);
  const double x = 0.1, y = 1.2, z = 0.3;
  const double f1 = pa.eval(x, y, z), f2 = pb.eval(x, y, z);
  const double expected =
      std::max(f1, f2) + 0.3 / (1 + (f1 / 0.5) * (f1 / 0.5) + (f2 / 2) * (f2 / 2));
  EXPECT_NEAR(blend.eval(x, y, z), expected, 1e-15);
}

}  // namespace
}  // namespace frep
