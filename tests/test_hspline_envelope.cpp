// Enveloping: CVs bound to skeleton segments, finer levels following their parents' frames,
// and seed 003's figure 3.2 (a joint enveloped on a refined level bends without collapsing,
// where blending every CV's position between the segments loses volume).
#include <gtest/gtest.h>

#include <cmath>

#include "base/errors.h"
#include "hspline/hspline.h"
#include "hspline/hspline_envelope.h"
#include "hspline/hspline_shapes.h"

using namespace frep;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Rotation about the x axis through c.
Mat34 rotationX(double degrees, const Vec3& c) {
  const double a = degrees * kPi / 180, co = std::cos(a), si = std::sin(a);
  // q = R (p - c) + c
  return {1, 0,  0,   0,
          0, co, -si, c[1] - co * c[1] + si * c[2],
          0, si, co,  c[2] - si * c[1] - co * c[2]};
}

Vec3 mapPoint(const Mat34& m, const Vec3& p) {
  return {m[0] * p[0] + m[1] * p[1] + m[2] * p[2] + m[3],
          m[4] * p[0] + m[5] * p[1] + m[6] * p[2] + m[7],
          m[8] * p[0] + m[9] * p[1] + m[10] * p[2] + m[11]};
}

// The surface sampled on a grid of its domain (u around, v along).
std::vector<std::vector<Vec3>> grid(const HSpline& h, int nu, int nv) {
  const HsLevel& l = h.level(0);
  const double u0 = l.u.lo(), u1 = l.u.hi();
  const double v0 = l.v.lo(), v1 = l.v.hi();
  std::vector<std::vector<Vec3>> rows;
  for (int b = 0; b <= nv; ++b) {
    std::vector<Vec3> row;
    for (int a = 0; a < nu; ++a)
      row.push_back(h.evaluate(u0 + (u1 - u0) * a / nu, v0 + (v1 - v0) * b / nv).position);
    rows.push_back(row);
  }
  return rows;
}

// The volume of a tube closed by flat fans at its two end rings (divergence theorem).
double tubeVolume(const HSpline& h) {
  const auto p = grid(h, 64, 160);
  const auto tet = [](const Vec3& a, const Vec3& b, const Vec3& c) {
    return vdot(a, vcross(b, c)) / 6;
  };
  double v = 0;
  const std::size_t nu = p[0].size();
  for (std::size_t b = 0; b + 1 < p.size(); ++b)
    for (std::size_t a = 0; a < nu; ++a) {
      const std::size_t n = (a + 1) % nu;
      v += tet(p[b][a], p[b][n], p[b + 1][n]) + tet(p[b][a], p[b + 1][n], p[b + 1][a]);
    }
  for (const auto& [row, sign] : {std::pair{std::size_t{0}, -1.0}, {p.size() - 1, 1.0}}) {
    Vec3 c{0, 0, 0};
    for (const Vec3& q : p[row]) vaxpy(c, 1.0 / static_cast<double>(nu), q);
    for (std::size_t a = 0; a < nu; ++a) v += sign * tet(c, p[row][a], p[row][(a + 1) % nu]);
  }
  return std::abs(v);
}

struct Arm {
  HSpline tube = hsplineCylinder(8, 12, 10, 80);
  Vec3 joint{0, 0, 40};
  std::vector<HsSegment> bent(double degrees) const {
    return {{{0, 0, 0}, joint, rotationX(0, joint)},
            {joint, {0, 0, 80}, rotationX(degrees, joint)}};
  }
};

// The usual enveloping that seed 003's figure 1.2 shows collapsing: every level-0 CV's
// position averaged between the two segments' motions, over the same band around the joint.
HSpline everyCvBlended(const HSpline& rest, const std::vector<HsSegment>& s, double reach) {
  HSpline out = rest;
  const auto positions = rest.positions(0);
  for (std::size_t k = 0; k < positions.size(); ++k) {
    const Vec3& p = positions[k];
    const double t = std::clamp(0.5 + (p[2] - 40) / (2 * reach), 0.0, 1.0);
    const double w = t * t * (3 - 2 * t);
    const Vec3 q =
        vadd(vscale(mapPoint(s[0].motion, p), 1 - w), vscale(mapPoint(s[1].motion, p), w));
    out.moveCv(0, rest.level(0).cvs[k].i, rest.level(0).cvs[k].j, q);
  }
  return out;
}

}  // namespace

