// The refiner's assembly: the outside triangles split where the seam's points were inserted,
// and the half cubes' triangles joined to them into one mesh.
#include "mesh/refiner.h"

namespace frep {
namespace refinement {

bool Refiner::splitTriangle(const Triangle& tr, std::vector<Triangle>* out) {
  std::vector<std::uint32_t> on[3];
  int cutEdges = 0, which = 0;
  for (int e = 0; e < 3; ++e) {
    on[e] = cells_.between(tr[e], tr[(e + 1) % 3]);
    if (!on[e].empty()) {
      ++cutEdges;
      which = e;
    }
  }
  if (cutEdges == 0) return false;
  if (cutEdges == 1) {
    std::vector<std::uint32_t> chain = {tr[which]};
    chain.insert(chain.end(), on[which].begin(), on[which].end());
    chain.push_back(tr[(which + 1) % 3]);
    for (std::size_t i = 0; i + 1 < chain.size(); ++i)
      out->push_back({tr[(which + 2) % 3], chain[i], chain[i + 1]});
    return true;
  }
  std::vector<std::uint32_t> poly;
  for (int e = 0; e < 3; ++e) {
    poly.push_back(tr[e]);
    poly.insert(poly.end(), on[e].begin(), on[e].end());
  }
  Vec3f cen;
  for (int k = 0; k < 3; ++k)
    cen[k] = static_cast<float>((double(mesh_.positions[tr[0]][k]) + mesh_.positions[tr[1]][k] +
                                 mesh_.positions[tr[2]][k]) /
                                3.0);
  const std::uint32_t v = newVertex(cen);
  for (std::size_t i = 0; i < poly.size(); ++i)
    out->push_back({v, poly[i], poly[(i + 1) % poly.size()]});
  return true;
}

void Refiner::splitTriangles() {
  if (cells_.cuts().empty()) return;
  std::vector<std::uint8_t> mark(mesh_.positions.size(), 0);
  for (const auto& [k, list] : cells_.cuts()) {
    mark[k >> 32] = 1;
    mark[k & 0xffffffffu] = 1;
  }
  auto marked = [&](const Triangle& t) {
    int n = 0;
    for (std::uint32_t v : t) n += v < mark.size() && mark[v];
    return n >= 2;
  };
  std::vector<Triangle> outside;
  for (std::size_t t = 0; t < mesh_.triangles.size(); ++t) {
    if (removed_[t] || !marked(mesh_.triangles[t])) continue;
    const Triangle tr = mesh_.triangles[t];
    if (splitTriangle(tr, &outside)) removed_[t] = 1;
  }
  std::vector<Triangle> inside;
  std::vector<Triangle>& added = cells_.added();
  inside.reserve(added.size());
  for (const Triangle& tr : added)
    if (!marked(tr) || !splitTriangle(tr, &inside)) inside.push_back(tr);
  added = std::move(inside);
  added.insert(added.end(), outside.begin(), outside.end());
}

void Refiner::assemble() {
  std::vector<Triangle> tris;
  const std::vector<Triangle>& added = cells_.added();
  tris.reserve(mesh_.triangles.size() + added.size());
  for (std::size_t t = 0; t < mesh_.triangles.size(); ++t)
    if (!removed_[t]) tris.push_back(mesh_.triangles[t]);
  stats_.trianglesAdded = added.size();
  tris.insert(tris.end(), added.begin(), added.end());
  const std::size_t oldCount = mesh_.normals.size();
  std::vector<std::uint32_t> remap(mesh_.positions.size(), UINT32_MAX);
  for (const Triangle& t : tris)
    for (std::uint32_t v : t) remap[v] = 0;
  std::vector<Vec3f> positions, normals;
  std::vector<std::uint32_t> fresh;  // new vertices (their new index) for normals
  const bool withNormals = oldCount > 0;
  for (std::size_t v = 0; v < remap.size(); ++v) {
    if (remap[v] == UINT32_MAX) continue;
    remap[v] = static_cast<std::uint32_t>(positions.size());
    positions.push_back(mesh_.positions[v]);
    if (withNormals) {
      normals.push_back(v < oldCount ? mesh_.normals[v] : Vec3f{0.f, 0.f, 0.f});
      if (v >= oldCount) fresh.push_back(remap[v]);
    }
  }
  for (Triangle& t : tris)
    for (std::uint32_t& v : t) v = remap[v];
  for (std::uint32_t i : fresh) {
    const Vec3f& p = positions[i];
    normals[i] = vertexNormal(field_.evalGradient(p[0], p[1], p[2]), *g_.base, p);
  }
  mesh_.positions = std::move(positions);
  mesh_.normals = std::move(normals);
  mesh_.triangles = std::move(tris);
}

}  // namespace refinement
}  // namespace frep
