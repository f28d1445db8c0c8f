#include "mesh/section.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "base/errors.h"

namespace frep {

namespace {

// Grid points a section samples at most (a 4096 x 4096 grid): 128 MB of values and vertex
// indices.
constexpr std::size_t kMostSectionPoints = std::size_t(1) << 24;

Vec3 at(const SectionPlane& p, double u, double v) {
  return {p.origin[0] + u * p.u[0] + v * p.v[0], p.origin[1] + u * p.u[1] + v * p.v[1],
          p.origin[2] + u * p.u[2] + v * p.v[2]};
}

bool inside(double f) {
  return f >= 0.0;
}  // (NaN: outside)

// The parameter in (0, 1) of the surface on the edge from a (value fa) to b (value fb), whose
// ends differ in inside(): regula falsi with the Illinois step, kept strictly inside the edge
// so that two edges' vertices never meet at their common grid point.
double edgeRoot(const Field& field, const Vec3& a, const Vec3& b, double fa, double fb) {
  const bool insideA = inside(fa);
  double t0 = 0.0, t1 = 1.0, f0 = std::isfinite(fa) ? fa : -1.0, f1 = std::isfinite(fb) ? fb : -1.0;
  int side = 0;
  double t = 0.5;
  for (int k = 0; k < 30; ++k) {
    t = (f0 != f1) ? t0 + (t1 - t0) * f0 / (f0 - f1) : 0.5 * (t0 + t1);
    if (!(t > t0 && t < t1)) t = 0.5 * (t0 + t1);
    const Vec3 p = {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])};
    double f = field.eval(p[0], p[1], p[2]);
    if (!std::isfinite(f)) f = -1.0;
    if (f == 0.0 || t1 - t0 < 1e-12) break;
    if (inside(f) == insideA) {
      t0 = t, f0 = f;
      if (side == -1) f1 *= 0.5;
      side = -1;
    } else {
      t1 = t, f1 = f;
      if (side == 1) f0 *= 0.5;
      side = 1;
    }
  }
  return std::clamp(t, 1e-3, 1.0 - 1e-3);
}

}  // namespace

bool sectionRectangle(const SectionPlane& plane, const Box3& box, double& u0, double& u1,
                      double& v0, double& v1) {
  const Vec3 n = {plane.u[1] * plane.v[2] - plane.u[2] * plane.v[1],
                  plane.u[2] * plane.v[0] - plane.u[0] * plane.v[2],
                  plane.u[0] * plane.v[1] - plane.u[1] * plane.v[0]};
  bool above = false, below = false;
  u0 = v0 = INFINITY;
  u1 = v1 = -INFINITY;
  for (int c = 0; c < 8; ++c) {
    const Vec3 p = {(c & 1 ? box.hi : box.lo)[0], (c & 2 ? box.hi : box.lo)[1],
                    (c & 4 ? box.hi : box.lo)[2]};
    const Vec3 d = {p[0] - plane.origin[0], p[1] - plane.origin[1], p[2] - plane.origin[2]};
    const double w = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
    above = above || w >= 0.0;
    below = below || w <= 0.0;
    const double u = d[0] * plane.u[0] + d[1] * plane.u[1] + d[2] * plane.u[2];
    const double v = d[0] * plane.v[0] + d[1] * plane.v[1] + d[2] * plane.v[2];
    u0 = std::min(u0, u), u1 = std::max(u1, u);
    v0 = std::min(v0, v), v1 = std::max(v1, v);
  }
  return above && below;
}

