// Triangle geometry in double precision on float vertices: the one cross product that the
// mesher (quad split quality), the STL writer (facet normals), the checker and the mesh
// measures share.
#pragma once

#include <array>
#include <cmath>

#include "base/triangle_mesh.h"

namespace frep {

using Vec3d = std::array<double, 3>;

// (b - a) x (c - a): twice the area, along the right-handed normal.
inline Vec3d triangleCross(const Vec3f& a, const Vec3f& b, const Vec3f& c) {
  const double u[3] = {double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2]};
  const double v[3] = {double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2]};
  return {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
}

inline double norm(const Vec3d& v) {
  return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

// Twice the area against the sum of the squared sides: 0 for a degenerate triangle, 0.29 for
// an equilateral one (the mesher's measure of a triangle's shape).
inline double triangleQuality(const Vec3f& a, const Vec3f& b, const Vec3f& c) {
  const double area2 = norm(triangleCross(a, b, c));
  auto sq = [](const Vec3f& p, const Vec3f& q) {
    const double d[3] = {double(q[0]) - p[0], double(q[1]) - p[1], double(q[2]) - p[2]};
    return d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  };
  const double edges = sq(a, b) + sq(a, c) + sq(b, c);
  return edges > 0 ? area2 / edges : 0.0;
}

inline double triangleArea(const Vec3f& a, const Vec3f& b, const Vec3f& c) {
  return 0.5 * norm(triangleCross(a, b, c));
}

// Signed volume of the tetrahedron (origin, a, b, c); summed over a closed outward mesh it is
// the enclosed volume.
inline double signedTetraVolume(const Vec3f& a, const Vec3f& b, const Vec3f& c) {
  return (double(a[0]) * (double(b[1]) * c[2] - double(b[2]) * c[1]) -
          double(a[1]) * (double(b[0]) * c[2] - double(b[2]) * c[0]) +
          double(a[2]) * (double(b[0]) * c[1] - double(b[1]) * c[0])) /
         6.0;
}

// The point of the triangle abc nearest to p, found by the triangle's Voronoi regions
// (Ericson, Real-Time Collision Detection, 5.1.5), and its distance from p.
Vec3d closestPointOnTriangle(const Vec3d& p, const Vec3d& a, const Vec3d& b, const Vec3d& c);
double pointTriangleDistance(const Vec3d& p, const Vec3d& a, const Vec3d& b, const Vec3d& c);

// Enclosed signed volume and surface area of a mesh (no welding, no checks).
double meshVolume(const TriangleMesh& mesh);
double meshArea(const TriangleMesh& mesh);

// The unit normal of triangle abc (right-hand rule) in float32, zero for a degenerate one:
// what STL's facet records hold.
inline Vec3f unitNormal(const Vec3f& a, const Vec3f& b, const Vec3f& c) {
  Vec3d n = triangleCross(a, b, c);
  const double len = norm(n);
  if (len > 0)
    for (double& x : n) x /= len;
  return {float(n[0]), float(n[1]), float(n[2])};
}

}  // namespace frep
