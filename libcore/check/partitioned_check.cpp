#include "check/partitioned_check.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "check/mesh_check_passes.h"
#include "check/self_intersections.h"
#include "check/volume_nesting.h"

namespace frep {

namespace {

struct SimpleUnionFind {
  std::vector<std::uint32_t> parent;
  explicit SimpleUnionFind(std::size_t n) : parent(n) {
    std::iota(parent.begin(), parent.end(), 0u);
  }
  std::uint32_t find(std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  bool join(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    parent[std::max(a, b)] = std::min(a, b);
    return true;
  }
};

bool holds(const Box3& b, const Vec3f& p) {
  for (int a = 0; a < 3; ++a)
    if (!(p[a] >= b.lo[a] && p[a] <= b.hi[a])) return false;
  return true;
}

bool overlap(const Box3& a, const Box3& b, Box3* both) {
  for (int k = 0; k < 3; ++k) {
    both->lo[k] = std::max(a.lo[k], b.lo[k]);
    both->hi[k] = std::min(a.hi[k], b.hi[k]);
    if (both->lo[k] > both->hi[k]) return false;
  }
  return true;
}

// A part welded as checkMesh welds, its faces with three distinct vertices, and each
// vertex's component (numbered from 0 in the order of the vertices).
struct WeldedPart {
  std::vector<Vec3f> pos;
  std::vector<FaceIndices> faces;
  std::size_t repeated = 0;              // faces repeating a vertex (degenerate)
  std::vector<std::uint32_t> component;  // by vertex (UINT32_MAX: in no face)
  std::uint32_t components = 0;
};

WeldedPart weldPart(const TriangleMesh& mesh) {
  WeldedPart w;
  const std::vector<std::uint32_t> map = weldIdenticalVertices(mesh.positions, w.pos);
  w.faces.reserve(mesh.triangles.size());
  for (const Triangle& t : mesh.triangles) {
    const std::uint32_t a = map[t[0]], b = map[t[1]], c = map[t[2]];
    if (a == b || b == c || a == c) {
      ++w.repeated;
      continue;
    }
    w.faces.push_back({a, b, c});
  }
  SimpleUnionFind parts(w.pos.size());
  for (const FaceIndices& f : w.faces) {
    parts.join(f[0], f[1]);
    parts.join(f[0], f[2]);
  }
  std::vector<char> used(w.pos.size(), 0);
  for (const FaceIndices& f : w.faces)
    for (std::uint32_t v : f) used[v] = 1;
  std::vector<std::uint32_t> label(w.pos.size(), UINT32_MAX);
  w.component.assign(w.pos.size(), UINT32_MAX);
  for (std::uint32_t v = 0; v < w.pos.size(); ++v) {
    if (!used[v]) continue;
    std::uint32_t& l = label[parts.find(v)];
    if (l == UINT32_MAX) l = w.components++;
    w.component[v] = l;
  }
  return w;
}

}  // namespace

struct PartitionedCheck::State {
  std::vector<Box3> boxes;
  std::vector<char> added;
  std::vector<std::uint32_t> firstNode;  // by part: its components' first node
  std::vector<ComponentFacts> nodes;     // every part's components, part by part
  CheckReport sum;                       // the parts' own shares
  bool undecidable = false;              // checkMesh would answer from the whole soup
  std::size_t partZonePairs = 0;         // self-intersections among each part's zone faces
  // the zone: faces reaching where boxes overlap, with their points (per part, unwelded)
  std::vector<Vec3f> zonePoints;
  std::vector<std::uint32_t> zoneNode;  // by zone point: its part's component node
  std::vector<FaceIndices> zoneFaces;
};

PartitionedCheck::PartitionedCheck(std::vector<Box3> boxes) : s_(new State) {
  for (int a = 0; a < 3; ++a) {
    s_->sum.bbox.lo[a] = HUGE_VAL;
    s_->sum.bbox.hi[a] = -HUGE_VAL;
  }
  s_->added.assign(boxes.size(), 0);
  s_->firstNode.assign(boxes.size(), 0);
  s_->boxes = std::move(boxes);
}

PartitionedCheck::~PartitionedCheck() {
  delete s_;
}

std::size_t PartitionedCheck::zoneFaces() const {
  return s_->zoneFaces.size();
}

bool PartitionedCheck::addPart(std::size_t index, const TriangleMesh& mesh) {
  State& s = *s_;
  const Box3& box = s.boxes.at(index);
  s.added.at(index) = 1;
  for (const Vec3f& p : mesh.positions)
    if (!holds(box, p)) return false;  // (a non-finite point is outside every box too)
  for (const Triangle& t : mesh.triangles)
    for (std::uint32_t v : t)
      if (v >= mesh.positions.size()) return false;
  // where this part meets the others
  std::vector<Box3> meets;
  for (std::size_t k = 0; k < s.boxes.size(); ++k) {
    Box3 both;
    if (k != index && overlap(box, s.boxes[k], &both)) meets.push_back(both);
  }
  auto inZone = [&](const Vec3f& p) {
    for (const Box3& b : meets)
      if (holds(b, p)) return true;
    return false;
  };

  const WeldedPart w = weldPart(mesh);
  CheckReport& r = s.sum;
  r.faces += mesh.triangles.size();
  r.vertices += w.pos.size();
  r.degenerateFaces += w.repeated;
  sumAreaAndVolume(w.pos, w.faces, &r.area, &r.volume);
  std::vector<char> collinear;
  r.degenerateFaces += collinearFaces(w.pos, w.faces, &collinear);
  for (const Vec3f& p : w.pos)
    for (int a = 0; a < 3; ++a) {
      r.bbox.lo[a] = std::min(r.bbox.lo[a], double(p[a]));
      r.bbox.hi[a] = std::max(r.bbox.hi[a], double(p[a]));
    }

  // the vertices whose faces all lie in this part: outside the zone
  std::vector<char> own(w.pos.size());
  for (std::size_t v = 0; v < w.pos.size(); ++v) own[v] = !inZone(w.pos[v]);
  CheckReport topology;
  std::vector<char> fans;
  {
    std::vector<std::uint32_t> start, incident;
    judgeVertices(w.pos, w.faces, &own, true, &topology, &fans, &start, &incident);
  }
  r.borderEdges += topology.borderEdges;
  r.nonManifoldEdges += topology.nonManifoldEdges;
  r.misorientedEdges += topology.misorientedEdges;
  r.nonManifoldVertices += topology.nonManifoldVertices;
  if (topology.nonManifoldEdges || topology.misorientedEdges || topology.nonManifoldVertices) {
    s.undecidable = true;  // not a polygon mesh: CGAL counts its crossings on the whole
    return true;
  }

  // components, and what the nesting rays need of them
  s.firstNode[index] = static_cast<std::uint32_t>(s.nodes.size());
  s.nodes.resize(s.nodes.size() + w.components);
  ComponentFacts* facts = s.nodes.data() + s.firstNode[index];
  for (const FaceIndices& f : w.faces)
    facts[w.component[f[0]]].add(w.pos[f[0]], w.pos[f[1]], w.pos[f[2]]);

  r.selfIntersections += countSelfIntersections(w.pos, w.faces, nullptr, kSelfIntersectionLimit,
                                                FaceFacts{&collinear, &fans});

  // the faces reaching into the zone, kept for the zone's judgement
  std::vector<std::uint32_t> zoneIndex(w.pos.size(), UINT32_MAX);
  std::vector<Vec3f> points;
  std::vector<FaceIndices> faces;
  for (const FaceIndices& f : w.faces) {
    Box3 fb;
    for (int a = 0; a < 3; ++a) {
      fb.lo[a] = std::min({w.pos[f[0]][a], w.pos[f[1]][a], w.pos[f[2]][a]});
      fb.hi[a] = std::max({w.pos[f[0]][a], w.pos[f[1]][a], w.pos[f[2]][a]});
    }
    bool reaches = false;
    Box3 both;
    for (const Box3& b : meets) reaches = reaches || overlap(fb, b, &both);
    if (!reaches) continue;
    FaceIndices z;
    for (int i = 0; i < 3; ++i) {
      std::uint32_t& at = zoneIndex[f[i]];
      if (at == UINT32_MAX) {
        at = static_cast<std::uint32_t>(points.size());
        points.push_back(w.pos[f[i]]);
      }
      z[i] = at;
    }
    faces.push_back(z);
  }
  // pairs among this part's own zone faces are in its count already: the zone's count of
  // all its pairs less these is the pairs across parts
  s.partZonePairs += countSelfIntersections(points, faces, nullptr, kSelfIntersectionLimit);
  // every vertex in the zone (another part may have it too: it is counted once), also one
  // only degenerate faces use
  for (std::size_t v = 0; v < w.pos.size(); ++v)
    if (!own[v] && zoneIndex[v] == UINT32_MAX) {
      zoneIndex[v] = static_cast<std::uint32_t>(points.size());
      points.push_back(w.pos[v]);
    }
  const std::uint32_t base = static_cast<std::uint32_t>(s.zonePoints.size());
  s.zoneNode.resize(base + points.size());
  for (std::size_t v = 0; v < w.pos.size(); ++v)
    if (zoneIndex[v] != UINT32_MAX)
      s.zoneNode[base + zoneIndex[v]] =
          w.component[v] == UINT32_MAX ? UINT32_MAX : s.firstNode[index] + w.component[v];
  s.zonePoints.insert(s.zonePoints.end(), points.begin(), points.end());
  for (const FaceIndices& f : faces) s.zoneFaces.push_back({f[0] + base, f[1] + base, f[2] + base});
  return true;
}

std::optional<CheckReport> PartitionedCheck::finish(
    std::size_t inputVertices, const std::function<TriangleMesh(std::size_t)>& part) {
  State& s = *s_;
  for (char a : s.added)
    if (!a) return std::nullopt;
  if (s.undecidable) return std::nullopt;
  CheckReport r = s.sum;
  r.inputVertices = inputVertices;
  if (r.faces == 0) return std::nullopt;  // (checkMesh's own words for an empty mesh)

  // the zone, welded across parts
  std::vector<Vec3f> pos;
  const std::vector<std::uint32_t> map = weldIdenticalVertices(s.zonePoints, pos);
  r.vertices -= s.zonePoints.size() - pos.size();
  std::vector<FaceIndices> faces(s.zoneFaces.size());
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (int i = 0; i < 3; ++i) faces[f][i] = map[s.zoneFaces[f][i]];
  std::vector<char> inZone(pos.size(), 0);  // in two boxes or more: the zone's own vertices
  for (std::size_t v = 0; v < pos.size(); ++v) {
    int in = 0;
    for (const Box3& b : s.boxes) in += holds(b, pos[v]);
    inZone[v] = in > 1;
  }
  std::vector<char> fans;
  {
    std::vector<std::uint32_t> start, incident;
    judgeVertices(pos, faces, &inZone, false, &r, &fans, &start, &incident);
  }
  r.closed = r.borderEdges == 0;
  if (r.nonManifoldEdges || r.misorientedEdges || r.nonManifoldVertices) return std::nullopt;
  const std::size_t all = countSelfIntersections(pos, faces, nullptr, kSelfIntersectionLimit,
                                                 FaceFacts{nullptr, &fans});
  r.selfIntersections += all - std::min(all, s.partZonePairs);
  r.selfIntersectionsAtLeast = r.selfIntersections >= kSelfIntersectionLimit;
  if (r.selfIntersectionsAtLeast) r.selfIntersections = kSelfIntersectionLimit;

  // components: the parts' own, joined through the zone's shared points
  SimpleUnionFind nodes(s.nodes.size());
  {
    std::vector<std::uint32_t> first(pos.size(), UINT32_MAX);
    for (std::size_t i = 0; i < s.zonePoints.size(); ++i) {
      if (s.zoneNode[i] == UINT32_MAX) continue;  // in no face
      std::uint32_t& f = first[map[i]];
      if (f == UINT32_MAX)
        f = s.zoneNode[i];
      else
        nodes.join(f, s.zoneNode[i]);
    }
  }
  std::vector<std::uint32_t> global(s.nodes.size());
  std::vector<ComponentFacts> components;
  {
    std::vector<std::uint32_t> label(s.nodes.size(), UINT32_MAX);
    for (std::uint32_t n = 0; n < s.nodes.size(); ++n) {
      std::uint32_t& l = label[nodes.find(n)];
      if (l == UINT32_MAX) {
        l = static_cast<std::uint32_t>(components.size());
        components.emplace_back();
      }
      global[n] = l;
      components[l].merge(s.nodes[n]);
    }
  }
  r.components = components.size();

  if (r.closed && r.selfIntersections == 0) {
    if (r.components == 1) {
      r.outward = r.volume > 0;
    } else {
      const std::optional<bool> nested = nestingByRays(components, [&](const FaceVisitor& visit) {
        for (std::size_t i = 0; i < s.boxes.size(); ++i) {
          const WeldedPart w = weldPart(part(i));
          const std::uint32_t base = s.firstNode[i];
          tbb::parallel_for(std::size_t(0), w.faces.size(), [&](std::size_t f) {
            const FaceIndices& t = w.faces[f];
            visit(w.pos[t[0]], w.pos[t[1]], w.pos[t[2]], global[base + w.component[t[0]]]);
          });
        }
      });
      if (!nested) return std::nullopt;  // CGAL decides on the whole mesh
      r.outward = *nested;
    }
  }
  addReasons(r);
  return r;
}

}  // namespace frep
