// Plane sections of a solid: the closed contours where a plane cuts F >= 0, as polylines in
// space (FreeCAD wires, a slicer's outlines). Marching squares on a grid in the plane: the
// crossed grid edges get a vertex by bracketed root finding on the field itself (as the
// mesher places its vertices), a square whose diagonal corners agree (a saddle) is decided
// by the field at its centre, and the segments are joined into loops with the solid on their
// left (seen against the plane's normal u x v).
#pragma once

#include <vector>

#include "base/progress.h"
#include "base/vec.h"
#include "frep/field.h"

namespace frep {

struct SectionPlane {
  Vec3 origin{0, 0, 0};
  Vec3 u{1, 0, 0};  // unit in-plane axes, at right angles; the normal is u x v
  Vec3 v{0, 1, 0};
};

struct SectionLoop {
  std::vector<Vec3> points;  // the first point is not repeated at the end
  bool closed = true;        // false where the solid runs past the sampled rectangle
};

// The contours of `field` on `plane` within the rectangle [u0, u1] x [v0, v1] of plane
// coordinates, sampled at `cell`. Throws ModelError for a cell or rectangle that means
// nothing or a grid of more than 2^26 points; Cancelled through `progress`.
std::vector<SectionLoop> sectionField(const Field& field, const SectionPlane& plane, double u0,
                                      double u1, double v0, double v1, double cell,
                                      const Progress& progress = Progress());

// The rectangle of plane coordinates that covers `box` seen along the plane's normal, or
// false when the plane misses the box.
bool sectionRectangle(const SectionPlane& plane, const Box3& box, double& u0, double& u1,
                      double& v0, double& v1);

}  // namespace frep
