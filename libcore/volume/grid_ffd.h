// Free-form deformation of OpenVDB grids by a lattice, without gaps: every voxel of the
// deformed grid is pulled back through the lattice's inverse map and samples the source there
// (backward resampling), so however far the lattice stretches, no voxel is left unfilled.
// Seed 002's forward splatting (each source voxel written where it lands) is kept as an option
// to show the difference: stretched, it leaves holes.
//
// Value types: float, double, int32, bool, vec3s, vec3d (others are refused naming the grid).
// Scalars are interpolated (nearest, trilinear or triquadratic; int32 and bool always take the
// nearest voxel), and a point within 1e-6 voxel of a voxel centre takes that voxel's value, so
// the undeformed lattice gives the source back bit for bit. Vectors follow their grid's OpenVDB
// vector type: covariant ones (normals, gradients) by the inverse transpose of the map's
// Jacobian, contravariant relative ones (velocities, displacements) by the Jacobian,
// contravariant absolute ones (positions) through the map itself; OpenVDB's default,
// "invariant", counts as a direction field and transforms by the Jacobian unless the caller
// keeps vectors as they are. Level sets are rebuilt afterwards (signed flood fill, then
// OpenVDB's levelSetRebuild), so the result is again a signed distance narrow band.
#pragma once

#include <cstdint>
#include <functional>

#include "lattice/ffd_lattice.h"
#include "volume/grid_set.h"

namespace frep {

struct GridFfdOptions {
  enum class Method { Backward, ForwardSplat };
  Method method = Method::Backward;
  int interpolation = 1;     // 0 nearest, 1 trilinear, 2 triquadratic
  bool keepVectors = false;  // true: vectors are copied, not transformed
  bool rebuildLevelSets = true;
  // A deformed grid needing more voxels than this is refused before it is built.
  std::uint64_t maxVoxels = std::uint64_t(1) << 31;
  // Called with the fraction done (every grid together); return false to cancel (throws
  // Cancelled).
  std::function<bool(double)> progress;
};

// Every grid of the set deformed, names, classes, transforms and metadata kept. Throws
// ModelError for an unsupported value type, a folded lattice or an output too large.
GridSet deformGrids(const GridSet& grids, const FfdLattice& lattice,
                    const GridFfdOptions& options = {});

}  // namespace frep
