// Wall thickness by rays through CGAL's AABB tree (the shape diameter function's measure,
// computed here on a triangle soup so that a mesh needs no halfedge structure and the rays
// run in parallel); overhangs and mass from the triangles.
#include "check/printability.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

#include "base/errors.h"
#include "base/library_compat.h"
#include "base/triangle_geometry.h"
#include "check/mesh_check_passes.h"

namespace frep {

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Vector = Kernel::Vector_3;
using Ray = Kernel::Ray_3;
using Tri = Kernel::Triangle_3;
using Iterator = std::vector<Tri>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, Iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

const std::vector<Material> kMaterials = {
    {"pla", 1.24}, {"petg", 1.27},  {"abs", 1.04},  {"asa", 1.07},  {"nylon", 1.01},
    {"tpu", 1.21}, {"resin", 1.15}, {"316l", 7.99}, {"ti64", 4.43}, {"alsi10mg", 2.67},
};

Vector unit(const Vector& v) {
  const double l = std::sqrt(v.squared_length());
  return l > 0 ? v / l : v;
}

// Two unit vectors perpendicular to n and to each other.
void basis(const Vector& n, Vector& a, Vector& b) {
  const Vector helper = std::abs(n.x()) < 0.9 ? Vector(1, 0, 0) : Vector(0, 1, 0);
  a = unit(CGAL::cross_product(n, helper));
  b = CGAL::cross_product(n, a);
}

}  // namespace

const std::vector<Material>& materials() {
  return kMaterials;
}

double materialDensity(const std::string& name) {
  std::string known;
  for (const Material& m : kMaterials) {
    if (name == m.name) return m.density;
    known += (known.empty() ? "" : ", ") + std::string(m.name);
  }
  throw ModelError("unknown material '" + name + "'; known: " + known +
                   " (or give --density in g/cm3)");
}

namespace {

// Where a drain hole empties each cavity: on its floor (the wall within 2 % of the cavity's
// height of its lowest point), the floor's point farthest, along the mesh, from the floor's
// edge: a hole there opens onto the cavity, not onto the wall that rises beside the floor
// (a flat floor has many lowest points, most of them at its edge).
void placeDrains(const TriangleMesh& mesh, const std::vector<std::uint32_t>& id,
                 const std::vector<std::uint32_t>& first, const Vec3& up, PrintabilityReport& r) {
  const std::size_t points = first.size(), cavities = r.cavityList.size();
  auto height = [&](std::uint32_t v) {
    const Vec3f& q = mesh.positions[first[v]];
    return q[0] * up[0] + q[1] * up[1] + q[2] * up[2];
  };
  constexpr double kNone = std::numeric_limits<double>::max();
  std::vector<double> low(cavities, kNone), high(cavities, -kNone);
  std::vector<std::int32_t> cavityOfPoint(points, -1);
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const std::int32_t k = r.cavityOf[i];
    if (k < 0) continue;
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t v = id[mesh.triangles[i][c]];
      cavityOfPoint[v] = k;
      low[k] = std::min(low[k], height(v));
      high[k] = std::max(high[k], height(v));
    }
  }
  auto onFloor = [&](std::uint32_t v) {
    const std::int32_t k = cavityOfPoint[v];
    return k >= 0 && height(v) <= low[k] + 0.02 * (high[k] - low[k]);
  };
  // The floors' edges (as a graph over the welded points) and their rims: floor points with an
  // edge to a point off the floor.
  std::vector<std::vector<std::uint32_t>> next(points);
  std::vector<double> distance(points, kNone);
  using Reached = std::pair<double, std::uint32_t>;
  std::priority_queue<Reached, std::vector<Reached>, std::greater<Reached>> queue;
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    if (r.cavityOf[i] < 0) continue;
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t a = id[mesh.triangles[i][c]], b = id[mesh.triangles[i][(c + 1) % 3]];
      const bool aFloor = onFloor(a), bFloor = onFloor(b);
      if (aFloor && bFloor) {
        next[a].push_back(b);
        next[b].push_back(a);
      } else if (aFloor != bFloor) {
        const std::uint32_t rim = aFloor ? a : b;
        if (distance[rim] != 0.0) queue.push({distance[rim] = 0.0, rim});
      }
    }
  }
  // Distances from the rims across each floor (Dijkstra along the mesh's edges).
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > distance[v]) continue;
    const Vec3f& p = mesh.positions[first[v]];
    for (std::uint32_t w : next[v]) {
      const Vec3f& q = mesh.positions[first[w]];
      const double step =
          std::sqrt(double(p[0] - q[0]) * (p[0] - q[0]) + double(p[1] - q[1]) * (p[1] - q[1]) +
                    double(p[2] - q[2]) * (p[2] - q[2]));
      if (d + step < distance[w]) queue.push({distance[w] = d + step, w});
    }
  }
  // Per cavity the floor point deepest inside its floor (a floor without a rim, such as a
  // ball's cap that is all floor, keeps its lowest point).
  std::vector<double> deepest(cavities, -1.0), lowest(cavities, kNone);
  for (std::uint32_t v = 0; v < points; ++v) {
    const std::int32_t k = cavityOfPoint[v];
    if (k < 0 || !onFloor(v)) continue;
    const Vec3f& q = mesh.positions[first[v]];
    const double depth = distance[v] == kNone ? 0.0 : distance[v];
    if (depth > deepest[k] || (depth == deepest[k] && height(v) < lowest[k])) {
      deepest[k] = depth;
      lowest[k] = height(v);
      r.cavityList[k].drainAt = {q[0], q[1], q[2]};
    }
  }
}

