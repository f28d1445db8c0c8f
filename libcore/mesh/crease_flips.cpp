#include "mesh/crease_flips.h"

#include <algorithm>
#include <cmath>

#include "base/triangle_geometry.h"

namespace frep {

namespace {

double dot(const Vec3d& u, const Vec3d& v) {
  return u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
}

double squaredLength(const Vec3f& p, const Vec3f& q) {
  double s = 0.0;
  for (int a = 0; a < 3; ++a) s += (double(q[a]) - p[a]) * (double(q[a]) - p[a]);
  return s;
}

// Twice the area against the longest side squared: 0 for a degenerate triangle.
bool wellShaped(const Vec3f& a, const Vec3f& b, const Vec3f& c) {
  const Vec3d n = triangleCross(a, b, c);
  const double longest = std::max({squaredLength(a, b), squaredLength(b, c), squaredLength(c, a)});
  return std::sqrt(dot(n, n)) > 1e-3 * longest;
}

}  // namespace

void flipCreases(TriangleMesh& mesh, const std::vector<std::uint32_t>& flippable) {
  // directed edge a -> b of each listed triangle (apex, a, b), sorted for lookups
  std::vector<std::pair<std::uint64_t, std::uint32_t>> byEdge;
  byEdge.reserve(flippable.size());
  auto key = [](std::uint32_t a, std::uint32_t b) { return (std::uint64_t(a) << 32) | b; };
  for (std::uint32_t t : flippable)
    byEdge.emplace_back(key(mesh.triangles[t][1], mesh.triangles[t][2]), t);
  std::sort(byEdge.begin(), byEdge.end());
  const std::vector<Vec3f>& P = mesh.positions;
  for (std::uint32_t t1 : flippable) {
    const Triangle first = mesh.triangles[t1];
    const std::uint32_t v1 = first[0], a = first[1], b = first[2];
    const auto at =
        std::lower_bound(byEdge.begin(), byEdge.end(), std::make_pair(key(b, a), std::uint32_t(0)));
    if (at == byEdge.end() || at->first != key(b, a)) continue;
    const std::uint32_t t2 = at->second;
    if (t2 < t1) continue;  // each pair once
    const std::uint32_t v2 = mesh.triangles[t2][0];
    if (!wellShaped(P[v1], P[a], P[v2]) || !wellShaped(P[v1], P[v2], P[b])) continue;
    const Vec3d before1 = triangleCross(P[v1], P[a], P[b]),
                before2 = triangleCross(P[v2], P[b], P[a]);
    const Vec3d was = {before1[0] + before2[0], before1[1] + before2[1], before1[2] + before2[2]};
    if (!(dot(triangleCross(P[v1], P[a], P[v2]), was) > 0.0) ||
        !(dot(triangleCross(P[v1], P[v2], P[b]), was) > 0.0))
      continue;
    mesh.triangles[t1] = {v1, a, v2};
    mesh.triangles[t2] = {v1, v2, b};
  }
}

}  // namespace frep
