#include "pipeline/accuracy.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "base/errors.h"
#include "base/triangle_adjacency.h"
#include "base/triangle_geometry.h"
#include "mesh/mesher.h"

namespace frep {

namespace {

Vec3d toD(const Vec3f& p) {
  return {p[0], p[1], p[2]};
}
Vec3d minus(const Vec3d& a, const Vec3d& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
double dotD(const Vec3d& a, const Vec3d& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// |G| / |grad G| for G = min(F, distance to the box): the first-order distance to G = 0.
double distanceToSurface(const Field& f, const Box3& box, const Vec3d& p) {
  double toBox = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) toBox = std::min({toBox, p[a] - box.lo[a], box.hi[a] - p[a]});
  const Dual g = f.evalGradient(p[0], p[1], p[2]);
  if (toBox < g.v) return std::abs(toBox);
  const double len = std::sqrt(g.d[0] * g.d[0] + g.d[1] * g.d[1] + g.d[2] * g.d[2]);
  if (!(len > 0.0) || !std::isfinite(len)) return std::abs(g.v) > 0 ? HUGE_VAL : 0.0;
  return std::abs(g.v) / len;
}

// The distance from p to triangle abc (closest point by regions of the triangle: Ericson,
// Real-Time Collision Detection, 5.1.5).
double pointTriangleDistance(const Vec3d& p, const Vec3d& a, const Vec3d& b, const Vec3d& c) {
  const Vec3d ab = minus(b, a), ac = minus(c, a), ap = minus(p, a);
  const double d1 = dotD(ab, ap), d2 = dotD(ac, ap);
  auto at = [&](const Vec3d& q) { return std::sqrt(dotD(minus(p, q), minus(p, q))); };
  auto along = [](const Vec3d& o, const Vec3d& d, double t) {
    return Vec3d{o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]};
  };
  if (d1 <= 0 && d2 <= 0) return at(a);
  const Vec3d bp = minus(p, b);
  const double d3 = dotD(ab, bp), d4 = dotD(ac, bp);
  if (d3 >= 0 && d4 <= d3) return at(b);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return at(along(a, ab, d1 / (d1 - d3)));
  const Vec3d cp = minus(p, c);
  const double d5 = dotD(ab, cp), d6 = dotD(ac, cp);
  if (d6 >= 0 && d5 <= d6) return at(c);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return at(along(a, ac, d2 / (d2 - d6)));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return at(along(b, minus(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6))));
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  return at({a[0] + ab[0] * v + ac[0] * w, a[1] + ab[1] * v + ac[1] * w,
             a[2] + ab[2] * v + ac[2] * w});
}

// The mesh's triangles in a uniform grid, for nearest-triangle queries.
class TriangleGrid {
 public:
  TriangleGrid(const TriangleMesh& m, double cell) : m_(m), cell_(cell) {
    for (std::uint32_t t = 0; t < m.triangles.size(); ++t) {
      std::int64_t lo[3], hi[3];
      range(t, lo, hi);
      for (std::int64_t k = lo[2]; k <= hi[2]; ++k)
        for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
          for (std::int64_t i = lo[0]; i <= hi[0]; ++i) cells_[key(i, j, k)].push_back(t);
    }
  }

  // The distance from p to the nearest triangle, searching shells of cells outwards until no
  // nearer triangle can be found; infinity beyond `limit` cells.
  double nearest(const Vec3d& p, int limit, std::vector<std::uint32_t>& seen) const {
    const std::int64_t c[3] = {index(p[0]), index(p[1]), index(p[2])};
    double best = std::numeric_limits<double>::infinity();
    seen.clear();
    for (int r = 0; r <= limit; ++r) {
      // every point of shell r is at least (r - 1) cells from p
      if (best <= (r - 1) * cell_) break;
      for (std::int64_t k = c[2] - r; k <= c[2] + r; ++k)
        for (std::int64_t j = c[1] - r; j <= c[1] + r; ++j)
          for (std::int64_t i = c[0] - r; i <= c[0] + r; ++i) {
            if (std::max({std::abs(i - c[0]), std::abs(j - c[1]), std::abs(k - c[2])}) != r)
              continue;  // inside the shell: done in an earlier round
            const auto it = cells_.find(key(i, j, k));
            if (it == cells_.end()) continue;
            for (std::uint32_t t : it->second) {
              const Triangle& tr = m_.triangles[t];
              best = std::min(best, pointTriangleDistance(p, toD(m_.positions[tr[0]]),
                                                          toD(m_.positions[tr[1]]),
                                                          toD(m_.positions[tr[2]])));
            }
          }
    }
    return best;
  }