TEST(HsEnvelope, AJointEnvelopedOnARefinedLevelKeepsItsVolume) {
  const Arm arm;
  const double restVolume = tubeVolume(arm.tube);
  EXPECT_NEAR(restVolume, kPi * 100 * 80, 0.01 * kPi * 100 * 80);
  for (const auto& [degrees, kept, naiveLoss] :
       {std::tuple{90.0, 0.025, 0.05}, std::tuple{120.0, 0.04, 0.08}}) {
    const auto segments = arm.bent(degrees);
    const HsEnvelope e = envelope(arm.tube, segments, HsEnvelopeSettings{});
    ASSERT_EQ(e.joints.size(), 1u);
    EXPECT_GE(e.surface.levelCount(), 2);  // refined around the joint
    EXPECT_GT(e.blended, 0u);
    EXPECT_GT(e.boundPerLevel[1], 0u);
    const double hierarchical = tubeVolume(e.surface) / restVolume;
    const double naive = tubeVolume(everyCvBlended(arm.tube, segments, e.jointReach)) / restVolume;
    EXPECT_NEAR(hierarchical, 1.0, kept) << degrees << " degrees";
    EXPECT_LT(naive, 1.0 - naiveLoss) << degrees << " degrees";
    // The far end went rigidly with the rotated segment.
    const auto end = grid(e.surface, 16, 4).back();
    const auto restEnd = grid(arm.tube, 16, 4).back();
    for (std::size_t a = 0; a < end.size(); ++a)
      EXPECT_LT(vlength(vsub(end[a], mapPoint(segments[1].motion, restEnd[a]))), 1e-9);
  }
}

TEST(HsEnvelope, EnvelopingOnlyLevelZeroCollapsesMoreThanTheHierarchy) {
  const Arm arm;
  HsEnvelopeSettings levelZero;
  levelZero.levels = {0};
  levelZero.refineJoints = false;
  const auto segments = arm.bent(90);
  const double rest = tubeVolume(arm.tube);
  const double coarse = tubeVolume(envelope(arm.tube, segments, levelZero).surface) / rest;
  const double fine = tubeVolume(envelope(arm.tube, segments, {}).surface) / rest;
  EXPECT_LT(coarse, fine - 0.03);
}

TEST(HsEnvelope, RestPoseChangesNothing) {
  const Arm arm;
  const HsEnvelope e = envelope(arm.tube, arm.bent(0), HsEnvelopeSettings{});
  const auto a = grid(arm.tube, 24, 40), b = grid(e.surface, 24, 40);
  for (std::size_t r = 0; r < a.size(); ++r)
    for (std::size_t c = 0; c < a[r].size(); ++c) EXPECT_LT(vlength(vsub(a[r][c], b[r][c])), 1e-9);
}

TEST(HsEnvelope, FinerLevelsFollowTheirParentsFrames) {
  // A bump modelled on level 1, not enveloped: one segment turning the whole tube carries the
  // bump with it, exactly, through the frames its offsets are measured in.
  HSpline tube = hsplineCylinder(8, 12, 10, 80);
  tube.refine(0, {{2, 5}, {3, 5}});
  for (const HsCv& cv : std::vector<HsCv>(tube.level(1).cvs))
    if (tube.movable(1, cv.i, cv.j)) tube.setValue(1, cv.i, cv.j, {0.5, -0.25, 3});
  const Mat34 turn = rotationX(70, {0, 5, 30});
  HsEnvelopeSettings s;
  s.levels = {0};
  const HsEnvelope e = envelope(tube, {{{0, 0, 0}, {0, 0, 80}, turn}}, s);
  EXPECT_EQ(e.boundPerLevel[0], tube.level(0).cvs.size());
  const auto a = grid(tube, 24, 40), b = grid(e.surface, 24, 40);
  for (std::size_t r = 0; r < a.size(); ++r)
    for (std::size_t c = 0; c < a[r].size(); ++c)
      EXPECT_LT(vlength(vsub(mapPoint(turn, a[r][c]), b[r][c])), 1e-9);
}

TEST(HsEnvelope, BadSegmentsAreRefusedWithTheReason) {
  const Arm arm;
  const auto message = [&](std::vector<HsSegment> s, HsEnvelopeSettings settings = {}) {
    try {
      envelope(arm.tube, s, settings);
    } catch (const ModelError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message({}).find("no segments"), std::string::npos);
  auto s = arm.bent(30);
  s[1].end = s[1].start;
  EXPECT_NE(message(s).find("segment 2 has zero length"), std::string::npos);
  s = arm.bent(30);
  s[0].motion[0] = 2;  // a stretch
  EXPECT_NE(message(s).find("segment 1: its motion must be rigid"), std::string::npos);
  s = arm.bent(30);
  s[1].motion[5] = -s[1].motion[5], s[1].motion[6] = -s[1].motion[6];  // a mirror
  EXPECT_NE(message(s).find("must be rigid"), std::string::npos);
  HsEnvelopeSettings bad;
  bad.jointReach = -1;
  EXPECT_NE(message(arm.bent(30), bad).find("joint reach"), std::string::npos);
  bad = {};
  bad.levels = {-1};
  EXPECT_NE(message(arm.bent(30), bad).find("level -1"), std::string::npos);
}
