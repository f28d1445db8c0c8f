#include "mesh/openmesh_bridge.h"

#include "base/errors.h"

namespace frep {

OMesh toOpenMesh(const TriangleMesh& mesh) {
  OMesh om;
  om.reserve(mesh.positions.size(), mesh.triangles.size() * 3 / 2, mesh.triangles.size());
  std::vector<OMesh::VertexHandle> handles;
  handles.reserve(mesh.positions.size());
  for (const Vec3f& p : mesh.positions) handles.push_back(om.add_vertex(OMesh::Point(p[0], p[1], p[2])));
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const Triangle& t = mesh.triangles[i];
    if (!om.add_face(handles[t[0]], handles[t[1]], handles[t[2]]).is_valid())
      throw ModelError("OpenMesh rejected triangle " + std::to_string(i) +
                       " (non-manifold configuration)");
  }
  return om;
}

TriangleMesh fromOpenMesh(const OMesh& om) {
  TriangleMesh mesh;
  mesh.positions.reserve(om.n_vertices());
  for (auto v : om.vertices()) {
    const auto& p = om.point(v);
    mesh.positions.push_back({p[0], p[1], p[2]});
  }
  for (auto f : om.faces()) {
    Triangle t{};
    int i = 0;
    for (auto v : om.fv_range(f)) t[i++ < 3 ? i - 1 : 2] = static_cast<std::uint32_t>(v.idx());
    mesh.triangles.push_back(t);
  }
  return mesh;
}

}  // namespace frep
