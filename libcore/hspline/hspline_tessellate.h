// An hspline (through its flattened B-spline) as a triangle mesh within a distance tolerance:
// every knot span is cut so that the chord of a cubic stays within the tolerance, using the
// second derivative the span has. Periodic directions close up: a torus gives a closed mesh.
#pragma once

#include <cstddef>
#include <vector>

#include "base/triangle_mesh.h"
#include "hspline/hspline_flatten.h"

namespace frep {

struct HsTessellation {
  TriangleMesh mesh;  // float positions and unit normals (du x dv)
  int samplesU = 0, samplesV = 0;
  std::vector<double> us, vs;  // the sample parameters (vertex i + samplesU * j is at us[i], vs[j])
  bool closed = false;         // periodic both ways: no boundary
};

// Throws ModelError on a tolerance that is not positive or a mesh over maxTriangles.
HsTessellation tessellate(const FlatBSpline& surface, double tolerance,
                          std::size_t maxTriangles = 20'000'000);

}  // namespace frep
