#include "mesh/flat_vertex_removal.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "base/triangle_geometry.h"

// Why the planned fan cannot meet another triangle but where they share a vertex or an edge.
// Everything is judged in projection along the star's normal N.
// - The star's triangles all face along N and wind once round v, so the polygon of v's
//   neighbours is star-shaped from v: a simple polygon.
// - A fan over a polygon covers each point inside it, counting its triangles with their signs,
//   as often as the polygon winds round the point: once inside, never outside. With every
//   triangle facing along N none counts negative, so the fan tiles the polygon exactly: its
//   triangles meet each other only along their shared edges.
// - No other triangle of the region reaches into the polygon (none of its vertices is inside
//   or near the polygon, none of its edges crosses or nears an edge of the polygon that it
//   does not share, no vertex of the polygon lies in or near it; or, quicker, the line of one
//   edge of the polygon has the polygon's other vertices inside and the triangle's corners
//   outside, by a margin, but for that edge's ends), so in projection it meets the new fan
//   only on the polygon's boundary. There the fan's points are the polygon's
//   edges themselves, edges of the mesh before, which that triangle met only where it shares
//   them (the mesh was embedded).
// - Every triangle outside the region lies outside the box but for its boundary, and the fan
//   lies inside the polygon's convex hull, in the box; no new edge lies in a face of the box,
//   so the fan meets the box's boundary only on edges and vertices the mesh had.
// - No new edge is an edge already: the surface stays 2-manifold.

namespace frep {
namespace {

struct Point2 {
  double x, y;
};

// i mod k for i < 2k: the ring's indices wrap at most once (an integer division per index
// was a tenth of the planning).
std::size_t wrap(std::size_t i, std::size_t k) {
  return i < k ? i : i - k;
}

double orient(const Point2& a, const Point2& b, const Point2& c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

double pointSegmentDistance2(const Point2& p, const Point2& a, const Point2& b) {
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double len2 = dx * dx + dy * dy;
  double t = len2 > 0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  const double ex = p.x - a.x - t * dx, ey = p.y - a.y - t * dy;
  return ex * ex + ey * ey;
}

// Whether segments ab and cd cross or come within eps (eps2 its square) of each other.
bool segmentsNear(const Point2& a, const Point2& b, const Point2& c, const Point2& d, double eps,
                  double eps2) {
  // (apart by more than eps on an axis: neither)
  if (std::max(a.x, b.x) + eps < std::min(c.x, d.x) ||
      std::max(c.x, d.x) + eps < std::min(a.x, b.x) ||
      std::max(a.y, b.y) + eps < std::min(c.y, d.y) ||
      std::max(c.y, d.y) + eps < std::min(a.y, b.y))
    return false;
  const double o1 = orient(a, b, c), o2 = orient(a, b, d);
  const double o3 = orient(c, d, a), o4 = orient(c, d, b);
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0)))
    return true;
  return pointSegmentDistance2(a, c, d) < eps2 || pointSegmentDistance2(b, c, d) < eps2 ||
         pointSegmentDistance2(c, a, b) < eps2 || pointSegmentDistance2(d, a, b) < eps2;
}

// The number of times the closed polygon winds round p.
int windingNumber(const Point2& p, const Point2* poly, std::size_t k) {
  int winding = 0;
  for (std::size_t i = 0; i < k; ++i) {
    const Point2 &a = poly[i], &b = poly[wrap(i + 1, k)];
    if (a.y <= p.y) {
      if (b.y > p.y && orient(a, b, p) > 0) ++winding;
    } else if (b.y <= p.y && orient(a, b, p) < 0) {
      --winding;
    }
  }
  return winding;
}

// Whether p lies inside the closed polygon or within eps (eps2 its square) of its boundary.
bool inOrNearPolygon(const Point2& p, const Point2* poly, std::size_t k, double eps, double eps2) {
  if (windingNumber(p, poly, k) != 0) return true;
  for (std::size_t i = 0; i < k; ++i) {
    const Point2 &a = poly[i], &b = poly[wrap(i + 1, k)];
    if (p.x + eps < std::min(a.x, b.x) || p.x - eps > std::max(a.x, b.x) ||
        p.y + eps < std::min(a.y, b.y) || p.y - eps > std::max(a.y, b.y))
      continue;
    if (pointSegmentDistance2(p, a, b) < eps2) return true;
  }
  return false;
}

