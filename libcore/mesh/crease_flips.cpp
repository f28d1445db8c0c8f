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

bool flipCrease(const Triangle& first, const Triangle& second, const std::vector<Vec3f>& P,
                Triangle* newFirst, Triangle* newSecond) {
  // the pair in a fixed order, whichever triangle was met first
  const bool swap = P[second[0]] < P[first[0]];
  const Triangle& t1 = swap ? second : first;
  const Triangle& t2 = swap ? first : second;
  const std::uint32_t v1 = t1[0], a = t1[1], b = t1[2], v2 = t2[0];
  if (!wellShaped(P[v1], P[a], P[v2]) || !wellShaped(P[v1], P[v2], P[b])) return false;
  const Vec3d before1 = triangleCross(P[v1], P[a], P[b]),
              before2 = triangleCross(P[v2], P[b], P[a]);
  const Vec3d was = {before1[0] + before2[0], before1[1] + before2[1], before1[2] + before2[2]};
  const Vec3d after1 = triangleCross(P[v1], P[a], P[v2]),
              after2 = triangleCross(P[v1], P[v2], P[b]);
  // Taken where both new triangles face the side the two old ones face together (the old
  // pair nearly flat: no fold made), where the old pair folds by over 90 degrees along a-b
  // (a crease cut across at the face, a on one side of it and b on the other: the new edge
  // v1-v2 follows it), or where the new pair folds less than the old. Never where the new
  // triangles would overlap: that needs v1-v2 to cross the face on the line through a and
  // b, beyond them, and then the four points lie in one plane with v1 and v2 on either side
  // of that line, so the old pair is flat and the new one folded back by 180 degrees, which
  // no rule here takes (docs/mesher.md, "Sharp features").
  const bool sameSide = dot(after1, was) > 0.0 && dot(after2, was) > 0.0;
  const double oldTurn =
      dot(before1, before2) / std::sqrt(dot(before1, before1) * dot(before2, before2));
  const double newTurn = dot(after1, after2) / std::sqrt(dot(after1, after1) * dot(after2, after2));
  if (!sameSide && !(oldTurn < 0.0) && !(newTurn > oldTurn)) return false;
  *(swap ? newSecond : newFirst) = {v1, a, v2};
  *(swap ? newFirst : newSecond) = {v1, v2, b};
  return true;
}

std::vector<std::uint32_t> flipCreases(TriangleMesh& mesh,
                                       const std::vector<std::uint32_t>& flippable) {
  // directed edge a -> b of each listed triangle (apex, a, b), sorted for lookups
  std::vector<std::pair<std::uint64_t, std::uint32_t>> byEdge;
  byEdge.reserve(flippable.size());
  auto key = [](std::uint32_t a, std::uint32_t b) { return (std::uint64_t(a) << 32) | b; };
  for (std::uint32_t t : flippable)
    byEdge.emplace_back(key(mesh.triangles[t][1], mesh.triangles[t][2]), t);
  std::sort(byEdge.begin(), byEdge.end());
  // each listed triangle's partner, found before any flip changes a triangle
  std::vector<std::uint32_t> unpaired;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  for (std::uint32_t t1 : flippable) {
    const Triangle& t = mesh.triangles[t1];
    const auto at = std::lower_bound(byEdge.begin(), byEdge.end(),
                                     std::make_pair(key(t[2], t[1]), std::uint32_t(0)));
    if (at == byEdge.end() || at->first != key(t[2], t[1])) {
      unpaired.push_back(t1);
      continue;
    }
    if (at->second > t1) pairs.emplace_back(t1, at->second);  // each pair once
  }
  for (const auto& [t1, t2] : pairs) {
    Triangle f1, f2;
    if (flipCrease(mesh.triangles[t1], mesh.triangles[t2], mesh.positions, &f1, &f2)) {
      mesh.triangles[t1] = f1;
      mesh.triangles[t2] = f2;
    }
  }
  return unpaired;
}

}  // namespace frep
