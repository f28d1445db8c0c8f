// hsplines in OpenCASCADE: the flattened hierarchy as one Geom_BSplineSurface (exact: the same
// knots and poles, not a fit), a closed hspline as a solid, STEP files. The only files of
// libcore that include OpenCASCADE; this header names none of its types.
#pragma once

#include <string>

#include "hspline/hspline.h"

namespace frep {

struct OccShapeSummary {
  int solids = 0, shells = 0, faces = 0;
  bool valid = false;  // BRepCheck_Analyzer's verdict
  double volume = 0;   // of the solids (GProp), 0 without one
  double area = 0;
};

// The largest distance between OpenCASCADE's surface and the hierarchy, at n x n parameters
// spread over the domain (corners and knots included).
double occSurfaceDeviation(const HSpline& h, int samplesPerAxis);

// Writes the hspline as STEP (AP214), atomically: a solid when the hspline is closed (periodic
// in u and v, like a torus), otherwise one face. Throws ModelError when OpenCASCADE refuses
// the shape and FileError when the file cannot be written.
OccShapeSummary writeHsStep(const HSpline& h, const std::string& path);

// The hspline as OpenCASCADE's binary BRep (a solid when closed and `solid`, else one face)
// with our own tessellation attached to the face as its triangulation, within a quarter of
// the deflection FreeCAD's 3D view asks at its default Deviation (0.5 % of the box's mean
// side, / 3): FreeCAD reads it with Part.Shape.importBinary, and the view then keeps that
// triangulation instead of meshing the face with BRepMesh (the better part of a second on a
// face of thousands of poles). The geometry is the exact surface either way.
std::string hsBrepBinary(const HSpline& h, bool solid);

// Reads a STEP file with OpenCASCADE and describes what it holds (throws FileError).
OccShapeSummary readStepSummary(const std::string& path);

}  // namespace frep
