// Strut lattices and foams under an `ffd` node with struts = straight: each strut in the
// FFD's rest box, cut to it, becomes the straight segment between the images of its ends, so
// the cells follow the deformation while every strut stays straight (as a printer and a 3MF
// beam lattice hold them). The field is radius - the exact distance to those segments, found in
// the world among the few binned segments near the point (an unrepeated PeriodicSegmentsField):
// no inverse map per point, unlike the curved struts' pullback.
#pragma once

#include <memory>
#include <vector>

#include "base/vec.h"
#include "frep/strut_cells.h"
#include "frep/tree.h"

namespace frep {

class FfdLattice;
class PeriodicSegmentsField;

// A strut_lattice or voronoi_foam node: what struts = straight straightens.
bool isStrutNetwork(const Node& node);

// The most struts a rest box may hold for straight struts: each is kept in memory, with its
// bins about 750 bytes (an octet cell's 24 struts about 18 kB), so at most about 400 MB.
constexpr double kMostStraightStruts = 5e5;
// About how many struts of the network lie in `rest` (counted from its cells, before any
// is made): what the check compares with kMostStraightStruts.
double strutCountEstimate(const Node& network, const Box3& rest);

// The network's struts in the rest box, each cut to it (in the rest box's coordinates).
std::vector<StrutPiece> strutsInRest(const Node& network, const Box3& rest);
// The network's nodes (where struts meet) in the rest box.
std::vector<Vec3> strutNodesInRest(const Node& network, const Box3& rest);

// The distances to the straight struts and to the images of the nodes (null without node
// spheres) of `network` bent by `bend`. The last one made is kept: a recompute that changes
// neither costs nothing.
struct StraightStrutFields {
  std::shared_ptr<const PeriodicSegmentsField> struts, nodes;
};
StraightStrutFields straightStrutFields(const Node& network, const FfdLattice& bend);

}  // namespace frep
