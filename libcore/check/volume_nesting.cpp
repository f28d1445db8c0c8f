#include "check/volume_nesting.h"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>

#include "base/triangle_geometry.h"

namespace frep {

namespace {

using Fast = CGAL::Exact_predicates_inexact_constructions_kernel;
using Exact = CGAL::Exact_predicates_exact_constructions_kernel;

constexpr std::uint32_t kMostComponents = 8192;
constexpr std::size_t kMostAsking = 4096;

struct Bounds {
  float lo[3] = {HUGE_VALF, HUGE_VALF, HUGE_VALF}, hi[3] = {-HUGE_VALF, -HUGE_VALF, -HUGE_VALF};
  void add(const Vec3f& p) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], p[a]);
      hi[a] = std::max(hi[a], p[a]);
    }
  }
  bool holds(const Bounds& o) const {
    for (int a = 0; a < 3; ++a)
      if (o.lo[a] < lo[a] || o.hi[a] > hi[a]) return false;
    return true;
  }
};

// The ray starts at the centroid of a face (s0, s1, s2): off the grid lines and planes the
// mesher's vertices lie on, where an axis ray from a vertex would graze every vertex on its
// line. The orientations below are affine in the start point, so at the centroid their sign
// is that of the sum over the face's corners: exact (Epick) where the corners agree, and
// computed with exact constructions (Epeck) where they do not (rare).
struct Start {
  Vec3f s[3];
};

int sumSign(int a, int b, int c) {
  if (a >= 0 && b >= 0 && c >= 0) return (a > 0 || b > 0 || c > 0) ? 1 : 0;
  if (a <= 0 && b <= 0 && c <= 0) return -1;
  return 2;  // undecided
}

Fast::Point_2 yz(const Vec3f& p) {
  return {p[1], p[2]};
}
Fast::Point_3 xyz(const Vec3f& p) {
  return {p[0], p[1], p[2]};
}
Exact::Point_3 exact3(const Vec3f& p) {
  return {p[0], p[1], p[2]};
}

// Orientation of (a, b, centroid) projected on (y, z).
int orient2(const Vec3f& a, const Vec3f& b, const Start& q) {
  int s[3];
  for (int i = 0; i < 3; ++i) s[i] = CGAL::orientation(yz(a), yz(b), yz(q.s[i]));
  const int sign = sumSign(s[0], s[1], s[2]);
  if (sign != 2) return sign;
  const Exact::Point_3 c = CGAL::centroid(exact3(q.s[0]), exact3(q.s[1]), exact3(q.s[2]));
  return CGAL::orientation(Exact::Point_2(a[1], a[2]), Exact::Point_2(b[1], b[2]),
                           Exact::Point_2(c.y(), c.z()));
}

// Orientation of (a, b, c, centroid).
int orient3(const Vec3f& a, const Vec3f& b, const Vec3f& c, const Start& q) {
  int s[3];
  for (int i = 0; i < 3; ++i) s[i] = CGAL::orientation(xyz(a), xyz(b), xyz(c), xyz(q.s[i]));
  const int sign = sumSign(s[0], s[1], s[2]);
  if (sign != 2) return sign;
  return CGAL::orientation(exact3(a), exact3(b), exact3(c),
                           CGAL::centroid(exact3(q.s[0]), exact3(q.s[1]), exact3(q.s[2])));
}

// The ray from the start along +x against face (a, b, c): 1 it crosses the face's interior,
// 0 it misses, -1 it grazes an edge or a vertex, or runs in the face's plane.
int crossing(const Start& q, const Vec3f& a, const Vec3f& b, const Vec3f& c) {
  const int face = CGAL::orientation(yz(a), yz(b), yz(c));
  const int s0 = orient2(a, b, q), s1 = orient2(b, c, q), s2 = orient2(c, a, q);
  if (face == 0) {  // the face seen edge-on: a graze when the start's line meets it
    if (s0 != 0 && s0 == s1 && s1 == s2) return 0;
    return (s0 == 0 || s1 == 0 || s2 == 0) ? -1 : 0;
  }
  auto inOrOn = [&](int s) { return s == face || s == 0; };
  if (!(inOrOn(s0) && inOrOn(s1) && inOrOn(s2))) return 0;
  if (s0 == 0 || s1 == 0 || s2 == 0) return -1;
  // inside the projection: orientation(a, b, c, q) > 0 puts q on the side the normal N
  // points to; the ray meets the plane at t = -N.(q - a) / N.x, ahead of q when N.(q - a)
  // and N.x (the projection's orientation) differ in sign
  const int side = orient3(a, b, c, q);
  if (side == 0) return -1;
  return (side > 0) != (face > 0) ? 1 : 0;
}

}  // namespace

