#include "check/face_pair_test.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/intersections.h>

#include <cmath>

namespace frep {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Segment = Kernel::Segment_3;
using TriangleK = Kernel::Triangle_3;

Point point(const Vec3f& p) {
  return {p[0], p[1], p[2]};
}

// The sign of the orientation of (a, b, c, d) where double arithmetic proves it: +1 or -1,
// and 0 where the rounding could hide the sign (CGAL's exact predicates decide then).
// Shewchuk's first error bound for orient3d (Adaptive precision floating-point arithmetic,
// 1997): (7 + 56 eps) eps times the permanent, eps = 2^-53.
int provenOrientation(const Vec3f& a, const Vec3f& b, const Vec3f& c, const Vec3f& d) {
  const double adx = double(a[0]) - d[0], ady = double(a[1]) - d[1], adz = double(a[2]) - d[2];
  const double bdx = double(b[0]) - d[0], bdy = double(b[1]) - d[1], bdz = double(b[2]) - d[2];
  const double cdx = double(c[0]) - d[0], cdy = double(c[1]) - d[1], cdz = double(c[2]) - d[2];
  const double bc = bdx * cdy - cdx * bdy, ca = cdx * ady - adx * cdy, ab = adx * bdy - bdx * ady;
  const double det = adz * bc + bdz * ca + cdz * ab;
  const double permanent = (std::abs(bdx * cdy) + std::abs(cdx * bdy)) * std::abs(adz) +
                           (std::abs(cdx * ady) + std::abs(adx * cdy)) * std::abs(bdz) +
                           (std::abs(adx * bdy) + std::abs(bdx * ady)) * std::abs(cdz);
  const double eps = 1.1102230246251565e-16;
  const double bound = (7.0 + 56.0 * eps) * eps * permanent;
  if (det > bound) return 1;
  if (-det > bound) return -1;
  return 0;
}

// The sign of the orientation of (a, b, c) projected along axis `drop`, where doubles prove it
// (Shewchuk's first bound for orient2d, (3 + 16 eps) eps); 0 where they cannot.
int provenOrientation2(const Vec3f& a, const Vec3f& b, const Vec3f& c, int drop) {
  const int x = (drop + 1) % 3, y = (drop + 2) % 3;
  const double l = (double(a[x]) - c[x]) * (double(b[y]) - c[y]);
  const double r = (double(a[y]) - c[y]) * (double(b[x]) - c[x]);
  const double det = l - r;
  const double eps = 1.1102230246251565e-16;
  const double bound = (3.0 + 16.0 * eps) * eps * (std::abs(l) + std::abs(r));
  if (det > bound) return 1;
  if (-det > bound) return -1;
  return 0;
}

// CGAL::coplanar_orientation(a, b, c, d) for four coplanar points, abc not collinear, where
// doubles decide it: in a projection along an axis that keeps abc a triangle (proved), the
// plane maps one to one, so c and d are on the same side of ab there exactly when they are
// in the plane. 0 where the doubles cannot tell (CGAL decides then).
int provenCoplanarOrientation(const Vec3f& a, const Vec3f& b, const Vec3f& c, const Vec3f& d) {
  for (int drop = 0; drop < 3; ++drop) {
    const int sc = provenOrientation2(a, b, c, drop);
    if (sc == 0) continue;
    const int sd = provenOrientation2(a, b, d, drop);
    return sd == 0 ? 0 : (sd == sc ? 1 : -1);
  }
  return 0;
}

// Whether every point of `q` (n of them) is proved strictly on one side of the plane of t.
bool provenApart(const std::vector<Vec3f>& p, const Triangle& t, const std::uint32_t* q, int n) {
  int side = 0;
  for (int i = 0; i < n; ++i) {
    const int o = provenOrientation(p[t[0]], p[t[1]], p[t[2]], p[q[i]]);
    if (o == 0 || (side != 0 && o != side)) return false;
    side = o;
  }
  return true;
}

// The axis along which triangle t (indices into p) is largest in projection.
int flattestAxis(const std::vector<Vec3f>& p, const Triangle& t) {
  double u[3], v[3];
  for (int k = 0; k < 3; ++k) {
    u[k] = double(p[t[1]][k]) - p[t[0]][k];
    v[k] = double(p[t[2]][k]) - p[t[0]][k];
  }
  const double n[3] = {std::abs(u[1] * v[2] - u[2] * v[1]), std::abs(u[2] * v[0] - u[0] * v[2]),
                       std::abs(u[0] * v[1] - u[1] * v[0])};
  return n[0] >= n[1] && n[0] >= n[2] ? 0 : (n[1] >= n[2] ? 1 : 2);
}

// Whether, projected along `drop`, the points q (n of them) are proved strictly on the other
// side of the line e0 e1 from e2.
bool provenOutside(const std::vector<Vec3f>& p, std::uint32_t e0, std::uint32_t e1,
                   std::uint32_t e2, const std::uint32_t* q, int n, int drop) {
  const int inside = provenOrientation2(p[e0], p[e1], p[e2], drop);
  if (inside == 0) return false;
  for (int i = 0; i < n; ++i)
    if (provenOrientation2(p[e0], p[e1], p[q[i]], drop) != -inside) return false;
  return true;
}

// Whether triangle t and the triangle or segment q (n = 3 or 2 points) are proved apart in
// their projections along `drop` (an edge line of one separates them): then they are apart
// in space too, since a common point would project to a common point.
bool provenApartInProjection(const std::vector<Vec3f>& p, const Triangle& t, const std::uint32_t* q,
                             int n, int drop) {
  for (int k = 0; k < 3; ++k)
    if (provenOutside(p, t[k], t[(k + 1) % 3], t[(k + 2) % 3], q, n, drop)) return true;
  if (n == 3) {
    for (int k = 0; k < 3; ++k)
      if (provenOutside(p, q[k], q[(k + 1) % 3], q[(k + 2) % 3], t.data(), 3, drop)) return true;
    return false;
  }
  // a segment: t's three corners strictly on one side of its line
  const int side = provenOrientation2(p[q[0]], p[q[1]], p[t[0]], drop);
  return side != 0 && provenOrientation2(p[q[0]], p[q[1]], p[t[1]], drop) == side &&
         provenOrientation2(p[q[0]], p[q[1]], p[t[2]], drop) == side;
}

}  // namespace

