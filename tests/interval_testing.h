// Checks for rigorous intervals: an end point is right when it encloses the exact value and
// lies within a few ulps of it (outward rounding widens every result a little).
#pragma once

#include <cmath>
#include <limits>

#include "frep/interval.h"

namespace frep::testing {

inline bool tightBelow(double bound, double exact, int ulps = 8) {
  double v = exact;
  for (int i = 0; i < ulps; ++i) v = std::nextafter(v, -std::numeric_limits<double>::infinity());
  return bound <= exact && bound >= v;
}
inline bool tightAbove(double bound, double exact, int ulps = 8) {
  double v = exact;
  for (int i = 0; i < ulps; ++i) v = std::nextafter(v, std::numeric_limits<double>::infinity());
  return bound >= exact && bound <= v;
}
// [lo, hi] encloses [exactLo, exactHi] within a few ulps on each side.
inline bool tightly(const Interval& iv, double exactLo, double exactHi) {
  return tightBelow(iv.lo, exactLo) && tightAbove(iv.hi, exactHi);
}

}  // namespace frep::testing
