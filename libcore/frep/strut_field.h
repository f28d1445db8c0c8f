// The field of a strut lattice at a point, for the nodes that build on it (strut_lattice,
// infill's strut lattices): defined in node_types_struts.cpp.
#pragma once

#include <array>

#include "base/vec.h"
#include "frep/registry.h"
#include "frep/tree.h"

namespace frep {

struct UnitCell;

// radius - the distance from p to the lattice's nearest strut (cells of `size` from `origin`),
// and max with node_radius - the distance to the nearest node when nodeRadius > 0; with
// blend > 0 the smooth minimum of the struts' distances (rounded joints).
Slot strutLatticeField(ProgramBuilder& b, const Point3Slots& p, const UnitCell& cell,
                       const Vec3& size, const Vec3& origin, Slot radius, double nodeRadius,
                       double blend = 0.0);

// radius - the distance from p to the nearest edge of a voronoi_foam node's foam (its network
// from the node's loader, volume/voronoi_foam.h), and max with node_radius - the distance to
// the nearest vertex when nodeRadius > 0.
Slot voronoiFoamField(ProgramBuilder& b, const Point3Slots& p, const Node& foam, Slot radius,
                      double nodeRadius);

// The cells of a Voronoi foam's period along each axis: `tile` times the cell's longest side
// (rounded up to whole cells) along every axis.
std::array<int, 3> foamCellsPerPeriod(const Vec3& cell, int tile);
constexpr int kMostFoamSeeds = 4096;  // a period's seeds: bounds the foam's memory and set-up

// The foam an infill's `voronoi_struts` lattice is: seeds in cubes of `cell` from `origin`,
// the node's default seed, jitter and tile.
NodePtr infillFoam(double cell, const Vec3& origin);

}  // namespace frep
