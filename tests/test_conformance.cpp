// Every node type through all four evaluator modes, checked against each other:
// point vs batch bit-exact, gradient vs central finite differences, and the interval
// enclosing sampled values on random boxes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <limits>

#include "base/errors.h"
#include "frep/registry.h"
#include "interval_testing.h"
#include "lattice_samples.h"
#include "random_trees.h"
#include "volume_samples.h"

namespace frep {
namespace {

using testing::RandomTrees;

// wide: a third of the draws go to the ends of the allowed range (just inside an exclusive
// end, magnitudes up to 1e3 where the range is open), not only its usual middle.
ParamValue randomValue(const ParamTemplate& p, RandomTrees& r, bool wide = false) {
  auto number = [&]() {
    double lo = std::isfinite(p.min) ? p.min : (p.unit == "angle" ? -180.0 : -1.5);
    double hi = std::isfinite(p.max) ? p.max : (p.unit == "angle" ? 180.0 : 1.5);
    if (p.min == 0.0 && !std::isfinite(p.max)) lo = 0.05;
    if (p.minExclusive) lo += 1e-3 * (hi - lo);
    double v = r.uniform(lo, hi);
    if (wide && r.integer(0, 2) == 0) {
      const double far = 1e3;
      const double wlo = std::isfinite(p.min) ? p.min : -far;
      const double whi = std::isfinite(p.max) ? p.max : far;
      switch (r.integer(0, 3)) {
        case 0: v = p.minExclusive ? std::nextafter(wlo, whi) + 1e-9 * (whi - wlo) : wlo; break;
        case 1: v = p.maxExclusive ? whi - 1e-9 * (whi - wlo) : whi; break;
        case 2: v = std::max(wlo, std::min(whi, (r.integer(0, 1) ? 1 : -1) * 1e-3)); break;
        default: v = std::max(wlo, std::min(whi, std::exp(r.uniform(std::log(1e-3), std::log(far))))); break;
      }
      if (p.minExclusive && !(v > p.min)) v = std::nextafter(p.min, whi);
    }
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
// arcs, an odd one for pairs, an empty solid as the instancer's copy): such draws are redrawn,
// with bounded inputs on the second half of the attempts.
NodePtr randomInstance(const NodeType& type, RandomTrees& r, bool wide = false,
                       const std::function<NodePtr()>& input = nullptr) {
  registerVolumeSources();  // the loaders of the file-backed types and the Voronoi foam
  for (int attempt = 0;; ++attempt) {
    std::map<std::string, ParamValue> params;
    for (const auto& p : type.params) params[p.name] = randomValue(p, r, wide);
    // File-backed types read the sample files, with grids fine enough to hold the sample.
    for (const auto& p : type.params)
      if (p.filePath) params[p.name] = textValue(testing::sampleFileFor(type.id));
    // A lattice's points must match its divisions and must not fold: a random lattice,
    // twisted and shaken, mild to strong.
    if (type.id == "ffd") {
      const Vec3 lo{r.uniform(-1.5, -0.3), r.uniform(-1.5, -0.3), r.uniform(-1.5, -0.3)};
      const Box3 rest{lo, {lo[0] + r.uniform(1, 2.5), lo[1] + r.uniform(1, 2.5), lo[2] + r.uniform(1, 2.5)}};
      const auto lattice = testing::twistedLattice(r.integer(1, 3), r.integer(1, 3), r.integer(1, 4),
                                                   r.uniform(0, 1.5), r.uniform(0, 0.25),
                                                   unsigned(r.integer(0, 1000)), rest);
      for (auto& kv : testing::ffdParams(lattice)) params[kv.first] = kv.second;
    }
    // A foam's set-up grows with its period's seeds (test_voronoi_foam.cpp tries longer ones).
    if (type.id == "voronoi_foam") params["tile"] = realValue(4);
    // A lattice's blend is at most half its cell (and 0, sharp joints, a third of the time).
    if (type.id == "voronoi_foam" || type.id == "strut_lattice") {
      const std::vector<double>& cell = params["cell"].numbers;
      const double shortest = std::min({cell[0], cell[1], cell[2]});
      params["blend"] = realValue(r.integer(0, 2) ? r.uniform(0.0, 0.5) * shortest : 0.0);
    }
    if (type.findParam("voxel")) params["voxel"] = realValue(r.integer(0, 1) ? r.uniform(0.05, 0.3) : 0.0);
    std::vector<NodePtr> inputs;
    // Variadic types get one or two more than their least; optional inputs are tried both ways.
    const int most = type.maxInputs == kVariadic ? type.minInputs + 1 : type.maxInputs;
    const int n = r.integer(type.minInputs, most);
    for (int i = 0; i < n; ++i)
      inputs.push_back(input && attempt < 10 ? input()
                       : attempt < 10        ? r.primitive()
                                             : r.boundedPrimitive());
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
  int gradientChecks = 0, gradientPoints = 0, intervalChecks = 0, specialised = 0;
};

// The interval over random boxes encloses every sampled value exactly (no tolerance: intervals
// are outward rounded), NaN included; the program specialised to the box gives bit-identical
// point, batch and gradient values there, and the identical interval on a sub-box.
void checkIntervalsAndSpecialisation(const Program& prog, const std::string& what,
                                     RandomTrees& r, ModeChecks& count, double spread = 1.5) {
  for (int b = 0; b < 20; ++b) {
    Interval box[3];
    for (auto& iv : box) {
      const double c = r.uniform(-spread, spread), h = r.uniform(0, 0.6) * (r.integer(0, 3) ? 1 : 0.01);
      iv = {c - h, c + h};
    }
    const Interval range = prog.evalInterval(box[0], box[1], box[2]);
    const Box3 b3{{box[0].lo, box[1].lo, box[2].lo}, {box[0].hi, box[1].hi, box[2].hi}};
    bool changed = false;
    const Program spec = prog.specialised(b3, &changed);
    if (changed) ++count.specialised;
    std::vector<double> px(30), py(30), pz(30), out(30);
    for (int s = 0; s < 30; ++s) {
      auto pick = [&](const Interval& iv, int bit) {
        if (s < 8) return (s & bit) ? iv.hi : iv.lo;
        if (s < 10 && iv.contains(0.0)) return 0.0;  // exactly 0 where the box holds it
        if (s < 11 && iv.contains(-0.0)) return -0.0;
        return r.uniform(iv.lo, iv.hi);
      };
      px[s] = pick(box[0], 1);
      py[s] = pick(box[1], 2);
      pz[s] = pick(box[2], 4);
      const double v = prog.eval(px[s], py[s], pz[s]);
      ASSERT_TRUE(range.contains(v))
          << what << ": " << v << " outside [" << range.lo << ", " << range.hi
          << "] nan=" << range.nan << " at " << px[s] << "," << py[s] << "," << pz[s];
      ++count.intervalChecks;
      ASSERT_TRUE(sameValue(spec.eval(px[s], py[s], pz[s]), v))
          << what << ": specialised to the box, a different value at " << px[s] << ","
          << py[s] << "," << pz[s] << "\n" << spec.disassemble();
      const Dual g = prog.evalGradient(px[s], py[s], pz[s]), h = spec.evalGradient(px[s], py[s], pz[s]);
      ASSERT_TRUE(sameValue(g.v, h.v) && sameValue(g.d[0], h.d[0]) && sameValue(g.d[1], h.d[1]) &&
                  sameValue(g.d[2], h.d[2]))
          << what << ": specialised gradient differs";
    }
    spec.evalBatch(px.data(), py.data(), pz.data(), 30, out.data());
    for (int s = 0; s < 30; ++s)
      ASSERT_TRUE(sameValue(out[s], prog.eval(px[s], py[s], pz[s]))) << what << ": specialised batch";
    Interval sub[3];
    for (int a = 0; a < 3; ++a) {
      const double u = r.uniform(box[a].lo, box[a].hi), v = r.uniform(box[a].lo, box[a].hi);
      sub[a] = {std::min(u, v), std::max(u, v)};
    }
    const Interval whole = prog.evalInterval(sub[0], sub[1], sub[2]);
    const Interval part = spec.evalInterval(sub[0], sub[1], sub[2]);
    ASSERT_TRUE(sameValue(whole.lo, part.lo) && sameValue(whole.hi, part.hi) && whole.nan == part.nan)
        << what << ": specialised interval [" << part.lo << ", " << part.hi << "] vs ["
        << whole.lo << ", " << whole.hi << "]";
  }
}

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
  // gradient batch vs gradient at each point: bit-identical
  std::vector<Dual> dx(n), dy(n), dz(n), grads(n);
  for (std::size_t i = 0; i < n; ++i) {
    dx[i] = Dual(x[i], 1, 0, 0);
    dy[i] = Dual(y[i], 0, 1, 0);
    dz[i] = Dual(z[i], 0, 0, 1);
  }
  prog.evalGradientBatch(dx.data(), dy.data(), dz.data(), n, grads.data());
  for (std::size_t i = 0; i < n; ++i) {
    const Dual g = prog.evalGradient(x[i], y[i], z[i]);
    ASSERT_TRUE(sameValue(grads[i].v, g.v) && sameValue(grads[i].d[0], g.d[0]) &&
                sameValue(grads[i].d[1], g.d[1]) && sameValue(grads[i].d[2], g.d[2]))
        << what << ": gradient batch differs at " << x[i] << "," << y[i] << "," << z[i];
  }

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
        const double fp = prog.eval(p[0], p[1], p[2]), fq = prog.eval(q[0], q[1], q[2]);
        const double d = (fp - fq) / (2 * h);
        (k == 0 ? fd : fd2)[a] = d;
        // Rounding noise of the difference quotient: where the field's magnitude is huge
        // (steep superquadrics far out) it swamps the derivative, and nothing is learnt.
        const double noise = 1e3 * std::numeric_limits<double>::epsilon() *
                             std::max(std::abs(fp), std::abs(fq)) / h;
        if (!(noise < 1e-4 * (1 + std::abs(d)))) smooth = false;
      }
      // a kink (min/max, abs) or a steep curve within reach: the two step sizes disagree
      if (std::abs(fd[a] - fd2[a]) > 1e-6 * (1 + std::abs(fd[a]))) smooth = false;
    }
    if (!smooth) continue;
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(g.d[a], fd[a], 1e-4 * (1 + std::abs(fd[a])))
          << what << " d/d"
          << "xyz"[a] << " at " << x[i] << "," << y[i] << "," << z[i];
    ++count.gradientChecks;
  }

