#include "frep/structural_bounds.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "frep/node_helpers.h"

namespace frep {

namespace {

Vec3 corner(const Box3& b, int k) {
  return {(k & 1) ? b.hi[0] : b.lo[0], (k & 2) ? b.hi[1] : b.lo[1], (k & 4) ? b.hi[2] : b.lo[2]};
}

Box3 boundsOf(const NodePtr& n, std::map<const Node*, Box3>& memo) {
  const auto found = memo.find(n.get());
  if (found != memo.end()) return found->second;
  std::vector<Box3> inputs;
  for (const NodePtr& i : n->inputs) inputs.push_back(boundsOf(i, memo));
  const Box3 b = n->type->bounds ? n->type->bounds(*n, inputs) : unknownBounds();
  memo[n.get()] = b;
  return b;
}
}  // namespace

Box3 unknownBounds() {
  return Box3{{-kInf, -kInf, -kInf}, {kInf, kInf, kInf}};
}

bool isFinite(const Box3& b) {
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(b.lo[a]) || !std::isfinite(b.hi[a])) return false;
  return true;
}

Box3 boxAround(const Vec3& center, const Vec3& half) {
  return Box3{{center[0] - half[0], center[1] - half[1], center[2] - half[2]},
              {center[0] + half[0], center[1] + half[1], center[2] + half[2]}};
}

Box3 paddedBox(const Box3& b, double pad) {
  return Box3{{b.lo[0] - pad, b.lo[1] - pad, b.lo[2] - pad},
              {b.hi[0] + pad, b.hi[1] + pad, b.hi[2] + pad}};
}

Box3 pointsBounds(const std::vector<Vec3>& points, double pad) {
  Box3 b = boxAround(points.at(0), {pad, pad, pad});
  for (const Vec3& q : points) b = boxHull(b, boxAround(q, {pad, pad, pad}));
  return b;
}

Box3 affineImage(const Mat34& m, const Box3& b) {
  Box3 r;
  for (int row = 0; row < 3; ++row) {
    double lo = m[row * 4 + 3], hi = lo;
    for (int j = 0; j < 3; ++j) {
      const double k = m[row * 4 + j];
      if (k == 0.0) continue;  // an infinite side times 0 adds nothing
      lo += k > 0 ? k * b.lo[j] : k * b.hi[j];
      hi += k > 0 ? k * b.hi[j] : k * b.lo[j];
    }
    r.lo[row] = lo;
    r.hi[row] = hi;
  }
  return r;
}

Box3 cylinderBounds(const Vec3& origin, const Vec3& axis, double lo, double hi, double radius) {
  Box3 r;
  for (int i = 0; i < 3; ++i) {
    // A disc of the radius across the axis reaches radius * sqrt(1 - axis_i^2) along axis i.
    const double across = radius * std::sqrt(std::max(0.0, 1.0 - axis[i] * axis[i]));
    // axis_i = 0: the extent along i does not depend on lo and hi (which may be infinite).
    const double a = origin[i] + (axis[i] == 0.0 ? 0.0 : lo * axis[i]);
    const double b = origin[i] + (axis[i] == 0.0 ? 0.0 : hi * axis[i]);
    r.lo[i] = std::min(a, b) - across;
    r.hi[i] = std::max(a, b) + across;
  }
  return r;
}

void radialExtent(const Box3& b, const Vec3& origin, const Vec3& axis, double* radius, double* lo,
                  double* hi) {
  // Distance from a line is convex, so its maximum over a box is at a corner.
  *radius = 0.0;
  *lo = kInf;
  *hi = -kInf;
  for (int k = 0; k < 8; ++k) {
    const Vec3 c = corner(b, k);
    const Vec3 d = {c[0] - origin[0], c[1] - origin[1], c[2] - origin[2]};
    const double t = d[0] * axis[0] + d[1] * axis[1] + d[2] * axis[2];
    const double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] - t * t;
    *radius = std::max(*radius, std::sqrt(std::max(0.0, r2)));
    *lo = std::min(*lo, t);
    *hi = std::max(*hi, t);
  }
}

Box3 turnedAboutAxis(const Box3& b, const Vec3& origin, const Vec3& axis) {
  // Turning keeps the distance from the axis and the height along it.
  if (!isFinite(b)) return unknownBounds();
  const Vec3 w = normalized(axis);
  double radius, lo, hi;
  radialExtent(b, origin, w, &radius, &lo, &hi);
  return cylinderBounds(origin, w, lo, hi, radius);
}

Box3 structuralBounds(const NodePtr& root) {
  std::map<const Node*, Box3> memo;
  return boundsOf(root, memo);
}

}  // namespace frep