// Whether p lies inside triangle abc (either orientation) or within sqrt(eps2) of its edges.
bool inOrNearTriangle(const Point2& p, const Point2& a, const Point2& b, const Point2& c,
                      double eps2) {
  const double o1 = orient(a, b, p), o2 = orient(b, c, p), o3 = orient(c, a, p);
  if ((o1 >= 0 && o2 >= 0 && o3 >= 0) || (o1 <= 0 && o2 <= 0 && o3 <= 0)) return true;
  return pointSegmentDistance2(p, a, b) < eps2 || pointSegmentDistance2(p, b, c) < eps2 ||
         pointSegmentDistance2(p, c, a) < eps2;
}

// The point's coordinates in the plan's plane, relative to its vertex (and its height).
Point2 project(const FlatVertexRemoval& plan, const Vec3f& p, double* height) {
  const double d[3] = {double(p[0]) - plan.origin[0], double(p[1]) - plan.origin[1],
                       double(p[2]) - plan.origin[2]};
  if (height) *height = d[0] * plan.n[0] + d[1] * plan.n[1] + d[2] * plan.n[2];
  return {d[0] * plan.u[0] + d[1] * plan.u[1] + d[2] * plan.u[2],
          d[0] * plan.w[0] + d[1] * plan.w[1] + d[2] * plan.w[2]};
}

}  // namespace

