// Tag tools (seed 003, A.5 and 5.1.2): selections of CVs by level, parameter region,
// movability, offset and along the parametric lines of a selection. Tags drive refine, zero
// offsets and the display; each returns CVs sorted, without repeats.
#pragma once

#include <vector>

#include "hspline/hspline.h"

namespace frep {

std::vector<HsCvRef> selectLevel(const HSpline& h, int level);
// The level's CVs whose reference parameter lies in [u0, u1] x [v0, v1] (periodic axes:
// the region may run across the seam, u0 > u1 meaning [u0, period) and [lo, u1]).
std::vector<HsCvRef> selectRegion(const HSpline& h, int level, double u0, double u1, double v0,
                                  double v1);
// "Tag Movable": every movable CV of the level; "Untag Fixed": keeps the movable ones of `among`.
std::vector<HsCvRef> selectMovable(const HSpline& h, int level);
std::vector<HsCvRef> keepMovable(const HSpline& h, const std::vector<HsCvRef>& among);
// "Tag along U" (the CVs with a selected CV's j on its level) and "along V" (same i).
std::vector<HsCvRef> selectAlongU(const HSpline& h, const std::vector<HsCvRef>& from);
std::vector<HsCvRef> selectAlongV(const HSpline& h, const std::vector<HsCvRef>& from);
// "Tag Neighbours": the selection and the up to 8 CVs around each of its CVs.
std::vector<HsCvRef> selectNeighbours(const HSpline& h, const std::vector<HsCvRef>& from);
// "Tag Non-Zero Offsets": CVs of levels >= 1 whose offset is not zero (level < 0: all levels).
std::vector<HsCvRef> selectNonZeroOffsets(const HSpline& h, int level = -1);

// Refines each level named in `cvs` around its CVs there (finest level first).
void refineSelection(HSpline& h, const std::vector<HsCvRef>& cvs);

}  // namespace frep
