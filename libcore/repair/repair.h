// Repair of any triangle mesh into a printable one, judged by the check before and after:
//   1. near-duplicate vertices welded within a small distance (cracks of CAD exports);
//   2. CGAL's local repairs (repair/cgal_repair.h): soup clean-up, orientation, stitching,
//      degenerate faces, non-manifold vertices, holes, self-intersections, outward normals;
//   3. where the check still refuses the result (intersecting shells, crossings CGAL cannot
//      undo locally), a rebuild: the closed mesh becomes an OpenVDB level set (its sign from a
//      flood fill, so windings and overlaps stop mattering) and FRepCAD's own mesher meshes
//      that as a field, which gives a printable mesh by construction, within about a voxel.
// The deviation of the result from the input is measured (check/mesh_deviation.h).
#pragma once

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

struct RepairOptions {
  // Vertices closer than this are welded into one; < 0: a hundredth of the median edge
  // length (wider than the cracks of CAD exports, narrower than any edge but a sliver's),
  // widened up to a tenth of it while that closes borders; 0: identical coordinates only.
  double weldDistance = -1.0;
  bool fillHoles = true;
  RebuildPolicy rebuild = RebuildPolicy::Auto;
  double voxel =
      0.0;  // the rebuild's voxel size; 0: the box's longest side / kDefaultRebuildVoxels
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
  bool printable() const { return after.printable(); }
};

// Throws ModelError for bad options (naming `name` and the option), Cancelled. A mesh that
// cannot be made printable is not an error: result.after says why.
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
