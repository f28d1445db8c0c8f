#include "mesh/hidden_parts.h"

#include <cmath>

namespace frep {

bool tentCrossesZero(double before, double a, double b, double after, double* t) {
  // Seen from outside (a, b < 0) the tent rises towards the edge from both sides; from
  // inside (a, b >= 0) it falls. Flipping the signs of an inside edge's values makes both
  // cases the first (comparisons with NaN are false: no tent).
  if (std::isnan(a) || std::isnan(b)) return false;
  const bool inside = a >= 0.0;
  if (inside != (b >= 0.0)) return false;
  const double s = inside ? -1.0 : 1.0;
  const double fa = s * a, fb = s * b, riseA = fa - s * before, riseB = fb - s * after;
  if (!(riseA > 0.0) || !(riseB > 0.0)) return false;
  // fa + riseA t = fb + riseB (1 - t)
  const double at = (fb + riseB - fa) / (riseA + riseB);
  if (!(at > 0.0 && at < 1.0)) return false;
  const double peak = fa + riseA * at;
  // outside: the tent must reach zero (inside is >= 0); inside: it must go below it
  if (inside ? !(peak > 0.0) : !(peak >= 0.0)) return false;
  *t = at;
  return true;
}

// On x86-64 an AVX2 clone too, chosen when the processor has it (GCC's ifunc dispatch): four
// values a step instead of SSE2's two.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
bool sieveTentRow(const double* __restrict beforeRow, const double* __restrict aRow,
                  const double* __restrict bRow, const double* __restrict afterRow,
                  std::int64_t count, double* __restrict flags) {
  std::int64_t flagged = 0;  // (an integer or: a sum of doubles would not run in lanes)
  for (std::int64_t i = 0; i < count; ++i) {
    const double before = beforeRow[i], a = aRow[i], b = bRow[i], after = afterRow[i];
    const double riseBefore = a - before, riseAfter = b - after;
    const double crossBefore = 2.0 * a - before, crossAfter = 2.0 * b - after;
    const double high = a > b ? a : b, low = a < b ? a : b;
    const double leastRise = riseBefore < riseAfter ? riseBefore : riseAfter;
    const double mostRise = riseBefore > riseAfter ? riseBefore : riseAfter;
    const double leastCross = crossBefore < crossAfter ? crossBefore : crossAfter;
    const double mostCross = crossBefore > crossAfter ? crossBefore : crossAfter;
    // (products of 0 / 1 factors, not && : no branch. NaN compares false everywhere: 0.)
    const double outside =
        (high < 0.0 ? 1.0 : 0.0) * (leastRise > 0.0 ? 1.0 : 0.0) * (leastCross >= 0.0 ? 1.0 : 0.0);
    const double inside =
        (low >= 0.0 ? 1.0 : 0.0) * (mostRise < 0.0 ? 1.0 : 0.0) * (mostCross < 0.0 ? 1.0 : 0.0);
    flags[i] = outside + inside;
    flagged |= static_cast<std::int64_t>(outside + inside > 0.0);
  }
  return flagged != 0;
}

}  // namespace frep
