#include "hspline/hspline_attach.h"

#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/CatmullClarkT.hh>
#include <string>
#include <vector>

#include "base/errors.h"

namespace frep {

namespace {

struct Traits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
};
using ControlNet = OpenMesh::PolyMesh_ArrayKernelT<Traits>;

[[noreturn]] void refuse(const std::string& why) {
  throw ModelError("hspline attachment: " + why);
}

}  // namespace

HSpline hsplineWithLevel(const HSpline& h, int level) {
  HSpline out = h;
  // Refining one CV adds the next level's knots (its grid); zero offsets leave the surface.
  while (out.levelCount() <= level) {
    const HsLevel& last = out.level(out.levelCount() - 1);
    out.refine(out.levelCount() - 1, {{last.cvs.front().i, last.cvs.front().j}});
  }
  return out;
}

HsAttachment attachCylinder(const HSpline& parentSurface, int i0, int i1, int j0, int j1,
                            const HSpline& cylinder, int subdivisions, bool closeEnd,
                            int parentLevel) {
  if (parentLevel < 0 || parentLevel > kMaxAttachLevel)
    refuse("the seam level must be 0 to " + std::to_string(kMaxAttachLevel) + ", got " +
           std::to_string(parentLevel));
  const HSpline parent = hsplineWithLevel(parentSurface, parentLevel);
  const HsLevel& p = parent.level(parentLevel);
  const HsLevel& c = cylinder.level(0);
  const int nu = p.u.count(), nv = p.v.count();
  if (static_cast<std::size_t>(nu) * static_cast<std::size_t>(nv) > kMaxAttachGrid)
    refuse("the parent's level " + std::to_string(parentLevel) + " has " + std::to_string(nu) +
           " x " + std::to_string(nv) + " CVs, more than the " + std::to_string(kMaxAttachGrid) +
           " a seam's net may have; choose a lower level");
  if (subdivisions < 0 || subdivisions > 6)
    refuse("subdivisions must be 0 to 6, got " + std::to_string(subdivisions));
  if (!(0 <= i0 && i0 < i1 && i1 < nu && 0 <= j0 && j0 < j1 && j1 < nv))
    refuse("the rectangle [" + std::to_string(i0) + ", " + std::to_string(i1) + "] x [" +
           std::to_string(j0) + ", " + std::to_string(j1) + "] must lie inside the parent's " +
           std::to_string(nu) + " x " + std::to_string(nv) + " CVs, with i0 < i1 and j0 < j1");
  const int ring = 2 * (i1 - i0) + 2 * (j1 - j0);
  if (!c.u.isPeriodic() || c.v.isPeriodic())
    refuse("the cylinder must be periodic around (u) and open along (v)");
  if (c.u.count() != ring)
    refuse("the cylinder has " + std::to_string(c.u.count()) +
           " CVs around; the ring around the rectangle has " + std::to_string(ring));
  if (c.v.count() < 3) refuse("the cylinder needs at least 3 rows of CVs along v");

  ControlNet net;
  const std::vector<Vec3> cylinderPoints = cylinder.positions(0);
  auto point = [](const Vec3& x) { return ControlNet::Point(x[0], x[1], x[2]); };
  // The parent's net on its chosen level (every grid point, through its parents' nets and
  // offsets: the detail of the levels up to it is kept), but the points strictly inside the
  // rectangle, whose patches give way.
  std::vector<ControlNet::VertexHandle> pv(static_cast<std::size_t>(nu) * nv);
  auto inside = [&](int i, int j) { return i0 < i && i < i1 && j0 < j && j < j1; };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i)
      if (!inside(i, j))
        pv[i + static_cast<std::size_t>(nu) * j] =
            net.add_vertex(point(parent.position(parentLevel, i, j)));
  const int cellsU = p.u.isPeriodic() ? nu : nu - 1, cellsV = p.v.isPeriodic() ? nv : nv - 1;
  auto at = [&](int i, int j) { return pv[(i % nu) + static_cast<std::size_t>(nu) * (j % nv)]; };
  for (int j = 0; j < cellsV; ++j)
    for (int i = 0; i < cellsU; ++i) {
      if (i0 <= i && i < i1 && j0 <= j && j < j1) continue;
      net.add_face(std::vector<ControlNet::VertexHandle>{at(i, j), at(i + 1, j), at(i + 1, j + 1),
                                                         at(i, j + 1)});
    }
  // The ring, in the cylinder's order around.
  std::vector<ControlNet::VertexHandle> ringVertices;
  for (int i = i0; i < i1; ++i) ringVertices.push_back(at(i, j0));
  for (int j = j0; j < j1; ++j) ringVertices.push_back(at(i1, j));
  for (int i = i1; i > i0; --i) ringVertices.push_back(at(i, j1));
  for (int j = j1; j > j0; --j) ringVertices.push_back(at(i0, j));
  // The cylinder from row 1 (the ring) up; row 0 is dropped.
  const int rows = c.v.count();
  std::vector<std::vector<ControlNet::VertexHandle>> cyl(static_cast<std::size_t>(rows));
  cyl[1] = ringVertices;
  for (int r = 2; r < rows; ++r)
    for (int k = 0; k < ring; ++k)
      cyl[static_cast<std::size_t>(r)].push_back(net.add_vertex(
          point(cylinderPoints[static_cast<std::size_t>(k) + static_cast<std::size_t>(ring) * r])));
  for (int r = 1; r + 1 < rows; ++r)
    for (int k = 0; k < ring; ++k) {
      const auto& a = cyl[static_cast<std::size_t>(r)];
      const auto& b = cyl[static_cast<std::size_t>(r) + 1];
      const int k1 = (k + 1) % ring;
      if (!net.add_face(std::vector<ControlNet::VertexHandle>{a[k], a[k1], b[k1], b[k]}).is_valid())
        refuse(
            "the cylinder's CVs do not join the ring consistently (its u must run along the ring's "
            "order)");
    }

  if (closeEnd) {
    // One face over the last row, turning the way the quads below it leave that row's edges.
    const auto& top = cyl[static_cast<std::size_t>(rows) - 1];
    if (!net.add_face(top).is_valid())
      refuse("the cylinder's last row cannot be closed by one face");
  }

  HsAttachment out;
  out.controlFaces = net.n_faces();
  for (auto v : net.vertices())
    if (!net.is_boundary(v) && net.valence(v) != 4) ++out.extraordinary;
  OpenMesh::Subdivider::Uniform::CatmullClarkT<ControlNet> subdivide;
  subdivide.attach(net);
  subdivide(static_cast<std::size_t>(subdivisions));
  subdivide.detach();
  net.garbage_collection();
  for (auto v : net.vertices()) {
    const auto& x = net.point(v);
    out.mesh.positions.push_back({float(x[0]), float(x[1]), float(x[2])});
  }
  for (auto f : net.faces()) {
    std::vector<std::uint32_t> corner;
    for (auto v : net.fv_range(f)) corner.push_back(static_cast<std::uint32_t>(v.idx()));
    for (std::size_t k = 1; k + 1 < corner.size(); ++k)
      out.mesh.triangles.push_back({corner[0], corner[k], corner[k + 1]});
  }
  std::vector<char> seen(net.n_halfedges(), 0);
  for (auto h : net.halfedges()) {
    if (!net.is_boundary(h) || seen[static_cast<std::size_t>(h.idx())]) continue;
    ++out.boundaryLoops;
    for (auto g = h; !seen[static_cast<std::size_t>(g.idx())]; g = net.next_halfedge_handle(g))
      seen[static_cast<std::size_t>(g.idx())] = 1;
  }
  return out;
}

}  // namespace frep