// The components of a printable mesh (faces joined through shared coordinates), each with its
// signed volume: an outward shell adds volume, the wall of a void inside it takes volume away
// (its normals point into the void, away from the material).
void countCavities(const TriangleMesh& mesh, const Vec3& up, PrintabilityReport& r) {
  std::vector<std::uint32_t> first;
  const std::vector<std::uint32_t> id = distinctPoints(mesh.positions, &first);
  UnionFind pieces(first.size());
  for (const Triangle& t : mesh.triangles)
    for (int i = 1; i < 3; ++i) pieces.join(id[t[0]], id[t[i]]);
  std::vector<double> volume(first.size(), 0.0);
  for (const Triangle& t : mesh.triangles)
    volume[pieces.find(id[t[0]])] +=
        signedTetraVolume(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
  // The cavities by their piece, largest first.
  std::vector<std::uint32_t> walls;
  for (std::uint32_t piece = 0; piece < volume.size(); ++piece)
    if (volume[piece] < 0) walls.push_back(piece);
  std::sort(walls.begin(), walls.end(),
            [&](std::uint32_t a, std::uint32_t b) { return volume[a] < volume[b]; });
  std::vector<std::int32_t> cavityOfPiece(volume.size(), -1);
  r.cavities = static_cast<long long>(walls.size());
  r.cavityVolume = 0.0;
  r.cavityList.assign(walls.size(), {});
  for (std::size_t k = 0; k < walls.size(); ++k) {
    cavityOfPiece[walls[k]] = static_cast<std::int32_t>(k);
    r.cavityList[k].volume = -volume[walls[k]];
    r.cavityVolume -= volume[walls[k]];
  }
  r.cavityOf.assign(mesh.triangles.size(), -1);
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
    r.cavityOf[i] = cavityOfPiece[pieces.find(id[mesh.triangles[i][0]])];
  placeDrains(mesh, id, first, up, r);
}

}  // namespace

