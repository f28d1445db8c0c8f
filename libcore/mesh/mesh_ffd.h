// Free-form deformation of a triangle mesh: every vertex pushed forward through the lattice
// (FfdLattice::deform: inside the rest box X(local(v)), outside it untouched), normals by the
// inverse transpose of the map's Jacobian. The triangles are kept as they are, so a closed
// mesh stays closed; a lattice that folds can make it self-intersect, which the check
// reports. In parallel (TBB), with progress and cancel.
#pragma once

#include <functional>

#include "base/triangle_mesh.h"
#include "lattice/ffd_lattice.h"

namespace frep {

struct MeshFfdOptions {
  // Called with the fraction done; return false to cancel (throws Cancelled).
  std::function<bool(double)> progress;
};

TriangleMesh deformMesh(const TriangleMesh& mesh, const FfdLattice& lattice,
                        const MeshFfdOptions& options = {});

}  // namespace frep
