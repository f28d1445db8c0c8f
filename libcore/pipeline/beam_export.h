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
  bool clipped = false;  // the beams are clipped by the part's mesh (not for an infill)
  std::size_t clipTriangles = 0, skinTriangles = 0;  // the part's mesh; an infill's skin
  CheckReport clipReport, skinReport;                // their checks, where they are written
  // The distance from the surface the written mesh was simplified within (the settings'
  // tolerance, else a tenth of a cell); 0: the mesher's own mesh.
  double meshTolerance = 0.0;
  bool written = false;  // false: a mesh the check refused (and force was not given)
  std::string notes;     // what the file leaves out (node spheres), one line; empty if nothing
  double seconds = 0.0;
};

// Writes `root`'s strut lattice as beams into the 3MF `path` (atomically), with the part's mesh
// (meshed in `box` with `settings`, simplified within their tolerance or else a tenth of a cell,
// checked) as the beams' clipping mesh; for an infill its
// skin as a printed mesh instead, and each beam cut where it leaves the part's inside deeper
// than half the skin (its end and cap in the skin: no clipping mesh, a much smaller file).
// Throws ModelError naming what the root must be, FileError, Cancelled.
BeamExportResult exportBeamLattice(const NodePtr& root, const MeshingBox& box,
                                   const MeshSettings& settings, const ThreeMfOptions& options,
                                   const std::string& name, const std::string& path, bool force,
                                   const std::function<bool(double)>& progress = nullptr);

// "N beams on V vertices, clipped by the part's mesh (T triangles)" or "... ending in the
// middle of the skin (S triangles)": what the CLI and the workbench say was written.
std::string beamExportSummary(const BeamExportResult& r);

}  // namespace frep
