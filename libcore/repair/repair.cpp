#include "repair/repair.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <sstream>
#include <unordered_map>

#include "base/errors.h"
#include "base/process_memory.h"
#include "base/progress.h"
#include "mesh/mesher.h"
#include "repair/cgal_repair.h"
#include "simplify/simplify.h"
#include "volume/grid_field.h"
#include "volume/level_sets.h"

namespace frep {

namespace {

constexpr const char* kPolicyNames[] = {"auto", "never", "always"};

std::string plural(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

Box3 boxOf(const TriangleMesh& m) {
  Box3 b;
  bool first = true;
  for (const Triangle& t : m.triangles)
    for (std::uint32_t v : t) {
      if (v >= m.positions.size()) continue;
      const Vec3f& p = m.positions[v];
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) continue;
      for (int a = 0; a < 3; ++a) {
        b.lo[a] = first ? p[a] : std::min(b.lo[a], double(p[a]));
        b.hi[a] = first ? p[a] : std::max(b.hi[a], double(p[a]));
      }
      first = false;
    }
  return b;
}

// The median edge length (0 for a mesh without edges): the scale of the default weld, a
// hundredth of it, far wider than the cracks of CAD exports and STL round-offs, far narrower
// than any edge but a sliver's.
double medianEdgeLength(const TriangleMesh& m) {
  std::vector<double> lengths;
  lengths.reserve(m.triangles.size());
  for (const Triangle& t : m.triangles) {
    if (t[0] >= m.positions.size() || t[1] >= m.positions.size()) continue;
    const Vec3f& a = m.positions[t[0]];
    const Vec3f& b = m.positions[t[1]];
    const double l = std::sqrt((double(a[0]) - b[0]) * (double(a[0]) - b[0]) +
                               (double(a[1]) - b[1]) * (double(a[1]) - b[1]) +
                               (double(a[2]) - b[2]) * (double(a[2]) - b[2]));
    if (std::isfinite(l) && l > 0) lengths.push_back(l);
  }
  if (lengths.empty()) return 0.0;
  std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
  return lengths[lengths.size() / 2];
}

// Edges of exactly one triangle (cracks and holes; an edge of three is no crack).
std::size_t borderEdgeCount(const TriangleMesh& m) {
  std::vector<std::uint64_t> edges;
  edges.reserve(3 * m.triangles.size());
  for (const Triangle& t : m.triangles)
    for (int i = 0; i < 3; ++i) {
      const std::uint64_t a = t[i], b = t[(i + 1) % 3];
      edges.push_back(a < b ? a << 32 | b : b << 32 | a);
    }
  std::sort(edges.begin(), edges.end());
  std::size_t n = 0;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    n += j - i == 1;
    i = j;
  }
  return n;
}

// CGAL's log as sentences, appended to `actions`.
void describe(const CgalRepairLog& log, std::vector<std::string>& actions) {
  if (log.soupPointsMerged)
    actions.push_back("merged " +
                      plural(log.soupPointsMerged, "duplicate point", "duplicate points"));
  if (log.soupFacesRemoved)
    actions.push_back("removed " + plural(log.soupFacesRemoved, "degenerate or duplicate triangle",
                                          "degenerate or duplicate triangles"));
  if (log.bordersStitched)
    actions.push_back("stitched " + plural(log.bordersStitched, "pair", "pairs") +
                      " of coincident border edges");
  if (log.degenerateFacesLeft)
    actions.push_back(
        plural(log.degenerateFacesLeft, "degenerate triangle", "degenerate triangles") +
        " could not be removed");
  if (log.nonManifoldVerticesSplit)
    actions.push_back("split " + plural(log.nonManifoldVerticesSplit, "non-manifold vertex",
                                        "non-manifold vertices"));
  if (log.holesFilled)
    actions.push_back("filled " + plural(log.holesFilled, "hole", "holes") + " with " +
                      plural(log.facesAdded, "triangle", "triangles"));
  if (log.flatShellsRemoved)
    actions.push_back("removed " + plural(log.flatShellsRemoved, "shell", "shells") +
                      " of no volume (slivers split off sound edges)");
  if (log.holesLeft)
    actions.push_back(plural(log.holesLeft, "hole", "holes") + " could not be filled");
  if (log.selfIntersected && log.selfIntersectionsRemoved)
    actions.push_back("removed the self-intersections locally (CGAL)");
  if (log.reoriented) actions.push_back("oriented every shell to bound a volume, normals out");
}

// The closed mesh through a level set and the mesher (see repair.h, step 3).
TriangleMesh rebuildThroughLevelSet(const TriangleMesh& closed, double voxel,
                                    const std::string& name, const Progress& progress) {
  // the level set half the bar, meshing it 30 %, simplifying the rest
  const std::vector<Progress> phase = progress.phases({0.5, 0.3, 0.2});
  LevelSetOptions ls;
  ls.voxel = voxel;
  ls.name = "repair";
  const GridSet grids = meshToLevelSet(closed, ls, name);
  phase[1].step(0.0);
  const auto field = gridField(grids, 0, GridFieldOptions(), name);
  Box3 box = boxOf(closed);
  for (int a = 0; a < 3; ++a) {
    box.lo[a] -= 2 * voxel;
    box.hi[a] += 2 * voxel;
  }
  MeshingOptions mo;
  mo.bbox = box;
  mo.resolution = voxel;
  mo.normals = false;
  mo.findThinParts = false;
  mo.progress = phase[1].callback();
  const TriangleMesh fine = polygonize(*field, mo);
  // The mesher's triangles are a few per voxel wherever the surface goes; guarded collapses
  // (simplify/, each proved intersection-free and within the tolerance of the level set)
  // bring that down to what the shape needs.
  SimplifyOptions so;
  so.bbox = box;
  so.cell = voxel;
  so.tolerance = 0.25 * voxel;
  so.sharpFeatures = true;
  so.progress = phase[2].callback();
  return simplifyMesh(fine, *field, so);
}

// Three significant digits (0.0213, 1.2e+03 as 1200).
std::string figure(double v) {
  std::ostringstream os;
  os.precision(3);
  if (std::abs(v) >= 1000.0 && std::abs(v) < 1e15)
    os << std::llround(v);
  else
    os << v;
  return os.str();
}

std::string percentOf(double v, double whole) {
  return whole > 0 ? figure(100.0 * v / whole) + " % of the diagonal" : "the box is a point";
}

struct Judgement {
  DeviationReport deviation;  // a: the input, b: the result
  double lost = 0.0;          // the input's largest distance outside the result's solid
  std::vector<std::string> departures;
};

// The result against the input, by the rules of repair.h: pieces, invented surface, lost
// surface. `check` is the result's check (the inside test needs a closed, oriented result;
// an unprintable one is measured plainly).
Judgement judge(const TriangleMesh& input, std::size_t piecesBefore, const TriangleMesh& result,
                const CheckReport& check, double bound, double diagonal, bool allowMorePieces) {
  Judgement j;
  if (result.triangles.empty()) return j;
  j.deviation = meshDeviation(input, result);
  j.lost = check.printable() ? largestDistanceOutside(input, result) : j.deviation.aToB;
  if (!allowMorePieces && check.components > piecesBefore)
    j.departures.push_back("the result has " + plural(check.components, "piece", "pieces") +
                           " where the input has " + std::to_string(piecesBefore) +
                           ": the repair split the part");
  if (j.deviation.bToA > bound)
    j.departures.push_back("the result's surface lies up to " + figure(j.deviation.bToA) +
                           " from the input's (" + percentOf(j.deviation.bToA, diagonal) +
                           "), beyond the bound " + figure(bound) +
                           ": surface invented there (a cap over an open sheet or a wide "
                           "hole, or a rebuild too coarse)");
  if (j.lost > bound)
    j.departures.push_back("parts of the input lie up to " + figure(j.lost) +
                           " from the result, outside its solid (" + percentOf(j.lost, diagonal) +
                           "), beyond the bound " + figure(bound) +
                           ": the repair dropped them (thin walls, sheets or small pieces "
                           "finer than the rebuild's voxel)");
  return j;
}

// The rebuild's level set and mesher need memory for every voxel along the surface: refused
// before any of it is allocated when the budget (or the mesher's grid) cannot hold it, naming
// the smallest voxel that fits both.
void refuseRebuildOverBudget(double area, double longest, double voxel, std::size_t budget,
                             const std::string& name) {
  const double cellsAlong = longest / voxel;
  const double surfaceVoxels = area / (voxel * voxel);
  const double bytes = surfaceVoxels * kRebuildBytesPerSurfaceVoxel;
  const bool tooManyAlong = cellsAlong > double(kMaxCellsPerAxis);
  const bool tooLarge = budget > 0 && bytes > double(budget);
  if (!tooManyAlong && !tooLarge) return;
  double fits = 1.01 * longest / double(kMaxCellsPerAxis);
  if (budget > 0)
    fits = std::max(fits, 1.1 * std::sqrt(area * kRebuildBytesPerSurfaceVoxel / double(budget)));
  throw TooLargeError(
      name + ": the rebuild at voxel size " + figure(voxel) +
      (tooLarge ? " covers about " + figure(surfaceVoxels / 1e6) +
                      " million voxels of surface, needing about " + figure(bytes / 1e9) +
                      " GB, and " + figure(double(budget) / 1e9) + " GB is available"
                : " needs " + figure(cellsAlong) + " voxels along the longest side, and at most " +
                      std::to_string(kMaxCellsPerAxis) + " are allowed") +
      ": use a voxel size of at least " + figure(fits));
}

}  // namespace

