// A stochastic Voronoi foam: the edges of the Voronoi diagram of random seeds, one seed
// jittered in each cell of a grid, repeated with a period of `tile` times the cell's longest
// side along each axis (more cells along a shorter side), so that the network, and the field
// holding it, stay the same size for a lattice of any extent.
// CGAL's Delaunay triangulation finds the edges (each the dual of a Delaunay facet: the
// segment between the circumcentres of the two tetrahedra on it).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "frep/periodic_segments.h"
#include "frep/tree.h"

namespace frep {

struct VoronoiFoamSettings {
  Vec3 cell{1, 1, 1};  // the grid the seeds are jittered in: one seed per cell
  Vec3 origin{0, 0, 0};
  std::uint64_t seed = 1;
  double jitter = 1.0;  // 0: seeds at the cells' centres; 1: anywhere in their cells
  int tile = 5;         // the period in the cell's longest side
  double blend = 0.0;   // the joints' rounding (PeriodicSegmentsField)
};

struct VoronoiFoamNetwork {
  std::vector<Vec3> seeds;        // the tile's seeds
  std::vector<StrutPiece> edges;  // each edge of the periodic diagram once, starting in the tile
  std::vector<Vec3> nodes;        // each vertex once, in the tile
  Vec3 period{0, 0, 0};
  std::array<int, 3> cells{0, 0, 0};  // cells per period along each axis
};

// The same settings give the same foam on every machine (the random numbers are ours, not a
// standard library's distribution).
VoronoiFoamNetwork voronoiFoamNetwork(const VoronoiFoamSettings& s);

// The voronoi_foam node's settings, and its network as a field (a PeriodicNetworkField; the
// node's loader, volume/field_sources.cpp, keeps the recent ones). Throws ModelError naming
// 'tile' when the period is too short for the foam's struts.
VoronoiFoamSettings voronoiFoamSettings(const Node& node);
std::shared_ptr<const Field> makeVoronoiFoam(const VoronoiFoamSettings& s);

}  // namespace frep
