#include "hspline/hspline_envelope.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "base/affine.h"
#include "base/errors.h"

namespace frep {
namespace {

struct Joint {
  std::size_t before = 0, after = 0;  // the segments meeting there
  Vec3 point{0, 0, 0};
  Vec3 normal{0, 0, 0};  // of the plane halfway between the segments' directions
};

struct Weights {
  std::size_t a = 0, b = 0;  // b == a: one segment
  double wb = 0;
  const Joint* joint = nullptr;
};

Vec3 mapPoint(const Mat34& m, const Vec3& p) {
  return {m[0] * p[0] + m[1] * p[1] + m[2] * p[2] + m[3],
          m[4] * p[0] + m[5] * p[1] + m[6] * p[2] + m[7],
          m[8] * p[0] + m[9] * p[1] + m[10] * p[2] + m[11]};
}

double distanceToSegment(const HsSegment& s, const Vec3& p) {
  const Vec3 d = vsub(s.end, s.start);
  const double t = std::clamp(vdot(vsub(p, s.start), d) / vdot(d, d), 0.0, 1.0);
  Vec3 q = s.start;
  vaxpy(q, t, d);
  return vlength(vsub(p, q));
}

void checkSegments(const std::vector<HsSegment>& segments) {
  if (segments.empty()) throw ModelError("envelope: no segments were given");
  for (std::size_t k = 0; k < segments.size(); ++k) {
    const HsSegment& s = segments[k];
    const std::string name = "envelope: segment " + std::to_string(k + 1);
    for (double x : s.motion)
      if (!std::isfinite(x)) throw ModelError(name + ": its motion must be finite");
    if (!(vlength(vsub(s.end, s.start)) > 0))
      throw ModelError(name + " has zero length; a segment runs from one point to another");
    if (!isRigid(s.motion))
      throw ModelError(name +
                       ": its motion must be rigid (a rotation and a translation, "
                       "no scaling or mirroring)");
  }
}

std::vector<Joint> jointsOf(const std::vector<HsSegment>& segments) {
  double size = 0;
  for (const HsSegment& s : segments) size = std::max(size, vlength(vsub(s.end, s.start)));
  std::vector<Joint> joints;
  for (std::size_t k = 0; k + 1 < segments.size(); ++k) {
    const HsSegment &a = segments[k], &b = segments[k + 1];
    if (vlength(vsub(a.end, b.start)) > 1e-6 * size) continue;
    const Vec3 n = vadd(vscale(vsub(a.end, a.start), 1 / vlength(vsub(a.end, a.start))),
                        vscale(vsub(b.end, b.start), 1 / vlength(vsub(b.end, b.start))));
    if (vlength(n) < 1e-9) continue;  // folded straight back: no plane between them
    joints.push_back({k, k + 1, a.end, vscale(n, 1 / vlength(n))});
  }
  return joints;
}

// The nearest segment; within `reach` of one of its joints (measured across the joint's
// plane), that joint's two segments with a smooth weight going from one to the other.
Weights weightsAt(const std::vector<HsSegment>& segments, const std::vector<Joint>& joints,
                  const Vec3& p, double reach) {
  Weights w;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < segments.size(); ++k) {
    const double d = distanceToSegment(segments[k], p);
    if (d < best) best = d, w.a = w.b = k;
  }
  if (reach <= 0) return w;
  double closest = reach;
  for (const Joint& j : joints) {
    if (j.before != w.a && j.after != w.a) continue;
    const double s = vdot(vsub(p, j.point), j.normal);
    if (std::abs(s) >= closest) continue;
    closest = std::abs(s);
    const double t = 0.5 + s / (2 * reach);
    w.a = j.before, w.b = j.after, w.wb = t * t * (3 - 2 * t), w.joint = &j;
  }
  return w;
}

// Where the weights carry rest point p: one segment's motion, or the two segments' rotations
// interpolated about the joint, which goes where the two motions take it (they agree there
// when the skeleton stays joined; otherwise their average).
Vec3 carried(const std::vector<HsSegment>& segments, const Weights& w, const Vec3& p) {
  const Mat34& ma = segments[w.a].motion;
  if (w.b == w.a || w.wb <= 0) return mapPoint(ma, p);
  const Mat34& mb = segments[w.b].motion;
  if (w.wb >= 1) return mapPoint(mb, p);
  return mapPoint(rotationAbout(ma, mb, w.wb, w.joint->point), p);
}

double meanControlEdge(const HSpline& h) {
  const HsLevel& l0 = h.level(0);
  double sum = 0;
  std::size_t n = 0;
  for (const HsCv& cv : l0.cvs)
    for (const auto& [di, dj] : {std::pair{1, 0}, std::pair{0, 1}}) {
      const HsCv* next = h.find(0, cv.i + di, cv.j + dj);
      if (next && next != &cv) sum += vlength(vsub(next->value, cv.value)), ++n;
    }
  return n ? sum / static_cast<double>(n) : 0;
}

}  // namespace

HsEnvelope envelope(const HSpline& rest, const std::vector<HsSegment>& segments,
                    const HsEnvelopeSettings& settings) {
  checkSegments(segments);
  if (!(settings.jointReach >= 0) || !std::isfinite(settings.jointReach))
    throw ModelError("envelope: the joint reach must be 0 (sized from the surface) or more");
  for (int level : settings.levels)
    if (level < 0 || level >= HSpline::kMaxLevels)
      throw ModelError("envelope: level " + std::to_string(level) + " is not a level (0 to " +
                       std::to_string(HSpline::kMaxLevels - 1) + ")");
  HsEnvelope out;
  const std::vector<Joint> joints = jointsOf(segments);
  for (const Joint& j : joints) out.joints.push_back(j.point);
  out.jointReach = settings.jointReach > 0 ? settings.jointReach : 1.25 * meanControlEdge(rest);

  HSpline bound = rest;
  if (settings.refineJoints && !joints.empty()) {
    std::vector<std::pair<int, int>> near;
    for (const HsCv& cv : rest.level(0).cvs)
      for (const Joint& j : joints)
        if (std::abs(vdot(vsub(cv.value, j.point), j.normal)) < out.jointReach) {
          near.emplace_back(cv.i, cv.j);
          break;
        }
    if (!near.empty()) bound.refine(0, near);
  }

  std::vector<int> levels = settings.levels;
  std::sort(levels.begin(), levels.end());
  levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
  out.boundPerSegment.assign(segments.size(), 0);
  out.boundPerLevel.assign(settings.levels.size(), 0);
  out.surface = bound;
  for (int level : levels) {
    if (level >= bound.levelCount()) continue;
    // Rest positions first: moving a coarser CV must not change where a finer one is bound.
    const std::vector<Vec3> restPositions = bound.positions(level);
    const double reach = level == 0 ? 0.0 : out.jointReach;
    std::size_t count = 0;
    for (std::size_t k = 0; k < restPositions.size(); ++k) {
      const HsCv& cv = bound.level(level).cvs[k];
      if (!bound.movable(level, cv.i, cv.j)) continue;
      const Weights w = weightsAt(segments, joints, restPositions[k], reach);
      out.surface.moveCv(level, cv.i, cv.j, carried(segments, w, restPositions[k]));
      ++out.boundPerSegment[w.wb > 0.5 ? w.b : w.a];
      if (w.b != w.a && w.wb > 0 && w.wb < 1) ++out.blended;
      ++count;
    }
    for (std::size_t e = 0; e < settings.levels.size(); ++e)
      if (settings.levels[e] == level) out.boundPerLevel[e] = count;
  }
  return out;
}

}  // namespace frep
