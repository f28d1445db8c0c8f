// Level-0 hsplines to start modelling from: a plane, a cylinder, a torus (seed 003's tutorial
// starts from such surfaces). Cylinder and torus are uniform cubic B-splines, periodic around,
// whose curves pass through the circle at every knot: close to, not exactly, round (a polynomial
// spline cannot be a circle), as in any hspline modeller.
#pragma once

#include "hspline/hspline.h"

namespace frep {

// cvsU x cvsV CVs (4 to 1,000 each), clamped at the edges, over sizeU x sizeV in the z = 0
// plane centred on the origin; the normal is +z.
HSpline hsplinePlane(int cvsU, int cvsV, double sizeU, double sizeV);
// cvsAround (periodic, u) x cvsAlong (clamped, v) CVs: radius about the z axis, z from 0 to
// height; the normal points outwards.
HSpline hsplineCylinder(int cvsAround, int cvsAlong, double radius, double height);
// Periodic both ways: u around the z axis at majorRadius, v around the tube of minorRadius;
// a closed surface with outward normals.
HSpline hsplineTorus(int cvsAround, int cvsTube, double majorRadius, double minorRadius);

}  // namespace frep
