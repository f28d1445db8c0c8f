// Hierarchical B-spline surfaces: the spline axis, refinement, offsets in the
// parent's frame, the movable-CV rule, zero offsets and unrefine, flattening, tessellation.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <tuple>

#include "base/errors.h"
#include "hspline/hspline.h"
#include "hspline/hspline_flatten.h"
#include "hspline/hspline_shapes.h"
#include "hspline/hspline_tessellate.h"
#include "hspline/spline_axis.h"

using namespace frep;

namespace {

double curveAt(const SplineAxis& a, const std::vector<double>& c, double t, int derivative = 0) {
  const SpanBasis b = a.basis(t);
  double x = 0;
  for (int q = 0; q < 4; ++q) {
    const auto& w = derivative == 0 ? b.value : derivative == 1 ? b.first : b.second;
    x += w[q] * c[static_cast<std::size_t>(a.wrap(b.span - 3 + q))];
  }
  return x;
}

std::vector<SplineAxis> someAxes() {
  return {SplineAxis::clampedUniform(5), SplineAxis::periodicUniform(7),
          SplineAxis::open({0, 0, 0, 0, 0.3, 0.3, 1.1, 2, 2.5, 2.5, 2.5, 2.5}),
          SplineAxis::open({-3, -2, -1, 0, 1, 2, 3, 4, 5, 6}),
          SplineAxis::periodic({0.5, 0.75, 1.5, 2.0, 2.0, 3.25}, 4.0)};
}

double distance(const Vec3& a, const Vec3& b) {
  return vlength(vsub(a, b));
}

// A plane with a level-0 bump and detail on levels 1 and 2.
HSpline detailedPlane() {
  HSpline h = hsplinePlane(8, 7, 10, 9);
  h.moveCv(0, 3, 3, {h.position(0, 3, 3)[0], h.position(0, 3, 3)[1], 2.0});
  std::vector<std::pair<int, int>> all;
  for (const HsCv& cv : h.level(0).cvs) all.push_back({cv.i, cv.j});
  h.refine(0, all);
  h.setValue(1, 6, 6, {0.1, -0.2, 0.7});
  h.refine(1, {{6, 6}, {7, 6}});
  h.setValue(2, 14, 14, {0, 0, -0.4});
  return h;
}

std::vector<std::pair<double, double>> samplesOf(const HSpline& h, int n, unsigned seed) {
  std::mt19937 rng(seed);
  const HsLevel& l = h.level(0);
  std::uniform_real_distribution<double> u(l.u.lo(), l.u.hi()), v(l.v.lo(), l.v.hi());
  std::vector<std::pair<double, double>> out;
  for (int k = 0; k < n; ++k) out.push_back({u(rng), v(rng)});
  // Knots and the domain's corners, where spans meet.
  out.push_back({l.u.lo(), l.v.lo()});
  out.push_back({l.u.hi(), l.v.hi()});
  out.push_back({l.u.knot(5), l.v.knot(4)});
  return out;
}

}  // namespace

TEST(SplineAxis, BasisSumsToOneAndDerivativesMatchDifferences) {
  for (const SplineAxis& a : someAxes()) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> t(a.lo(), a.hi());
    std::vector<double> c(static_cast<std::size_t>(a.count()));
    for (double& x : c) x = std::uniform_real_distribution<double>(-1, 1)(rng);
    for (int k = 0; k < 200; ++k) {
      const double x = t(rng);
      const SpanBasis b = a.basis(x);
      EXPECT_NEAR(b.value[0] + b.value[1] + b.value[2] + b.value[3], 1.0, 1e-14);
      const double h = 1e-6;
      if (x - h < a.lo() || x + h > a.hi()) continue;
      EXPECT_NEAR(curveAt(a, c, x, 1), (curveAt(a, c, x + h) - curveAt(a, c, x - h)) / (2 * h),
                  1e-5);
      EXPECT_NEAR(curveAt(a, c, x, 2),
                  (curveAt(a, c, x + h, 1) - curveAt(a, c, x - h, 1)) / (2 * h), 1e-4);
    }
  }
}

TEST(SplineAxis, RefinementRowsReproduceTheCurveExactly) {
  for (const SplineAxis& a : someAxes()) {
    const SplineAxis fine = a.refined();
    EXPECT_EQ(fine.lo(), a.lo());
    EXPECT_EQ(fine.hi(), a.hi());
    std::mt19937 rng(5);
    std::vector<double> c(static_cast<std::size_t>(a.count()));
    for (double& x : c) x = std::uniform_real_distribution<double>(-1, 1)(rng);
    std::vector<double> f(static_cast<std::size_t>(fine.count()), 0);
    const auto rows = a.rowsOnto(fine);
    for (std::size_t j = 0; j < rows.size(); ++j) {
      ASSERT_FALSE(rows[j].empty());
      for (const auto& [i, w] : rows[j]) f[j] += w * c[static_cast<std::size_t>(i)];
    }
    std::uniform_real_distribution<double> t(a.lo(), a.hi());
    for (int k = 0; k < 300; ++k) {
      const double x = t(rng);
      EXPECT_NEAR(curveAt(fine, f, x), curveAt(a, c, x), 1e-13);
    }
  }
}

