// What OpenVDB offers for a function, shared by the benchmarks that measure against it: every
// grid point of [lo, hi] (voxel h) evaluated with the field's batches, in parallel over x
// slabs as our sampler is, negated (OpenVDB's level sets are negative inside) and clamped to
// a band of 3 voxels, then copied to a sparse level set (the far values become tiles).
#pragma once

#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <vector>

#include "frep/field.h"

namespace frep::bench {

inline openvdb::FloatGrid::Ptr denseLevelSet(const Field& field, const openvdb::Coord& lo,
                                             const openvdb::Coord& hi, double h) {
  const float band = 3.0f * static_cast<float>(h);
  openvdb::tools::Dense<float> dense(openvdb::CoordBBox(lo, hi));
  tbb::parallel_for(lo[0], hi[0] + 1, [&](int i) {
    const int n = hi[2] - lo[2] + 1;
    std::vector<double> x(n), y(n), z(n), v(n);
    for (int j = lo[1]; j <= hi[1]; ++j) {
      for (int k = 0; k < n; ++k) {
        x[k] = i * h;
        y[k] = j * h;
        z[k] = (lo[2] + k) * h;
      }
      field.evalBatch(x.data(), y.data(), z.data(), n, v.data());
      for (int k = 0; k < n; ++k)
        dense.setValue(openvdb::Coord(i, j, lo[2] + k),
                       std::clamp(static_cast<float>(-v[k]), -band, band));
    }
  });
  auto grid = openvdb::FloatGrid::create(band);
  grid->setTransform(openvdb::math::Transform::createLinearTransform(h));
  openvdb::tools::copyFromDense(dense, grid->tree(), 0.0f);
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  return grid;
}

}  // namespace frep::bench
