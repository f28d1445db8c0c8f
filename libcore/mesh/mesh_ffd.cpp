// deformMesh: the forward map per vertex, in chunks so progress and cancel are prompt.
#include "mesh/mesh_ffd.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <cmath>
#include <sstream>

#include "base/errors.h"

namespace frep {

namespace {

// Each moved vertex sums every control point (the map is one Bezier volume): 100,000 vertices
// (an STL of 35,000 triangles) by a 64 x 64 x 64 lattice's 274,625 points took 15 s on two
// cores. Past this many products the deformation is refused before it starts, with figures.
constexpr double kMostVertexPointProducts = 6e9;

void refuseTooMuchWork(const TriangleMesh& mesh, const FfdLattice& lattice) {
  std::size_t moved = 0;
  for (const Vec3f& p : mesh.positions) {
    const Vec3 s = lattice.local(Vec3{p[0], p[1], p[2]});
    moved += s[0] >= 0 && s[0] <= 1 && s[1] >= 0 && s[1] <= 1 && s[2] >= 0 && s[2] <= 1;
  }
  const double products = double(moved) * double(lattice.pointCount());
  if (products <= kMostVertexPointProducts) return;
  std::ostringstream os;
  os.precision(3);
  os << "deform: " << moved << " vertices inside the lattice, each summing its "
     << lattice.pointCount() << " control points (" << lattice.divisions(0) << " x "
     << lattice.divisions(1) << " x " << lattice.divisions(2) << " divisions), make " << products
     << " products; at most " << kMostVertexPointProducts
     << " are allowed: use a lattice of fewer divisions or a mesh of fewer vertices";
  throw TooLargeError(os.str());
}

}  // namespace

TriangleMesh deformMesh(const TriangleMesh& mesh, const FfdLattice& lattice,
                        const MeshFfdOptions& options) {
  refuseTooMuchWork(mesh, lattice);
  TriangleMesh out;
  out.triangles = mesh.triangles;
  out.positions.resize(mesh.positions.size());
  const bool normals = mesh.normals.size() == mesh.positions.size();
  if (normals) out.normals.resize(mesh.normals.size());
  const Box3& rest = lattice.rest();
  constexpr std::size_t kChunk = 1 << 14;
  const std::size_t n = mesh.positions.size();
  std::atomic<bool> cancelled{false};
  for (std::size_t start = 0; start < n; start += kChunk) {
    const std::size_t end = std::min(n, start + kChunk);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(start, end, 256), [&](const auto& range) {
      for (std::size_t v = range.begin(); v != range.end(); ++v) {
        const Vec3f& p = mesh.positions[v];
        const Vec3 x{p[0], p[1], p[2]};
        const Vec3 s = lattice.local(x);
        const bool moved =
            s[0] >= 0 && s[0] <= 1 && s[1] >= 0 && s[1] <= 1 && s[2] >= 0 && s[2] <= 1;
        if (!moved) {
          out.positions[v] = p;
          if (normals) out.normals[v] = mesh.normals[v];
          continue;
        }
        Mat3 j;
        const Vec3 y = lattice.forward(s, normals ? &j : nullptr);
        out.positions[v] = {float(y[0]), float(y[1]), float(y[2])};
        if (!normals) continue;
        // dy/dx = J diag(1 / size); a normal maps by its inverse transpose, i.e. by the
        // cofactor matrix up to a positive factor when the map keeps orientation.
        Mat3 a;
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) a[r][c] = j[r][c] / (rest.hi[c] - rest.lo[c]);
        const Vec3f& m = mesh.normals[v];
        Vec3 q{0, 0, 0};
        for (int r = 0; r < 3; ++r) {
          const int r1 = (r + 1) % 3, r2 = (r + 2) % 3;
          for (int c = 0; c < 3; ++c) {
            const int c1 = (c + 1) % 3, c2 = (c + 2) % 3;
            q[r] += (a[r1][c1] * a[r2][c2] - a[r1][c2] * a[r2][c1]) * m[c];
          }
        }
        const double det = determinant(a);
        const double len = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]) * (det < 0 ? -1 : 1);
        out.normals[v] =
            len != 0 ? Vec3f{float(q[0] / len), float(q[1] / len), float(q[2] / len)} : m;
      }
    });
    if (options.progress && !options.progress(double(end) / double(n))) cancelled = true;
    if (cancelled) throw Cancelled();
  }
  if (options.progress && n == 0 && !options.progress(1.0)) throw Cancelled();
  return out;
}

}  // namespace frep
