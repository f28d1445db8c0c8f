#include "base/triangle_geometry.h"

namespace frep {

double meshVolume(const TriangleMesh& mesh) {
  double v = 0.0;
  for (const Triangle& t : mesh.triangles)
    v += signedTetraVolume(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
  return v;
}

double meshArea(const TriangleMesh& mesh) {
  double a = 0.0;
  for (const Triangle& t : mesh.triangles)
    a += triangleArea(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
  return a;
}

}  // namespace frep
