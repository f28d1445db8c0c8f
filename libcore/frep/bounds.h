// Where is a solid? The tight axis-aligned box of {F >= 0}, found from the compiled program
// alone by interval arithmetic: the automatic bounding box of the workbench's previews and
// Polygonize features, and how "empty" and "unbounded" results are detected.
#pragma once

#include <cstddef>
#include <limits>

#include "frep/field.h"
#include "base/vec.h"

namespace frep {

struct BoundsOptions {
  // The region searched. A solid reaching its boundary is reported unbounded on that side.
  Box3 search{{-1e6, -1e6, -1e6}, {1e6, 1e6, 1e6}};
  // Each side of the result is within this distance outside the true extent (never inside,
  // as far as interval arithmetic is conservative).
  double tolerance = 1e-4;
  // Interval evaluations allowed per side; past it the bound found so far (still
  // conservative, only looser) is returned.
  std::size_t maxEvaluations = 20000;
  // A box the solid is known to lie in (structuralBounds): its finite sides narrow the search
  // and are never reported unbounded, where intervals alone may not prove the far side empty.
  Box3 known = {{-kNoBound, -kNoBound, -kNoBound}, {kNoBound, kNoBound, kNoBound}};
  static constexpr double kNoBound = std::numeric_limits<double>::infinity();
};

struct SolidBounds {
  bool empty = false;         // no point of the search box can be inside
  bool unbounded[3][2] = {};  // [axis][0 = low side, 1 = high side] reaches the search box
  Box3 box;                   // valid unless empty; unbounded sides hold the search box
  bool bounded() const;
};

// Best-first branch and bound per side: the cell reaching furthest in that direction is split
// until it is tolerance-thin or proven outside (interval upper bound < 0).
SolidBounds findBounds(const Field& program, const BoundsOptions& options = {});

}  // namespace frep