const char* rebuildPolicyName(RebuildPolicy p) {
  return kPolicyNames[static_cast<int>(p)];
}

RebuildPolicy parseRebuildPolicy(const std::string& name) {
  for (int i = 0; i < 3; ++i)
    if (name == kPolicyNames[i]) return static_cast<RebuildPolicy>(i);
  throw ModelError("unknown rebuild policy '" + name + "'; allowed: auto, never, always");
}

std::size_t weldNearbyVertices(TriangleMesh& mesh, double distance, std::size_t& removed) {
  removed = 0;
  const std::size_t n = mesh.positions.size();
  std::vector<std::uint32_t> order(n), target(n);
  std::iota(order.begin(), order.end(), 0u);
  std::iota(target.begin(), target.end(), 0u);
  std::size_t moved = 0;
  if (distance > 0) {
    // A hash grid of cells `distance` wide holds the kept vertices; a vertex looks in the 27
    // cells around its own for a kept one within reach. Kept vertices never move, so welding
    // does not chain along a row of close vertices.
    std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
      return mesh.positions[a] < mesh.positions[b];
    });
    auto key = [&](long long x, long long y, long long z) {
      return (std::uint64_t(x) * 73856093ull) ^ (std::uint64_t(y) * 19349663ull) ^
             (std::uint64_t(z) * 83492791ull);
    };
    std::unordered_multimap<std::uint64_t, std::uint32_t> kept;
    kept.reserve(n);
    const double d2 = distance * distance;
    for (std::uint32_t v : order) {
      const Vec3f& p = mesh.positions[v];
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) continue;
      long long c[3];
      for (int a = 0; a < 3; ++a) c[a] = static_cast<long long>(std::floor(p[a] / distance));
      std::uint32_t best = v;
      double bestD = d2;
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz) {
            auto range = kept.equal_range(key(c[0] + dx, c[1] + dy, c[2] + dz));
            for (auto it = range.first; it != range.second; ++it) {
              const Vec3f& q = mesh.positions[it->second];
              const double e = (double(p[0]) - q[0]) * (double(p[0]) - q[0]) +
                               (double(p[1]) - q[1]) * (double(p[1]) - q[1]) +
                               (double(p[2]) - q[2]) * (double(p[2]) - q[2]);
              if (e <= bestD && (best == v || e < bestD || it->second < best)) {
                best = it->second;
                bestD = e;
              }
            }
          }
      if (best != v) {
        target[v] = best;
        moved += !(mesh.positions[best] == p);
      } else {
        kept.emplace(key(c[0], c[1], c[2]), v);
      }
    }
  }
  std::vector<Triangle> kept;
  kept.reserve(mesh.triangles.size());
  for (Triangle t : mesh.triangles) {
    for (std::uint32_t& v : t)
      if (v < n) v = target[v];
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
      ++removed;
    else
      kept.push_back(t);
  }
  mesh.triangles.swap(kept);
  return moved;
}

