// A brick's feature points: a vertex on the crease or corner a cube holds (mesh/feature_point.h),
// followed into a uniform neighbour where the tip lies beyond the cube.
#include "mesh/brick_mesher.h"

namespace frep {
namespace meshing {

bool BrickMesher::placeFeature(const Field& whole, const CellRange& r, const std::int64_t n[3],
                               std::uint32_t base, std::uint32_t mask, const std::uint32_t* L,
                               std::uint32_t len, Scratch& s, BrickResult& out) const {
  const std::vector<Vec3f>& P = out.positions;
  double leastCos;
  std::size_t spreadA, spreadB;  // the two most different normals
  if (!mostDifferentNormals(
          len, [&](std::size_t i) { return s.unit[L[2 * i]]; }, &leastCos, &spreadA, &spreadB) ||
      leastCos > kFeatureCos)
    return false;
  Quadric q;
  Vec3 normalSum{0, 0, 0};
  for (std::uint32_t i = 0; i < len; ++i) {
    const Vec3f& p = P[L[2 * i]];
    const Vec3f& u = s.unit[L[2 * i]];
    q.addPlane(Vec3{p[0], p[1], p[2]}, Vec3{u[0], u[1], u[2]});
    for (int a = 0; a < 3; ++a) normalSum[a] += u[a];
  }
  int rank = 0;
  Vec3 x = q.minimiser(kFeatureCutoff, &rank);
  if (rank < 2) return false;
  double lo[3], hi[3];
  innerBox(r, n, base, lo, hi);
  // A crease whose point nearest the planes' mean lies outside the cube may still cross
  // it: then the vertex goes where the crease line does, inside (the two most different
  // normals give its direction); else to the cube's point nearest the minimiser.
  if (rank == 2) moveAlongCreaseIntoBox(x, s.unit[L[2 * spreadA]], s.unit[L[2 * spreadB]], lo, hi);
  Vec3f at;
  int beyond = 0, outAxis = -1;  // the axes on which the point lies off the inner box
  for (int a = 0; a < 3; ++a) {
    const double h = (hi[a] - lo[a]) / (1.0 - 2.0 * kInnerMargin);
    if (!(x[a] > lo[a] - h && x[a] < hi[a] + h)) return false;
    at[a] = static_cast<float>(std::clamp(x[a], lo[a], hi[a]));
    if (x[a] < lo[a] || x[a] > hi[a]) {
      ++beyond;
      outAxis = a;
    }
  }
  // A crease or corner whose tip pokes through one face into a cube no surface crosses
  // goes there, within the pyramid over that face with its apex at that cube's centre.
  const bool extended =
      rank >= 2 && beyond == 1 &&
      reachIntoUniformNeighbour(whole, r, n, base, outAxis, x[outAxis] > hi[outAxis], x, s, at);
  for (std::uint32_t j = 0; j < len; ++j) {
    const std::uint32_t u = L[2 * j], w = L[2 * (j + 1 == len ? 0 : j + 1)];
    const Vec3d nt = triangleCross(at, P[u], P[w]);
    double dot = 0.0;
    for (int a = 0; a < 3; ++a) dot += nt[a] * (double(s.unit[u][a]) + s.unit[w][a]);
    if (!(dot > 0.0)) return false;
  }
  const std::uint32_t apex = addInnerVertex(r, n, base, at, normalSum, s, out);
  const CubeLoopTables& cl = cubeLoopTables();
  for (std::uint32_t j = 0; j < len; ++j) {
    // A fan triangle over the only line the loop draws on a face (two of the face's edges
    // crossed, no diagonal vertex) may be flipped with its neighbour cube's across that
    // line to join the two feature vertices (mesh/crease_flips.h).
    const std::uint32_t a = L[2 * j + 1], b = L[2 * (j + 1 == len ? 0 : j + 1) + 1];
    if (!extended && a < kFirstFaceDiagonal && b < kFirstFaceDiagonal &&
        crossedEdgesOnFace(mask, cl.faces[a] & cl.faces[b]) == 2)
      out.flippable.push_back(static_cast<std::uint32_t>(out.triangles.size()));
    out.triangles.push_back({apex, L[2 * j], L[2 * (j + 1 == len ? 0 : j + 1)]});
  }
  return true;
}

bool BrickMesher::reachIntoUniformNeighbour(const Field& whole, const CellRange& r,
                                            const std::int64_t n[3], std::uint32_t base, int axis,
                                            bool upper, const Vec3& x, const Scratch& s,
                                            Vec3f& at) const {
  const std::int64_t l[3] = {base % n[0], (base / n[0]) % n[1], base / (n[0] * n[1])};
  const std::int64_t side = upper ? 1 : 0;
  const std::int64_t far = l[axis] + (upper ? 2 : -1);  // the neighbour's far grid layer
  const std::int64_t farGlobal = r.lo[axis] + far;
  if (farGlobal < 0 || farGlobal >= g_.points[axis]) return false;
  int sign = -1;  // all eight corners alike: 0 outside, 1 inside
  for (int v = 0; v < 8; ++v) {
    std::int64_t p[3];
    for (int b = 0; b < 3; ++b) p[b] = l[b] + ((v >> b) & 1);
    p[axis] = (v >> axis) & 1 ? far : l[axis] + side;
    double value;
    if (p[axis] >= 0 && p[axis] < n[axis]) {
      value = s.f[static_cast<std::size_t>(p[0] + n[0] * (p[1] + n[1] * p[2]))];
    } else {
      double c[3];
      for (int b = 0; b < 3; ++b) c[b] = g_.coord(b, r.lo[b] + p[b]);
      value = combine(whole.eval(c[0], c[1], c[2]), g_.boxField(c[0], c[1], c[2]));
    }
    const int in = isInside(value);
    if (sign >= 0 && in != sign) return false;
    sign = in;
  }
  const double face = g_.coord(axis, r.lo[axis] + l[axis] + side);
  const double h = g_.h[axis];
  double lateral = 0.0;  // off the neighbour's centre line across the face, in cells
  for (int b = 0; b < 3; ++b) {
    if (b == axis) continue;
    lateral = std::max(lateral, std::abs(double(at[b]) - g_.mid(b, r.lo[b] + l[b])) / g_.h[b]);
  }
  const double limit = (0.5 - lateral - kInnerMargin) * h;
  const double depth = std::min(std::abs(x[axis] - face), limit);
  if (!(depth > kReachAtLeast * h) || std::abs(x[axis] - face) < kReachBeyond * h) return false;
  at[axis] = static_cast<float>(upper ? face + depth : face - depth);
  return true;
}

}  // namespace meshing
}  // namespace frep