TEST(SplineAxis, UniformRefinementIsTheSubdivisionMask) {
  const SplineAxis a = SplineAxis::periodicUniform(6);
  const auto rows = a.rowsOnto(a.refined());
  const auto centres = a.childCentres(a.refined());
  // The fine CV at a coarse CV's centre is (1/8, 3/4, 1/8) of it and its neighbours.
  for (int i = 0; i < 6; ++i) {
    const auto& row = rows[static_cast<std::size_t>(centres[static_cast<std::size_t>(i)])];
    double self = 0, total = 0;
    for (const auto& [k, w] : row) {
      total += w;
      if (k == i) self = w;
    }
    EXPECT_NEAR(self, 0.75, 1e-15);
    EXPECT_NEAR(total, 1.0, 1e-15);
  }
}

TEST(SplineAxis, BadKnotsAreRefusedWithTheReason) {
  auto message = [](auto make) {
    try {
      make();
    } catch (const ModelError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message([] {
              SplineAxis::open({0, 0, 0, 0, 2, 1, 3, 3, 3, 3});
            }).find("smaller than the one before"),
            std::string::npos);
  EXPECT_NE(message([] {
              SplineAxis::open({0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2});
            }).find("repeated 4 times"),
            std::string::npos);
  EXPECT_NE(message([] {
              SplineAxis::open({0, 0, 0, 0, NAN, 2, 2, 2, 2});
            }).find("not a finite number"),
            std::string::npos);
  EXPECT_NE(message([] {
              SplineAxis::periodic({0, 1, 2, 5}, 4);
            }).find("within one period"),
            std::string::npos);
  EXPECT_NE(message([] {
              SplineAxis::open({0, 0, 0, 1, 1, 1});
            }).find("at least 8 knots"),
            std::string::npos);
}

TEST(HSpline, RefiningDoesNotChangeTheSurface) {
  for (HSpline h : {detailedPlane(), hsplineTorus(8, 6, 5, 1.5)}) {
    const auto at = samplesOf(h, 400, 11);
    std::vector<Vec3> before;
    for (const auto& [u, v] : at) before.push_back(h.evaluate(u, v).position);
    const int finest = h.levelCount() - 1;
    std::vector<std::pair<int, int>> some;
    for (std::size_t k = 0; k < h.level(finest).cvs.size(); k += 3)
      some.push_back({h.level(finest).cvs[k].i, h.level(finest).cvs[k].j});
    const std::size_t cvs = h.cvCount();
    h.refine(finest, some);
    EXPECT_EQ(h.levelCount(), finest + 2);
    EXPECT_GT(h.cvCount(), cvs);
    for (std::size_t k = 0; k < at.size(); ++k) {
      const Vec3 p = h.evaluate(at[k].first, at[k].second).position;
      EXPECT_LE(distance(p, before[k]), 1e-12)
          << "at (" << at[k].first << ", " << at[k].second << ")";
    }
  }
}

TEST(HSpline, NewCvsSitWhereTheParentNetPutsThem) {
  HSpline h = detailedPlane();
  // A fresh refinement's CV positions are the parent's net refined by knot insertion: the
  // flattened level-0-and-1 net at those CVs.
  h.refine(2, {{14, 14}});
  const auto positions = h.positions(3);
  ASSERT_EQ(positions.size(), 49u);
  for (std::size_t k = 0; k < positions.size(); ++k) {
    const HsCv& cv = h.level(3).cvs[k];
    const auto [u, v] = h.referenceParameter(3, cv.i, cv.j);
    // A uniform cubic's control point lies within its curvature of the surface point it
    // peaks at; here just nearby.
    EXPECT_LT(distance(positions[k], h.evaluate(u, v).position), 0.2);
  }
}

TEST(HSpline, DetailFollowsTheParentWhenLevelZeroTurns) {
  HSpline h = detailedPlane();
  const auto at = samplesOf(h, 200, 17);
  std::vector<Vec3> before;
  for (const auto& [u, v] : at) before.push_back(h.evaluate(u, v).position);
  // Turn every level-0 CV by 90 degrees about the x axis and shift it: the detail, stored in
  // the parent's frame, must turn and shift with it.
  auto turn = [](const Vec3& p) { return Vec3{p[0] + 1, -p[2] + 2, p[1] - 3}; };
  for (const HsCv& cv : std::vector<HsCv>(h.level(0).cvs)) h.moveCv(0, cv.i, cv.j, turn(cv.value));
  for (std::size_t k = 0; k < at.size(); ++k)
    EXPECT_LE(distance(h.evaluate(at[k].first, at[k].second).position, turn(before[k])), 1e-9);
  // Offsets are what they were.
  EXPECT_EQ(h.find(1, 6, 6)->value, (Vec3{0.1, -0.2, 0.7}));
}

TEST(HSpline, MovingALevelZeroCvCarriesLevelOneDetailAlong) {
  HSpline h = detailedPlane();
  const Vec3 detailBefore =
      vsub(h.position(1, 6, 6),
           h.evaluate(h.referenceParameter(1, 6, 6).first, h.referenceParameter(1, 6, 6).second, 0)
               .position);
  const Vec3 start = h.position(0, 3, 3), cvBefore = h.position(1, 6, 6);
  h.moveCv(0, 3, 3, {start[0], start[1], start[2] + 3});
  const auto [u, v] = h.referenceParameter(1, 6, 6);
  const Vec3 detailAfter = vsub(h.position(1, 6, 6), h.evaluate(u, v, 0).position);
  // The CV rose with the parent surface under it...
  EXPECT_GT(h.position(1, 6, 6)[2], cvBefore[2] + 0.5);
  // ...and its offset turned with the parent's frame: the displacement keeps its length.
  const HsFrame f = h.frame(1, 6, 6);
  const Vec3 d = vadd(vadd(vscale(f.tu, 0.1), vscale(f.tv, -0.2)), vscale(f.n, 0.7));
  const HsCv* cv = h.find(1, 6, 6);
  ASSERT_NE(cv, nullptr);
  const auto k = static_cast<int>(cv - h.level(1).cvs.data());
  EXPECT_LE(distance(h.displacement(1, k), d), 1e-12);
  EXPECT_NEAR(vlength(h.displacement(1, k)), std::sqrt(0.01 + 0.04 + 0.49), 1e-12);
  EXPECT_GT(f.n[0] * f.n[0] + f.n[1] * f.n[1], 1e-4);    // the frame did turn
  EXPECT_GT(distance(detailAfter, detailBefore), 1e-3);  // not a mere translation
}

TEST(HSpline, AMoveRefreshesExactlyWhatAFullRebuildGives) {
  // A move refreshes only the CVs whose frame it can reach; the rest must already be what a
  // hierarchy built afresh from the same values has, to the bit.
  for (HSpline h : {detailedPlane(), [] {
                      HSpline t = hsplineTorus(8, 6, 5, 1.5);
                      t.refine(0, {{0, 0}, {7, 5}, {3, 3}});  // across both seams
                      for (const HsCv& cv : std::vector<HsCv>(t.level(1).cvs))
                        t.setValue(1, cv.i, cv.j, {0.01 * cv.i, 0, 0.02 * cv.j});
                      return t;
                    }()}) {
    for (const auto& [level, i, j] :
         std::vector<std::tuple<int, int, int>>{{0, 0, 0}, {0, 3, 3}, {0, 7, 5}, {1, 6, 6}}) {
      if (!h.find(level, i, j) || !h.movable(level, i, j)) continue;
      h.moveCv(level, i, j, vadd(h.position(level, i, j), {0.3, -0.2, 0.5}));
      std::vector<std::vector<HsCv>> levels;
      for (int l = 0; l < h.levelCount(); ++l) levels.push_back(h.level(l).cvs);
      const HSpline fresh = HSpline::fromLevels(h.level(0).u, h.level(0).v, levels);
      for (int l = 0; l < h.levelCount(); ++l)
        for (std::size_t k = 0; k < h.level(l).cvs.size(); ++k)
          ASSERT_EQ(h.displacement(l, int(k)), fresh.displacement(l, int(k)))
              << "level " << l << " CV " << k;
    }
  }
}

TEST(HSpline, AMoveChangesTheSurfaceOnlyWithinItsReach) {
  HSpline h = hsplineTorus(8, 6, 5, 1.5);
  h.refine(0, {{0, 0}, {1, 0}, {7, 5}});
  for (const HsCv& cv : std::vector<HsCv>(h.level(1).cvs))
    h.setValue(1, cv.i, cv.j, {0, 0.01 * cv.j, 0.02 * cv.i});
  std::vector<double> us, vs;
  for (int a = 0; a < 64; ++a) us.push_back(8.0 * a / 64);
  for (int b = 0; b < 48; ++b) vs.push_back(6.0 * b / 48);
  const std::vector<std::pair<std::size_t, std::size_t>> all{{0, us.size() * vs.size()}};
  const auto before = h.evaluateGrid(us, vs, all);
  // The grid evaluation is the point evaluation.
  for (std::size_t k = 0; k < before.size(); k += 37)
    EXPECT_EQ(before[k].position, h.evaluate(us[k % us.size()], vs[k / us.size()]).position);
  const HsRegion r = h.reach(0, 0, 0);  // a CV whose support crosses both seams
  h.moveCv(0, 0, 0, vadd(h.position(0, 0, 0), {0.5, 0.2, -0.4}));
  const auto after = h.evaluateGrid(us, vs, all);
  std::size_t inside = 0, moved = 0;
  for (std::size_t k = 0; k < after.size(); ++k) {
    const bool in = h.contains(r, us[k % us.size()], vs[k / us.size()]);
    inside += in;
    if (after[k].position != before[k].position) {
      ++moved;
      EXPECT_TRUE(in) << "a point outside the reach moved, at " << us[k % us.size()] << ", "
                      << vs[k / us.size()];
    }
  }
  EXPECT_GT(moved, 100u);
  EXPECT_LT(inside, after.size());  // the reach is not the whole surface
}

TEST(HSpline, AFixedCvRefusesToMove) {
  HSpline h = hsplinePlane(12, 12, 10, 10);
  h.refine(0, {{5, 5}});
  ASSERT_EQ(h.level(1).cvs.size(), 49u);
  const HsCv centre = h.level(1).cvs[24];
  EXPECT_TRUE(h.movable(1, centre.i, centre.j));
  EXPECT_FALSE(h.movable(1, centre.i + 1, centre.j));
  const Vec3 p = h.position(1, centre.i + 1, centre.j);
  try {
    h.moveCv(1, centre.i + 1, centre.j, {p[0], p[1], p[2] + 1});
    FAIL() << "a fixed CV moved";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("is fixed"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("7 x 7"), std::string::npos) << e.what();
  }
  // Refining the neighbours makes it movable.
  h.refine(0, {{6, 5}, {4, 5}, {5, 6}, {5, 4}, {6, 6}, {6, 4}, {4, 6}, {4, 4}});
  EXPECT_TRUE(h.movable(1, centre.i + 1, centre.j));
  EXPECT_NO_THROW(h.moveCv(1, centre.i + 1, centre.j, {p[0], p[1], p[2] + 1}));
  EXPECT_NEAR(h.position(1, centre.i + 1, centre.j)[2], p[2] + 1, 1e-12);
}

TEST(HSpline, TheSurfaceStaysC2AcrossTheBorderOfARefinedRegion) {
  HSpline h = hsplinePlane(12, 12, 10, 10);
  h.refine(0, {{5, 5}, {6, 5}});
  for (const HsCv& cv : h.level(1).cvs)
    if (h.movable(1, cv.i, cv.j)) h.setValue(1, cv.i, cv.j, {0.2, 0.1, 0.5 + 0.1 * cv.i});
  h.refine(1, {{h.level(1).cvs[24].i, h.level(1).cvs[24].j}});
  for (const HsCv& cv : h.level(2).cvs)
    if (h.movable(2, cv.i, cv.j)) h.setValue(2, cv.i, cv.j, {0, 0, -0.3});
  // Across every knot line of level 2 (which hold the borders of both refined regions), value,
  // first and second derivatives agree from both sides.
  const SplineAxis& u = h.level(2).u;
  int checked = 0;
  for (int k = 4; k < u.count(); ++k) {
    const double t = u.knot(k), e = 1e-7;
    for (double v : {3.0, 4.4, 5.1, 6.3}) {
      const HsSurfacePoint a = h.evaluate(t - e, v), b = h.evaluate(t + e, v);
      EXPECT_LT(distance(a.position, b.position), 1e-5);
      EXPECT_LT(distance(a.du, b.du), 1e-4);
      EXPECT_LT(distance(a.duu, b.duu), 1e-3) << "at u " << t << ", v " << v;
      ++checked;
    }
  }
  EXPECT_GT(checked, 40);
}

TEST(HSpline, UnrefineAfterZeroOffsetsRestoresTheCvsAndKeepsTheSurface) {
  HSpline h = hsplineTorus(8, 6, 5, 1.5);
  const std::size_t cvs = h.cvCount();
  std::vector<std::pair<int, int>> all;
  for (const HsCv& cv : h.level(0).cvs) all.push_back({cv.i, cv.j});
  h.refine(0, all);
  h.setValue(1, 4, 4, {0, 0, 0.3});
  h.refine(1, {{4, 4}});
  h.setValue(2, 10, 10, {0.1, 0, 0.2});
  // Unrefine keeps what carries detail: the 7 x 7 blocks and the parents of level 2.
  const auto at = samplesOf(h, 300, 23);
  std::vector<Vec3> before;
  for (const auto& [u, v] : at) before.push_back(h.evaluate(u, v).position);
  const std::size_t removed = h.unrefine();
  EXPECT_GT(removed, 0u);
  EXPECT_EQ(h.levelCount(), 3);
  EXPECT_EQ(h.level(2).cvs.size(), 49u);
  for (std::size_t k = 0; k < at.size(); ++k)
    EXPECT_EQ(h.evaluate(at[k].first, at[k].second).position, before[k]);
  // Zero everything above level 0: unrefine leaves level 0 alone, as it was.
  std::vector<HsCvRef> refs;
  for (int l = 1; l < h.levelCount(); ++l)
    for (const HsCv& cv : h.level(l).cvs) refs.push_back({l, cv.i, cv.j});
  h.zeroOffsets(refs);
  const HSpline plain = hsplineTorus(8, 6, 5, 1.5);
  h.unrefine();
  EXPECT_EQ(h.levelCount(), 1);
  EXPECT_EQ(h.cvCount(), cvs);
  for (const auto& [u, v] : at) EXPECT_EQ(h.evaluate(u, v).position, plain.evaluate(u, v).position);
}

TEST(HSpline, ZeroOffsetsRefusesLevelZeroAndMissingCvs) {
  HSpline h = detailedPlane();
  EXPECT_THROW(h.zeroOffsets({{0, 1, 1}}), ModelError);
  EXPECT_THROW(h.zeroOffsets({{1, 500, 1}}), ModelError);
  EXPECT_THROW(h.refine(2, {{0, 0}}), ModelError);  // level 2 has no CV there
  EXPECT_THROW(h.refine(7, {{0, 0}}), ModelError);
  // Nothing changed on refusal.
  EXPECT_EQ(h.find(1, 6, 6)->value, (Vec3{0.1, -0.2, 0.7}));
}

TEST(HSpline, LevelsAreCapped) {
  HSpline h = hsplinePlane(4, 4, 1, 1);
  int level = 0;
  try {
    for (; level < 40; ++level)
      h.refine(level, {{h.level(level).cvs[0].i, h.level(level).cvs[0].j}});
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("levels"), std::string::npos) << e.what();
  }
  EXPECT_EQ(h.levelCount(), HSpline::kMaxLevels);
}