std::string repairToText(const RepairResult& r, const CheckReport& verdict,
                         const std::string& name) {
  std::ostringstream os;
  os << "repair " << name << ": " << (r.before.printable() ? "printable already" : "not printable")
     << "\n";
  for (const auto& reason : r.before.reasons) os << "  - " << reason << "\n";
  for (const auto& action : r.actions) os << "  * " << action << "\n";
  os << "result: " << r.mesh.triangles.size() << " triangles, "
     << (!verdict.printable()    ? "NOT printable"
         : !r.departures.empty() ? "printable but NOT faithful to the input"
                                 : "printable")
     << "; its surface within " << r.deviation.bToA << " of the input's (mean "
     << r.deviation.meanBToA << "), the input's within " << r.lostDistance << " of it (bound "
     << r.deviationBound << ")\n";
  for (const auto& reason : verdict.reasons) os << "  - " << reason << "\n";
  for (const auto& departure : r.departures) os << "  - " << departure << "\n";
  return os.str();
}

RepairResult repairMesh(const TriangleMesh& input, const RepairOptions& options,
                        const std::string& name) {
  if (!(options.voxel >= 0) || !std::isfinite(options.voxel))
    throw ModelError(name +
                     ": the rebuild's voxel size must be a number > 0 (or 0 for the "
                     "default), got " +
                     figure(options.voxel));
  if (std::isnan(options.weldDistance) || std::isinf(options.weldDistance))
    throw ModelError(name + ": the weld distance must be a finite number >= 0");
  if (std::isnan(options.maxDeviation) || std::isinf(options.maxDeviation))
    throw ModelError(name +
                     ": the deviation bound must be a finite distance > 0 (or < 0 for the "
                     "default, 2 % of the diagonal)");
  // The bar: the CGAL repair to 35 %, its check to 40 %, the local self-intersection
  // removal to 55 %, the rebuild to 90 %, the deviation the rest.
  const Progress bar(options.progress);
  RepairResult r;
  r.before = checkMesh(input);
  r.piecesBefore = r.before.components;
  const Box3 box = boxOf(input);
  double diagonal = 0, longest = 0;
  for (int a = 0; a < 3; ++a) {
    diagonal += (box.hi[a] - box.lo[a]) * (box.hi[a] - box.lo[a]);
    longest = std::max(longest, box.hi[a] - box.lo[a]);
  }
  diagonal = std::sqrt(diagonal);
  r.deviationBound =
      options.maxDeviation > 0 ? options.maxDeviation : kDefaultDeviationFraction * diagonal;
  if (r.before.faces == 0) {
    r.after = r.before;
    r.mesh = input;
    r.actions.push_back("nothing to repair: the mesh has no triangles");
    return r;
  }
  if (r.before.printable() && options.rebuild != RebuildPolicy::Always) {
    r.after = r.before;
    r.mesh = input;
    r.actions.push_back("nothing to repair: the mesh is printable");
    return r;
  }
  bar.step(0.02);

  TriangleMesh mesh = input;
  const double median = medianEdgeLength(input);
  double weld = options.weldDistance < 0 ? 0.01 * median : options.weldDistance;
  std::size_t collapsed = 0;
  std::size_t welded = weldNearbyVertices(mesh, weld, collapsed);
  if (options.weldDistance < 0) {
    // Cracks wider than the first weld: widen it, up to a tenth of the median edge, as long
    // as that closes borders (admesh's nearby search does the same), so that a cracked mesh
    // keeps its own triangles rather than being filled and rebuilt.
    std::size_t open = borderEdgeCount(mesh);
    for (double factor : {0.03, 0.1}) {
      if (open == 0) break;
      TriangleMesh wider = input;
      std::size_t widerCollapsed = 0;
      const std::size_t widerWelded = weldNearbyVertices(wider, factor * median, widerCollapsed);
      const std::size_t widerOpen = borderEdgeCount(wider);
      if (widerOpen >= open) break;
      mesh = std::move(wider);
      weld = factor * median;
      welded = widerWelded;
      collapsed = widerCollapsed;
      open = widerOpen;
    }
  }
  if (welded)
    r.actions.push_back("welded " + plural(welded, "vertex", "vertices") + " within " +
                        figure(weld) + " of another");
  if (collapsed)
    r.actions.push_back("removed " + plural(collapsed, "triangle", "triangles") +
                        " that welding collapsed");

  const double voxel = options.voxel > 0 ? options.voxel : longest / kDefaultRebuildVoxels;

  // Local repairs first, crossings left alone; then, where crossings remain, CGAL's local
  // removal of self-intersections, kept only when its result passes the check, lies on the
  // input's surface (within a voxel) and has no more pieces than the mesh had. The last rule
  // is what the first two miss: on two crossing balls the removal returned four nested
  // shells, every face on the input, the inner caps kept as cavities and a third of the
  // union's volume gone (bench/repair_comparison.py). Otherwise the rebuild through a level
  // set runs, whose flood fill takes the union, which is what overlapping shells mean.
  CgalRepairOptions co;
  co.fillHoles = options.fillHoles;
  co.removeSelfIntersections = false;
  co.progress = bar.sub(0.05, 0.3).callback();
  CgalRepairLog log;
  mesh = repairWithCgal(mesh, co, log);
  describe(log, r.actions);
  const Progress checking = bar.sub(0.35, 0.05);
  r.after = checkMesh(mesh, [&checking](double f) { checking.step(f); });
  // The level set's flood fill needs a watertight surface only: non-manifold edges and
  // crossings it resolves.
  const bool closed = r.after.closed;
  const std::size_t openEdges = r.after.borderEdges;
  const bool rebuildPossible = options.rebuild != RebuildPolicy::Never && closed;
  // CGAL's local removal grows with the crossings (100,000 random triangles: minutes); a
  // mesh crossed that often is no job for a local repair.
  const bool fewCrossings = r.after.selfIntersections <= kMaxLocallyRemovedCrossings;
  if (!r.after.printable() && r.after.selfIntersections && !fewCrossings)
    r.actions.push_back("CGAL's local removal of self-intersections was not tried: " +
                        plural(r.after.selfIntersections, "pair", "pairs") +
                        (r.after.selfIntersectionsAtLeast ? " (at least)" : "") +
                        " of crossing triangles, more than the " +
                        std::to_string(kMaxLocallyRemovedCrossings) + " it removes locally");
  if (!r.after.printable() && r.after.selfIntersections && fewCrossings &&
      options.rebuild != RebuildPolicy::Always) {
    CgalRepairOptions local = co;
    local.removeSelfIntersections = true;
    local.progress = bar.sub(0.4, 0.15).callback();
    CgalRepairLog localLog;
    TriangleMesh removed = repairWithCgal(mesh, local, localLog);
    CheckReport judged = checkMesh(removed);
    const bool sound = judged.printable() && judged.components <= r.after.components &&
                       meshDeviation(removed, input).aToB <= voxel;
    const bool better = judged.printable() || judged.reasons.size() < r.after.reasons.size();
    if (sound || (!rebuildPossible && better)) {
      describe(localLog, r.actions);
      mesh = std::move(removed);
      r.after = std::move(judged);
    } else if (!rebuildPossible) {
      r.actions.push_back("CGAL's local removal of self-intersections did not succeed");
    } else {
      r.actions.push_back("CGAL's local removal of self-intersections was not kept (" +
                          std::string(judged.printable() ? "it changed the solid's pieces or "
                                                           "moved its surface"
                                                         : "not printable") +
                          "): rebuilding instead");
    }
  }

  std::optional<Judgement> keptRebuild;  // the rebuild's judgement, when it is kept
  const bool rebuild = options.rebuild == RebuildPolicy::Always ||
                       (options.rebuild == RebuildPolicy::Auto && !r.after.printable());
  if (rebuild) {
    if (mesh.triangles.empty()) {
      r.actions.push_back(
          "nothing is left: the mesh encloses no volume (a sheet or a surface, "
          "not a solid)");
    } else if (!closed) {
      r.actions.push_back(
          "no rebuild through a level set: after the local repairs the mesh "
          "still has " +
          plural(openEdges, "border edge", "border edges") +
          " (holes that could not be filled), so its inside is not known");
    } else {
      refuseRebuildOverBudget(r.after.area, longest, voxel,
                              options.memoryBudget ? options.memoryBudget : availableMemory(),
                              name);
      r.voxel = voxel;
      TriangleMesh rebuilt = rebuildThroughLevelSet(mesh, r.voxel, name, bar.sub(0.55, 0.35));
      CheckReport judged = checkMesh(rebuilt);
      r.actions.push_back("rebuilt through a level set at voxel size " + figure(r.voxel) + " (" +
                          plural(rebuilt.triangles.size(), "triangle", "triangles") +
                          "; the inside from a flood fill, so overlapping shells become one)");
      Judgement j = judge(input, r.piecesBefore, rebuilt, judged, r.deviationBound, diagonal,
                          options.allowMorePieces);
      // Keep the rebuild when it passes and is faithful, or when nothing passes and it is the
      // closer miss (a sheet's flood fill finds no inside and rebuilds to nothing: that is
      // no closer). A printable rebuild that shreds or moves the part is not kept: its
      // departures are the reasons the repair gives.
      if (judged.printable() && !j.departures.empty()) {
        r.actions.push_back(
            "the rebuild was not kept: it is printable but not faithful to "
            "the input");
        r.departures = std::move(j.departures);
      } else if (judged.printable() ||
                 (!rebuilt.triangles.empty() && judged.reasons.size() < r.after.reasons.size())) {
        mesh = std::move(rebuilt);
        r.after = std::move(judged);
        r.rebuilt = true;
        keptRebuild = std::move(j);
      }
    }
  }
  bar.step(0.9);
  if (!mesh.triangles.empty()) {
    // (a kept rebuild was judged as it is: not measured again)
    Judgement j = keptRebuild ? std::move(*keptRebuild)
                              : judge(input, r.piecesBefore, mesh, r.after, r.deviationBound,
                                      diagonal, options.allowMorePieces);
    r.deviation = j.deviation;
    r.lostDistance = j.lost;
    // a rebuild not kept has said why; the mesh kept instead is judged on its own
    if (r.after.printable() || r.departures.empty()) r.departures = std::move(j.departures);
  }
  r.mesh = std::move(mesh);
  bar.step(1.0);
  return r;
}

}  // namespace frep