std::optional<bool> boundsAVolumeByRays(const std::vector<Vec3f>& points,
                                        const std::vector<FaceIndices>& faces,
                                        const std::vector<std::uint32_t>& component,
                                        std::uint32_t components) {
  // The boxes are compared pair by pair: many components (an array of parts) go to CGAL.
  if (components > kMostComponents) return std::nullopt;
  // Each component's box, volume and first faces: by fixed blocks of faces in parallel,
  // merged in block order (the same facts on any number of threads), where the blocks'
  // tables stay small; else in one pass.
  std::vector<ComponentFacts> facts(components);
  auto addFaces = [&](std::size_t from, std::size_t to, std::vector<ComponentFacts>& into) {
    for (std::size_t f = from; f < to; ++f)
      into[component[f]].add(points[faces[f][0]], points[faces[f][1]], points[faces[f][2]]);
  };
  constexpr std::size_t kBlock = std::size_t(1) << 16, kMostPartials = std::size_t(1) << 18;
  const std::size_t blocks = (faces.size() + kBlock - 1) / kBlock;
  if (blocks > 1 && blocks * components <= kMostPartials) {
    std::vector<std::vector<ComponentFacts>> partial(blocks);
    tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t b) {
      partial[b].resize(components);
      addFaces(b * kBlock, std::min(faces.size(), (b + 1) * kBlock), partial[b]);
    });
    for (const std::vector<ComponentFacts>& p : partial)
      for (std::uint32_t c = 0; c < components; ++c) facts[c].merge(p[c]);
  } else {
    addFaces(0, faces.size(), facts);
  }
  return nestingByRays(facts, [&](const FaceVisitor& visit) {
    tbb::parallel_for(std::size_t(0), faces.size(), [&](std::size_t f) {
      visit(points[faces[f][0]], points[faces[f][1]], points[faces[f][2]], component[f]);
    });
  });
}

void ComponentFacts::add(const Vec3f& a, const Vec3f& b, const Vec3f& c) {
  for (const Vec3f* p : {&a, &b, &c})
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], (*p)[k]);
      hi[k] = std::max(hi[k], (*p)[k]);
    }
  volume += signedTetraVolume(a, b, c);
  if (someFaces.size() < 8) someFaces.push_back({a, b, c});
}

void ComponentFacts::merge(const ComponentFacts& o) {
  for (int k = 0; k < 3; ++k) {
    lo[k] = std::min(lo[k], o.lo[k]);
    hi[k] = std::max(hi[k], o.hi[k]);
  }
  volume += o.volume;
  for (const auto& f : o.someFaces)
    if (someFaces.size() < 8) someFaces.push_back(f);
}