 private:
  std::int64_t index(double v) const { return static_cast<std::int64_t>(std::floor(v / cell_)); }
  static std::uint64_t key(std::int64_t i, std::int64_t j, std::int64_t k) {
    const std::uint64_t m = (1u << 21) - 1;
    return ((static_cast<std::uint64_t>(k) & m) << 42) | ((static_cast<std::uint64_t>(j) & m) << 21) |
           (static_cast<std::uint64_t>(i) & m);
  }
  void range(std::uint32_t t, std::int64_t lo[3], std::int64_t hi[3]) const {
    const Triangle& tr = m_.triangles[t];
    for (int a = 0; a < 3; ++a) {
      lo[a] = index(std::min({m_.positions[tr[0]][a], m_.positions[tr[1]][a], m_.positions[tr[2]][a]}));
      hi[a] = index(std::max({m_.positions[tr[0]][a], m_.positions[tr[1]][a], m_.positions[tr[2]][a]}));
    }
  }
  const TriangleMesh& m_;
  double cell_;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells_;
};

}  // namespace

AccuracyReport measureAccuracy(const TriangleMesh& mesh, const Field& field,
                               const AccuracyOptions& o) {
  if (!(o.cell > 0.0) || !std::isfinite(o.cell))
    throw ModelError("accuracy: cell must be a positive number");
  if (o.sampleRefinement < 1 || o.sampleRefinement > 8)
    throw ModelError("accuracy: sampleRefinement must be 1 to 8");
  AccuracyReport r;
  r.volume = meshVolume(mesh);
  if (mesh.triangles.empty()) return r;

  // mesh -> surface: vertices, edge midpoints (three per face: each inner edge twice, which
  // changes the mean a little, not the largest) and face centres
  const std::size_t nt = mesh.triangles.size();
  tbb::enumerable_thread_specific<std::pair<double, double>> worst(std::make_pair(0.0, 0.0));  // max, sum
  tbb::parallel_for(std::size_t(0), nt, [&](std::size_t t) {
    const Triangle& tr = mesh.triangles[t];
    const Vec3d a = toD(mesh.positions[tr[0]]), b = toD(mesh.positions[tr[1]]),
                c = toD(mesh.positions[tr[2]]);
    const Vec3d points[5] = {a,
                             {(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2},
                             {(b[0] + c[0]) / 2, (b[1] + c[1]) / 2, (b[2] + c[2]) / 2},
                             {(c[0] + a[0]) / 2, (c[1] + a[1]) / 2, (c[2] + a[2]) / 2},
                             {(a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3,
                              (a[2] + b[2] + c[2]) / 3}};
    auto& w = worst.local();
    // each face measures its first corner: every vertex of a closed mesh is some face's first
    // corner or is measured as another face's (a vertex is in several faces)
    for (const Vec3d& p : points) {
      const double d = distanceToSurface(field, o.bbox, p);
      w.first = std::max(w.first, d);
      w.second += d;
    }
  });
  double sum = 0.0;
  for (const auto& w : worst) {
    r.meshToSurface = std::max(r.meshToSurface, w.first);
    sum += w.second;
  }
  r.samples = 5 * nt;
  r.meshToSurfaceMean = sum / static_cast<double>(r.samples);

  // surface -> mesh: the vertices of a finer mesh of the same field lie on the surface
  MeshingOptions fine;
  fine.bbox = o.bbox;
  fine.resolution = o.cell / o.sampleRefinement;
  fine.normals = false;
  const TriangleMesh samples = polygonize(field, fine);
  const TriangleGrid grid(mesh, o.cell);
  tbb::enumerable_thread_specific<double> far(0.0);
  tbb::enumerable_thread_specific<std::vector<std::uint32_t>> scratch;
  tbb::parallel_for(std::size_t(0), samples.positions.size(), [&](std::size_t v) {
    const double d = grid.nearest(toD(samples.positions[v]), 64, scratch.local());
    double& f = far.local();
    f = std::max(f, d);
  });
  for (double f : far) r.surfaceToMesh = std::max(r.surfaceToMesh, f);
  r.samples += samples.positions.size();
  r.hausdorff = std::max(r.meshToSurface, r.surfaceToMesh);

  // creases: edges whose two faces' normals differ by more than the angle
  const auto neighbours = facetNeighbours(mesh);
  const double cosLimit = std::cos(o.creaseAngleDeg * M_PI / 180.0);
  for (std::uint32_t t = 0; t < nt; ++t)
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t u = neighbours[t][e];
      if (u == kNoNeighbour || u < t) continue;  // each edge once
      const Triangle &a = mesh.triangles[t], &b = mesh.triangles[u];
      const Vec3d na = triangleCross(mesh.positions[a[0]], mesh.positions[a[1]], mesh.positions[a[2]]);
      const Vec3d nb = triangleCross(mesh.positions[b[0]], mesh.positions[b[1]], mesh.positions[b[2]]);
      const double la = norm(na), lb = norm(nb);
      if (!(la > 0) || !(lb > 0) || dotD(na, nb) >= cosLimit * la * lb) continue;
      const Vec3d p = toD(mesh.positions[a[e]]), q = toD(mesh.positions[a[(e + 1) % 3]]);
      r.creaseLength += norm(minus(p, q));
    }
  return r;
}

}  // namespace frep
