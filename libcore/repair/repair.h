// Repair of any triangle mesh into a printable one, judged by the check before and after:
//   1. near-duplicate vertices welded within a small distance (cracks of CAD exports);
//   2. CGAL's local repairs (repair/cgal_repair.h): soup clean-up, orientation, stitching,
//      degenerate faces, non-manifold vertices, holes, self-intersections, outward normals;
//   3. where the check still refuses the result (intersecting shells, crossings CGAL cannot
//      undo locally), a rebuild: the closed mesh becomes an OpenVDB level set (its sign from a
//      flood fill, so windings and overlaps stop mattering) and FRepCAD's own mesher meshes
//      that as a field, which gives a printable mesh by construction, within about a voxel.
// Every route's result, the rebuild included, is then judged against the input
// (repairJudgement): no more pieces than the input had, no surface invented farther than a
// bound from the input's, no part of the input lost farther than it (parts inside the
// result's solid, the inner walls of overlapping shells, are absorbed, not lost). A result
// that fails is not accepted, whatever the check says: a repair never shreds a part and calls
// it printable. Open sheets are one case of this rule: closing one invents a cap far from any
// input surface, refused unless the bound is raised to cover it.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "base/triangle_mesh.h"
#include "check/mesh_check.h"
#include "check/mesh_deviation.h"

namespace frep {

enum class RebuildPolicy {
  Auto,    // only when the local repairs leave the mesh unprintable (the default)
  Never,   // local repairs only: the shape never moves more than they move it
  Always,  // straight to the level set (after the local repairs close the mesh)
};

// "auto", "never", "always"; parseRebuildPolicy throws ModelError naming the allowed values.
const char* rebuildPolicyName(RebuildPolicy p);
RebuildPolicy parseRebuildPolicy(const std::string& name);

// Voxels along the longest side of the mesh's box for the rebuild when no voxel size is given.
constexpr int kDefaultRebuildVoxels = 192;

// The default bound on how far a repair may move or invent surface: this fraction of the
// diagonal of the input's box. The rebuild at the default voxel stays within a third of it; a
// hole filled in a scan, within it unless the hole is wider than a few percent of the part.
constexpr double kDefaultDeviationFraction = 0.02;

// The most crossing pairs CGAL's local removal of self-intersections is given; a mesh
// crossed more often goes to the rebuild (when closed) or is refused.
constexpr std::size_t kMaxLocallyRemovedCrossings = 20000;

// What the rebuild's level set and mesher take per voxel of surface (bytes, and seconds on
// one core of the machines FRepCAD is tested on): measured on rebuilds of a cube at 8e-3 to
// 2e-3 (350-530 bytes, 10 microseconds), rounded up.
constexpr double kRebuildBytesPerSurfaceVoxel = 600.0;
struct RepairOptions {
  // Vertices closer than this are welded into one; < 0: a hundredth of the median edge
  // length (wider than the cracks of CAD exports, narrower than any edge but a sliver's),
  // widened up to a tenth of it while that closes borders; 0: identical coordinates only.
  double weldDistance = -1.0;
  bool fillHoles = true;
  RebuildPolicy rebuild = RebuildPolicy::Auto;
  double voxel =
      0.0;  // the rebuild's voxel size; 0: the box's longest side / kDefaultRebuildVoxels
  // How far the result may lie from the input, and the input from the result (outside its
  // solid); < 0: kDefaultDeviationFraction of the input box's diagonal.
  double maxDeviation = -1.0;
  // Accept a result of more pieces than the input had (a part meant to fall apart).
  bool allowMorePieces = false;
  // The memory the rebuild may take (bytes); 0: what the system has available now. A rebuild
  // estimated to need more is refused before it starts (TooLargeError).
  std::size_t memoryBudget = 0;
  // (fraction done); false cancels: repairMesh throws Cancelled.
  std::function<bool(double)> progress;
};

struct RepairResult {
  TriangleMesh mesh;
  CheckReport before, after;
  std::vector<std::string> actions;  // what was done, in order, each a sentence with counts
  bool rebuilt = false;
  double voxel = 0.0;         // when rebuilt
  DeviationReport deviation;  // the result against the input
  // The judgement of the result against the input: the bound used, the input's pieces, the
  // largest distance of the input outside the result's solid, and why the result is not
  // faithful to the input (empty when it is).
  double deviationBound = 0.0;
  std::size_t piecesBefore = 0;
  double lostDistance = 0.0;
  std::vector<std::string> departures;
  bool printable() const { return after.printable(); }
  // Printable and faithful: what may be written.
  bool accepted() const { return after.printable() && departures.empty(); }
};

// Throws ModelError for bad options (naming `name` and the option), TooLargeError for a
// rebuild estimated beyond the memory budget (with the smallest voxel that fits), Cancelled.
// A mesh that cannot be made printable, or only unfaithfully, is not an error:
// result.after.reasons and result.departures say why.
RepairResult repairMesh(const TriangleMesh& input, const RepairOptions& options,
                        const std::string& name);

// The report for people: the verdict before, each action, the result and its deviation both
// ways, the reasons left. `verdict` is the check of what was written (a 3MF's package as read
// back), which is result.after for every other format.
std::string repairToText(const RepairResult& result, const CheckReport& verdict,
                         const std::string& name);

// Vertices within `distance` of an earlier kept vertex (in x order) take its index; returns
// how many moved. Triangles left with a repeated vertex are removed (counted in `removed`).
std::size_t weldNearbyVertices(TriangleMesh& mesh, double distance, std::size_t& removed);

}  // namespace frep