TEST(HsFlatten, TheFlattenedSurfaceIsTheHierarchy) {
  HSpline torus = hsplineTorus(8, 6, 5, 1.5);
  torus.refine(0, {{2, 2}, {3, 2}});
  torus.setValue(1, 6, 6, {0.1, 0.2, 0.4});
  torus.refine(1, {{6, 6}});
  torus.setValue(2, 14, 14, {0, 0, -0.2});
  for (const HSpline& h : {detailedPlane(), torus, hsplineCylinder(6, 5, 2, 4)}) {
    const FlatBSpline f = flatten(h);
    // Only where finer levels are do their knots enter.
    EXPECT_LE(f.u.count(), h.level(h.levelCount() - 1).u.count());
    for (const auto& [u, v] : samplesOf(h, 500, 29)) {
      const HsSurfacePoint a = h.evaluate(u, v), b = f.evaluate(u, v);
      EXPECT_LE(distance(a.position, b.position), 1e-9);
      EXPECT_LE(distance(a.du, b.du), 1e-8);
    }
  }
}

TEST(HsFlatten, ALevelOfDetailIsTheSurfaceOfTheLevelsUpToIt) {
  const HSpline h = detailedPlane();
  for (int level = 0; level < h.levelCount(); ++level) {
    const FlatBSpline f = flatten(h, level);
    for (const auto& [u, v] : samplesOf(h, 200, 43))
      EXPECT_LE(distance(f.evaluate(u, v).position, h.evaluate(u, v, level).position), 1e-9)
          << "level " << level;
  }
  // Level 0 of the plane is its bump alone; the finer levels' detail is not in it.
  const auto [u, v] = h.referenceParameter(1, 6, 6);
  EXPECT_GT(distance(flatten(h, 0).evaluate(u, v).position, flatten(h).evaluate(u, v).position),
            0.1);
}

