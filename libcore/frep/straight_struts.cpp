// Straight struts through a free-form deformation (straight_struts.h).
#include "frep/straight_struts.h"

#include <algorithm>
#include <cmath>
#include <mutex>

#include "base/errors.h"
#include "frep/field_sources.h"
#include "frep/periodic_segments.h"
#include "lattice/ffd_lattice.h"

namespace frep {

namespace {

// Bins of about half the smallest cell side, at most this many in all (each costs a few bytes
// and a short list of segments).
constexpr double kMostBins = 2e6;

// A foam's edges per seed: a Voronoi cell has 14 faces and about 36 edges, each shared by 3.
constexpr double kFoamEdgesPerCell = 12.0;

std::shared_ptr<const PeriodicNetworkField> foamNetwork(const Node& foam) {
  auto net = std::dynamic_pointer_cast<const PeriodicNetworkField>(loadFieldSource(foam));
  if (!net) throw ModelError("voronoi_foam: its loader made no strut network");
  return net;
}

std::vector<StrutPiece> cutTo(const std::vector<StrutPiece>& struts, const Box3& box) {
  std::vector<StrutPiece> out;
  StrutPiece piece;
  for (const StrutPiece& s : struts)
    if (clip(s.a, s.b, box.lo, box.hi, &piece)) out.push_back(piece);
  return out;
}

bool inBox(const Vec3& p, const Box3& box) {
  for (int a = 0; a < 3; ++a)
    if (p[a] < box.lo[a] || p[a] > box.hi[a]) return false;
  return true;
}

// The bins round the segments: their box grown by `pad`, the distance exact within `pad` of
// a segment.
std::shared_ptr<const PeriodicSegmentsField> binned(const std::vector<StrutPiece>& segments,
                                                    double pad, double binSide, double blend) {
  Box3 box{segments[0].a, segments[0].a};
  for (const StrutPiece& s : segments)
    for (const Vec3& p : {s.a, s.b}) box = boxHull(box, {p, p});
  std::array<int, 3> bins{};
  Vec3 size;
  for (int a = 0; a < 3; ++a) {
    box.lo[a] -= pad;
    box.hi[a] += pad;
    size[a] = box.hi[a] - box.lo[a];
  }
  const double volume = size[0] * size[1] * size[2];
  const double side = std::max(binSide, std::cbrt(volume / kMostBins));
  for (int a = 0; a < 3; ++a) bins[a] = std::max(1, int(std::ceil(size[a] / side)));
  return PeriodicSegmentsField::unrepeated(segments, box, bins, pad, blend);
}

}  // namespace

bool isStrutNetwork(const Node& node) {
  return node.type && (node.type->id == "strut_lattice" || node.type->id == "voronoi_foam");
}

double strutCountEstimate(const Node& network, const Box3& rest) {
  const Vec3 size = network.vec3("cell");
  double cells = 1.0;
  for (int a = 0; a < 3; ++a) cells *= std::floor((rest.hi[a] - rest.lo[a]) / size[a]) + 1.0;
  if (network.type->id == "voronoi_foam") return cells * kFoamEdgesPerCell;
  return cells * double(unitCell(network.param("cell_type").text).struts.size());
}

std::vector<StrutPiece> strutsInRest(const Node& network, const Box3& rest) {
  if (network.type->id == "voronoi_foam")
    return cutTo(foamNetwork(network)->segmentsInBox(rest), rest);
  return cutTo(strutsInBox(unitCell(network.param("cell_type").text), network.vec3("cell"),
                           network.vec3("origin"), rest),
               rest);
}

std::vector<Vec3> strutNodesInRest(const Node& network, const Box3& rest) {
  std::vector<Vec3> out;
  if (network.type->id == "voronoi_foam") {
    for (const StrutPiece& p : foamNetwork(network)->nodes()->segmentsInBox(rest))
      if (inBox(p.a, rest)) out.push_back(p.a);
    return out;
  }
  const UnitCell& cell = unitCell(network.param("cell_type").text);
  const Vec3 size = network.vec3("cell"), origin = network.vec3("origin");
  long long lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = (long long)std::floor((rest.lo[a] - origin[a]) / size[a]) - 1;
    hi[a] = (long long)std::floor((rest.hi[a] - origin[a]) / size[a]) + 1;
  }
  // A cell lists each of its nodes once (their copies by integer vectors are other cells'),
  // so every node comes once; rounding may put one a hair outside the box (kept if in it).
  for (long long k = lo[2]; k <= hi[2]; ++k)
    for (long long j = lo[1]; j <= hi[1]; ++j)
      for (long long i = lo[0]; i <= hi[0]; ++i)
        for (const Vec3& n : cell.nodes) {
          const Vec3 p{origin[0] + (n[0] + double(i)) * size[0],
                       origin[1] + (n[1] + double(j)) * size[1],
                       origin[2] + (n[2] + double(k)) * size[2]};
          if (inBox(p, rest)) out.push_back(p);
        }
  return out;
}

StraightStrutFields straightStrutFields(const Node& network, const FfdLattice& bend) {
  // The last fields made, for the same network and lattice (a key of every parameter).
  std::vector<double> key;
  std::string text = network.type->id;
  for (const auto& [name, value] : network.params) {
    key.insert(key.end(), value.numbers.begin(), value.numbers.end());
    text += "|" + name + "=" + value.text;
  }
  for (const Vec3& p : {bend.rest().lo, bend.rest().hi}) key.insert(key.end(), p.begin(), p.end());
  for (int a = 0; a < 3; ++a) key.push_back(bend.divisions(a));
  for (const Vec3& p : bend.points()) key.insert(key.end(), p.begin(), p.end());
  static std::mutex mutex;
  static std::vector<double> lastKey;
  static std::string lastText;
  static StraightStrutFields last;
  {
    std::lock_guard<std::mutex> lock(mutex);
    if (last.struts && key == lastKey && text == lastText) return last;
  }

  const Box3 rest = bend.rest();
  std::vector<StrutPiece> struts = strutsInRest(network, rest);
  if (struts.empty())
    throw ModelError(network.type->id + ": no strut of its cells lies in the ffd's rest box");
  for (StrutPiece& s : struts) s = {bend.deform(s.a), bend.deform(s.b)};
  const Vec3 cell = network.vec3("cell");
  const double smallest = std::min({cell[0], cell[1], cell[2]});
  const double largest = std::max({cell[0], cell[1], cell[2]});
  const double blend = network.real("blend");
  // Exact within a cell of the struts (a strut's radius or a node's sphere never reaches that
  // far); farther out only an upper bound, which no surface needs.
  const double pad = largest + blend;
  StraightStrutFields made;
  made.struts = binned(struts, pad, 0.5 * smallest, blend);
  if (network.real("node_radius") > 0.0) {
    std::vector<StrutPiece> nodes;
    for (const Vec3& n : strutNodesInRest(network, rest)) {
      const Vec3 p = bend.deform(n);
      nodes.push_back({p, p});
    }
    if (!nodes.empty()) made.nodes = binned(nodes, pad, 0.5 * smallest, 0.0);
  }
  std::lock_guard<std::mutex> lock(mutex);
  lastKey = std::move(key);
  lastText = std::move(text);
  last = made;
  return made;
}

}  // namespace frep
