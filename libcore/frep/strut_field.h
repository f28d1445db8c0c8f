// The field of a strut lattice at a point, for the nodes that build on it (strut_lattice,
// infill's strut lattices): defined in node_types_struts.cpp.
#pragma once

#include "base/vec.h"
#include "frep/registry.h"

namespace frep {

struct UnitCell;

// radius - the distance from p to the lattice's nearest strut (cells of `size` from `origin`),
// and max with node_radius - the distance to the nearest node when nodeRadius > 0.
Slot strutLatticeField(ProgramBuilder& b, const Point3Slots& p, const UnitCell& cell,
                       const Vec3& size, const Vec3& origin, Slot radius, double nodeRadius);

}  // namespace frep