TEST(HsTessellation, ATorusClosesAndStaysWithinTheTolerance) {
  HSpline h = hsplineTorus(10, 8, 5, 1.5);
  h.refine(0, {{3, 3}});
  h.setValue(1, 8, 8, {0, 0, 0.5});
  const FlatBSpline f = flatten(h);
  const HsTessellation t = tessellate(f, 0.01);
  EXPECT_TRUE(t.closed);
  EXPECT_EQ(t.mesh.triangles.size(), 2u * t.samplesU * t.samplesV);
  // Each edge of every triangle appears once each way: closed and consistently oriented.
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
  for (const Triangle& tri : t.mesh.triangles)
    for (int e = 0; e < 3; ++e) ++edges[{tri[e], tri[(e + 1) % 3]}];
  for (const auto& [e, n] : edges) {
    EXPECT_EQ(n, 1);
    EXPECT_EQ(edges.count({e.second, e.first}), 1u);
  }
  // The surface in the middle of each cell lies within the tolerance (the chord estimate,
  // with the twist term's factor 2 of slack) of the cells' shared diagonal.
  ASSERT_EQ(t.us.size(), static_cast<std::size_t>(t.samplesU));
  double worst = 0;
  for (int j = 0; j < t.samplesV; ++j)
    for (int i = 0; i < t.samplesU; ++i) {
      const std::size_t i1 = (i + 1) % t.samplesU, j1 = (j + 1) % t.samplesV;
      const double u1 = i1 ? t.us[i1] : f.u.hi(), v1 = j1 ? t.vs[j1] : f.v.hi();
      const Vec3 mid = f.evaluate(0.5 * (t.us[i] + u1), 0.5 * (t.vs[j] + v1)).position;
      const auto& a = t.mesh.positions[i + t.samplesU * j];
      const auto& c = t.mesh.positions[i1 + t.samplesU * j1];
      const Vec3 chord{0.5 * (a[0] + c[0]), 0.5 * (a[1] + c[1]), 0.5 * (a[2] + c[2])};
      worst = std::max(worst, distance(mid, chord));
    }
  EXPECT_LE(worst, 0.02);
  EXPECT_GT(worst, 0.001);  // and not far finer than asked
  EXPECT_THROW(tessellate(f, 0), ModelError);
  EXPECT_THROW(tessellate(f, 1e-9, 1000), ModelError);
}

