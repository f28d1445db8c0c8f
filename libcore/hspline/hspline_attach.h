// Attachments (seed 003, 2.4): a cylinder-like hspline joined to a parent hspline around a
// rectangle of the parent's CVs that need not follow the cylinder's own parametrisation. The
// cylinder's next-to-last row of CVs is constrained to the ring of parent CVs around the
// rectangle (whose inner patches give way), which makes the four ring corners extraordinary
// (five edges); the joined control net is then a Catmull-Clark surface, subdivided with
// OpenMesh. The cylinder's level 0 takes part, and the parent's chosen level (level 0, as in seed
// 003, unless the seam is refined).
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
// 1 takes the ring's positions and its row 0 is dropped. closeEnd closes the cylinder's free
// end with one face over its last row (subdivision rounds it off), so that a limb on a closed
// parent makes a closed surface. parentLevel refines the seam: the ring and the parent's net
// are taken on that level of the parent (created by knot insertion where the hierarchy lacks
// it), so each level doubles the CVs around the joint and keeps the parent's detail up to it;
// the rectangle's indices are on that level. Subdivided `subdivisions` times (0 to 6). Throws
// ModelError naming what does not fit.
constexpr int kMaxAttachLevel = 3;
// The hierarchy with a grid on `level` (levels it lacks made by knot insertion around one CV,
// with zero offsets: the surface does not change), as a seam on that level uses it.
HSpline hsplineWithLevel(const HSpline& h, int level);
constexpr std::size_t kMaxAttachGrid = 1u << 20;  // parent net points on the seam's level
HsAttachment attachCylinder(const HSpline& parent, int i0, int i1, int j0, int j1,
                            const HSpline& cylinder, int subdivisions, bool closeEnd = false,
                            int parentLevel = 0);

}  // namespace frep
