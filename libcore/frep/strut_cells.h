// The unit cells of strut (beam) lattices and the struts one point needs: the pieces of the
// periodic strut network that lie in the small domain a point is folded into. The strut
// lattice node (node_types_struts.cpp) compiles these pieces into the field; the tests compare
// the field with the distance to every strut of many cells (brute force).
#pragma once

#include <string>
#include <vector>

#include "base/vec.h"

namespace frep {

// A strut of one cell, in cell coordinates (the cell is [0, 1]^3); the lattice is its copies
// moved by every integer vector. A strut may reach out of the cell (it is then also another
// cell's copy: each strut of the lattice is listed once).
struct UnitStrut {
  Vec3 a, b;
};

struct UnitCell {
  std::string id;   // "simple_cubic", "bcc", ...
  std::string doc;  // one line for the node reference
  std::vector<UnitStrut> struts;
  std::vector<Vec3> nodes;  // where struts meet, in the cell (their copies by integer vectors)
  // Mirror symmetric in the planes x = k / 2, y = k / 2, z = k / 2 (k integer): the point is
  // then folded into [0, 1/2]^3 and only the struts there count (the distance to a set
  // symmetric in a plane is the distance to its part on the point's side, the other part
  // mirrored). Without it (diamond) the point is folded into the cell by translation only and
  // the struts within the network's covering radius of the cell count.
  bool mirrorSymmetric = true;
  // Else, whether the mirrors x = +-y, y = +-z and x = +-z through the origin are symmetries
  // (diamond, whose origin is a node): with a cube cell the point is then folded into one
  // 24th of the cell round it as well.
  bool tetrahedral = false;
};

// Every unit cell, in the order the node's choice lists them.
const std::vector<UnitCell>& unitCells();
const UnitCell& unitCell(const std::string& id);  // throws ModelError naming the id

// A segment [a, b] of the network in world units (a == b: a point).
struct StrutPiece {
  Vec3 a, b;
};

// What a point of the lattice with this cell (sizes per axis) needs, in the coordinates of its
// folded point: the pieces of struts in the fold domain and the nodes there. With blend > 0
// (smooth joints) every strut within the covering radius plus the blend of the cell, folded
// by translation only: a smooth minimum needs each strut near the point, not its nearest.
struct FoldedCell {
  enum class Fold {
    Mirror,       // into [0, c / 2] by the axes' mirrors
    Translate,    // into [0, c) by translation (the struts within the covering radius)
    Tetrahedral,  // into [-c / 2, c / 2] by translation, then into x >= y >= |z| by the
                  // mirrors through a node (x = +-y, y = +-z, x = +-z: a cube cell's diamond)
  };
  Fold fold = Fold::Mirror;
  std::vector<StrutPiece> pieces;
  std::vector<Vec3> nodes;
};
FoldedCell foldedCell(const UnitCell& cell, const Vec3& size, double blend = 0.0);

// Every strut of the lattice (cells of `size` from `origin`) whose segment's box meets `box`,
// each once, unclipped: what a beam lattice file lists.
std::vector<StrutPiece> strutsInBox(const UnitCell& cell, const Vec3& size, const Vec3& origin,
                                    const Box3& box);

// The part of [a, b] in the closed box [lo, hi] (bounds may be infinite) and the half-spaces
// n . p >= 0 (Liang and Barsky), its ends a and b themselves where they are in; false where
// none.
bool clip(const Vec3& a, const Vec3& b, const Vec3& lo, const Vec3& hi, StrutPiece* piece,
          const std::vector<Vec3>& halfSpaces = {});

// The distance from p to the segment [a, b].
double distanceToSegment(const Vec3& p, const Vec3& a, const Vec3& b);

// The largest distance from a point to the nearest strut of the unit cell's network (cell
// size 1), from a fine sample and a margin for what the sample misses: how far round the cell
// a translation-folded point must look.
double coveringRadius(const UnitCell& cell);

}  // namespace frep
