// How far a mesh is from the exact surface it was made of, sampled through the function
// (`frepcad export --stats`): the two one-sided distances whose larger is the Hausdorff
// distance, the volume, and the length of the creases.
#pragma once

#include <cstddef>

#include "base/triangle_mesh.h"
#include "base/vec.h"
#include "frep/field.h"

namespace frep {

struct AccuracyOptions {
  Box3 bbox;          // the meshing box: the surface is min(F, distance to the box) = 0
  double cell = 0.0;  // the meshing cell size (> 0)
  // Exact surface points are the vertices of a mesh of the field at cell / sampleRefinement.
  int sampleRefinement = 2;
  double creaseAngleDeg = 45.0;  // an edge whose faces' normals differ by more is a crease
};

struct AccuracyReport {
  // the largest and the mean distance from the mesh (its vertices and face centres) to the
  // surface: an upper bound, the distance to the nearer of the surface points Newton's steps
  // along the gradient reach from the point and from the nearest point of a finer mesh; where
  // neither reaches it (`unreached` points: the gradient vanishes near them), the distance to
  // the finer mesh
  double meshToSurface = 0.0, meshToSurfaceMean = 0.0;
  std::size_t unreached = 0;
  // the largest distance from a point of the surface (sampled) to the mesh
  double surfaceToMesh = 0.0;
  // where each largest distance was measured: the mesh's point (a vertex or face centre) and
  // the surface's sampled point, so the place the mesh is worst can be looked at
  Vec3 meshToSurfaceAt{0, 0, 0}, surfaceToMeshAt{0, 0, 0};
  double hausdorff = 0.0;  // the larger of the two
  double volume = 0.0;     // signed, of the mesh
  double creaseLength = 0.0;
  std::size_t samples = 0;  // points measured, both ways
};

// Throws ModelError for options out of range.
AccuracyReport measureAccuracy(const TriangleMesh& mesh, const Field& field,
                               const AccuracyOptions& options);

}  // namespace frep