std::vector<SectionLoop> sectionField(const Field& field, const SectionPlane& plane, double u0,
                                      double u1, double v0, double v1, double cell,
                                      const Progress& progress) {
  if (!(cell > 0.0) || !std::isfinite(cell))
    throw ModelError("section: cell size " + std::to_string(cell) + " is not allowed; > 0");
  if (!(u1 > u0) || !(v1 > v0) || !std::isfinite(u1 - u0) || !std::isfinite(v1 - v0))
    throw ModelError("section: the rectangle to sample is empty or infinite");
  const double nuReal = std::ceil((u1 - u0) / cell) + 1.0,
               nvReal = std::ceil((v1 - v0) / cell) + 1.0;
  if (nuReal * nvReal > static_cast<double>(kMostSectionPoints))
    throw ModelError("section: a grid of " + std::to_string(static_cast<long long>(nuReal)) +
                     " x " + std::to_string(static_cast<long long>(nvReal)) + " points; at most " +
                     std::to_string(kMostSectionPoints) + " (a larger cell)");
  const std::size_t nu = static_cast<std::size_t>(nuReal), nv = static_cast<std::size_t>(nvReal);
  auto node = [&](std::size_t i, std::size_t j) {
    return at(plane, u0 + static_cast<double>(i) * cell, v0 + static_cast<double>(j) * cell);
  };

  // the field at every grid point, a row at a time
  std::vector<double> value(nu * nv);
  {
    std::vector<double> x(nu), y(nu), z(nu);
    for (std::size_t j = 0; j < nv; ++j) {
      for (std::size_t i = 0; i < nu; ++i) {
        const Vec3 p = node(i, j);
        x[i] = p[0], y[i] = p[1], z[i] = p[2];
      }
      field.evalBatch(x.data(), y.data(), z.data(), nu, value.data() + j * nu);
      progress.step(0.7 * static_cast<double>(j + 1) / static_cast<double>(nv));
    }
  }
  auto f = [&](std::size_t i, std::size_t j) { return value[j * nu + i]; };

  // a vertex on each crossed edge: horizontal (i, j)-(i+1, j), vertical (i, j)-(i, j+1)
  std::vector<Vec3> points;
  std::vector<std::int64_t> across(nu * nv, -1), up(nu * nv, -1);
  auto vertexOn = [&](std::size_t i0, std::size_t j0, std::size_t i1, std::size_t j1,
                      std::vector<std::int64_t>& ids) {
    std::int64_t& id = ids[j0 * nu + i0];
    if (id < 0) {
      const Vec3 a = node(i0, j0), b = node(i1, j1);
      const double t = edgeRoot(field, a, b, f(i0, j0), f(i1, j1));
      points.push_back(
          {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])});
      id = static_cast<std::int64_t>(points.size()) - 1;
    }
    return id;
  };

  // marching squares: each segment from where the boundary leaves the inside (going round
  // the square counterclockwise) to where it comes back, so the solid is on its left
  std::vector<std::int64_t> next;
  auto link = [&](std::int64_t from, std::int64_t to) {
    if (next.size() < points.size()) next.resize(points.size(), -1);
    next[static_cast<std::size_t>(from)] = to;
  };
  for (std::size_t j = 0; j + 1 < nv; ++j) {
    for (std::size_t i = 0; i + 1 < nu; ++i) {
      const bool in[4] = {inside(f(i, j)), inside(f(i + 1, j)), inside(f(i + 1, j + 1)),
                          inside(f(i, j + 1))};
      if (in[0] == in[1] && in[1] == in[2] && in[2] == in[3]) continue;
      // the square's sides counterclockwise: bottom, right, top (right to left), left (down)
      struct Crossing {
        std::int64_t id;
        bool exit;  // from inside to outside, going counterclockwise
      };
      Crossing c[4];
      int count = 0;
      for (int s = 0; s < 4; ++s) {
        const bool a = in[s], b = in[(s + 1) % 4];
        if (a == b) continue;
        std::int64_t id = 0;
        if (s == 0) id = vertexOn(i, j, i + 1, j, across);
        if (s == 1) id = vertexOn(i + 1, j, i + 1, j + 1, up);
        if (s == 2) id = vertexOn(i, j + 1, i + 1, j + 1, across);
        if (s == 3) id = vertexOn(i, j, i, j + 1, up);
        c[count++] = {id, a};
      }
      // a saddle: the inside corners are joined across the square when its centre is inside
      bool joined = true;
      if (count == 4) {
        const Vec3 m = at(plane, u0 + (static_cast<double>(i) + 0.5) * cell,
                          v0 + (static_cast<double>(j) + 0.5) * cell);
        joined = inside(field.eval(m[0], m[1], m[2]));
      }
      for (int k = 0; k < count; ++k) {
        if (!c[k].exit) continue;
        // joined (and every plain square): the next crossing; apart: the one before
        const int to = joined ? (k + 1) % count : (k + count - 1) % count;
        link(c[k].id, c[to].id);
      }
    }
    if (j % 64 == 0) progress.step(0.7 + 0.25 * static_cast<double>(j) / static_cast<double>(nv));
  }
  next.resize(points.size(), -1);

  // loops: chains that start at the rectangle's edge first (open), then the closed ones
  std::vector<bool> used(points.size(), false), hasIncoming(points.size(), false);
  for (std::int64_t n : next)
    if (n >= 0) hasIncoming[static_cast<std::size_t>(n)] = true;
  std::vector<SectionLoop> loops;
  auto walk = [&](std::size_t start, bool closed) {
    SectionLoop loop;
    loop.closed = closed;
    std::int64_t k = static_cast<std::int64_t>(start);
    while (k >= 0 && !used[static_cast<std::size_t>(k)]) {
      used[static_cast<std::size_t>(k)] = true;
      loop.points.push_back(points[static_cast<std::size_t>(k)]);
      k = next[static_cast<std::size_t>(k)];
    }
    if (loop.points.size() >= 2) loops.push_back(std::move(loop));
  };
  for (std::size_t k = 0; k < points.size(); ++k)
    if (!hasIncoming[k] && !used[k]) walk(k, false);
  for (std::size_t k = 0; k < points.size(); ++k)
    if (!used[k]) walk(k, true);
  progress.step(1.0);
  return loops;
}

}  // namespace frep