std::optional<bool> nestingByRays(const std::vector<ComponentFacts>& facts,
                                  const std::function<void(const FaceVisitor&)>& forEachFace) {
  const std::uint32_t components = static_cast<std::uint32_t>(facts.size());
  if (components > kMostComponents) return std::nullopt;
  std::vector<Bounds> box(components);
  for (std::uint32_t c = 0; c < components; ++c)
    for (int k = 0; k < 3; ++k) {
      box[c].lo[k] = facts[c].lo[k];
      box[c].hi[k] = facts[c].hi[k];
    }
  // Which components may enclose which: a surface inside another lies in its box.
  std::vector<std::vector<std::uint32_t>> mayEnclose(components);
  std::vector<std::uint32_t> asking;
  std::vector<char> isCandidate(components, 0);
  for (std::uint32_t a = 0; a < components; ++a) {
    for (std::uint32_t b = 0; b < components; ++b)
      if (a != b && box[b].holds(box[a])) {
        mayEnclose[a].push_back(b);
        isCandidate[b] = 1;
      }
    if (!mayEnclose[a].empty()) asking.push_back(a);
    if (asking.size() > kMostAsking) return std::nullopt;
  }
  std::vector<int> depth(components, 0);

  // Rays from one face of each asking component, all in one pass over the faces; a
  // component whose ray grazed something tries its next face.
  std::vector<std::size_t> attempt(components, 0);
  std::vector<Start> start(components);
  std::vector<std::array<double, 3>> approx(components);  // the centroids, rounded
  std::vector<std::uint32_t> open = asking;
  while (!open.empty()) {
    double ylo = HUGE_VAL, yhi = -HUGE_VAL, zlo = HUGE_VAL, zhi = -HUGE_VAL;
    for (std::uint32_t a : open) {
      if (attempt[a] >= facts[a].someFaces.size()) return std::nullopt;
      const std::array<Vec3f, 3>& f = facts[a].someFaces[attempt[a]];
      for (int i = 0; i < 3; ++i) start[a].s[i] = f[i];
      for (int k = 0; k < 3; ++k) approx[a][k] = (double(f[0][k]) + f[1][k] + f[2][k]) / 3.0;
      ylo = std::min(ylo, approx[a][1]);
      yhi = std::max(yhi, approx[a][1]);
      zlo = std::min(zlo, approx[a][2]);
      zhi = std::max(zhi, approx[a][2]);
    }
    // the start points in a grid over (y, z), about one per cell; a face is looked up in the
    // cells its box covers, widened by the room the centroids' rounding is given
    const double side = std::max(1.0, std::ceil(std::sqrt(double(open.size()))));
    const double cy = std::max((yhi - ylo) / side, 1e-30), cz = std::max((zhi - zlo) / side, 1e-30);
    const long cells = static_cast<long>(side) + 1;
    auto cellOf = [&](double y, double z, long* i, long* j) {  // clamped before the cast
      *i = static_cast<long>(std::clamp(std::floor((y - ylo) / cy), -1.0, double(cells)));
      *j = static_cast<long>(std::clamp(std::floor((z - zlo) / cz), -1.0, double(cells)));
    };
    // (cells -1 .. cells on each axis, as a dense table of each cell's starts: a face looks
    // up nine cells, a hash map's lookups were most of this pass)
    const long width = cells + 2;
    auto cellIndex = [&](long i, long j) {
      return static_cast<std::size_t>((i + 1) * width + (j + 1));
    };
    std::vector<std::uint32_t> cellStart(static_cast<std::size_t>(width * width) + 1, 0),
        inCell(open.size());
    for (std::uint32_t a : open) {
      long i, j;
      cellOf(approx[a][1], approx[a][2], &i, &j);
      ++cellStart[cellIndex(i, j) + 1];
    }
    for (std::size_t c = 1; c < cellStart.size(); ++c) cellStart[c] += cellStart[c - 1];
    {
      std::vector<std::uint32_t> fill(cellStart.begin(), cellStart.end() - 1);
      for (std::uint32_t a : open) {
        long i, j;
        cellOf(approx[a][1], approx[a][2], &i, &j);
        inCell[fill[cellIndex(i, j)]++] = a;
      }
    }
    // the largest room any start is given below
    double roomAll = 0.0;
    for (std::uint32_t a : open) {
      const std::array<double, 3>& q = approx[a];
      roomAll = std::max(roomAll, 1e-9 * (1.0 + std::abs(q[0]) + std::abs(q[1]) + std::abs(q[2])));
    }
    struct Hits {
      std::unordered_map<std::uint64_t, int> parity;  // (asker << 32 | candidate) -> odd
      std::vector<std::uint32_t> grazed;
    };
    tbb::enumerable_thread_specific<Hits> hits;
    forEachFace([&](const Vec3f& p0, const Vec3f& p1, const Vec3f& p2, std::uint32_t b) {
      if (!isCandidate[b]) return;
      const double xmax = std::max({p0[0], p1[0], p2[0]});
      const double ymin = std::min({p0[1], p1[1], p2[1]}), ymax = std::max({p0[1], p1[1], p2[1]});
      const double zmin = std::min({p0[2], p1[2], p2[2]}), zmax = std::max({p0[2], p1[2], p2[2]});
      // (the cells of the starts the test below lets through: cellOf is monotone)
      long i0, j0, i1, j1;
      cellOf(ymin - roomAll, zmin - roomAll, &i0, &j0);
      cellOf(ymax + roomAll, zmax + roomAll, &i1, &j1);
      for (long i = i0; i <= i1; ++i)
        for (long j = j0; j <= j1; ++j) {
          const std::size_t cell = cellIndex(i, j);
          for (std::uint32_t k = cellStart[cell]; k < cellStart[cell + 1]; ++k) {
            const std::uint32_t a = inCell[k];
            if (a == b) continue;
            // wholly behind the start, or beside its line (with room for the centroid's
            // rounding): the exact test only where the ray may meet the face
            const std::array<double, 3>& q = approx[a];
            const double room = 1e-9 * (1.0 + std::abs(q[0]) + std::abs(q[1]) + std::abs(q[2]));
            if (xmax < q[0] - room || q[1] < ymin - room || q[1] > ymax + room ||
                q[2] < zmin - room || q[2] > zmax + room)
              continue;
            if (!std::binary_search(mayEnclose[a].begin(), mayEnclose[a].end(), b)) continue;
            const int c = crossing(start[a], p0, p1, p2);
            if (c == 0) continue;
            Hits& h = hits.local();
            if (c < 0)
              h.grazed.push_back(a);
            else
              h.parity[(std::uint64_t(a) << 32) | b] ^= 1;
          }
        }
    });
    std::vector<char> grazed(components, 0);
    std::unordered_map<std::uint64_t, int> parity;
    for (Hits& h : hits) {
      for (std::uint32_t a : h.grazed) grazed[a] = 1;
      for (const auto& [key, odd] : h.parity) parity[key] ^= odd;
    }
    std::vector<std::uint32_t> again;
    for (std::uint32_t a : open) {
      if (grazed[a]) {
        ++attempt[a];
        again.push_back(a);
        continue;
      }
      for (std::uint32_t b : mayEnclose[a]) depth[a] += parity[(std::uint64_t(a) << 32) | b];
    }
    open.swap(again);
  }
  for (std::uint32_t c = 0; c < components; ++c)
    if ((facts[c].volume > 0) != (depth[c] % 2 == 0)) return false;
  return true;
}

}  // namespace frep
