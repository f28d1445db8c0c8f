// How far two meshes are apart: the Hausdorff distance both ways, sampled (each mesh's
// vertices, face centres and area-weighted random points, measured to the other's nearest
// triangle through CGAL's AABB tree). Used to report what a repair changed and to compare a
// repaired file with the shape it should have.
#pragma once

#include <cstddef>

#include "base/triangle_mesh.h"

namespace frep {

struct DeviationReport {
  double aToB = 0.0;  // largest distance from a point of a to b
  double bToA = 0.0;
  double meanAToB = 0.0;
  double meanBToA = 0.0;
  std::size_t samples = 0;  // points measured, both ways together
  double hausdorff() const { return aToB > bToA ? aToB : bToA; }
};

// At most `samplesPerMesh` points of each mesh (vertices first, then face centres, then
// random points; the same for the same meshes). A mesh without triangles is a FileError.
DeviationReport meshDeviation(const TriangleMesh& a, const TriangleMesh& b,
                              std::size_t samplesPerMesh = 60000);

// The largest distance from a sample of `a` to the surface of `solid` (closed and oriented)
// among the samples outside the solid: a repair that takes the union of overlapping shells
// absorbs their inner walls into the solid (not lost), while a sheet it drops or shreds lies
// outside. Inside by ray parity (the majority of three rays), for the samples farther than
// the answer only.
double largestDistanceOutside(const TriangleMesh& a, const TriangleMesh& solid,
                              std::size_t samplesPerMesh = 60000);

}  // namespace frep
