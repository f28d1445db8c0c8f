#include "pipeline/accuracy.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <unordered_map>

#include "base/errors.h"
#include "base/triangle_adjacency.h"
#include "base/triangle_geometry.h"
#include "mesh/mesher.h"
#include "mesh/sampling_grid.h"

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

// The box-capped field's value at x.
double cappedValue(const Field& f, const Box3& box, const Vec3d& x) {
  return cappedByBox(Dual(f.eval(x[0], x[1], x[2])), box, x).v;
}

// A point of G = 0 on the segment from p (value gp) to q (of the other side), by bisection:
// its distance from p bounds the distance from p to the surface.
double crossingDistance(const Field& f, const Box3& box, const Vec3d& p, double gp,
                        const Vec3d& q) {
  double lo = 0.0, hi = 1.0;  // the side of p at lo, the other at hi
  for (int k = 0; k < 40; ++k) {
    const double t = 0.5 * (lo + hi);
    const Vec3d x{p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1]), p[2] + t * (q[2] - p[2])};
    if ((cappedValue(f, box, x) >= 0.0) == (gp >= 0.0))
      lo = t;
    else
      hi = t;
  }
  return hi * std::sqrt(dotD(minus(q, p), minus(q, p)));
}

// A nearer surface point than `bound` from p (value gp), searched best first through the
// cubes round p: a cube whose values the field's intervals put all on p's side holds none;
// another's centre, where it lies on the other side, gives a crossing on the segment from p
// (crossingDistance), and the cube is split while it is larger than `smallest`. Newton's
// steps follow one piece of a min or max and miss a nearer piece (the gyroid's sheet a tenth
// of a cell away, where the steps go to the sphere 0.7 cell away). Returns the bound lowered
// (never a distance that no crossing gives: an interval rule too wide only makes it search
// more). At most `budget` cubes are looked at.
double searchNearer(const Field& f, const Box3& box, const Vec3d& p, double gp, double bound,
                    double smallest, int budget) {
  struct Cube {
    double dist;  // from p to the cube
    Vec3d lo;
    double size;
    bool operator<(const Cube& o) const { return dist > o.dist; }  // (nearest first)
  };
  const bool inside = gp >= 0.0;
  Grid boxOnly;  // (its box as a field, over intervals)
  boxOnly.lo = box.lo;
  boxOnly.hi = box.hi;
  auto distTo = [&](const Vec3d& lo, double size) {
    double s2 = 0.0;
    for (int a = 0; a < 3; ++a) {
      const double d = p[a] < lo[a]          ? lo[a] - p[a]
                       : p[a] > lo[a] + size ? p[a] - lo[a] - size
                                             : 0.0;
      s2 += d * d;
    }
    return std::sqrt(s2);
  };
  std::priority_queue<Cube> queue;
  queue.push({0.0, {p[0] - bound, p[1] - bound, p[2] - bound}, 2.0 * bound});
  double best = bound;
  for (int looked = 0; !queue.empty() && looked < budget; ++looked) {
    const Cube c = queue.top();
    queue.pop();
    if (c.dist >= best) break;
    const Interval x(c.lo[0], c.lo[0] + c.size), y(c.lo[1], c.lo[1] + c.size),
        z(c.lo[2], c.lo[2] + c.size);
    const Interval v = min(f.evalInterval(x, y, z), boxOnly.boxField(x, y, z));
    const bool otherSide = inside ? (v.lo < 0.0 || v.nan) : v.hi >= 0.0;
    if (!otherSide) continue;
    const double h = 0.5 * c.size;
    const Vec3d centre{c.lo[0] + h, c.lo[1] + h, c.lo[2] + h};
    const double gc = cappedValue(f, box, centre);
    if ((gc >= 0.0) != inside) {
      const double d = crossingDistance(f, box, p, gp, centre);
      best = std::min(best, d);
    }
    if (c.size <= smallest) continue;
    for (int k = 0; k < 8; ++k) {
      const Vec3d lo{c.lo[0] + (k & 1) * h, c.lo[1] + ((k >> 1) & 1) * h, c.lo[2] + (k >> 2) * h};
      const double d = distTo(lo, h);
      if (d < best) queue.push({d, lo, h});
    }
  }
  return best;
}

