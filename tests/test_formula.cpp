// The formula node: what a formula means (precedence, functions, parameters, inputs), the
// column of every kind of error, and the interval rules of the instructions formulas added.
#include <gtest/gtest.h>

#include "interval_testing.h"

#include <cmath>
#include <random>

#include "base/errors.h"
#include "frep/formula.h"
#include "frep/interval.h"
#include "frep/tree.h"

namespace frep {
namespace {

NodePtr formula(const std::string& f, const std::string& params = "",
                std::vector<NodePtr> inputs = {}) {
  return makeNode("formula", {{"formula", textValue(f)}, {"parameters", textValue(params)}},
                  std::move(inputs), "part");
}

double at(const std::string& f, double x, double y = 0, double z = 0,
          const std::string& params = "") {
  return compile(formula(f, params)).eval(x, y, z);
}

// The ModelError message of a bad formula, or "" when it is accepted.
std::string problem(const std::string& f, const std::string& params = "", int inputs = 0) {
  std::vector<NodePtr> in;
  for (int i = 0; i < inputs; ++i) in.push_back(makeNode("sphere", {}, {}));
  try {
    formula(f, params, in);
  } catch (const ModelError& e) {
    return e.what();
  }
  return "";
}

TEST(Formula, SphereFormulaIsTheSphereNode) {
  const Program f = compile(formula("r - sqrt((x - a)^2 + y^2 + z^2)", "r = 0.7, a = 0.2"));
  const Program s = compile(
      makeNode("sphere", {{"radius", realValue(0.7)}, {"center", vec3Value({0.2, 0, 0})}}, {}));
  std::mt19937 g(5);
  std::uniform_real_distribution<double> u(-2, 2);
  for (int i = 0; i < 2000; ++i) {
    const double x = u(g), y = u(g), z = u(g);
    EXPECT_NEAR(f.eval(x, y, z), s.eval(x, y, z), 1e-12);
  }
}

TEST(Formula, PrecedenceAndAssociativity) {
  EXPECT_DOUBLE_EQ(at("2^3^2", 0), 512.0);  // right-associative
  EXPECT_DOUBLE_EQ(at("-x^2", 3), -9.0);    // ^ binds tighter than unary minus
  EXPECT_DOUBLE_EQ(at("2*3+4*5", 0), 26.0);
  EXPECT_DOUBLE_EQ(at("10-4-3", 0), 3.0);  // left-associative
  EXPECT_DOUBLE_EQ(at("12/3/2", 0), 2.0);
  EXPECT_DOUBLE_EQ(at("2**-1", 0), 0.5);
  EXPECT_DOUBLE_EQ(at("(1+2)*(3+4)", 0), 21.0);
  EXPECT_DOUBLE_EQ(at("x*y - z", 2, 3, 1), 5.0);
  EXPECT_DOUBLE_EQ(at("1.5e2 + .5", 0), 150.5);
  EXPECT_DOUBLE_EQ(at("pi", 0), 3.14159265358979323846);
}

TEST(Formula, FunctionsMatchTheStandardLibrary) {
  std::mt19937 g(9);
  std::uniform_real_distribution<double> u(-0.99, 0.99);
  for (int i = 0; i < 200; ++i) {
    const double x = u(g), y = u(g);
    EXPECT_NEAR(at("tan(x)", x), std::tan(x), 1e-14);
    EXPECT_NEAR(at("atan(x)", x), std::atan(x), 1e-15);
    EXPECT_NEAR(at("log(y + 1)", 0, y), std::log(y + 1), 1e-15);
    EXPECT_NEAR(at("pow(x, 3)", x), std::pow(x, 3), 1e-15);
    EXPECT_NEAR(at("pow(x + 1, 2.5)", x), std::pow(x + 1, 2.5), 1e-14);
    EXPECT_NEAR(at("pow(x + 1, y)", x, y), std::pow(x + 1, y), 1e-13);  // exp(y log(x + 1))
    EXPECT_NEAR(at("asin(x)", x), std::asin(x), 1e-14);
    EXPECT_NEAR(at("acos(x)", x), std::acos(x), 1e-14);
    EXPECT_NEAR(at("sinh(x) + cosh(y)", x, y), std::sinh(x) + std::cosh(y), 1e-14);
    EXPECT_NEAR(at("tanh(3*x)", x), std::tanh(3 * x), 1e-15);
    EXPECT_NEAR(at("mod(x, 0.3)", x), x - 0.3 * std::floor(x / 0.3), 1e-15);
    EXPECT_NEAR(at("ceil(5*x)", x), std::ceil(5 * x), 0);
    EXPECT_NEAR(at("hypot(x, y, 2)", x, y), std::sqrt(x * x + y * y + 4), 1e-15);
    EXPECT_NEAR(at("clamp(x, -0.5, 0.5)", x), std::min(std::max(x, -0.5), 0.5), 0);
    EXPECT_NEAR(at("min(x, y, 0.2)", x, y), std::min({x, y, 0.2}), 0);
  }
  // outside the real domain: NaN, which the mesher counts as outside
  EXPECT_TRUE(std::isnan(at("log(x)", -1)));
  EXPECT_TRUE(std::isnan(at("pow(x, 0.5)", -1)));
  EXPECT_DOUBLE_EQ(at("pow(x, 3)", -2), -8.0);  // an integer power of a negative base is real
}

TEST(Formula, ParametersMayUseEarlierOnes) {
  const auto p = parseFormulaParameters("k = 2*pi; half = k/2\n n = 3,");
  ASSERT_EQ(p.size(), 3u);
  EXPECT_EQ(p[0].name, "k");
  EXPECT_DOUBLE_EQ(p[0].value, 2 * 3.14159265358979323846);
  EXPECT_DOUBLE_EQ(p[1].value, 3.14159265358979323846);
  EXPECT_DOUBLE_EQ(p[2].value, 3.0);
  EXPECT_DOUBLE_EQ(at("half - n", 0, 0, 0, "k = 2*pi; half = k/2\n n = 3,"),
                   3.14159265358979323846 - 3.0);
}

TEST(Formula, InputsAreFieldsF1F2) {
  const NodePtr a = makeNode("sphere", {{"center", vec3Value({-0.5, 0, 0})}}, {});
  const NodePtr b = makeNode("box", {}, {});
  const Program f = compile(formula("max(f1, f2) - 0.1*f1*f2", "", {a, b}));
  const Program pa = compile(a), pb = compile(b);
  std::mt19937 g(2);
  std::uniform_real_distribution<double> u(-2, 2);
  for (int i = 0; i < 500; ++i) {
    const double x = u(g), y = u(g), z = u(g);
    const double fa = pa.eval(x, y, z), fb = pb.eval(x, y, z);
    EXPECT_NEAR(f.eval(x, y, z), std::max(fa, fb) - 0.1 * fa * fb, 1e-12);
  }
}

TEST(Formula, ErrorsNameTheParameterAndColumn) {
  struct Case {
    std::string formula, params;
    int inputs;
    std::string expected;
  };
  const Case cases[] = {
      {"r - sqrt(x^2 + y^2", "r = 1", 0, "parameter 'formula' column 19: missing ')' or ','"},
      {"r - sqrt(x^2 + y^2))", "r = 1", 0, "column 20: unmatched ')'"},
      {"1 - sinn(x)", "", 0, "column 5: unknown function 'sinn'; functions: abs,"},
      {"1 - q*x", "", 0, "column 5: unknown name 'q'; names: x, y, z, pi"},
      {"1 - 2x", "", 0, "column 6: a number is followed by a name; write '*'"},
      {"1 - x # y", "", 0, "column 7: unexpected character '#'"},
      {"atan2(x)", "", 0, "column 1: 'atan2' takes 2 arguments, got 1"},
      {"min(x)", "", 0, "column 1: 'min' takes 2 or more arguments, got 1"},
      {"1 - x y", "", 0, "column 7: unexpected 'y' after a complete expression"},
      {"1 - ", "", 0, "column 5: the formula ends where a value is expected"},
      {"", "", 0, "column 1: the formula is empty"},
      {"1 - sin", "", 0, "column 5: 'sin' is a function; call it as sin(...)"},
      {"f1 + f3", "", 2, "column 6: unknown name 'f3'"},
      {"1", "r = 1, r = 2", 0, "parameter 'parameters' column 8: 'r' is defined twice"},
      {"1", "r = 1, sin = 2", 0, "parameter 'parameters' column 8: 'sin' is reserved"},
      {"1", "r = x", 0, "column 4: the value of 'r' must be a constant"},
      {"1", "r = 1, k = 2 *", 0, "parameter 'parameters' column 15: the formula ends"},
      {"1", "r 1", 0, "parameter 'parameters' column 1: expected 'name = value'"},
      {"1", "f2 = 1", 0, "'f2' is reserved for the inputs"},
      {"1", "r = 1/0", 0, "the value of 'r' is not a finite number"},
  };
  for (const Case& c : cases) {
    const std::string message = problem(c.formula, c.params, c.inputs);
    EXPECT_NE(message.find(c.expected), std::string::npos)
        << "formula \"" << c.formula << "\" parameters \"" << c.params << "\"\n got: " << message;
    // every message names the node and, for a column, shows a caret under it
    EXPECT_NE(message.find("part (formula)"), std::string::npos) << message;
  }
  EXPECT_EQ(problem("1 - x", "a = 1"), "");
  // the caret sits under the column
  const std::string m = problem("1 - q*x");
  EXPECT_NE(m.find("\n  1 - q*x\n      ^"), std::string::npos) << m;
}

TEST(Formula, NewInstructionIntervals) {
  constexpr double kHalfPi = 1.5707963267948966;
  // tan: monotone between poles; a pole inside gives an unbounded interval
  EXPECT_NEAR(tan(Interval(-1, 1)).hi, std::tan(1.0), 1e-15);
  EXPECT_TRUE(std::isinf(tan(Interval(1.5, 1.6)).hi));
  EXPECT_TRUE(std::isinf(tan(Interval(kHalfPi + 3.1, kHalfPi + 3.2)).lo));
  EXPECT_FALSE(std::isinf(tan(Interval(2.0, 4.0)).hi));  // between the poles at pi/2, 3pi/2
  // log: the positive part; log 0 = -inf
  EXPECT_TRUE(std::isinf(log(Interval(-1, 2)).lo));
  EXPECT_TRUE(testing::tightAbove(log(Interval(1, 2)).hi, std::log(2.0)));
  EXPECT_TRUE(log(Interval(-2, -1)).nan);  // no real value: NaN everywhere
  EXPECT_TRUE(log(Interval(-1, 2)).nan);   // NaN on the negative part
  EXPECT_FALSE(log(Interval(0.5, 2)).nan);
  // powConst: even, odd, negative and fractional exponents (outward rounded)
  EXPECT_EQ(powConst(Interval(-2, 1), 2).lo, 0.0);
  EXPECT_TRUE(testing::tightAbove(powConst(Interval(-2, 1), 2).hi, 4.0));
  EXPECT_TRUE(testing::tightBelow(powConst(Interval(-2, 1), 3).lo, -8.0));
  EXPECT_TRUE(testing::tightBelow(powConst(Interval(1, 2), -1).lo, 0.5));
  EXPECT_TRUE(std::isinf(powConst(Interval(-1, 2), -2).hi));
  EXPECT_EQ(powConst(Interval(-1, 4), 0.5).lo, 0.0);
  EXPECT_TRUE(powConst(Interval(-1, 4), 0.5).nan);
  EXPECT_TRUE(testing::tightAbove(powConst(Interval(-1, 4), 0.5).hi, 2.0));
  EXPECT_TRUE(testing::tightBelow(powConst(Interval(1, 4), -0.5).lo, 0.5));
  EXPECT_TRUE(testing::tightAbove(atan(Interval(-1, 1)).hi, std::atan(1.0)));
}

}  // namespace
}  // namespace frep