// CGAL's do_faces_intersect (self_intersections.h, CGAL 5.5), on vertex indices.
bool facesIntersect(const std::vector<Vec3f>& points, const Triangle& f, const Triangle& g) {
  auto in = [](std::uint32_t v, const Triangle& t) { return v == t[0] || v == t[1] || v == t[2]; };
  auto at = [&points](std::uint32_t v) { return point(points[v]); };
  for (int k = 0; k < 3; ++k) {
    const std::uint32_t a = f[k], b = f[(k + 1) % 3];
    if (in(a, g) && in(b, g)) {  // the shared edge a -> b (in f's order)
      const std::uint32_t c = f[(k + 2) % 3];
      std::uint32_t d = g[0];
      for (std::uint32_t v : g)
        if (v != a && v != b) d = v;
      // not coplanar, proved in doubles: no intersection
      if (provenOrientation(points[a], points[b], points[c], points[d]) != 0) return false;
      const Point pa = at(a), pb = at(b), pc = at(c), pd = at(d);
      if (!CGAL::coplanar(pa, pb, pc, pd)) return false;
      // (c and d on the same side of the edge: the faces overlap)
      const int side = provenCoplanarOrientation(points[a], points[b], points[c], points[d]);
      if (side != 0) return side > 0;
      return CGAL::coplanar_orientation(pa, pb, pc, pd) == CGAL::POSITIVE;
    }
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (f[i] == g[j]) {  // one shared vertex: the opposite sides against the other faces
        // each opposite side proved strictly off the other face's plane: they cannot cross
        const std::uint32_t sideF[2] = {f[(i + 1) % 3], f[(i + 2) % 3]};
        const std::uint32_t sideG[2] = {g[(j + 1) % 3], g[(j + 2) % 3]};
        const int drop = flattestAxis(points, f);
        if ((provenApart(points, f, sideG, 2) ||
             provenApartInProjection(points, f, sideG, 2, drop)) &&
            (provenApart(points, g, sideF, 2) ||
             provenApartInProjection(points, g, sideF, 2, drop)))
          return false;
        const TriangleK tf(at(f[0]), at(f[1]), at(f[2])), tg(at(g[0]), at(g[1]), at(g[2]));
        const Segment sf(at(f[(i + 1) % 3]), at(f[(i + 2) % 3]));
        const Segment sg(at(g[(j + 1) % 3]), at(g[(j + 2) % 3]));
        return CGAL::do_intersect(tf, sg) || CGAL::do_intersect(tg, sf);
      }
  // apart in a projection (an edge line separates them: most near neighbours on a smooth
  // surface), or one face proved strictly on one side of the other's plane: they cannot meet
  if (provenApartInProjection(points, f, g.data(), 3, flattestAxis(points, f)) ||
      provenApart(points, f, g.data(), 3) || provenApart(points, g, f.data(), 3))
    return false;
  const TriangleK tf(at(f[0]), at(f[1]), at(f[2])), tg(at(g[0]), at(g[1]), at(g[2]));
  return CGAL::do_intersect(tf, tg);
}

bool fanProvedEmbedded(const std::vector<Vec3f>& points, std::uint32_t v,
                       const std::pair<std::uint32_t, std::uint32_t>* sectors, std::size_t n) {
  if (n < 3) return false;
  // Project along the axis the fan's summed normal leans on most (any axis would be sound;
  // this one keeps a smooth fan's faces proper triangles).
  const Vec3f& c = points[v];
  double normal[3] = {0.0, 0.0, 0.0};
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3f &a = points[sectors[k].first], &b = points[sectors[k].second];
    double u[3], w[3];
    for (int i = 0; i < 3; ++i) {
      u[i] = double(a[i]) - c[i];
      w[i] = double(b[i]) - c[i];
    }
    normal[0] += u[1] * w[2] - u[2] * w[1];
    normal[1] += u[2] * w[0] - u[0] * w[2];
    normal[2] += u[0] * w[1] - u[1] * w[0];
  }
  const int drop =
      std::abs(normal[0]) >= std::abs(normal[1]) && std::abs(normal[0]) >= std::abs(normal[2])
          ? 0
          : (std::abs(normal[1]) >= std::abs(normal[2]) ? 1 : 2);
  const int y = (drop + 2) % 3;
  // Every face (v, w1, w2) turns the same way in the projection, each by less than half a
  // turn; the sectors, chained into one cycle, then turn round v a whole number of times,
  // counted as how many hold the direction +x (half-open, [w1, w2)): with counter-clockwise
  // faces that is w1.y <= v.y < w2.y (w2.y <= v.y < w1.y clockwise): comparisons of floats,
  // exact.
  const int turn = provenOrientation2(c, points[sectors[0].first], points[sectors[0].second], drop);
  if (turn == 0) return false;
  int winding = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3f &a = points[sectors[k].first], &b = points[sectors[k].second];
    if (k > 0 && provenOrientation2(c, a, b, drop) != turn) return false;
    const float from = turn > 0 ? a[y] : b[y], to = turn > 0 ? b[y] : a[y];
    winding += from <= c[y] && c[y] < to;
  }
  return winding == 1;
}

bool collinear(const Vec3f& a, const Vec3f& b, const Vec3f& c) {
  return CGAL::collinear(point(a), point(b), point(c));
}

}  // namespace frep
