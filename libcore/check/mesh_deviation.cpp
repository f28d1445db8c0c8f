// CGAL's AABB tree over a triangle soup (no topology needed: broken inputs are measured too).
#include "check/mesh_deviation.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "base/errors.h"

namespace frep {

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Tri = Kernel::Triangle_3;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Tri>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

std::vector<Tri> triangles(const TriangleMesh& m) {
  std::vector<Tri> t;
  t.reserve(m.triangles.size());
  auto p = [&](std::uint32_t v) {
    const Vec3f& q = m.positions[v];
    return Point(q[0], q[1], q[2]);
  };
  for (const Triangle& f : m.triangles) {
    if (f[0] >= m.positions.size() || f[1] >= m.positions.size() || f[2] >= m.positions.size())
      continue;
    Tri tri(p(f[0]), p(f[1]), p(f[2]));
    bool finite = true;
    for (int i = 0; i < 3; ++i)
      finite = finite && std::isfinite(tri[i].x()) && std::isfinite(tri[i].y()) &&
               std::isfinite(tri[i].z());
    if (finite) t.push_back(tri);
  }
  return t;
}

// Vertices and face centres (every triangle's when they fit in n, else an even stride
// through them, so that triangles added at the end of a large mesh, a repair's caps, are
// sampled too), then random area-weighted points: at most n, deterministic.
std::vector<Point> samples(const std::vector<Tri>& tris, std::size_t n) {
  std::vector<Point> s;
  if (tris.empty() || n == 0) return s;
  const std::size_t each = std::min(tris.size(), 2 * tris.size() <= n ? tris.size() : n / 3);
  s.reserve(n);
  for (std::size_t k = 0; k < each; ++k) s.push_back(tris[k * tris.size() / each][0]);
  for (std::size_t k = 0; k < each; ++k)
    s.push_back(CGAL::centroid(tris[(2 * k + 1) * tris.size() / (2 * each)]));
  std::vector<double> area(tris.size());
  for (std::size_t i = 0; i < tris.size(); ++i)
    area[i] = std::sqrt(std::max(0.0, tris[i].squared_area()));
  if (std::none_of(area.begin(), area.end(), [](double a) { return a > 0; })) return s;
  std::discrete_distribution<std::size_t> pick(area.begin(), area.end());
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  while (s.size() < n) {
    const Tri& t = tris[pick(rng)];
    double a = u(rng), b = u(rng);
    if (a + b > 1) a = 1 - a, b = 1 - b;
    s.push_back(t[0] + a * (t[1] - t[0]) + b * (t[2] - t[0]));
  }
  return s;
}

// Inside the closed surface of `tree` by ray parity, the majority of three rays in skew
// directions (a ray through an edge or vertex counts a crossing twice; another ray does not).
bool insideByRays(const Tree& tree, const Point& p) {
  static const Kernel::Vector_3 directions[3] = {
      {0.5773, 0.6089, 0.5441}, {-0.7071, 0.3162, -0.6325}, {0.2236, -0.8944, 0.3873}};
  int odd = 0;
  for (const auto& d : directions)
    odd += tree.number_of_intersected_primitives(Kernel::Ray_3(p, d)) % 2;
  return odd >= 2;
}

void measure(const std::vector<Point>& from, const Tree& to, double& largest, double& mean) {
  double sum = 0;
  for (const Point& p : from) {
    const double d = std::sqrt(to.squared_distance(p));
    largest = std::max(largest, d);
    sum += d;
  }
  mean = from.empty() ? 0.0 : sum / double(from.size());
}

}  // namespace

DeviationReport meshDeviation(const TriangleMesh& a, const TriangleMesh& b,
                              std::size_t samplesPerMesh) {
  const std::vector<Tri> ta = triangles(a), tb = triangles(b);
  if (ta.empty() || tb.empty())
    throw FileError("a mesh without triangles has no distance to another");
  Tree treeA(ta.begin(), ta.end()), treeB(tb.begin(), tb.end());
  treeA.accelerate_distance_queries();
  treeB.accelerate_distance_queries();
  const std::vector<Point> sa = samples(ta, samplesPerMesh), sb = samples(tb, samplesPerMesh);
  DeviationReport r;
  measure(sa, treeB, r.aToB, r.meanAToB);
  measure(sb, treeA, r.bToA, r.meanBToA);
  r.samples = sa.size() + sb.size();
  return r;
}

double largestDistanceOutside(const TriangleMesh& a, const TriangleMesh& solid,
                              std::size_t samplesPerMesh) {
  const std::vector<Tri> ta = triangles(a), tb = triangles(solid);
  if (ta.empty() || tb.empty())
    throw FileError("a mesh without triangles has no distance to another");
  Tree tree(tb.begin(), tb.end());
  tree.accelerate_distance_queries();
  const std::vector<Point> points = samples(ta, samplesPerMesh);
  std::vector<std::pair<double, std::size_t>> byDistance(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    byDistance[i] = {tree.squared_distance(points[i]), i};
  // Farthest first: the first one outside is the answer, so only the samples farther than it
  // (the absorbed walls) pay for the rays.
  std::sort(byDistance.begin(), byDistance.end(), std::greater<>());
  for (const auto& [d2, i] : byDistance)
    if (d2 <= 0 || !insideByRays(tree, points[i])) return std::sqrt(d2);
  return 0.0;
}

}  // namespace frep