// ---- .hs files ----

#include "hspline/hs_file.h"

namespace {

std::string errorOf(const std::string& text) {
  try {
    parseHs(text, "test.hs");
  } catch (const FileError& e) {
    return e.what();
  }
  return "";
}

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

}  // namespace

TEST(HsFile, RoundTripIsExact) {
  HSpline torus = hsplineTorus(8, 6, 5, 1.5);
  torus.refine(0, {{2, 2}});
  torus.setValue(1, 6, 6, {0.1, 1.0 / 3, -0.4});
  for (const HSpline& h : {detailedPlane(), torus}) {
    const std::string text = hsText(h);
    const HSpline back = parseHs(text);
    EXPECT_EQ(hsText(back), text);
    ASSERT_EQ(back.levelCount(), h.levelCount());
    for (const auto& [u, v] : samplesOf(h, 100, 31))
      EXPECT_EQ(back.evaluate(u, v).position, h.evaluate(u, v).position);
  }
}

TEST(HsFile, OptimisedSaveDropsUnusedCvsAndKeepsTheSurface) {
  const HSpline h = detailedPlane();
  const HSpline lean = parseHs(hsText(h, true));
  EXPECT_LT(lean.cvCount(), h.cvCount());
  for (const auto& [u, v] : samplesOf(h, 200, 37))
    EXPECT_EQ(lean.evaluate(u, v).position, h.evaluate(u, v).position);
}

TEST(HsFile, WritesAtomicallyAndReadsBack) {
  const std::string path = testing::TempDir() + "/plane.hs";
  writeHsFile(detailedPlane(), path);
  EXPECT_EQ(hsText(readHsFile(path)), hsText(detailedPlane()));
  EXPECT_THROW(readHsFile(path + ".missing"), FileError);
}