PrintabilityReport measurePrintability(const TriangleMesh& mesh, const PrintabilityOptions& o) {
  const double upLength = std::sqrt(o.up[0] * o.up[0] + o.up[1] * o.up[1] + o.up[2] * o.up[2]);
  if (!(upLength > 0) || !std::isfinite(upLength))
    throw ModelError("printability: the build direction must be a non-zero vector");
  if (!(o.overhangDeg >= 0 && o.overhangDeg <= 90))
    throw ModelError("printability: the overhang angle must be from 0 to 90 degrees");
  if (!(o.coneDeg >= 0 && o.coneDeg < 90) || o.rays < 1 || o.rays > 256)
    throw ModelError("printability: the cone must be from 0 to 90 degrees and rays 1 to 256");
  if (o.minWall && !(*o.minWall > 0 && std::isfinite(*o.minWall)))
    throw ModelError("printability: the minimum wall must be a distance > 0");
  if (!(o.density >= 0) || !std::isfinite(o.density))
    throw ModelError("printability: the density must be >= 0 (g/cm3)");
  const Vector up(o.up[0] / upLength, o.up[1] / upLength, o.up[2] / upLength);

  PrintabilityReport r;
  const std::size_t n = mesh.triangles.size();
  std::vector<Tri> tris;
  tris.reserve(n);
  for (const Triangle& t : mesh.triangles) {
    Point p[3];
    for (int i = 0; i < 3; ++i) {
      const Vec3f& q = t[i] < mesh.positions.size() ? mesh.positions[t[i]] : Vec3f{0, 0, 0};
      p[i] = Point(q[0], q[1], q[2]);
    }
    tris.emplace_back(p[0], p[1], p[2]);
  }
  if (tris.empty()) return r;

  // Heights along the build direction: the plate is the lowest point.
  double low = std::numeric_limits<double>::max(), high = -low;
  for (const Tri& t : tris)
    for (int i = 0; i < 3; ++i) {
      const double h = Vector(CGAL::ORIGIN, t[i]) * up;
      low = std::min(low, h);
      high = std::max(high, h);
    }
  r.height = high - low;
  const double plate = 1e-6 * std::max(1.0, r.height);
  const double support = std::sin(o.overhangDeg * M_PI / 180.0);
  for (const Tri& t : tris) {
    const Vector c = CGAL::cross_product(t[1] - t[0], t[2] - t[0]);
    const double a2 = std::sqrt(c.squared_length());
    r.volume += (Vector(CGAL::ORIGIN, t[0]) *
                 CGAL::cross_product(Vector(CGAL::ORIGIN, t[1]), Vector(CGAL::ORIGIN, t[2]))) /
                6.0;
    if (a2 <= 0) continue;
    const double down = -(c * up) / a2;
    bool onPlate = true;
    for (int i = 0; i < 3; ++i) onPlate = onPlate && Vector(CGAL::ORIGIN, t[i]) * up <= low + plate;
    if (down > support && !onPlate) {
      r.overhangArea += 0.5 * a2;
      ++r.overhangTriangles;
    }
  }
  if (o.density > 0) r.mass = std::abs(r.volume) * o.density / 1000.0;  // mm^3 * g/cm^3 -> g
  if (o.thickness) countCavities(mesh, {up.x(), up.y(), up.z()}, r);

  // Thickness: rays from each triangle's centre, against its normal, in a cone.
  r.thickness.assign(n, -1.0f);
  if (!o.thickness) return r;
  Tree tree(tris.begin(), tris.end());
  tree.build();
  const double cone = o.coneDeg * M_PI / 180.0;
  tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
    const Tri& t = tris[i];
    const Vector c = CGAL::cross_product(t[1] - t[0], t[2] - t[0]);
    if (!(c.squared_length() > 0)) return;
    const Vector inward = -unit(c);
    Vector a, b;
    basis(inward, a, b);
    const Point centre = CGAL::centroid(t);
    const Iterator self = tris.begin() + static_cast<std::ptrdiff_t>(i);
    // The wall under the triangle: the deepest of the rays' first hits, measured along the
    // normal. A flat wall measures exactly whatever the tilt; a triangle near a convex edge
    // keeps the depth of its axis ray although tilted rays leave through the side.
    double deepest = -1;
    for (int k = 0; k < o.rays; ++k) {
      // The axis first, then directions spread over the cone (golden angle).
      const double f = o.rays == 1 ? 0.0 : std::sqrt(double(k) / double(o.rays - 1));
      const double tilt = cone * f, turn = 2.399963229728653 * k;
      const Vector d =
          std::cos(tilt) * inward + std::sin(tilt) * (std::cos(turn) * a + std::sin(turn) * b);
      const auto hit =
          tree.first_intersection(Ray(centre, d), [&](const Iterator& id) { return id == self; });
      if (!hit) continue;
      const Point* p = intersectionAs<Point>(hit->first);
      if (!p) continue;
      deepest = std::max(deepest, std::sqrt(CGAL::squared_distance(centre, *p)) * std::cos(tilt));
    }
    if (deepest > 0) r.thickness[i] = static_cast<float>(deepest);
  });
  for (std::size_t i = 0; i < n; ++i) {
    const float w = r.thickness[i];
    if (w < 0) continue;
    if (r.minWall < 0 || w < r.minWall) {
      r.minWall = w;
      const Point c = CGAL::centroid(tris[i]);
      r.minWallAt = {c.x(), c.y(), c.z()};
    }
    if (o.minWall && w < *o.minWall) {
      ++r.thinTriangles;
      r.thinArea += std::sqrt(tris[i].squared_area());
    }
  }
  return r;
}

}  // namespace frep
