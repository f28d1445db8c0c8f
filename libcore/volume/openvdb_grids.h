// Inside volume/ only: the OpenVDB side of GridSet. Including OpenVDB costs seconds per
// translation unit, so only volume/*.cpp (and the volume test) include this header.
#pragma once

#include <openvdb/openvdb.h>

#include "volume/grid_set.h"

namespace frep {

struct GridSet::Impl {
  openvdb::GridPtrVec grids;
  openvdb::MetaMap fileMetadata;
};

// openvdb::initialize(), once per process (thread-safe).
void initializeOpenVdb();

// A set holding the given grids.
GridSet gridSetOf(openvdb::GridPtrVec grids);

}  // namespace frep
