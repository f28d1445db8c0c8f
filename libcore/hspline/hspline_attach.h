// Attachments (seed 003, 2.4): a cylinder-like hspline joined to a parent hspline around a
// rectangle of the parent's CVs that need not follow the cylinder's own parametrisation. The
// cylinder's next-to-last row of CVs is constrained to the ring of parent CVs around the
// rectangle (whose inner patches give way), which makes the four ring corners extraordinary
// (five edges); the joined control net is then a Catmull-Clark surface, subdivided with
// OpenMesh. Only level 0 of both takes part, as in seed 003.
#pragma once

#include "base/triangle_mesh.h"
#include "hspline/hspline.h"

namespace frep {

struct HsAttachment {
  TriangleMesh mesh;      // the subdivided surface, each quad split in two
  int extraordinary = 0;  // inner vertices of the joined net with other than four edges
  int boundaryLoops = 0;  // of the subdivided surface
  std::size_t controlFaces = 0;
};

// Joins `cylinder` (periodic along u, open along v, with 2 (i1 - i0) + 2 (j1 - j0) CVs around:
// CV k around sits over ring CV k, the ring starting at parent CV (i0, j0) and running along
// +i, +j, -i, -j) to `parent` around its CV rectangle [i0, i1] x [j0, j1]. The cylinder's row
// 1 takes the ring's positions and its row 0 is dropped. Subdivided `subdivisions` times
// (0 to 6). Throws ModelError naming what does not fit.
HsAttachment attachCylinder(const HSpline& parent, int i0, int i1, int j0, int j1,
                            const HSpline& cylinder, int subdivisions);

}  // namespace frep