TEST(HsFile, MalformedFilesNameTheLine) {
  HSpline h = hsplinePlane(8, 8, 2, 2);
  h.refine(0, {{3, 3}});
  h.setValue(1, 5, 5, {0, 0, 0.1});
  const std::string good = hsText(h);
  ASSERT_EQ(errorOf(good), "");
  // Lines: 1 comment, 2 hspline, 3 axis u, 4 knots, 5 axis v, 6 knots, 7 level 0, 8.. cvs.
  const std::string truncated = good.substr(0, good.find("level 1"));
  EXPECT_NE(errorOf(truncated).find("truncated?"), std::string::npos) << errorOf(truncated);
  const std::string fewer = good.substr(0, good.find("cv 5 5 0 0 0.1"));
  EXPECT_NE(errorOf(fewer).find("level 1 declares 49 CVs but has"), std::string::npos)
      << errorOf(fewer);
  const std::string cut = good.substr(0, good.size() / 2);
  EXPECT_NE(errorOf(cut).find("line "), std::string::npos);
  EXPECT_NE(
      errorOf(replaced(good, "hspline 1", "hspline 2")).find("line 2: version 2 is not known"),
      std::string::npos);
  EXPECT_NE(errorOf(replaced(good, "knots 0 0 0 0 1 2 3", "knots 0 0 0 0 1 0.5 3"))
                .find("line 4: axis u: knots: knot 5"),
            std::string::npos)
      << errorOf(replaced(good, "knots 0 0 0 0 1 2 3", "knots 0 0 0 0 1 0.5 3"));
  const std::string beyond = replaced(good, "cv 5 5 0 0 0.1", "cv 5 400 0 0 0.1");
  EXPECT_NE(errorOf(beyond).find("j is 400; it must be 0 to"), std::string::npos)
      << errorOf(beyond);
  EXPECT_NE(errorOf(beyond).find(", line "), std::string::npos);
  EXPECT_NE(errorOf(replaced(good, "cv 5 5 0 0 0.10000000000000001", "cv 5 5 0 nan 0.1"))
                .find("is not a finite number"),
            std::string::npos);
  EXPECT_NE(errorOf(replaced(good, "level 1 49", "level 1 999999999")).find("must be 0 to"),
            std::string::npos);
  EXPECT_NE(errorOf(replaced(good, "level 1", "level 3")).find("level 1 expected here"),
            std::string::npos);
  EXPECT_NE(errorOf(good + "cv 1 1 0 0 0\n").find("nothing may follow 'end'"), std::string::npos);
  EXPECT_NE(errorOf(replaced(good, "cv 0 0 ", "cv 0 1 ")).find("is given twice"),
            std::string::npos);
  EXPECT_NE(errorOf("").find("line 1: the file ends here"), std::string::npos) << errorOf("");
}

TEST(HsFile, MutatedFilesNeverCrash) {
  HSpline h = hsplineTorus(6, 5, 3, 1);
  h.refine(0, {{2, 2}, {3, 3}});
  h.setValue(1, 6, 6, {0.1, 0.2, 0.3});
  const std::string good = hsText(h);
  std::mt19937 rng(41);
  const std::string alphabet = "0123456789 .-+eE#\nnaicvlkotsuperd";
  int refused = 0, read = 0;
  for (int round = 0; round < 3000; ++round) {
    std::string s = good;
    const int edits = 1 + static_cast<int>(rng() % 4);
    for (int e = 0; e < edits; ++e) {
      const std::size_t at = rng() % s.size();
      switch (rng() % 5) {
        case 0:
          s.erase(at, 1 + rng() % 12);
          break;
        case 1:
          s.insert(at, 1, alphabet[rng() % alphabet.size()]);
          break;
        case 2:
          s[at] = alphabet[rng() % alphabet.size()];
          break;
        case 3:
          s.insert(at, rng() % 2 ? "999999999" : "1e308");
          break;
        default:
          s = s.substr(0, at);
          break;
      }
      if (s.empty()) s = "x";
    }
    try {
      const HSpline back = parseHs(s, "mutant.hs");
      back.evaluate(0.5, 0.5);
      ++read;
    } catch (const FileError&) {
      ++refused;
    }
  }
  EXPECT_GT(refused, 1000);
  EXPECT_GT(read, 10);
}

// ---- tags ----

#include "hspline/hspline_select.h"

TEST(HsTags, SelectionsFollowTheirRules) {
  HSpline h = hsplineTorus(8, 6, 5, 1.5);
  h.refine(0, {{2, 2}, {3, 2}});
  // Along U: every CV of the level on the selected CVs' v line (j), and no other.
  const auto along = selectAlongU(h, {{1, 8, 6}});
  ASSERT_FALSE(along.empty());
  for (const HsCvRef& c : along) {
    EXPECT_EQ(c.j, 6);
    EXPECT_EQ(c.level, 1);
  }
  std::size_t onLine = 0;
  for (const HsCv& cv : h.level(1).cvs) onLine += cv.j == 6;
  EXPECT_EQ(along.size(), onLine);
  for (const HsCvRef& c : selectAlongV(h, {{0, 3, 1}})) EXPECT_EQ(c.i, 3);
  EXPECT_EQ(selectAlongV(h, {{0, 3, 1}}).size(), 6u);
  // Movable: exactly the CVs with a whole 7 x 7 block.
  const auto movable = selectMovable(h, 1);
  // Neighbouring coarse CVs have children two apart: two 7 x 7 blocks make a 9 x 7 patch,
  // whose middle three CVs have a whole block.
  EXPECT_EQ(movable.size(), 3u);
  for (const HsCvRef& c : movable) EXPECT_TRUE(h.movable(1, c.i, c.j));
  EXPECT_EQ(keepMovable(h, selectLevel(h, 1)), movable);
  EXPECT_EQ(selectLevel(h, 1).size(), 63u);
  // Neighbours of one CV in the middle: 9.
  EXPECT_EQ(selectNeighbours(h, {movable[0]}).size(), 9u);
  // A region across the periodic seam of u: the CVs near u = 0 from both sides.
  const auto seam = selectRegion(h, 0, 7.5, 0.5, 0, 6);
  ASSERT_FALSE(seam.empty());
  for (const HsCvRef& c : seam) {
    const double u = std::fmod(h.level(0).u.reference(c.i), 8.0);
    EXPECT_TRUE(u >= 7.5 || u <= 0.5) << u;
  }
  // Non-zero offsets, then refining a selection made of two levels.
  h.setValue(1, movable[0].i, movable[0].j, {0, 0, 0.2});
  EXPECT_EQ(selectNonZeroOffsets(h), (std::vector<HsCvRef>{movable[0]}));
  refineSelection(h, {movable[0], {0, 6, 4}});
  EXPECT_EQ(h.levelCount(), 3);
  EXPECT_EQ(h.level(2).cvs.size(), 49u);
}

