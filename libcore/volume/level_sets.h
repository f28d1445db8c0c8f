// Conversions between fields, meshes and OpenVDB level sets (narrow-band signed distances,
// negative inside, as OpenVDB's tools expect), all through OpenVDB's tools/.
#pragma once

#include <functional>
#include <string>

#include "base/triangle_mesh.h"
#include "base/vec.h"
#include "frep/field.h"
#include "volume/grid_set.h"

namespace frep {

// How the sampled first-order distances F / |grad F| are made a level set's distances.
// Measured on the csg, twist and gyroid models at 256 voxels (docs/performance.md): as
// sampled is the fastest and puts the zero level closest to the exact surface (0.24 voxel
// on csg, against 0.31 normalized and 0.49 rebuilt, which meshes it again): the default.
enum class Redistance {
  None,       // as sampled: -F / |grad F| (the default)
  Normalize,  // then OpenVDB's LevelSetTracker::normalize (a few Eikonal iterations)
  Rebuild,    // then tools::levelSetRebuild (the isosurface meshed and converted again)
};

struct LevelSetOptions {
  double voxel = 0.0;             // voxel size (> 0)
  double halfWidthVoxels = 3.0;   // narrow band on either side of the surface, in voxels
  // meshToLevelSet only: the band inside the surface, in voxels; infinity fills the whole
  // inside with distances, which shells, offsets and infills deeper than the band need.
  double interiorWidthVoxels = 3.0;
  std::string name = "surface";   // the grid's name
  Redistance redistance = Redistance::None;
  // Each voxel's value within the band: the first-order distance -F / |grad F| (a gradient
  // batch of the voxels with |F| below the band's width), or -F itself (a value batch only:
  // faster, and the same near distance-like fields).
  bool firstOrder = true;
  // A fog volume instead (OpenVDB's sdfToFogVolume): 0 outside, 1 inside, a linear ramp across
  // the band inside the surface; its grid class is fog volume (sampleLevelSet only).
  bool fog = false;
  // Called with the fraction done, possibly from worker threads (one call at a time); return
  // false to cancel (sampleLevelSet throws Cancelled, nothing is kept).
  std::function<bool(double)> progress;
};

// Samples `field` over `box` into a level set of one float grid (-F / |grad F| in the band,
// optionally re-distanced). Regions of 32^3 voxels and blocks of 8^3 whose interval, widened
// by the band, cannot hold the surface cost one interval evaluation and no memory; the field
// is specialised to each region, and the blocks are evaluated in parallel (TBB), a value
// batch each and a gradient batch for the voxels that may lie in the band. Throws ModelError for a bad voxel size or a box too large for
// the grid's coordinates.
GridSet sampleLevelSet(const Field& field, const Box3& box, const LevelSetOptions& options);

// A closed triangle mesh as a level set (tools::meshToLevelSet, which takes the sign from a
// flood fill, so self-intersections and the winding do not matter). An open or non-manifold
// mesh is refused with FileError naming `where` and the count of its bad edges.
GridSet meshToLevelSet(const TriangleMesh& mesh, const LevelSetOptions& options,
                       const std::string& where);

// The isosurface of a scalar grid as triangles (tools::volumeToMesh; its quads split along
// the shorter diagonal), oriented outward. `adaptivity` in [0, 1] merges flat regions.
// The caller judges the result with the check, as every export does.
TriangleMesh levelSetToMesh(const GridSet& grids, std::size_t index, double iso = 0.0,
                            double adaptivity = 0.0);

}  // namespace frep