// An upper bound of the distance from p to G = 0 where Newton's steps along the gradient
// reach the surface within `maxStep` of path: the distance to the point they reach, or, where
// a step lands on the other side first, to where the segment from p to there crosses the
// surface (a kink of a min or max, where the steps would swing between two pieces). Where
// neither happens (a vanishing gradient), the first-order estimate |G| / |grad G| at p,
// flagged by *reached = false.
double distanceToSurface(const Field& f, const Box3& box, const Vec3d& p, double maxStep,
                         bool* reached) {
  Vec3d x = p;
  double travelled = 0.0, first = -1.0, gp = 0.0;
  for (int k = 0; k < 8; ++k) {
    const Dual g = cappedByBox(f.evalGradient(x[0], x[1], x[2]), box, x);
    const double len2 = g.d[0] * g.d[0] + g.d[1] * g.d[1] + g.d[2] * g.d[2];
    if (k == 0) gp = g.v;
    if (k > 0 && std::isfinite(g.v) && std::isfinite(gp) && (g.v >= 0.0) != (gp >= 0.0) &&
        gp != 0.0) {
      *reached = true;
      return crossingDistance(f, box, p, gp, x);
    }
    if (!(len2 > 0.0) || !std::isfinite(len2) || !std::isfinite(g.v)) break;
    const double step = std::abs(g.v) / std::sqrt(len2);
    if (first < 0) first = step;
    if (step <= 1e-6 * maxStep) {
      // the point reached is this far, so the nearest surface point is no farther
      *reached = true;
      return std::sqrt(dotD(minus(x, p), minus(x, p))) + step;
    }
    if (travelled > maxStep) break;  // wandering (a vanishing gradient): not trusted
    const double scale = std::min(1.0, maxStep / step) * g.v / len2;
    for (int a = 0; a < 3; ++a) x[a] -= scale * g.d[a];
    travelled += std::min(step, maxStep);
  }
  *reached = false;
  return first < 0 ? std::numeric_limits<double>::infinity() : first;
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
  // nearer triangle can be found; infinity beyond `limit` cells. *closest (when given) is set
  // to the nearest point found. A cell farther from p than the nearest triangle found so far
  // is passed over: the nearest triangle is listed in the cell holding its point nearest p,
  // which is no farther from p than that point (most queries then read one to four cells of
  // the 27 round p, not all of them).
  double nearest(const Vec3d& p, int limit, Vec3d* closest = nullptr) const {
    const std::int64_t c[3] = {index(p[0]), index(p[1]), index(p[2])};
    double best = std::numeric_limits<double>::infinity();
    const double slack = 1e-9 * cell_;  // (over rounding in the cell's bounds)
    auto cellDistance = [&](std::int64_t i, std::int64_t j, std::int64_t k) {
      const std::int64_t at[3] = {i, j, k};
      double s = 0.0;
      for (int a = 0; a < 3; ++a) {
        const double lo = static_cast<double>(at[a]) * cell_, hi = lo + cell_;
        const double d = p[a] < lo ? lo - p[a] : p[a] > hi ? p[a] - hi : 0.0;
        s += d * d;
      }
      return std::sqrt(s);
    };
    for (int r = 0; r <= limit; ++r) {
      // every point of shell r is at least (r - 1) cells from p
      if (best <= (r - 1) * cell_) break;
      for (std::int64_t k = c[2] - r; k <= c[2] + r; ++k)
        for (std::int64_t j = c[1] - r; j <= c[1] + r; ++j)
          for (std::int64_t i = c[0] - r; i <= c[0] + r; ++i) {
            if (std::max({std::abs(i - c[0]), std::abs(j - c[1]), std::abs(k - c[2])}) != r)
              continue;  // inside the shell: done in an earlier round
            if (cellDistance(i, j, k) > best + slack) continue;
            const auto it = cells_.find(key(i, j, k));
            if (it == cells_.end()) continue;
            for (std::uint32_t t : it->second) {
              const Triangle& tr = m_.triangles[t];
              const Vec3d q = closestPointOnTriangle(
                  p, toD(m_.positions[tr[0]]), toD(m_.positions[tr[1]]), toD(m_.positions[tr[2]]));
              const double d = std::sqrt(dotD(minus(p, q), minus(p, q)));
              if (d < best) {
                best = d;
                if (closest) *closest = q;
              }
            }
          }
    }
    return best;
  }

 private:
  std::int64_t index(double v) const { return static_cast<std::int64_t>(std::floor(v / cell_)); }
  static std::uint64_t key(std::int64_t i, std::int64_t j, std::int64_t k) {
    const std::uint64_t m = (1u << 21) - 1;
    return ((static_cast<std::uint64_t>(k) & m) << 42) |
           ((static_cast<std::uint64_t>(j) & m) << 21) | (static_cast<std::uint64_t>(i) & m);
  }
  void range(std::uint32_t t, std::int64_t lo[3], std::int64_t hi[3]) const {
    const Triangle& tr = m_.triangles[t];
    for (int a = 0; a < 3; ++a) {
      lo[a] =
          index(std::min({m_.positions[tr[0]][a], m_.positions[tr[1]][a], m_.positions[tr[2]][a]}));
      hi[a] =
          index(std::max({m_.positions[tr[0]][a], m_.positions[tr[1]][a], m_.positions[tr[2]][a]}));
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

  // The exact surface sampled: the vertices of a finer mesh of the same field lie on it (to
  // within the finer mesh's own error), and its triangles are near it everywhere.
  MeshingOptions fine;
  fine.bbox = o.bbox;
  fine.resolution = o.cell / o.sampleRefinement;
  fine.normals = false;
  fine.settings.dropFlatVertices = false;  // (every vertex a sample)
  fine.findThinParts = false;
  const TriangleMesh samples = polygonize(field, fine);
  const TriangleGrid fineGrid(samples, o.cell);

  // mesh -> surface: at every vertex and face centre, an upper bound of the distance to the
  // surface, the nearer of two surface points: where Newton's steps along the gradient from
  // the point reach the surface (within two cells of path), and, where that is farther than
  // a tenth of a cell or not reached, where they reach it from the nearest point of the finer
  // mesh. The first alone overstates the distance wherever the gradient does not point at
  // the nearest surface (the gyroid's thin sheets: their far side's pull, up to 4 cells at
  // 128 cells, where the second finds half a cell). Where neither reaches the surface (the
  // gradient vanishes), the distance to the finer mesh is taken, and the point counted in
  // `unreached`.
  const std::size_t nt = mesh.triangles.size(), nv = mesh.positions.size();
  // per thread: the largest distance, where it was, and the sum. Equal distances (a
  // symmetric model) keep the least point, so the place reported does not depend on how the
  // threads shared the work.
  struct Worst {
    double largest = -1.0, sum = 0.0;
    Vec3d at{0, 0, 0};
    void take(double d, const Vec3d& p) {
      if (d > largest || (d == largest && p < at)) {
        largest = d;
        at = p;
      }
    }
  };
  tbb::enumerable_thread_specific<Worst> worst;
  tbb::enumerable_thread_specific<std::size_t> unreachedCount(0);
  tbb::parallel_for(std::size_t(0), nv + nt, [&](std::size_t i) {
    Vec3d p;
    if (i < nv) {
      p = toD(mesh.positions[i]);
    } else {
      const Triangle& tr = mesh.triangles[i - nv];
      for (int a = 0; a < 3; ++a)
        p[a] = (double(mesh.positions[tr[0]][a]) + mesh.positions[tr[1]][a] +
                mesh.positions[tr[2]][a]) /
               3.0;
    }
    bool reached = false;
    double d = distanceToSurface(field, o.bbox, p, 2.0 * o.cell, &reached);
    if (!reached || d > 0.1 * o.cell) {
      Vec3d q = p;
      const double toFine = fineGrid.nearest(p, 64, &q);
      bool fromFine = false;
      const double rest = distanceToSurface(field, o.bbox, q, o.cell, &fromFine);
      if (fromFine) {
        // the surface point reached from q is within rest of q
        d = reached ? std::min(d, toFine + rest) : toFine + rest;
        reached = true;
      } else if (!reached) {
        d = toFine;
        ++unreachedCount.local();
      }
      if (d > 0.1 * o.cell && std::isfinite(d)) {
        const double gp = cappedValue(field, o.bbox, p);
        if (std::isfinite(gp) && gp != 0.0)
          d = searchNearer(field, o.bbox, p, gp, d, 0.02 * o.cell, 4000);
      }
    }
    Worst& w = worst.local();
    w.take(d, p);
    w.sum += d;
  });
  for (std::size_t u : unreachedCount) r.unreached += u;
  double sum = 0.0;
  Worst all;
  for (const Worst& w : worst) {
    all.take(w.largest, w.at);
    sum += w.sum;
  }
  r.meshToSurface = std::max(0.0, all.largest);
  r.meshToSurfaceAt = all.at;
  r.samples = nv + nt;
  r.meshToSurfaceMean = sum / static_cast<double>(r.samples);
  const TriangleGrid grid(mesh, o.cell);
  tbb::enumerable_thread_specific<Worst> farthest;
  tbb::parallel_for(std::size_t(0), samples.positions.size(), [&](std::size_t v) {
    const Vec3d p = toD(samples.positions[v]);
    const double d = grid.nearest(p, 64);
    farthest.local().take(d, p);
  });
  Worst far;
  for (const Worst& f : farthest) far.take(f.largest, f.at);
  r.surfaceToMesh = std::max(0.0, far.largest);
  r.surfaceToMeshAt = far.at;
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
      const Vec3d na =
          triangleCross(mesh.positions[a[0]], mesh.positions[a[1]], mesh.positions[a[2]]);
      const Vec3d nb =
          triangleCross(mesh.positions[b[0]], mesh.positions[b[1]], mesh.positions[b[2]]);
      const double la = norm(na), lb = norm(nb);
      if (!(la > 0) || !(lb > 0) || dotD(na, nb) >= cosLimit * la * lb) continue;
      const Vec3d p = toD(mesh.positions[a[e]]), q = toD(mesh.positions[a[(e + 1) % 3]]);
      r.creaseLength += norm(minus(p, q));
    }
  return r;
}

}  // namespace frep