// ---- attachments ----

#include "hspline/hspline_attach.h"

namespace {

// A cylinder over the ring of plane CVs around [3, 6] x [3, 6]: 12 CVs around, CV k over ring
// CV k, rising in rows of 10.
// The CVs around rectangle [i0, i1] x [j0, j1], in the order a cylinder's CVs go around it.
std::vector<std::pair<int, int>> ringAround(int i0, int i1, int j0, int j1) {
  std::vector<std::pair<int, int>> ring;
  for (int i = i0; i < i1; ++i) ring.push_back({i, j0});
  for (int j = j0; j < j1; ++j) ring.push_back({i1, j});
  for (int i = i1; i > i0; --i) ring.push_back({i, j1});
  for (int j = j1; j > j0; --j) ring.push_back({i0, j});
  return ring;
}

HSpline cylinderOverRing(const HSpline& plane, int rows) {
  const auto ring = ringAround(3, 6, 3, 6);
  Vec3 centre{0, 0, 0};
  for (const auto& [i, j] : ring)
    centre = vadd(centre, vscale(plane.position(0, i, j), 1.0 / ring.size()));
  std::vector<Vec3> p;
  for (int r = 0; r < rows; ++r)
    for (const auto& [i, j] : ring) {
      const Vec3 q = plane.position(0, i, j);
      p.push_back({centre[0] + 0.7 * (q[0] - centre[0]), centre[1] + 0.7 * (q[1] - centre[1]),
                   10.0 * (r - 1)});
    }
  return HSpline(SplineAxis::periodicUniform(12), SplineAxis::clampedUniform(rows - 3), p);
}

}  // namespace

TEST(HsAttachment, ACylinderJoinsAPlaneThroughFourExtraordinaryPoints) {
  const HSpline plane = hsplinePlane(10, 10, 90, 90);
  const HSpline cylinder = cylinderOverRing(plane, 5);
  const HsAttachment a = attachCylinder(plane, 3, 6, 3, 6, cylinder, 3);
  EXPECT_EQ(a.extraordinary, 4);  // the ring's corners: five edges each
  EXPECT_EQ(a.boundaryLoops, 2);  // the plane's edge and the cylinder's top rim
  EXPECT_EQ(a.controlFaces, 81u - 9u + 12u * 3u);
  // A manifold, consistently oriented surface: every directed edge once.
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
  for (const Triangle& t : a.mesh.triangles)
    for (int e = 0; e < 3; ++e) ++edges[{t[e], t[(e + 1) % 3]}];
  for (const auto& [e, n] : edges) EXPECT_EQ(n, 1);
  // The surface rises from the plane (z 0) up the tube; the open rim keeps its row's height
  // (the boundary rule), and nothing goes above it or below the plane's net.
  float top = -1e9f, bottom = 1e9f;
  std::size_t onTube = 0;
  for (const auto& p : a.mesh.positions) {
    top = std::max(top, p[2]), bottom = std::min(bottom, p[2]);
    onTube += p[2] > 5 && p[2] < 25;
  }
  EXPECT_NEAR(top, 30.0f, 1e-4);
  EXPECT_GT(bottom, -1e-4f);
  EXPECT_GT(onTube, 100u);
  EXPECT_GT(a.mesh.triangles.size(), 4000u);
}

