#include "base/triangle_geometry.h"

namespace frep {

double meshVolume(const TriangleMesh& mesh) {
  double v = 0.0;
  for (const Triangle& t : mesh.triangles)
    v += signedTetraVolume(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
  return v;
}

double meshArea(const TriangleMesh& mesh) {
  double a = 0.0;
  for (const Triangle& t : mesh.triangles)
    a += triangleArea(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
  return a;
}

namespace {

Vec3d minus(const Vec3d& a, const Vec3d& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
double dotD(const Vec3d& a, const Vec3d& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

}  // namespace

Vec3d closestPointOnTriangle(const Vec3d& p, const Vec3d& a, const Vec3d& b, const Vec3d& c) {
  const Vec3d ab = minus(b, a), ac = minus(c, a), ap = minus(p, a);
  const double d1 = dotD(ab, ap), d2 = dotD(ac, ap);
  auto along = [](const Vec3d& o, const Vec3d& d, double t) {
    return Vec3d{o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]};
  };
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3d bp = minus(p, b);
  const double d3 = dotD(ab, bp), d4 = dotD(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return along(a, ab, d1 / (d1 - d3));
  const Vec3d cp = minus(p, c);
  const double d5 = dotD(ab, cp), d6 = dotD(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return along(a, ac, d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return along(b, minus(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  return {a[0] + ab[0] * v + ac[0] * w, a[1] + ab[1] * v + ac[1] * w,
          a[2] + ab[2] * v + ac[2] * w};
}

double pointTriangleDistance(const Vec3d& p, const Vec3d& a, const Vec3d& b, const Vec3d& c) {
  const Vec3d q = minus(p, closestPointOnTriangle(p, a, b, c));
  return std::sqrt(dotD(q, q));
}

}  // namespace frep
