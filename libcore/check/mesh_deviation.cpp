// CGAL's AABB tree over a triangle soup (no topology needed: broken inputs are measured too).
#include "check/mesh_deviation.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <array>
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

// The mesh's distinct finite triangles: copies (a cube repeated 100,000 times, a million
// triangles on one point) add nothing to a distance and would make every query visit them.
std::vector<Tri> triangles(const TriangleMesh& m) {
  std::vector<std::array<float, 9>> keys;
  keys.reserve(m.triangles.size());
  for (const Triangle& f : m.triangles) {
    if (f[0] >= m.positions.size() || f[1] >= m.positions.size() || f[2] >= m.positions.size())
      continue;
    std::array<Vec3f, 3> c = {m.positions[f[0]], m.positions[f[1]], m.positions[f[2]]};
    bool finite = true;
    for (const Vec3f& q : c)
      finite = finite && std::isfinite(q[0]) && std::isfinite(q[1]) && std::isfinite(q[2]);
    if (!finite) continue;
    std::sort(c.begin(), c.end());  // the same triangle however its corners are listed
    keys.push_back(
        {c[0][0], c[0][1], c[0][2], c[1][0], c[1][1], c[1][2], c[2][0], c[2][1], c[2][2]});
  }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  std::vector<Tri> t;
  t.reserve(keys.size());
  for (const auto& k : keys)
    t.emplace_back(Point(k[0], k[1], k[2]), Point(k[3], k[4], k[5]), Point(k[6], k[7], k[8]));
  return t;
}

// The distance queries' starting hints: the triangles' distinct corners, each with a
// triangle it belongs to. CGAL's default (one corner per triangle, repeats kept) builds its
// k-d tree one level per repeat when thousands of triangles share a corner (a fan's apex).
void accelerate(Tree& tree, const std::vector<Tri>& tris) {
  std::vector<std::pair<Point, std::vector<Tri>::const_iterator>> hints;
  hints.reserve(3 * tris.size());
  for (auto it = tris.begin(); it != tris.end(); ++it)
    for (int i = 0; i < 3; ++i) hints.emplace_back((*it)[i], it);
  auto less = [](const auto& a, const auto& b) { return a.first < b.first; };
  std::sort(hints.begin(), hints.end(), less);
  hints.erase(std::unique(hints.begin(), hints.end(),
                          [](const auto& a, const auto& b) { return a.first == b.first; }),
              hints.end());
  tree.accelerate_distance_queries(hints.begin(), hints.end());
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

// How many samples the distance queries can afford: a query visits every triangle whose box
// could hold a nearer point, and in a soup of large crossing triangles (each box a good part
// of the whole) that is most of them. The boxes' summed volume over the whole box's says how
// deep they pile; a surface's boxes pile a fraction of one deep, 30,000 random triangles in a
// cube thousands. Past kDeepestPile the samples shrink in proportion (at least 1,000), so the
// measure of a soup stays seconds and is the same every time.
constexpr double kDeepestPile = 64.0;
std::size_t affordableSamples(const std::vector<Tri>& tris, std::size_t wanted) {
  CGAL::Bbox_3 all;
  for (const Tri& t : tris) all += t.bbox();
  const double pad = 1e-3 * std::sqrt(CGAL::square(all.xmax() - all.xmin()) +
                                      CGAL::square(all.ymax() - all.ymin()) +
                                      CGAL::square(all.zmax() - all.zmin()));
  auto volume = [pad](const CGAL::Bbox_3& b) {
    return (b.xmax() - b.xmin() + pad) * (b.ymax() - b.ymin() + pad) * (b.zmax() - b.zmin() + pad);
  };
  double piled = 0;
  for (const Tri& t : tris) piled += volume(t.bbox());
  const double depth = piled / volume(all);
  if (!(depth > kDeepestPile)) return wanted;
  return std::max<std::size_t>(std::min<std::size_t>(wanted, 1000),
                               static_cast<std::size_t>(double(wanted) * kDeepestPile / depth));
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
  accelerate(treeA, ta);
  accelerate(treeB, tb);
  // (each mesh's samples are queried in the other's tree)
  const std::vector<Point> sa = samples(ta, affordableSamples(tb, samplesPerMesh)),
                           sb = samples(tb, affordableSamples(ta, samplesPerMesh));
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
  accelerate(tree, tb);
  const std::vector<Point> points = samples(ta, affordableSamples(tb, samplesPerMesh));
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
