// meshDistanceField: CGAL's AABB tree and Side_of_triangle_mesh behind the Field seam.
#include "volume/mesh_distance.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "base/affine.h"
#include "base/errors.h"
#include "check/mesh_check.h"

namespace frep {

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

class MeshDistanceField final : public Field {
 public:
  MeshDistanceField(const TriangleMesh& mesh, bool inward) {
    // Identical coordinates welded as the check welds them, faces flipped outward.
    std::vector<Vec3f> welded;
    const std::vector<std::uint32_t> map = weldIdenticalVertices(mesh.positions, welded);
    for (const Vec3f& q : welded) sm_.add_vertex(Point(q[0], q[1], q[2]));
    for (const Triangle& t : mesh.triangles) {
      SurfaceMesh::Vertex_index a(map[t[0]]), b(map[t[1]]), c(map[t[2]]);
      if (a == b || b == c || a == c) continue;
      if (inward) std::swap(b, c);
      const auto f = sm_.add_face(a, b, c);
      if (f == SurfaceMesh::null_face()) throw FileError("the mesh's faces do not form a surface");
      const Vec3 pa = pos(a), pb = pos(b), pc = pos(c);
      Vec3 n = frep::cross(sub(pb, pa), sub(pc, pa));
      const double len = std::sqrt(dot(n, n));
      for (double& x : n) x = len > 0 ? x / len : 0.0;
      faces_.push_back({pa, pb, pc, n, {}, {a.idx(), b.idx(), c.idx()}});
    }
    // Pseudo-normals (Baerentzen and Aanaes): an edge's is the sum of its two faces' normals,
    // a vertex's the sum of its faces' normals weighted by their angles there. The sign of
    // (p - q) . N, with N the pseudo-normal of the feature the nearest point q lies on, is
    // the side of p for a closed, manifold, self-intersection-free mesh: no ray is cast.
    vertexNormals_.assign(sm_.number_of_vertices(), Vec3{0, 0, 0});
    for (std::size_t fi = 0; fi < faces_.size(); ++fi) {
      Face& f = faces_[fi];
      const Vec3 c[3] = {f.a, f.b, f.c};
      for (int k = 0; k < 3; ++k) {
        const Vec3 e1 = sub(c[(k + 1) % 3], c[k]), e2 = sub(c[(k + 2) % 3], c[k]);
        const double l1 = std::sqrt(dot(e1, e1)), l2 = std::sqrt(dot(e2, e2));
        const double angle = l1 > 0 && l2 > 0 ? std::acos(std::clamp(dot(e1, e2) / (l1 * l2), -1.0, 1.0)) : 0.0;
        Vec3& vn = vertexNormals_[f.vertex[k]];
        for (int a = 0; a < 3; ++a) vn[a] += angle * f.n[a];
      }
    }
    for (const auto fd : sm_.faces()) {
      Face& f = faces_[fd.idx()];
      auto h = sm_.halfedge(fd);
      for (int k = 0; k < 3; ++k, h = sm_.next(h)) {
        // The halfedge from corner k to corner k+1 (CGAL's halfedge(f) points at corner 0's
        // successor's... found by its source).
        const auto src = sm_.source(h);
        int corner = 0;
        while (corner < 3 && f.vertex[corner] != src.idx()) ++corner;
        const auto other = sm_.face(sm_.opposite(h));
        Vec3 en = f.n;
        if (other != SurfaceMesh::null_face())
          for (int a = 0; a < 3; ++a) en[a] += faces_[other.idx()].n[a];
        if (corner < 3) f.edgeNormal[corner] = en;
      }
    }
    tree_.insert(faces(sm_).first, faces(sm_).second, sm_);
    tree_.build();
    // CGAL's first guess of each closest-point query: the nearest of its k-d tree of the
    // primitives' reference points (a nanoflann tree of the vertices instead measured no
    // faster: random queries on a 1.3 M-triangle mesh are bound by cache misses, 100 us a
    // point, coherent ones as a mesher makes them 28 us either way).
    tree_.accelerate_distance_queries();
    for (int a = 0; a < 3; ++a) {
      bounds_.lo[a] = std::numeric_limits<double>::infinity();
      bounds_.hi[a] = -std::numeric_limits<double>::infinity();
    }
    for (const auto v : sm_.vertices())
      for (int a = 0; a < 3; ++a) {
        bounds_.lo[a] = std::min(bounds_.lo[a], sm_.point(v)[a]);
        bounds_.hi[a] = std::max(bounds_.hi[a], sm_.point(v)[a]);
      }
  }

  double eval(double x, double y, double z) const override { return signedDistance(x, y, z, nullptr); }

  Dual evalGradient(const Dual& x, const Dual& y, const Dual& z) const override {
    double g[3];
    const double v = signedDistance(x.v, y.v, z.v, g);
    return composed(v, g, x, y, z);
  }
  using Field::evalGradient;

