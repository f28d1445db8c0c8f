#include "frep/vector_trig.h"

#include <cmath>
#include <cstdint>
#include <cstring>

// Every lane: k = round(x 2/pi) by adding and subtracting 1.5 2^52 (exact); r = x - k pi/2
// with pi/2 = kP1 + kP2 + kP3 (kP1 and kP2 have 33 significant bits, so k kP1 and k kP2 are
// exact and the first two subtractions cancel exactly); then sin r and cos r by their Taylor
// series to r^15 and r^16 (|r| <= pi/4 + 1e-16: the first term left out is below 5e-17 of the
// result), and the quadrant k mod 4 picks one and its sign. One kernel, written on GCC's
// vector types, serves both widths: inlined into a function built for SSE2 it runs two lanes,
// into one built for AVX2 four, with the same IEEE operations lane by lane (a test checks the
// bits agree on two million arguments).

namespace frep {
namespace vector_trig {

namespace {

typedef double Lanes2 __attribute__((vector_size(16)));
typedef std::int64_t Ints2 __attribute__((vector_size(16)));
typedef double Lanes4 __attribute__((vector_size(32)));
typedef std::int64_t Ints4 __attribute__((vector_size(32)));

constexpr double kTwoOverPi = 0.6366197723675814;
constexpr double kRound = 6755399441055744.0;  // 1.5 2^52
constexpr double kP1 = 1.5707963267341256;     // 0x1.921fb544p+0
constexpr double kP2 = 6.077100506303966e-11;  // 0x1.0b4611a6p-34
constexpr double kP3 = 2.0222662487959506e-21;
// (-1)^i / (2i + 1)! for i = 1 .. 7 and (-1)^i / (2i)! for i = 2 .. 8.
constexpr double kS[7] = {
    -1.0 / 6.0,        1.0 / 120.0,        -1.0 / 5040.0,         1.0 / 362880.0,
    -1.0 / 39916800.0, 1.0 / 6227020800.0, -1.0 / 1307674368000.0};
constexpr double kC[7] = {
    1.0 / 24.0,        -1.0 / 720.0,         1.0 / 40320.0,         -1.0 / 3628800.0,
    1.0 / 479001600.0, -1.0 / 87178291200.0, 1.0 / 20922789888000.0};

// sin x and cos x (= sin(x + pi/2): the quadrant one further) from the same polynomials.
template <class V, class I>
__attribute__((always_inline)) inline void lanes(V x, V* sinOut, V* cosOut) {
  const V t = x * kTwoOverPi + kRound;
  const V k = t - kRound;
  const V r = ((x - k * kP1) - k * kP2) - k * kP3;
  const V z = r * r;
  V ps = V{} + kS[6];
  for (int i = 5; i >= 0; --i) ps = ps * z + kS[i];
  // r's sign bit: a no-op but at r = -0, where r + (-0 z) would give +0 (sin -0 = -0)
  const V s = (V)((I)(r + r * z * ps) | ((I)r & (I)(-V{})));
  V pc = V{} + kC[6];
  for (int i = 5; i >= 0; --i) pc = pc * z + kC[i];
  const V c = (1.0 - 0.5 * z) + z * z * pc;
  for (int quarter = 0; quarter < 2; ++quarter) {
    const I q = (I)t + quarter;
    const I odd = -(q & 1);        // all ones where the quadrant is odd: cos r
    const I sign = (q & 2) << 62;  // quadrants 2 and 3: negated
    const V v = (V)((((I)c & odd) | ((I)s & ~odd)) ^ sign);
    const V clamped = v < -1.0 ? V{} - 1.0 : v > 1.0 ? V{} + 1.0 : v;
    *(quarter == 0 ? sinOut : cosOut) = clamped;
  }
}

// Lanes whose argument the reduction cannot take (too large, NaN, infinite) go to `fallback`.
void patchFallbacks(const double* a, std::size_t n, double* out, Fallback fallback) {
  for (std::size_t j = 0; j < n; ++j)
    if (!(std::abs(a[j]) <= kDirectLimit)) out[j] = fallback(a[j]);
}

// sin (s) and cos (c) of a[0 .. n), either may be null (not wanted), W lanes at a time; the
// last few values go through a padded block. Returns whether any argument is beyond the
// direct limit or not finite (kept as a lane mask while running: a pass of its own to find
// them cost a quarter of the whole).
template <class V, class I>
__attribute__((always_inline)) inline bool run(const double* a, std::size_t n, double* s,
                                               double* c) {
  constexpr std::size_t W = sizeof(V) / sizeof(double);
  I beyond{};
  auto block = [&](std::size_t j, std::size_t m) {
    V x{}, vs, vc;
    std::memcpy(&x, a + j, m * sizeof(double));
    lanes<V, I>(x, &vs, &vc);
    const V magnitude = (V)((I)x & ~(I)(-V{}));
    beyond |= ~(magnitude <= kDirectLimit);  // (NaN compares false)
    if (s) std::memcpy(s + j, &vs, m * sizeof(double));
    if (c) std::memcpy(c + j, &vc, m * sizeof(double));
  };
  std::size_t j = 0;
  for (; j + W <= n; j += W) block(j, W);  // a constant size: one load, two stores
  if (j < n) block(j, n - j);
  for (std::size_t l = 0; l < W; ++l)
    if (beyond[l]) return true;
  return false;
}

bool runTwo(const double* a, std::size_t n, double* s, double* c) {
  return run<Lanes2, Ints2>(a, n, s, c);
}
__attribute__((target("avx2"))) bool runFour(const double* a, std::size_t n, double* s, double* c) {
  return run<Lanes4, Ints4>(a, n, s, c);
}

}  // namespace

void sinCosOne(double a, double* s, double* c, Fallback sinFallback, Fallback cosFallback) {
  if (!(std::abs(a) <= kDirectLimit)) {
    *s = sinFallback(a);
    *c = cosFallback(a);
    return;
  }
  Lanes2 vs, vc;
  lanes<Lanes2, Ints2>(Lanes2{a, a}, &vs, &vc);
  *s = vs[0];
  *c = vc[0];
}
void sinCosLanes(int width, const double* a, std::size_t n, double* s, double* c,
                 Fallback sinFallback, Fallback cosFallback) {
  const bool beyond = width == 4 ? runFour(a, n, s, c) : runTwo(a, n, s, c);
  if (!beyond) return;
  if (s) patchFallbacks(a, n, s, sinFallback);
  if (c) patchFallbacks(a, n, c, cosFallback);
}
int widestLanes() {
  // (Eight lanes with AVX-512 were measured too: the gyroid meshed no faster.)
  static const int widest = __builtin_cpu_supports("avx2") ? 4 : 2;
  return widest;
}

}  // namespace vector_trig
}  // namespace frep