TEST(HsAttachment, AClosedLimbOnATorusMakesAClosedSurface) {
  const HSpline torus = hsplineTorus(12, 8, 30, 10);
  const auto ring = ringAround(3, 5, 1, 3);
  Vec3 centre{0, 0, 0};
  for (const auto& [i, j] : ring)
    centre = vadd(centre, vscale(torus.position(0, i, j), 1.0 / ring.size()));
  // outward: from the tube's centre circle through the ring's centre
  const double r = std::hypot(centre[0], centre[1]);
  const Vec3 tube{centre[0] * 30 / r, centre[1] * 30 / r, 0};
  const Vec3 out = vscale(vsub(centre, tube), 1 / vlength(vsub(centre, tube)));
  std::vector<Vec3> p;
  for (int row = 0; row < 5; ++row)
    for (const auto& [i, j] : ring) {
      const Vec3 q = torus.position(0, i, j);
      const double taper = row <= 1 ? 1.0 : 0.7;
      p.push_back(vadd(vadd(centre, vscale(vsub(q, centre), taper)), vscale(out, 8.0 * (row - 1))));
    }
  const HSpline limb(SplineAxis::periodicUniform(8), SplineAxis::clampedUniform(2), p);
  const HsAttachment open = attachCylinder(torus, 3, 5, 1, 3, limb, 2, false);
  EXPECT_EQ(open.boundaryLoops, 1);  // the limb's rim
  const HsAttachment a = attachCylinder(torus, 3, 5, 1, 3, limb, 3, true);
  EXPECT_EQ(a.boundaryLoops, 0);
  // Closed and consistently oriented: each directed edge once, and its twin there too.
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
  for (const Triangle& t : a.mesh.triangles)
    for (int e = 0; e < 3; ++e) ++edges[{t[e], t[(e + 1) % 3]}];
  for (const auto& [e, n] : edges) {
    EXPECT_EQ(n, 1);
    EXPECT_EQ(edges.count({e.second, e.first}), 1u);
  }
  // It encloses the torus's volume and more (the limb), outward facing.
  double volume = 0;
  for (const Triangle& t : a.mesh.triangles) {
    const auto v = [&](int k) {
      const auto& x = a.mesh.positions[t[k]];
      return Vec3{x[0], x[1], x[2]};
    };
    volume += vdot(v(0), vcross(v(1), v(2))) / 6;
  }
  const double torusVolume = 2 * 3.14159265 * 3.14159265 * 30 * 100;
  EXPECT_GT(volume, 0.85 * torusVolume);
  EXPECT_LT(volume, 1.5 * torusVolume);
}

TEST(HsAttachment, ARefinedSeamDoublesTheRingAndKeepsTheParentsDetail) {
  // A bump modelled on the plane's level 1, away from the rectangle: a seam on level 0 drops
  // it (seed 003's attachment uses level 0 only); on level 1 the joined surface has it.
  HSpline plane = hsplinePlane(10, 10, 90, 90);
  plane.refine(0, {{1, 1}});
  for (const HsCv& cv : std::vector<HsCv>(plane.level(1).cvs))
    if (plane.movable(1, cv.i, cv.j)) plane.setValue(1, cv.i, cv.j, {0, 0, 6});
  const Vec3 bump = plane.position(0, 1, 1);
  const auto highest = [&](const HsAttachment& a) {  // near the bump, far from the limb
    float z = -1e9f;
    for (const auto& p : a.mesh.positions)
      if (std::abs(p[0] - bump[0]) < 15 && std::abs(p[1] - bump[1]) < 15) z = std::max(z, p[2]);
    return z;
  };
  const HsAttachment coarse = attachCylinder(plane, 3, 6, 3, 6, cylinderOverRing(plane, 5), 3);
  const auto [nu1, nv1] = std::pair{plane.level(1).u.count(), plane.level(1).v.count()};
  // The same rectangle on level 1 (each level-0 CV i has its child near 2 i - 1 there): a ring
  // of twice the CVs, and a cylinder of 24 around standing on it.
  const int a0 = 5, a1 = 11;
  const auto ring = ringAround(a0, a1, a0, a1);
  std::vector<Vec3> p;
  for (int r = 0; r < 5; ++r)
    for (const auto& [i, j] : ring) {
      const Vec3 q = plane.position(1, i, j);
      p.push_back({q[0] * (r <= 1 ? 1.0 : 0.7), q[1] * (r <= 1 ? 1.0 : 0.7), 10.0 * (r - 1)});
    }
  const HSpline limb(SplineAxis::periodicUniform(24), SplineAxis::clampedUniform(2), p);
  const HsAttachment fine = attachCylinder(plane, a0, a1, a0, a1, limb, 3, false, 1);
  EXPECT_GT(nu1, 10);
  EXPECT_EQ(fine.extraordinary, 4);
  EXPECT_EQ(fine.boundaryLoops, 2);
  EXPECT_LT(highest(coarse), 0.05f);  // flat where the plane has its bump
  EXPECT_GT(highest(fine), 2.0f);     // the bump is there
  EXPECT_GT(fine.mesh.triangles.size(), 2 * coarse.mesh.triangles.size());
  (void)nv1;
  // A level past the limit, and a ring that does not fit the level's grid, are refused.
  EXPECT_THROW(attachCylinder(plane, a0, a1, a0, a1, limb, 3, false, 4), ModelError);
  EXPECT_THROW(attachCylinder(plane, 3, 6, 3, 6, limb, 3, false, 1), ModelError);
}

TEST(HsAttachment, WhatDoesNotFitIsRefusedWithTheReason) {
  const HSpline plane = hsplinePlane(10, 10, 90, 90);
  auto message = [&](int i1, const HSpline& c, int subdivisions) {
    try {
      attachCylinder(plane, 3, i1, 3, 6, c, subdivisions);
    } catch (const ModelError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const HSpline cylinder = cylinderOverRing(plane, 5);
  EXPECT_NE(message(7, cylinder, 2).find("the ring around the rectangle has 14"),
            std::string::npos);
  EXPECT_NE(message(12, cylinder, 2).find("must lie inside the parent's 10 x 10 CVs"),
            std::string::npos);
  EXPECT_NE(message(6, cylinder, 9).find("subdivisions must be 0 to 6"), std::string::npos);
  EXPECT_NE(message(6, plane, 2).find("periodic around"), std::string::npos);
}