  checkIntervalsAndSpecialisation(prog, what, r, count);
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

// Strut lattices and foams straightened through random twisted lattices (the ffd's struts =
// straight): alone or cut to a primitive, with node spheres, a blend or a graded radius.
TEST(Conformance, StraightStrutsThroughRandomLattices) {
  registerVolumeSources();
  RandomTrees r(97531);
  ModeChecks count;
  const char* types[] = {"octet", "kelvin", "diamond", "bcc", "simple_cubic", "fcc"};
  for (int instance = 0; instance < 12; ++instance) {
    const Vec3 cell{r.uniform(0.3, 0.5), r.uniform(0.3, 0.5), r.uniform(0.3, 0.5)};
    std::map<std::string, ParamValue> p{{"cell", vec3Value(cell)},
                                        {"radius", realValue(r.uniform(0.02, 0.08))},
                                        {"node_radius", realValue(r.integer(0, 2) ? 0.0 : 0.09)},
                                        {"blend", realValue(r.integer(0, 2) ? 0.0 : 0.05)}};
    std::vector<NodePtr> grading;
    if (instance % 4 == 1) grading.push_back(r.primitive());
    NodePtr network;
    if (instance % 6 == 5) {
      p.erase("node_radius");
      p["tile"] = realValue(4);
      network = makeNode("voronoi_foam", p, grading);
    } else {
      p["cell_type"] = textValue(types[instance % 6]);
      network = makeNode("strut_lattice", p, grading);
    }
    const NodePtr input =
        r.integer(0, 1) ? network : makeNode("intersection", {}, {network, r.primitive()});
    const Vec3 lo{r.uniform(-1.5, -0.3), r.uniform(-1.5, -0.3), r.uniform(-1.5, -0.3)};
    const Box3 rest{
        lo, {lo[0] + r.uniform(1, 2.5), lo[1] + r.uniform(1, 2.5), lo[2] + r.uniform(1, 2.5)}};
    const auto lattice = testing::twistedLattice(r.integer(1, 3), r.integer(1, 3), r.integer(1, 4),
                                                 r.uniform(0, 1.5), r.uniform(0, 0.25),
                                                 unsigned(r.integer(0, 1000)), rest);
    auto params = testing::ffdParams(lattice);
    params["struts"] = textValue("straight");
    const std::string what = "straight struts " + std::to_string(instance);
    checkModesAgree(compile(makeNode("ffd", params, {input})), what, r, count);
    if (HasFatalFailure()) return;
  }
  EXPECT_GT(count.gradientChecks, count.gradientPoints / 2);
}

// Straight struts of cells round a cylinder or a sphere (the chords of each layer, filed per
// layer as points ask for them) through the four modes, round random slanted axes.
TEST(Conformance, StraightConformalStrutsRoundRandomAxes) {
  RandomTrees r(86420);
  ModeChecks count;
  const char* types[] = {"octet", "kelvin", "diamond", "bcc", "simple_cubic", "fcc"};
  for (int instance = 0; instance < 12; ++instance) {
    const bool sphere = instance % 2 == 1;
    std::map<std::string, ParamValue> p{
        {"cell_type", textValue(types[instance % 6])},
        {"cell", vec3Value({r.uniform(0.3, 0.6), r.uniform(0.3, 0.6), r.uniform(0.3, 0.6)})},
        {"radius", realValue(r.uniform(0.02, 0.08))},
        {"node_radius", realValue(r.integer(0, 2) ? 0.0 : 0.09)},
        {"blend", realValue(r.integer(0, 2) ? 0.0 : 0.05)},
        {"origin", vec3Value({r.uniform(-1, 1), r.uniform(-1, 1), r.uniform(-1, 1)})},
        {"axis", vec3Value({r.uniform(-1, 1), r.uniform(-1, 1), r.uniform(0.2, 1)})},
        {"conform", textValue(sphere ? "sphere" : "cylinder")},
        {"around", realValue(r.integer(6, 24))},
        {"struts", textValue("straight")}};
    std::vector<NodePtr> grading;
    if (instance % 4 == 1) grading.push_back(r.primitive());
    const NodePtr network = makeNode("strut_lattice", p, grading);
    const NodePtr input =
        r.integer(0, 1) ? network : makeNode("intersection", {}, {network, r.primitive()});
    checkModesAgree(
        compile(input),
        std::string("straight ") + (sphere ? "sphere " : "cylinder ") + std::to_string(instance), r,
        count);
    if (HasFatalFailure()) return;
  }
  EXPECT_GT(count.gradientChecks, count.gradientPoints / 2);
}

// Every formula function and operator through the four modes (the formula node's own
// conformance run above uses its default formula). Domains are kept where the functions are
// finite on the sampled cube [-2, 2]^3.
TEST(FormulaConformance, EveryFunctionInAllFourModes) {
  const char* formulas[] = {
      "sin(x) * cos(y) + tan(0.5 * z)",
      // sin and cos of one argument (one pass in the batch modes), nested (in place), alone
      "sin(x * y) * cos(x * y) + cos(cos(z)) - sin(sin(y + z))",
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

// Every node type with parameters drawn across their whole allowed range (ends, tiny and huge
// magnitudes), alone and as random trees that mix every type: intervals enclose and
// specialisation keeps every value. No finite differences here: extreme parameters make
// fields too steep for them.
TEST(IntervalSoundness, EveryTypeAcrossItsParameterRange) {
  RandomTrees r(2468);
  ModeChecks count;
  for (const NodeType* t : registry().all()) {
    for (int instance = 0; instance < 12; ++instance) {
      checkIntervalsAndSpecialisation(compile(randomInstance(*t, r, true)), t->id, r, count);
      if (HasFatalFailure()) return;
    }
  }
  EXPECT_GT(count.intervalChecks, 1000);
}

TEST(IntervalSoundness, RandomTreesMixingEveryType) {
  RandomTrees r(1357);
  const auto types = registry().all();
  ModeChecks count;
  std::function<NodePtr(int)> tree = [&](int depth) -> NodePtr {
    if (depth == 0) return r.primitive();
    for (;;) {
      const NodeType& t = *types[static_cast<std::size_t>(r.integer(0, int(types.size()) - 1))];
      if (depth > 0 && t.maxInputs == 0 && r.integer(0, 2)) continue;  // prefer inner nodes
      try {
        return randomInstance(t, r, true, [&] { return tree(depth - 1); });
      } catch (const ModelError&) {
        // a type that refuses every draw of inputs (e.g. the instancer of an empty solid)
      }
    }
  };
  for (int i = 0; i < 150; ++i) {
    const NodePtr root = tree(r.integer(1, 3));
    checkIntervalsAndSpecialisation(compile(root), "random tree " + std::to_string(i), r, count);
    if (HasFatalFailure()) return;
  }
  // Specialisation must actually have happened on a good share of the boxes.
  EXPECT_GT(count.specialised, 150);
}

// Every instruction alone on operand boxes spanning zero, tiny, huge and infinite
// magnitudes: the interval holds the value at every sampled operand, NaN included.
TEST(IntervalSoundness, EveryInstructionOnExtremeOperands) {
  RandomTrees r(99);
  const double edges[] = {0.0, -0.0, 1e-310, -1e-310, 1e-300, 1e-8, 0.5, 1.0, 3.0, 1e8, 1e160,
                          1e300, std::numeric_limits<double>::infinity()};
  auto draw = [&]() {
    double a = edges[r.integer(0, 12)], b = edges[r.integer(0, 12)];
    if (r.integer(0, 1)) a = -a;
    if (r.integer(0, 1)) b = r.uniform(-4, 4);
    return Interval(std::min(a, b), std::max(a, b));
  };
  auto sample = [&](const Interval& iv, int s) {
    if (s == 0) return iv.lo;
    if (s == 1) return iv.hi;
    if (s == 2 && iv.contains(0.0)) return 0.0;
    if (s == 3 && iv.contains(-0.0)) return -0.0;
    if (!std::isfinite(iv.lo) || !std::isfinite(iv.hi)) return std::isfinite(iv.lo) ? iv.lo : iv.hi;
    return iv.lo + r.uniform(0, 1) * (iv.hi - iv.lo);
  };
  int checks = 0;
  for (int op = 0; op < static_cast<int>(Op::Count_); ++op) {
    const Op o = static_cast<Op>(op);
    if (o == Op::External) continue;
    for (int trial = 0; trial < 400; ++trial) {
      double k[7];
      for (double& kj : k) kj = r.uniform(-2, 2);
      if (o == Op::RUnion || o == Op::RIntersect) k[0] = r.uniform(-0.99, 1.0);
      if (o == Op::BlendBump) k[1] = r.uniform(0.01, 2), k[2] = r.uniform(0.01, 2);
      if (o == Op::PowAbs) k[0] = r.uniform(0.05, 30);
      if (o == Op::PowConst) k[0] = r.integer(0, 1) ? double(r.integer(-4, 5)) : r.uniform(-3, 3);
      const Interval a = draw(), b = draw(), c = draw();
      const Interval range = applyOp<Interval>(o, a, b, c, k);
      ASSERT_FALSE(range.lo != range.lo || range.hi != range.hi) << opName(o) << ": NaN end point";
      for (int s = 0; s < 12; ++s) {
        const double x = sample(a, s % 6), y = sample(b, (s / 2) % 6), zz = sample(c, (s / 3) % 6);
        const double v = applyOp<double>(o, x, y, zz, k);
        ASSERT_TRUE(range.contains(v))
            << opName(o) << "(" << x << ", " << y << ", " << zz << ") k0=" << k[0] << " = " << v
            << " outside [" << range.lo << ", " << range.hi << "] nan=" << range.nan
            << " from [" << a.lo << ", " << a.hi << "], [" << b.lo << ", " << b.hi << "]";
        ++checks;
      }
    }
  }
  EXPECT_GT(checks, 50000);
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
  EXPECT_TRUE(testing::tightAbove(sqr(Interval(-1, 2)).hi, 4.0));
  const Interval s = sin(Interval(0.0, 3.2));
  EXPECT_EQ(s.hi, 1.0);
  EXPECT_LT(s.lo, 0.0);
  EXPECT_GT(s.lo, -0.1);
  const Interval c = cos(Interval(3.0, 3.3));
  EXPECT_EQ(c.lo, -1.0);
  const Interval d = Interval(1, 2) / Interval(-1, 1);
  EXPECT_TRUE(std::isinf(d.lo) && std::isinf(d.hi));
  EXPECT_FALSE(d.nan);  // 1/0 is infinite, not NaN
  EXPECT_TRUE((Interval(-1, 2) / Interval(-1, 1)).nan);  // 0/0
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

// Evaluation keeps only the values alive at once: a 200-sphere blend chain (over 2,000 SSA
// values) runs in a few dozen physical slots, and its values are those of the same chain
// evaluated slot per instruction (sum of the spheres' terms checked by hand below).
TEST(Compiler, EvaluationReusesSlotsOfDeadValues) {
  std::vector<NodePtr> spheres;
  for (int i = 0; i < 200; ++i)
    spheres.push_back(makeNode(
        "sphere", {{"center", vec3Value({0.1 * i, 0, 0})}, {"radius", realValue(0.3)}}, {}));
  const Program p = compile(makeNode("union", {}, spheres));
  ASSERT_GT(p.instructionCount(), 1000u);
  EXPECT_LT(p.evaluationSlotCount(), 16u) << p.instructionCount() << " instructions";
  // the union of spheres along x: the nearest centre decides
  for (double x : {-0.5, 0.05, 3.33, 19.9, 25.0}) {
    double best = -1e300;
    for (int i = 0; i < 200; ++i) best = std::max(best, 0.3 - std::abs(x - 0.1 * i));
    EXPECT_NEAR(p.eval(x, 0, 0), best, 1e-12) << x;
    double xs[1] = {x}, ys[1] = {0}, zs[1] = {0}, out[1];
    p.evalBatch(xs, ys, zs, 1, out);
    EXPECT_EQ(out[0], p.eval(x, 0, 0));
  }
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

namespace frep {
namespace {
// The interval's own next-double steps agree with std::nextafter everywhere, signs, zeros,
// subnormals and infinities included.
TEST(IntervalMath, NextUpAndDownAreNextafter) {
  const double inf = std::numeric_limits<double>::infinity();
  const double values[] = {0.0, -0.0, 1.0, -1.0, 1e-310, -1e-310,
                           std::numeric_limits<double>::denorm_min(),
                           -std::numeric_limits<double>::denorm_min(),
                           std::numeric_limits<double>::max(), -std::numeric_limits<double>::max(),
                           inf, -inf, 3.5e200, -2.25e-300};
  for (double v : values) {
    EXPECT_EQ(interval_detail::nextUp(v), std::nextafter(v, inf)) << v;
    EXPECT_EQ(interval_detail::nextDown(v), std::nextafter(v, -inf)) << v;
  }
  EXPECT_TRUE(std::isnan(interval_detail::nextUp(std::nan(""))));
}
}  // namespace
}  // namespace frep
