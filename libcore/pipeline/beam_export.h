// A strut lattice written as a 3MF beam lattice (the 3MF beam lattice extension): the struts
// as beams between vertices with their radii, clipped by the part's mesh, instead of the
// millions of triangles of the meshed struts. The model's root must be a strut lattice cut to a
// part (the intersection of a strut_lattice and the part) or an infill with a strut lattice
// (its skin is then written as a mesh beside the beams). docs/struts.md.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "check/mesh_check.h"
#include "frep/tree.h"
#include "io/mesh_3mf.h"
#include "mesh/mesh_settings.h"
#include "pipeline/export_pipeline.h"

namespace frep {

struct BeamExportResult {
  std::size_t beams = 0, vertices = 0;
  std::size_t clipTriangles = 0, skinTriangles = 0;  // the part's mesh; an infill's skin
  CheckReport clipReport, skinReport;                // their checks (the skin's when an infill)
  bool written = false;  // false: a mesh the check refused (and force was not given)
  std::string notes;     // what the file leaves out (node spheres), one line; empty if nothing
  double seconds = 0.0;
};

// Writes `root`'s strut lattice as beams into the 3MF `path` (atomically), with the part's mesh
// (meshed in `box` with `settings`, checked) as the beams' clipping mesh and, for an infill, its
// skin as a printed mesh. Throws ModelError naming what the root must be, FileError, Cancelled.
BeamExportResult exportBeamLattice(const NodePtr& root, const MeshingBox& box,
                                   const MeshSettings& settings, const ThreeMfOptions& options,
                                   const std::string& name, const std::string& path, bool force,
                                   const std::function<bool(double)>& progress = nullptr);

}  // namespace frep
