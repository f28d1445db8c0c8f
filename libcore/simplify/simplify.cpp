#include "simplify/simplify.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>

#include "base/errors.h"
#include "base/phase_times.h"
#include "base/qef.h"
#include "base/triangle_geometry.h"
#include "check/face_pair_test.h"
#include "simplify/region_simplifier.h"

namespace frep {

using namespace simplifying;

namespace {

// The vertices of the faces near a crease (kNearCreaseCos), and those moved before: a face
// whose normal turns from the surface's at a vertex (or that has no normal there).
void markNearCreases(State& s, const std::vector<Triangle>& faces) {
  std::vector<std::uint8_t> near(faces.size());
  tbb::parallel_for(std::size_t(0), faces.size(), [&](std::size_t f) {
    const Triangle& t = faces[f];
    const Vec3 n = faceNormal(s.pos, t);
    const double length = norm(n);
    bool turns = !(length > 0.0);
    for (int k = 0; k < 3 && !turns; ++k) {
      const Vec3 m = toVec3(s.normal[t[k]]);
      turns = s.moved[t[k]] || !(dot(n, m) > kNearCreaseCos * length);
    }
    near[f] = turns;
  });
  std::fill(s.nearCrease.begin(), s.nearCrease.end(), 0);
  for (std::size_t f = 0; f < faces.size(); ++f)
    if (near[f])
      for (std::uint32_t v : faces[f]) s.nearCrease[v] = 1;
}

// With collapses onto creases only: the work zone's blocks, and how far round a face near a
// crease it reaches, in cells. A change there moves the faces round an edge with an end near
// the crease: they reach about one edge (a cell, up to maxEdge) beyond the near faces, and a
// change whose faces leave the zone is refused. Measured on the twist (docs/performance.md,
// "Straightened creases"): ...
constexpr double kZoneBlockCells = 1.0;
constexpr double kZoneMarginCells = 2.0;

struct Box {
  float lo[3], hi[3];
};
Box boxOf(const std::vector<Vec3f>& pos, const Triangle& t) {
  Box b;
  for (int a = 0; a < 3; ++a) {
    b.lo[a] = std::min({pos[t[0]][a], pos[t[1]][a], pos[t[2]][a]});
    b.hi[a] = std::max({pos[t[0]][a], pos[t[1]][a], pos[t[2]][a]});
  }
  return b;
}

void validate(const SimplifyOptions& o) {
  auto bad = [](const std::string& what) { throw ModelError("simplify: " + what); };
  if (!(o.cell > 0.0) || !std::isfinite(o.cell)) bad("cell must be a positive number");
  if (!(o.tolerance > 0.0) || !std::isfinite(o.tolerance))
    bad("tolerance must be a positive distance");
  if (!(o.maxEdge >= 0.0)) bad("maxEdge must be 0 (no bound) or a positive length");
  if (o.regionCells < 4 || o.regionCells > 256) bad("regionCells must be 4 to 256");
  if (o.passes < 1 || o.passes > 16) bad("passes must be 1 to 16");
  if (o.creaseCollapsesOnly && !o.sharpFeatures)
    bad("collapses onto creases only need sharp features (the creases are found by them)");
}

}  // namespace

TriangleMesh simplifyMesh(const TriangleMesh& mesh, const Field& field, const SimplifyOptions& o,
                          SimplifyStats* stats) {
  const auto start = std::chrono::steady_clock::now();
  validate(o);
  const Surface surface(field, o.bbox);
  std::optional<Phase> phase(std::in_place, "simplify: set-up", PhaseKind::Serial);
  const std::size_t nv = mesh.positions.size();
  State s;
  s.pos = mesh.positions;
  s.quadric.assign(nv, Quadric());
  s.removed.assign(nv, 0);
  s.moved.assign(nv, 0);
  s.samples.resize(nv);
  for (std::size_t v = 0; v < nv; ++v) s.samples[v].assign(1, s.pos[v]);
  if (o.creaseCollapsesOnly) {
    s.normal.assign(nv, Vec3f{0, 0, 0});
    s.nearCrease.assign(nv, 0);
  }
  // Hermite data: each vertex's tangent plane of the meshed surface
  phase.emplace("simplify: Hermite data", PhaseKind::Parallel);
  tbb::parallel_for(std::size_t(0), nv, [&](std::size_t v) {
    const Vec3 p = toVec3(s.pos[v]);
    double value;
    Vec3 n;
    if (surface.plane(p, &value, &n)) {
      // the plane through the surface point nearest p along n
      const Vec3 foot{p[0] - value * n[0], p[1] - value * n[1], p[2] - value * n[2]};
      s.quadric[v].addPlane(foot, n);
      if (!s.normal.empty()) s.normal[v] = toVec3f({-n[0], -n[1], -n[2]});  // (F grows inwards)
    }
  });

  std::vector<Triangle> faces = mesh.triangles;
  std::size_t collapses = 0, flips = 0;
  double largest = 0.0;
  const double side = o.cell * o.regionCells;
  const double shifts[4] = {0.0, 0.5, 0.25, 0.75};
  for (int pass = 0; pass < o.passes; ++pass) {
    if (o.progress && !o.progress(static_cast<double>(pass) / o.passes)) throw Cancelled();
    Regions regions;
    for (int a = 0; a < 3; ++a)
      regions.origin[a] = o.bbox.lo[a] - shifts[pass % 4] * side - o.cell * (pass / 4) * 0.37;
    regions.side = side;
    // The faces in chunks, each chunk's lists in face order, joined in chunk order (the same
    // lists whatever the threads).
    constexpr std::size_t kChunk = 1 << 15;
    const std::size_t chunks = (faces.size() + kChunk - 1) / kChunk;
    auto chunkFaces = [&](std::size_t c) {
      return std::make_pair(static_cast<std::uint32_t>(c * kChunk),
                            static_cast<std::uint32_t>(std::min(faces.size(), (c + 1) * kChunk)));
    };
    // With collapses onto creases only, the regions holding a face near a crease (the others'
    // faces stay as they are and are not sorted in: most of the mesh)
    std::vector<std::uint64_t> active;
    auto isActive = [&](std::uint64_t r) {
      return !o.creaseCollapsesOnly || std::binary_search(active.begin(), active.end(), r);
    };
    if (o.creaseCollapsesOnly) {
      phase.emplace("simplify: faces near creases", PhaseKind::Parallel);
      markNearCreases(s, faces);
      std::vector<std::vector<std::uint64_t>> found(chunks);
      tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
        const auto [from, to] = chunkFaces(c);
        for (std::uint32_t f = from; f < to; ++f) {
          const Triangle& t = faces[f];
          if (!touchesCrease(s, t)) continue;
          const std::uint64_t r = regions.of(s.pos[t[0]]);
          if (regions.of(s.pos[t[1]]) == r && regions.of(s.pos[t[2]]) == r) found[c].push_back(r);
        }
      });
      for (const std::vector<std::uint64_t>& part : found)
        active.insert(active.end(), part.begin(), part.end());
      std::sort(active.begin(), active.end());
      active.erase(std::unique(active.begin(), active.end()), active.end());
    }
    // With collapses onto creases only: the work zone round the faces near a crease (where a region
    // holds one), the faces it loads, and the vertices with a face it leaves out.
    std::optional<WorkZone> zone;
    std::vector<std::uint8_t> loaded;
    if (!active.empty()) {
      phase.emplace("simplify: the work zone", PhaseKind::Parallel);
      zone.emplace(o.bbox, kZoneBlockCells * o.cell);
      tbb::parallel_for(std::size_t(0), faces.size(), [&](std::size_t f) {
        if (!touchesCrease(s, faces[f])) return;
        const Box b = boxOf(s.pos, faces[f]);
        zone->add(b.lo, b.hi, kZoneMarginCells * o.cell);
      });
      loaded.resize(faces.size());
      tbb::parallel_for(std::size_t(0), faces.size(), [&](std::size_t f) {
        const Box b = boxOf(s.pos, faces[f]);
        loaded[f] = zone->meets(b.lo, b.hi);
      });
      phase.emplace("simplify: vertices with faces left out", PhaseKind::Serial);
      s.incomplete.assign(nv, 0);
      for (std::size_t f = 0; f < faces.size(); ++f)
        if (!loaded[f])
          for (std::uint32_t v : faces[f]) s.incomplete[v] = 1;
      s.zone = &*zone;
    }
    phase.emplace("simplify: faces sorted into regions", PhaseKind::Parallel);
    // faces inside one region, grouped by it; faces crossing regions, frozen
    struct Sorted {
      std::vector<std::pair<std::uint64_t, std::uint32_t>> inner, frozen;
      std::vector<std::uint32_t> crossing;
    };
    std::vector<Sorted> sorted(chunks);
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
      Sorted& out = sorted[c];
      const auto [from, to] = chunkFaces(c);
      for (std::uint32_t f = from; f < to; ++f) {
        const Triangle& t = faces[f];
        if (!loaded.empty() && !loaded[f]) {
          out.crossing.push_back(f);  // (left as it is)
          continue;
        }
        const std::uint64_t r = regions.of(s.pos[t[0]]);
        if (regions.of(s.pos[t[1]]) == r && regions.of(s.pos[t[2]]) == r) {
          if (isActive(r))
            out.inner.emplace_back(r, f);
          else
            out.crossing.push_back(f);  // (left as it is)
          continue;
        }
        out.crossing.push_back(f);
        std::int64_t lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
          // every region whose closed cube the face's box meets
          const double mn = std::min({s.pos[t[0]][a], s.pos[t[1]][a], s.pos[t[2]][a]});
          const double mx = std::max({s.pos[t[0]][a], s.pos[t[1]][a], s.pos[t[2]][a]});
          lo[a] = static_cast<std::int64_t>(std::floor((mn - regions.origin[a]) / side - 1e-9));
          hi[a] = static_cast<std::int64_t>(std::floor((mx - regions.origin[a]) / side + 1e-9));
        }
        for (std::int64_t k = lo[2]; k <= hi[2]; ++k)
          for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
            for (std::int64_t i = lo[0]; i <= hi[0]; ++i)
              if (isActive(Regions::key(i, j, k)))
                out.frozen.emplace_back(Regions::key(i, j, k), f);
      }
    });
    std::vector<std::pair<std::uint64_t, std::uint32_t>> inner, frozen;
    std::vector<std::uint32_t> crossing;
    for (Sorted& part : sorted) {
      inner.insert(inner.end(), part.inner.begin(), part.inner.end());
      frozen.insert(frozen.end(), part.frozen.begin(), part.frozen.end());
      crossing.insert(crossing.end(), part.crossing.begin(), part.crossing.end());
    }
    sorted.clear();
    phase.emplace("simplify: regions' faces in order", PhaseKind::Parallel);
    tbb::parallel_sort(inner.begin(), inner.end());
    tbb::parallel_sort(frozen.begin(), frozen.end());
    std::vector<std::uint32_t> innerFaces(inner.size()), frozenFaces(frozen.size());
    for (std::size_t i = 0; i < inner.size(); ++i) innerFaces[i] = inner[i].second;
    for (std::size_t i = 0; i < frozen.size(); ++i) frozenFaces[i] = frozen[i].second;
    std::vector<RegionInput> work;
    for (std::size_t i = 0; i < inner.size();) {
      std::size_t j = i;
      while (j < inner.size() && inner[j].first == inner[i].first) ++j;
      const auto range = std::equal_range(
          frozen.begin(), frozen.end(), std::make_pair(inner[i].first, std::uint32_t(0)),
          [](const auto& a, const auto& b) { return a.first < b.first; });
      work.push_back({inner[i].first, innerFaces.data() + i, j - i,
                      frozenFaces.data() + (range.first - frozen.begin()),
                      static_cast<std::size_t>(range.second - range.first), pass + 2 >= o.passes});
      i = j;
    }
    phase.emplace("simplify: regions", PhaseKind::Parallel);
    std::vector<RegionOutput> results(work.size());
    tbb::enumerable_thread_specific<std::unique_ptr<RegionSimplifier>> simplifiers;
    tbb::parallel_for(std::size_t(0), work.size(), [&](std::size_t r) {
      std::unique_ptr<RegionSimplifier>& rs = simplifiers.local();
      if (!rs) rs = std::make_unique<RegionSimplifier>(s, field, o, regions, faces);
      rs->run(work[r], results[r]);
    });
    phase.emplace("simplify: regions' faces gathered", PhaseKind::Serial);
    std::vector<Triangle> next;
    next.reserve(faces.size());
    for (std::uint32_t f : crossing) next.push_back(faces[f]);
    for (RegionOutput& r : results) {
      next.insert(next.end(), r.faces.begin(), r.faces.end());
      collapses += r.collapses;
      flips += r.flips;
      largest = std::max(largest, r.largestDistance);
    }
    faces.swap(next);
    s.zone = nullptr;
  }

  // the surviving vertices, renumbered in their order
  phase.emplace("simplify: vertices renumbered", PhaseKind::Serial);
  TriangleMesh result;
  std::vector<std::uint32_t> number(nv, kNone);
  for (std::size_t v = 0; v < nv; ++v)
    if (!s.removed[v]) {
      number[v] = static_cast<std::uint32_t>(result.positions.size());
      result.positions.push_back(s.pos[v]);
    }
  if (!mesh.normals.empty()) {
    result.normals.resize(result.positions.size());
    tbb::parallel_for(std::size_t(0), nv, [&](std::size_t v) {
      if (number[v] == kNone) return;
      Vec3f& n = result.normals[number[v]];
      n = mesh.normals[v];
      if (!s.moved[v]) return;
      double value;
      Vec3 g;
      if (surface.plane(toVec3(s.pos[v]), &value, &g)) n = toVec3f({-g[0], -g[1], -g[2]});
    });
  }
  result.triangles.reserve(faces.size());
  for (const Triangle& t : faces)
    result.triangles.push_back({number[t[0]], number[t[1]], number[t[2]]});
  if (o.progress) o.progress(1.0);
  if (stats) {
    stats->trianglesBefore = mesh.triangles.size();
    stats->trianglesAfter = result.triangles.size();
    stats->collapses = collapses;
    stats->flips = flips;
    stats->largestDistance = largest;
    stats->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return result;
}

}  // namespace frep