  Interval evalInterval(const Interval& x, const Interval& y, const Interval& z) const override {
    const Interval in[3] = {x, y, z};
    double c[3], r2 = 0.0;
    for (int a = 0; a < 3; ++a) {
      if (!std::isfinite(in[a].lo) || !std::isfinite(in[a].hi)) return Interval::entire(x.nan || y.nan || z.nan);
      c[a] = 0.5 * (in[a].lo + in[a].hi);
      const double h = 0.5 * (in[a].hi - in[a].lo);
      r2 += h * h;
    }
    const double f = eval(c[0], c[1], c[2]);
    // A 1-Lipschitz function; the margin covers the rounding of both distances.
    const double r = std::sqrt(r2) * (1.0 + 1e-12) + 1e-9 * (std::abs(f) + scale());
    return Interval(f - r, f + r, x.nan || y.nan || z.nan);
  }

  Box3 bounds() const override { return bounds_; }

 private:
  struct Face {
    Vec3 a, b, c, n;
    std::array<Vec3, 3> edgeNormal;  // of the edge from corner k to corner k + 1
    std::array<std::uint32_t, 3> vertex;
  };
  static Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
  static double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
  Vec3 pos(SurfaceMesh::Vertex_index v) const {
    const Point& q = sm_.point(v);
    return {q.x(), q.y(), q.z()};
  }
  double scale() const {
    double s = 0;
    for (int a = 0; a < 3; ++a) s = std::max(s, std::abs(bounds_.lo[a]) + std::abs(bounds_.hi[a]));
    return s;
  }

  // The pseudo-normal of the feature of face f that q (its nearest point to p) lies on: the
  // face, one of its edges or one of its corners, from q's barycentric coordinates.
  const Vec3& featureNormal(const Face& f, const Vec3& q) const {
    const Vec3 e0 = sub(f.b, f.a), e1 = sub(f.c, f.a), d = sub(q, f.a);
    const double d00 = dot(e0, e0), d01 = dot(e0, e1), d11 = dot(e1, e1);
    const double d20 = dot(d, e0), d21 = dot(d, e1);
    const double den = d00 * d11 - d01 * d01;
    if (!(den > 0)) return f.n;  // a degenerate face: never the only nearest one
    const double v = (d11 * d20 - d01 * d21) / den, w = (d00 * d21 - d01 * d20) / den;
    const double bary[3] = {1.0 - v - w, v, w};
    constexpr double kOn = 1e-7;  // on an edge or corner within rounding
    const bool zero[3] = {bary[0] < kOn, bary[1] < kOn, bary[2] < kOn};
    const int zeros = zero[0] + zero[1] + zero[2];
    if (zeros == 0) return f.n;
    if (zeros == 1) {
      // On the edge opposite the zero corner: from corner k+1 to k+2.
      const int k = zero[0] ? 0 : zero[1] ? 1 : 2;
      return f.edgeNormal[(k + 1) % 3];
    }
    const int k = !zero[0] ? 0 : !zero[1] ? 1 : 2;  // at the one corner left
    return vertexNormals_[f.vertex[k]];
  }

  double signedDistance(double x, double y, double z, double* g) const {
    const Point p(x, y, z);
    const auto hit = tree_.closest_point_and_primitive(p);
    const Vec3 q = {hit.first.x(), hit.first.y(), hit.first.z()};
    const Face& f = faces_[hit.second.idx()];
    const Vec3 d = sub({x, y, z}, q);
    const double dist = std::sqrt(dot(d, d));
    const bool inside = dot(d, featureNormal(f, q)) < 0;
    if (g) {
      // dF = -(p - q)/|p - q| outside, +(p - q)/|p - q| inside; on the surface, -n.
      for (int k = 0; k < 3; ++k)
        g[k] = dist > 0 ? (inside ? d[k] : -d[k]) / dist : -f.n[k];
    }
    return inside ? dist : -dist;
  }

  SurfaceMesh sm_;
  std::vector<Face> faces_;
  Tree tree_;
  std::vector<Vec3> vertexNormals_;
  Box3 bounds_;
};

}  // namespace

std::shared_ptr<const Field> meshDistanceField(const TriangleMesh& mesh, const std::string& where) {
  const CheckReport r = checkMesh(mesh, nullptr, 1);
  std::string problem;
  if (r.faces == 0) problem = "the mesh has no triangles";
  else if (r.nonFiniteVertices) problem = std::to_string(r.nonFiniteVertices) + " vertices with non-finite coordinates";
  else if (r.borderEdges) problem = "the mesh is open (" + std::to_string(r.borderEdges) + " border edges), so it has no inside";
  else if (r.nonManifoldEdges) problem = std::to_string(r.nonManifoldEdges) + " non-manifold edges (shared by more than two triangles)";
  else if (r.misorientedEdges) problem = std::to_string(r.misorientedEdges) + " edges where neighbouring triangles disagree on orientation";
  else if (r.selfIntersections) problem = "its triangles intersect each other, so its inside is ambiguous";
  if (!problem.empty())
    throw FileError(where + ": " + problem + "; the exact distance needs a closed, "
                    "self-intersection-free mesh (method 'grid' accepts overlapping shells; "
                    "`frepcad check` shows every defect)");
  return std::make_shared<MeshDistanceField>(mesh, r.volume < 0);
}

}  // namespace frep
