// An OpenVDB grid as a Field: the solid where a level set is below `iso` (or any other scalar
// grid above it), in all four evaluation modes.
#pragma once

#include <memory>
#include <string>

#include "frep/field.h"
#include "volume/grid_set.h"

namespace frep {

enum class GridInterpolation { Linear, Quadratic };

struct GridFieldOptions {
  GridInterpolation interpolation = GridInterpolation::Linear;
  double iso = 0.0;
};

// The field of grid `index` of `grids` (a float or double grid with a linear transform; a
// frustum transform or another value type is refused with ModelError naming `where`).
//
// Values: OpenVDB's BoxSampler (trilinear) and QuadraticSampler (triquadratic, through the
// 27 voxels around the floor index) interpolants, computed here in double together with their
// derivatives, so that the value of evalGradient is bit for bit eval's (the samplers compute
// in the grid's value type and give no derivative). Intervals: the minimum and maximum of the
// voxels the interpolant can read over the box, from per-node extrema precomputed over the
// tree, so a query costs little more than the tree's nodes it meets; triquadratic ones are
// widened by its overshoot bound.
std::shared_ptr<const Field> gridField(const GridSet& grids, std::size_t index,
                                       const GridFieldOptions& options, const std::string& where);

}  // namespace frep