bool planFlatVertexRemoval(std::uint32_t v, const std::vector<Vec3f>& positions,
                           const std::vector<Triangle>& region, const double boxLo[3],
                           const double boxHi[3], double maxDeviation, double minQuality,
                           FlatVertexRemoval* plan) {
  constexpr std::size_t kMaxRing = FlatVertexRemoval::kMaxRing;
  // 1. The star, as spokes (a, b) of triangles (v, a, b), and the ring of neighbours.
  std::size_t k = 0;
  std::uint32_t from[kMaxRing], to[kMaxRing];
  for (std::size_t i = 0; i < region.size(); ++i) {
    const Triangle& t = region[i];
    for (int c = 0; c < 3; ++c) {
      if (t[c] != v) continue;
      if (k == kMaxRing) return false;
      from[k] = t[(c + 1) % 3];
      to[k] = t[(c + 2) % 3];
      plan->star[k++] = static_cast<std::uint32_t>(i);
    }
  }
  plan->size = k;
  if (k < 4) return false;  // (a triangle's corner: nothing to gain)
  std::uint32_t* ring = plan->ring;
  ring[0] = from[0];
  for (std::size_t step = 0; step < k; ++step) {
    std::size_t found = k;
    for (std::size_t s = 0; s < k; ++s)
      if (from[s] == ring[step]) {
        if (found != k) return false;  // v's star is not one fan
        found = s;
      }
    if (found == k) return false;
    if (step + 1 < k) {
      ring[step + 1] = to[found];
    } else if (to[found] != ring[0]) {
      return false;
    }
  }
  for (std::size_t i = 0; i < k; ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (ring[i] == ring[j]) return false;

  // 2. The plane the star faces, and every point in it relative to v.
  const Vec3f& pv = positions[v];
  Vec3d n{0, 0, 0};
  for (std::size_t s = 0; s < k; ++s) {
    const Vec3d c = triangleCross(pv, positions[from[s]], positions[to[s]]);
    for (int a = 0; a < 3; ++a) n[a] += c[a];
  }
  const double len = norm(n);
  if (!(len > 0.0) || !std::isfinite(len)) return false;
  for (double& x : n) x /= len;
  const int least = std::fabs(n[0]) <= std::fabs(n[1]) && std::fabs(n[0]) <= std::fabs(n[2]) ? 0
                    : std::fabs(n[1]) <= std::fabs(n[2])                                     ? 1
                                                                                             : 2;
  Vec3d e{0, 0, 0};
  e[least] = 1.0;
  Vec3d w{n[1] * e[2] - n[2] * e[1], n[2] * e[0] - n[0] * e[2], n[0] * e[1] - n[1] * e[0]};
  const double wl = norm(w);
  for (double& x : w) x /= wl;
  plan->origin = {pv[0], pv[1], pv[2]};
  plan->n = n;
  plan->w = w;
  plan->u = {w[1] * n[2] - w[2] * n[1], w[2] * n[0] - w[0] * n[2], w[0] * n[1] - w[1] * n[0]};
  Point2 poly[kMaxRing];
  double height[kMaxRing];
  double reach2 = 0.0;
  for (std::size_t i = 0; i < k; ++i) {
    poly[i] = project(*plan, positions[ring[i]], &height[i]);
    plan->poly[i][0] = poly[i].x;
    plan->poly[i][1] = poly[i].y;
    reach2 = std::max(reach2, poly[i].x * poly[i].x + poly[i].y * poly[i].y);
  }
  if (!(reach2 > 0.0)) return false;
  const double epsArea = 1e-6 * reach2;
  plan->eps2 = 1e-10 * reach2;  // (lengths: 1e-5 of the polygon's reach)

  // 3. The star faces N and winds once round v (its polygon is then star-shaped from v).
  const Point2 origin{0.0, 0.0};
  for (std::size_t i = 0; i < k; ++i)
    if (!(orient(origin, poly[i], poly[wrap(i + 1, k)]) > epsArea)) return false;
  if (windingNumber(origin, poly, k) != 1) return false;

  // 4. The best fan over the polygon: the one that moves the surface least.
  auto onOneBoxFace = [&](std::uint32_t p, std::uint32_t q) {
    const Vec3f &a = positions[p], &b = positions[q];
    for (int axis = 0; axis < 3; ++axis) {
      const double tol = 1e-6 * (boxHi[axis] - boxLo[axis]);
      if (std::fabs(a[axis] - boxLo[axis]) < tol && std::fabs(b[axis] - boxLo[axis]) < tol)
        return true;
      if (std::fabs(a[axis] - boxHi[axis]) < tol && std::fabs(b[axis] - boxHi[axis]) < tol)
        return true;
    }
    return false;
  };
  auto isEdge = [&](std::uint32_t p, std::uint32_t q) {
    for (const Triangle& t : region)
      for (int c = 0; c < 3; ++c)
        if ((t[c] == p && t[(c + 1) % 3] == q) || (t[c] == q && t[(c + 1) % 3] == p)) return true;
    return false;
  };
  // The fans whose triangles all face along N, by how far they pass from v; then, least first,
  // the first that keeps within maxDeviation everywhere, has no thin triangle and no new edge
  // that is an edge already or lies in a box face.
  double deviationOf[kMaxRing];
  std::size_t coverOf[kMaxRing];  // the fan triangle (apex, apex + j, apex + j + 1) under v
  std::size_t apexes[kMaxRing], candidates = 0;
  for (std::size_t apex = 0; apex < (k == 4 ? 2 : k); ++apex) {
    bool ok = true;
    for (std::size_t j = 1; j + 1 < k && ok; ++j)
      ok = orient(poly[apex], poly[wrap(apex + j, k)], poly[wrap(apex + j + 1, k)]) > epsArea;
    if (!ok) continue;
    // The new surface's height under v: v lies in the fan triangle (apex, b, c) where the
    // spokes from the apex pass from v's left to its right (the fan winds once).
    double deviation = 0.0;
    bool covered = false;
    double left = orient(poly[apex], poly[wrap(apex + 1, k)], origin);  // > 0: a ring edge
    for (std::size_t j = 1; j + 1 < k && !covered; ++j) {
      const std::size_t b = wrap(apex + j, k), c = wrap(apex + j + 1, k);
      const double right = orient(poly[apex], poly[c], origin);
      if (right <= 0.0 || j + 2 == k) {
        const double o0 = orient(poly[b], poly[c], origin), o1 = -right, o2 = left;
        covered = o1 >= 0.0 && o2 >= 0.0;
        coverOf[apex] = j;
        deviation = std::fabs(o0 * height[apex] + o1 * height[b] + o2 * height[c]) / (o0 + o1 + o2);
      }
      left = right;
    }
    if (!covered || !(deviation <= maxDeviation)) continue;
    deviationOf[apex] = deviation;
    apexes[candidates++] = apex;
  }
  // (least deviation first, ties by index: a dozen at most, sorted by insertion; std::sort
  // here drew GCC's array-bounds warning on its unrolled paths)
  auto before = [&](std::size_t x, std::size_t y) {
    return deviationOf[x] < deviationOf[y] || (deviationOf[x] == deviationOf[y] && x < y);
  };
  for (std::size_t i = 1; i < candidates; ++i)
    for (std::size_t j = i; j > 0 && before(apexes[j], apexes[j - 1]); --j)
      std::swap(apexes[j], apexes[j - 1]);
  bool found = false;
  std::size_t bestApex = 0;
  for (std::size_t i = 0; i < candidates && !found; ++i) {
    const std::size_t apex = apexes[i];
    // The two surfaces differ most at v or where a spoke v-r crosses a new diagonal (both
    // are linear along each piece of the overlay).
    double deviation = deviationOf[apex];
    for (std::size_t j = 2; j + 1 < k; ++j) {
      const std::size_t m = wrap(apex + j, k);  // the diagonal apex-m
      // v lies beyond it from the ring vertices apex + 1 .. m - 1 where its fan triangle
      // comes later, else from m + 1 .. apex - 1: only their spokes cross it
      const std::size_t from = coverOf[apex] >= j ? 1 : j + 1, to = coverOf[apex] >= j ? j : k;
      for (std::size_t q = from; q < to; ++q) {
        const std::size_t s = wrap(apex + q, k);
        const Point2 &a = poly[apex], &b = poly[m], &r = poly[s];
        const double den = orient(origin, r, b) - orient(origin, r, a);  // where a-b meets 0-r
        if (den == 0.0) continue;
        const double t = -orient(origin, r, a) / den;  // along a-b
        if (!(t > 0.0 && t < 1.0)) continue;
        const Point2 x{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
        const double along = (x.x * r.x + x.y * r.y) / (r.x * r.x + r.y * r.y);  // along 0-r
        if (!(along > 0.0 && along < 1.0)) continue;
        const double onFan = height[apex] + t * (height[m] - height[apex]);
        deviation = std::max(deviation, std::fabs(onFan - along * height[s]));
      }
    }
    if (!(deviation <= maxDeviation)) continue;
    double worst = std::numeric_limits<double>::infinity();
    bool ok = true;
    for (std::size_t j = 1; j + 1 < k && ok; ++j) {
      const std::size_t b = wrap(apex + j, k), c = wrap(apex + j + 1, k);
      worst = std::min(
          worst, triangleQuality(positions[ring[apex]], positions[ring[b]], positions[ring[c]]));
      ok = worst >= minQuality &&
           (j < 2 || (!onOneBoxFace(ring[apex], ring[b]) && !isEdge(ring[apex], ring[b])));
    }
    if (!ok) continue;
    found = true;
    bestApex = apex;
    plan->deviation = deviation;
    plan->quality = worst;
  }
  if (!found) return false;
  for (std::size_t j = 1; j + 1 < k; ++j)
    plan->replacement[j - 1] = {ring[bestApex], ring[wrap(bestApex + j, k)],
                                ring[wrap(bestApex + j + 1, k)]};
  return true;
}

bool flatVertexRemovalIsClear(const FlatVertexRemoval& plan, const std::vector<Vec3f>& positions,
                              const std::vector<Triangle>& region) {
  const std::size_t k = plan.size;
  Point2 poly[FlatVertexRemoval::kMaxRing];
  Point2 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  Point2 hi{-lo.x, -lo.y};
  for (std::size_t i = 0; i < k; ++i) {
    poly[i] = {plan.poly[i][0], plan.poly[i][1]};
    lo = {std::min(lo.x, poly[i].x), std::min(lo.y, poly[i].y)};
    hi = {std::max(hi.x, poly[i].x), std::max(hi.y, poly[i].y)};
  }
  const double eps2 = plan.eps2, margin = std::sqrt(eps2);
  auto ringIndex = [&](std::uint32_t id) {
    for (std::size_t i = 0; i < k; ++i)
      if (plan.ring[i] == id) return static_cast<int>(i);
    return -1;
  };
  // The polygon's edges whose line has every other ring vertex inside it by the margin: such
  // a line separates the polygon from what lies outside it (a convex polygon's edges all do).
  double edgeLength[FlatVertexRemoval::kMaxRing];
  bool separates[FlatVertexRemoval::kMaxRing];
  for (std::size_t i = 0; i < k; ++i) {
    const std::size_t j = wrap(i + 1, k);
    const Point2 &a = poly[i], &b = poly[j];
    edgeLength[i] = std::sqrt((b.x - a.x) * (b.x - a.x) + (b.y - a.y) * (b.y - a.y));
    separates[i] = edgeLength[i] > 0.0;
    for (std::size_t m = 0; m < k && separates[i]; ++m)
      if (m != i && m != j) separates[i] = orient(a, b, poly[m]) > margin * edgeLength[i];
  }
  // Whether an edge's line has the triangle outside, all but its corners that are that edge's
  // ends: then it meets the polygon only there, at a vertex or along the edge it shares.
  auto separated = [&](const int at[3], const Point2 q[3]) {
    for (std::size_t i = 0; i < k; ++i) {
      if (!separates[i]) continue;
      const std::size_t j = wrap(i + 1, k);
      bool outside = true;
      for (int c = 0; c < 3 && outside; ++c)
        outside = at[c] == static_cast<int>(i) || at[c] == static_cast<int>(j) ||
                  orient(poly[i], poly[j], q[c]) < -margin * edgeLength[i];
      if (outside) return true;
    }
    return false;
  };
  std::size_t nextStar = 0;  // (the star's indices ascend)
  for (std::size_t t = 0; t < region.size(); ++t) {
    if (nextStar < k && plan.star[nextStar] == t) {
      ++nextStar;
      continue;
    }
    const Triangle& tri = region[t];
    int at[3];
    Point2 q[3];
    for (int c = 0; c < 3; ++c) {
      at[c] = ringIndex(tri[c]);
      q[c] = project(plan, positions[tri[c]], nullptr);
    }
    // (far from the polygon's box: clear)
    if (std::max({q[0].x, q[1].x, q[2].x}) < lo.x - margin ||
        std::min({q[0].x, q[1].x, q[2].x}) > hi.x + margin ||
        std::max({q[0].y, q[1].y, q[2].y}) < lo.y - margin ||
        std::min({q[0].y, q[1].y, q[2].y}) > hi.y + margin)
      continue;
    if (separated(at, q)) continue;
    for (int c = 0; c < 3; ++c)
      if (at[c] < 0 && inOrNearPolygon(q[c], poly, k, margin, eps2)) return false;
    for (int c = 0; c < 3; ++c) {
      const int a = at[c], b = at[(c + 1) % 3];
      if (a >= 0 && b >= 0) {
        const std::size_t gap = wrap(static_cast<std::size_t>(b - a + static_cast<int>(k)), k);
        if (gap != 1 && gap != k - 1) {  // a chord: must run outside
          const Point2 mid{(q[c].x + q[(c + 1) % 3].x) / 2, (q[c].y + q[(c + 1) % 3].y) / 2};
          if (inOrNearPolygon(mid, poly, k, margin, eps2)) return false;
        }
      }
      for (std::size_t i = 0; i < k; ++i) {
        const int j = i + 1 == k ? 0 : static_cast<int>(i + 1);
        if (a == static_cast<int>(i) || a == j || b == static_cast<int>(i) || b == j) continue;
        if (segmentsNear(q[c], q[c == 2 ? 0 : c + 1], poly[i], poly[j], margin, eps2)) return false;
      }
    }
    for (std::size_t i = 0; i < k; ++i) {
      if (static_cast<int>(i) == at[0] || static_cast<int>(i) == at[1] ||
          static_cast<int>(i) == at[2])
        continue;
      if (poly[i].x + margin < std::min({q[0].x, q[1].x, q[2].x}) ||
          poly[i].x - margin > std::max({q[0].x, q[1].x, q[2].x}) ||
          poly[i].y + margin < std::min({q[0].y, q[1].y, q[2].y}) ||
          poly[i].y - margin > std::max({q[0].y, q[1].y, q[2].y}))
        continue;  // (outside the triangle's box)
      if (inOrNearTriangle(poly[i], q[0], q[1], q[2], eps2)) return false;
    }
  }
  return true;
}

}  // namespace frep
