#include "check/partitioned_check.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <type_traits>

#include "base/errors.h"
#include "check/mesh_check_passes.h"
#include "check/self_intersections.h"
#include "check/volume_nesting.h"

namespace frep {

namespace {

bool holds(const Box3& b, const Vec3f& p) {
  for (int a = 0; a < 3; ++a)
    if (!(p[a] >= b.lo[a] && p[a] <= b.hi[a])) return false;
  return true;
}

// How many of the boxes hold p: two or more, and p lies in the zone.
int boxesHolding(const std::vector<Box3>& boxes, const Vec3f& p) {
  int in = 0;
  for (const Box3& b : boxes) in += holds(b, p);
  return in;
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
  UnionFind parts(w.pos.size());
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

// A part's (or late faces') own counts, added to r: faces, welded vertices, degenerate
// faces (repeated or collinear corners: *collinear by face), area, volume, bounding box.
void countOwnFaces(const WeldedPart& w, std::size_t triangles, CheckReport* r,
                   std::vector<char>* collinear) {
  r->faces += triangles;
  r->vertices += w.pos.size();
  r->degenerateFaces += w.repeated;
  sumAreaAndVolume(w.pos, w.faces, &r->area, &r->volume);
  r->degenerateFaces += collinearFaces(w.pos, w.faces, collinear);
  for (const Vec3f& p : w.pos)
    for (int a = 0; a < 3; ++a) {
      r->bbox.lo[a] = std::min(r->bbox.lo[a], double(p[a]));
      r->bbox.hi[a] = std::max(r->bbox.hi[a], double(p[a]));
    }
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
  std::vector<std::size_t> lateFaces;  // zone faces given by addZoneFaces
  bool escaped = false;                // a part's vertex outside its box
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

namespace {

// What judging one part leaves for the rest: its own share of the counts, its components'
// facts, and its zone (faces reaching where boxes overlap, their points, each point's
// component in the part or UINT32_MAX).
struct Contribution {
  CheckReport sum;
  bool escaped = false, undecidable = false;
  std::uint64_t zonePairs = 0;
  std::vector<ComponentFacts> nodes;
  std::vector<Vec3f> zonePoints;
  std::vector<std::uint32_t> zoneNode;
  std::vector<FaceIndices> zoneFaces;
};

Contribution judge(const std::vector<Box3>& boxes, std::size_t index, const TriangleMesh& mesh) {
  Contribution out;
  const Box3& box = boxes.at(index);
  for (const Vec3f& p : mesh.positions)
    if (!holds(box, p)) out.escaped = true;  // (a non-finite point is outside every box too)
  for (const Triangle& t : mesh.triangles)
    for (std::uint32_t v : t)
      if (v >= mesh.positions.size()) out.escaped = true;
  if (out.escaped) return out;
  // where this part meets the others
  std::vector<Box3> meets;
  for (std::size_t k = 0; k < boxes.size(); ++k) {
    Box3 both;
    if (k != index && overlap(box, boxes[k], &both)) meets.push_back(both);
  }
  auto inZone = [&](const Vec3f& p) {
    for (const Box3& b : meets)
      if (holds(b, p)) return true;
    return false;
  };

  const WeldedPart w = weldPart(mesh);
  CheckReport& r = out.sum;
  for (int a = 0; a < 3; ++a) {
    r.bbox.lo[a] = HUGE_VAL;
    r.bbox.hi[a] = -HUGE_VAL;
  }
  std::vector<char> collinear;
  countOwnFaces(w, mesh.triangles.size(), &r, &collinear);

  // the vertices whose faces all lie in this part: outside the zone
  std::vector<char> own(w.pos.size());
  for (std::size_t v = 0; v < w.pos.size(); ++v) own[v] = !inZone(w.pos[v]);
  std::vector<char> fans;
  {
    std::vector<std::uint32_t> start, incident;
    vertexFaces(w.pos.size(), w.faces, &start, &incident);
    judgeVertices(w.pos, w.faces, &own, true, &r, &fans, start, incident);
  }
  if (r.nonManifoldEdges || r.misorientedEdges || r.nonManifoldVertices) {
    out.undecidable = true;  // not a polygon mesh: CGAL counts its crossings on the whole
    return out;
  }

  // components, and what the nesting rays need of them
  out.nodes.resize(w.components);
  for (const FaceIndices& f : w.faces)
    out.nodes[w.component[f[0]]].add(w.pos[f[0]], w.pos[f[1]], w.pos[f[2]]);

  r.selfIntersections = countSelfIntersections(w.pos, w.faces, nullptr, kSelfIntersectionLimit,
                                               FaceFacts{&collinear, &fans});

  // the faces reaching into the zone, kept for the zone's judgement
  std::vector<std::uint32_t> zoneIndex(w.pos.size(), UINT32_MAX);
  std::vector<Vec3f>& points = out.zonePoints;
  std::vector<FaceIndices>& faces = out.zoneFaces;
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
  out.zonePairs = countSelfIntersections(points, faces, nullptr, kSelfIntersectionLimit);
  // every vertex in the zone (another part may have it too: it is counted once), also one
  // only degenerate faces use
  for (std::size_t v = 0; v < w.pos.size(); ++v)
    if (!own[v] && zoneIndex[v] == UINT32_MAX) {
      zoneIndex[v] = static_cast<std::uint32_t>(points.size());
      points.push_back(w.pos[v]);
    }
  out.zoneNode.assign(points.size(), UINT32_MAX);
  for (std::size_t v = 0; v < w.pos.size(); ++v)
    if (zoneIndex[v] != UINT32_MAX) out.zoneNode[zoneIndex[v]] = w.component[v];
  return out;
}

// A contribution as bytes (a summary a worker hands back), and back; little-endian, the
// counts checked against the size.
constexpr char kSummaryMagic[8] = {'F', 'R', 'E', 'P', 'J', 'D', 'G', '1'};

template <class T>
void put(std::vector<char>& out, const T& value) {
  const char* p = reinterpret_cast<const char*>(&value);
  out.insert(out.end(), p, p + sizeof(T));
}
template <class T>
void putArray(std::vector<char>& out, const std::vector<T>& values) {
  put(out, static_cast<std::uint64_t>(values.size()));
  const char* p = reinterpret_cast<const char*>(values.data());
  out.insert(out.end(), p, p + values.size() * sizeof(T));
}

std::vector<char> serialize(const Contribution& c) {
  std::vector<char> out(kSummaryMagic, kSummaryMagic + 8);
  const CheckReport& r = c.sum;
  const std::uint64_t counts[9] = {r.faces,
                                   r.vertices,
                                   r.degenerateFaces,
                                   r.borderEdges,
                                   r.nonManifoldEdges,
                                   r.nonManifoldVertices,
                                   r.misorientedEdges,
                                   r.selfIntersections,
                                   c.zonePairs};
  for (std::uint64_t n : counts) put(out, n);
  const double numbers[8] = {r.area,       r.volume,     r.bbox.lo[0], r.bbox.lo[1],
                             r.bbox.lo[2], r.bbox.hi[0], r.bbox.hi[1], r.bbox.hi[2]};
  for (double x : numbers) put(out, x);
  put(out, static_cast<std::uint8_t>((c.escaped ? 1 : 0) | (c.undecidable ? 2 : 0)));
  put(out, static_cast<std::uint64_t>(c.nodes.size()));
  for (const ComponentFacts& f : c.nodes) {
    for (int a = 0; a < 3; ++a) put(out, f.lo[a]);
    for (int a = 0; a < 3; ++a) put(out, f.hi[a]);
    put(out, f.volume);
    putArray(out, f.someFaces);
  }
  putArray(out, c.zonePoints);
  putArray(out, c.zoneNode);
  putArray(out, c.zoneFaces);
  return out;
}

Contribution deserialize(const std::vector<char>& in) {
  std::size_t at = 0;
  auto take = [&](void* to, std::size_t bytes) {
    if (bytes > in.size() - at) throw FileError("check summary: truncated");
    std::memcpy(to, in.data() + at, bytes);
    at += bytes;
  };
  auto count = [&](std::size_t itemBytes) {
    std::uint64_t n;
    take(&n, 8);
    if (n > (in.size() - at) / itemBytes) throw FileError("check summary: a count beyond its size");
    return static_cast<std::size_t>(n);
  };
  auto array = [&](auto& values) {
    using T = typename std::decay_t<decltype(values)>::value_type;
    values.resize(count(sizeof(T)));
    take(values.data(), values.size() * sizeof(T));
  };
  char magic[8];
  take(magic, 8);
  if (std::memcmp(magic, kSummaryMagic, 8) != 0) throw FileError("check summary: not one");
  Contribution c;
  std::uint64_t counts[9];
  take(counts, sizeof(counts));
  CheckReport& r = c.sum;
  r.faces = counts[0];
  r.vertices = counts[1];
  r.degenerateFaces = counts[2];
  r.borderEdges = counts[3];
  r.nonManifoldEdges = counts[4];
  r.nonManifoldVertices = counts[5];
  r.misorientedEdges = counts[6];
  r.selfIntersections = counts[7];
  c.zonePairs = counts[8];
  double numbers[8];
  take(numbers, sizeof(numbers));
  r.area = numbers[0];
  r.volume = numbers[1];
  for (int a = 0; a < 3; ++a) {
    r.bbox.lo[a] = numbers[2 + a];
    r.bbox.hi[a] = numbers[5 + a];
  }
  std::uint8_t flags;
  take(&flags, 1);
  c.escaped = flags & 1;
  c.undecidable = flags & 2;
  c.nodes.resize(count(3 * 4 * 2 + 8 + 8));
  for (ComponentFacts& f : c.nodes) {
    take(f.lo, sizeof(f.lo));
    take(f.hi, sizeof(f.hi));
    take(&f.volume, 8);
    array(f.someFaces);
  }
  array(c.zonePoints);
  array(c.zoneNode);
  array(c.zoneFaces);
  if (at != in.size() || c.zoneNode.size() != c.zonePoints.size())
    throw FileError("check summary: inconsistent");
  for (const FaceIndices& f : c.zoneFaces)
    for (std::uint32_t v : f)
      if (v >= c.zonePoints.size()) throw FileError("check summary: a face past its points");
  for (std::uint32_t n : c.zoneNode)
    if (n != UINT32_MAX && n >= c.nodes.size()) throw FileError("check summary: a bad component");
  return c;
}

}  // namespace

void PartitionedCheck::absorb(std::size_t index, const void* contribution) {
  const Contribution& c = *static_cast<const Contribution*>(contribution);
  State& s = *s_;
  s.added.at(index) = 1;
  if (c.escaped) {
    s.escaped = true;
    return;
  }
  if (c.undecidable) s.undecidable = true;
  CheckReport& r = s.sum;
  r.faces += c.sum.faces;
  r.vertices += c.sum.vertices;
  r.degenerateFaces += c.sum.degenerateFaces;
  r.borderEdges += c.sum.borderEdges;
  r.nonManifoldEdges += c.sum.nonManifoldEdges;
  r.nonManifoldVertices += c.sum.nonManifoldVertices;
  r.misorientedEdges += c.sum.misorientedEdges;
  r.selfIntersections += c.sum.selfIntersections;
  r.area += c.sum.area;
  r.volume += c.sum.volume;
  for (int a = 0; a < 3; ++a) {
    r.bbox.lo[a] = std::min(r.bbox.lo[a], c.sum.bbox.lo[a]);
    r.bbox.hi[a] = std::max(r.bbox.hi[a], c.sum.bbox.hi[a]);
  }
  s.partZonePairs += c.zonePairs;
  const std::uint32_t first = static_cast<std::uint32_t>(s.nodes.size());
  s.firstNode[index] = first;
  s.nodes.insert(s.nodes.end(), c.nodes.begin(), c.nodes.end());
  const std::uint32_t base = static_cast<std::uint32_t>(s.zonePoints.size());
  s.zonePoints.insert(s.zonePoints.end(), c.zonePoints.begin(), c.zonePoints.end());
  for (std::uint32_t n : c.zoneNode) s.zoneNode.push_back(n == UINT32_MAX ? n : first + n);
  for (const FaceIndices& f : c.zoneFaces)
    s.zoneFaces.push_back({f[0] + base, f[1] + base, f[2] + base});
}

bool PartitionedCheck::addPart(std::size_t index, const TriangleMesh& part) {
  const Contribution c = judge(s_->boxes, index, part);
  absorb(index, &c);
  return !c.escaped;
}

std::vector<char> PartitionedCheck::judgePart(const std::vector<Box3>& boxes, std::size_t index,
                                              const TriangleMesh& part) {
  return serialize(judge(boxes, index, part));
}

bool PartitionedCheck::addSummary(std::size_t index, const std::vector<char>& summary) {
  const Contribution c = deserialize(summary);
  absorb(index, &c);
  return !c.escaped;
}

void PartitionedCheck::addZoneFaces(const TriangleMesh& faces) {
  State& s = *s_;
  // each corner must lie where two boxes overlap: then every face the part's own judgement
  // saw at that corner is in the zone too, and these faces change nothing it decided
  for (const Vec3f& p : faces.positions)
    if (boxesHolding(s.boxes, p) < 2) s.undecidable = true;
  for (const Triangle& t : faces.triangles)
    for (std::uint32_t v : t)
      if (v >= faces.positions.size()) s.undecidable = true;
  if (s.undecidable) return;
  // their own counts (no vertex of theirs is new: each is welded with the zone's points)
  const WeldedPart w = weldPart(faces);
  std::vector<char> collinear;
  countOwnFaces(w, faces.triangles.size(), &s.sum, &collinear);
  const std::uint32_t base = static_cast<std::uint32_t>(s.zonePoints.size());
  s.zonePoints.insert(s.zonePoints.end(), w.pos.begin(), w.pos.end());
  s.zoneNode.insert(s.zoneNode.end(), w.pos.size(), UINT32_MAX);
  for (const FaceIndices& f : w.faces) {
    s.zoneFaces.push_back({f[0] + base, f[1] + base, f[2] + base});
    s.lateFaces.push_back(s.zoneFaces.size() - 1);
  }
}

std::optional<CheckReport> PartitionedCheck::finish(
    std::size_t inputVertices, const std::function<TriangleMesh(std::size_t)>& part) {
  State& s = *s_;
  for (char a : s.added)
    if (!a) return std::nullopt;
  if (s.undecidable || s.escaped) return std::nullopt;
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
  for (std::size_t v = 0; v < pos.size(); ++v) inZone[v] = boxesHolding(s.boxes, pos[v]) > 1;
  std::vector<char> fans;
  {
    std::vector<std::uint32_t> start, incident;
    vertexFaces(pos.size(), faces, &start, &incident);
    judgeVertices(pos, faces, &inZone, false, &r, &fans, start, incident);
  }
  r.closed = r.borderEdges == 0;
  if (r.nonManifoldEdges || r.misorientedEdges || r.nonManifoldVertices) return std::nullopt;
  const std::size_t all = countSelfIntersections(pos, faces, nullptr, kSelfIntersectionLimit,
                                                 FaceFacts{nullptr, &fans});
  r.selfIntersections += all - std::min(all, s.partZonePairs);
  r.selfIntersectionsAtLeast = r.selfIntersections >= kSelfIntersectionLimit;
  if (r.selfIntersectionsAtLeast) r.selfIntersections = kSelfIntersectionLimit;

  // components: the parts' own, joined through the zone's shared points and across the
  // faces given late (whose points carry no component of their own)
  std::vector<ComponentFacts> nodeFacts = s.nodes;
  std::vector<std::uint32_t> first(pos.size(), UINT32_MAX);  // a node at each zone vertex
  for (std::size_t i = 0; i < s.zonePoints.size(); ++i)
    if (s.zoneNode[i] != UINT32_MAX && first[map[i]] == UINT32_MAX) first[map[i]] = s.zoneNode[i];
  for (std::size_t f : s.lateFaces)
    for (std::uint32_t v : faces[f])
      if (first[v] == UINT32_MAX) {  // (a vertex of late faces only: a node of its own)
        first[v] = static_cast<std::uint32_t>(nodeFacts.size());
        nodeFacts.emplace_back();
      }
  UnionFind nodes(nodeFacts.size());
  for (std::size_t i = 0; i < s.zonePoints.size(); ++i)
    if (s.zoneNode[i] != UINT32_MAX) nodes.join(first[map[i]], s.zoneNode[i]);
  for (std::size_t f : s.lateFaces) {
    nodes.join(first[faces[f][0]], first[faces[f][1]]);
    nodes.join(first[faces[f][0]], first[faces[f][2]]);
  }
  std::vector<std::uint32_t> global(nodeFacts.size());
  std::vector<ComponentFacts> components;
  {
    std::vector<std::uint32_t> label(nodeFacts.size(), UINT32_MAX);
    for (std::uint32_t n = 0; n < nodeFacts.size(); ++n) {
      std::uint32_t& l = label[nodes.find(n)];
      if (l == UINT32_MAX) {
        l = static_cast<std::uint32_t>(components.size());
        components.emplace_back();
      }
      global[n] = l;
      components[l].merge(nodeFacts[n]);
    }
  }
  for (std::size_t f : s.lateFaces) {
    const FaceIndices& t = faces[f];
    components[global[first[t[0]]]].add(pos[t[0]], pos[t[1]], pos[t[2]]);
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
        for (std::size_t f : s.lateFaces) {
          const FaceIndices& t = faces[f];
          visit(pos[t[0]], pos[t[1]], pos[t[2]], global[first[t[0]]]);
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
