#include "frep/vector_trig.h"

#include <immintrin.h>

#include <algorithm>
#include <cmath>

// Every lane: k = round(x 2/pi) by adding and subtracting 1.5 2^52 (exact); r = x - k pi/2
// with pi/2 = kP1 + kP2 + kP3 (kP1 and kP2 have 33 significant bits, so k kP1 and k kP2 are
// exact and the first two subtractions cancel exactly); then sin r and cos r by their Taylor
// series to r^15 and r^16 (|r| <= pi/4 + 1e-16: the first term left out is below 5e-17 of the
// result), and the quadrant k mod 4 picks one and its sign. The two widths below are the same
// sequence of operations written with SSE2 and with AVX2 intrinsics; a test checks their bits
// agree on two million arguments.

namespace frep {
namespace vector_trig {

namespace {

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

// Lanes whose argument the reduction cannot take (too large, NaN, infinite) go to `fallback`.
void patchFallbacks(const double* a, std::size_t n, double* out, Fallback fallback) {
  for (std::size_t j = 0; j < n; ++j)
    if (!(std::abs(a[j]) <= kDirectLimit)) out[j] = fallback(a[j]);
}

// sin x and cos x (= sin(x + pi/2): the quadrant one further) from the same polynomials.
inline void twoLanes(__m128d x, __m128d* sinOut, __m128d* cosOut) {
  const __m128d t = _mm_add_pd(_mm_mul_pd(x, _mm_set1_pd(kTwoOverPi)), _mm_set1_pd(kRound));
  const __m128d k = _mm_sub_pd(t, _mm_set1_pd(kRound));
  __m128d r = _mm_sub_pd(x, _mm_mul_pd(k, _mm_set1_pd(kP1)));
  r = _mm_sub_pd(r, _mm_mul_pd(k, _mm_set1_pd(kP2)));
  r = _mm_sub_pd(r, _mm_mul_pd(k, _mm_set1_pd(kP3)));
  const __m128d z = _mm_mul_pd(r, r);
  __m128d ps = _mm_set1_pd(kS[6]);
  for (int i = 5; i >= 0; --i) ps = _mm_add_pd(_mm_mul_pd(ps, z), _mm_set1_pd(kS[i]));
  // r's sign bit: a no-op but at r = -0, where r + (-0 z) would give +0 (sin -0 = -0)
  const __m128d s =
      _mm_or_pd(_mm_add_pd(r, _mm_mul_pd(_mm_mul_pd(r, z), ps)), _mm_and_pd(r, _mm_set1_pd(-0.0)));
  __m128d pc = _mm_set1_pd(kC[6]);
  for (int i = 5; i >= 0; --i) pc = _mm_add_pd(_mm_mul_pd(pc, z), _mm_set1_pd(kC[i]));
  const __m128d c = _mm_add_pd(_mm_sub_pd(_mm_set1_pd(1.0), _mm_mul_pd(_mm_set1_pd(0.5), z)),
                               _mm_mul_pd(_mm_mul_pd(z, z), pc));
  for (int quarter = 0; quarter < 2; ++quarter) {
    const __m128i q = _mm_add_epi64(_mm_castpd_si128(t), _mm_set1_epi64x(quarter));
    const __m128d odd =
        _mm_castsi128_pd(_mm_sub_epi64(_mm_setzero_si128(), _mm_and_si128(q, _mm_set1_epi64x(1))));
    const __m128d sign = _mm_castsi128_pd(_mm_slli_epi64(_mm_and_si128(q, _mm_set1_epi64x(2)), 62));
    const __m128d v = _mm_xor_pd(_mm_or_pd(_mm_and_pd(odd, c), _mm_andnot_pd(odd, s)), sign);
    *(quarter == 0 ? sinOut : cosOut) =
        _mm_min_pd(_mm_max_pd(v, _mm_set1_pd(-1.0)), _mm_set1_pd(1.0));
  }
}

inline __m128d twoLanes(__m128d x, int quarter) {
  __m128d v[2];
  twoLanes(x, &v[0], &v[1]);
  return v[quarter];
}

void runTwoLanes(const double* a, std::size_t n, double* out, int quarter, Fallback fallback) {
  std::size_t j = 0;
  for (; j + 2 <= n; j += 2) _mm_storeu_pd(out + j, twoLanes(_mm_loadu_pd(a + j), quarter));
  if (j < n) out[j] = _mm_cvtsd_f64(twoLanes(_mm_set1_pd(a[j]), quarter));
  patchFallbacks(a, n, out, fallback);
}

__attribute__((target("avx2"))) inline void fourLanes(__m256d x, __m256d* sinOut, __m256d* cosOut) {
  const __m256d t =
      _mm256_add_pd(_mm256_mul_pd(x, _mm256_set1_pd(kTwoOverPi)), _mm256_set1_pd(kRound));
  const __m256d k = _mm256_sub_pd(t, _mm256_set1_pd(kRound));
  __m256d r = _mm256_sub_pd(x, _mm256_mul_pd(k, _mm256_set1_pd(kP1)));
  r = _mm256_sub_pd(r, _mm256_mul_pd(k, _mm256_set1_pd(kP2)));
  r = _mm256_sub_pd(r, _mm256_mul_pd(k, _mm256_set1_pd(kP3)));
  const __m256d z = _mm256_mul_pd(r, r);
  __m256d ps = _mm256_set1_pd(kS[6]);
  for (int i = 5; i >= 0; --i) ps = _mm256_add_pd(_mm256_mul_pd(ps, z), _mm256_set1_pd(kS[i]));
  const __m256d s = _mm256_or_pd(_mm256_add_pd(r, _mm256_mul_pd(_mm256_mul_pd(r, z), ps)),
                                 _mm256_and_pd(r, _mm256_set1_pd(-0.0)));
  __m256d pc = _mm256_set1_pd(kC[6]);
  for (int i = 5; i >= 0; --i) pc = _mm256_add_pd(_mm256_mul_pd(pc, z), _mm256_set1_pd(kC[i]));
  const __m256d c =
      _mm256_add_pd(_mm256_sub_pd(_mm256_set1_pd(1.0), _mm256_mul_pd(_mm256_set1_pd(0.5), z)),
                    _mm256_mul_pd(_mm256_mul_pd(z, z), pc));
  for (int quarter = 0; quarter < 2; ++quarter) {
    const __m256i q = _mm256_add_epi64(_mm256_castpd_si256(t), _mm256_set1_epi64x(quarter));
    const __m256d odd = _mm256_castsi256_pd(
        _mm256_sub_epi64(_mm256_setzero_si256(), _mm256_and_si256(q, _mm256_set1_epi64x(1))));
    const __m256d sign =
        _mm256_castsi256_pd(_mm256_slli_epi64(_mm256_and_si256(q, _mm256_set1_epi64x(2)), 62));
    const __m256d v =
        _mm256_xor_pd(_mm256_or_pd(_mm256_and_pd(odd, c), _mm256_andnot_pd(odd, s)), sign);
    *(quarter == 0 ? sinOut : cosOut) =
        _mm256_min_pd(_mm256_max_pd(v, _mm256_set1_pd(-1.0)), _mm256_set1_pd(1.0));
  }
}

__attribute__((target("avx2"))) inline __m256d fourLanes(__m256d x, int quarter) {
  __m256d v[2];
  fourLanes(x, &v[0], &v[1]);
  return v[quarter];
}

__attribute__((target("avx2"))) void runFourLanes(const double* a, std::size_t n, double* out,
                                                  int quarter, Fallback fallback) {
  std::size_t j = 0;
  for (; j + 4 <= n; j += 4) _mm256_storeu_pd(out + j, fourLanes(_mm256_loadu_pd(a + j), quarter));
  if (j < n) {
    double in[4] = {0.0, 0.0, 0.0, 0.0}, res[4];
    std::copy(a + j, a + n, in);
    _mm256_storeu_pd(res, fourLanes(_mm256_loadu_pd(in), quarter));
    std::copy(res, res + (n - j), out + j);
  }
  patchFallbacks(a, n, out, fallback);
}

void patchBoth(const double* a, std::size_t n, double* s, double* c, Fallback sinFallback,
               Fallback cosFallback) {
  patchFallbacks(a, n, s, sinFallback);
  patchFallbacks(a, n, c, cosFallback);
}

void runTwoLanesBoth(const double* a, std::size_t n, double* s, double* c) {
  std::size_t j = 0;
  for (; j + 2 <= n; j += 2) {
    __m128d vs, vc;
    twoLanes(_mm_loadu_pd(a + j), &vs, &vc);
    _mm_storeu_pd(s + j, vs);
    _mm_storeu_pd(c + j, vc);
  }
  if (j < n) {
    __m128d vs, vc;
    twoLanes(_mm_set1_pd(a[j]), &vs, &vc);
    s[j] = _mm_cvtsd_f64(vs);
    c[j] = _mm_cvtsd_f64(vc);
  }
}

__attribute__((target("avx2"))) void runFourLanesBoth(const double* a, std::size_t n, double* s,
                                                      double* c) {
  std::size_t j = 0;
  for (; j + 4 <= n; j += 4) {
    __m256d vs, vc;
    fourLanes(_mm256_loadu_pd(a + j), &vs, &vc);
    _mm256_storeu_pd(s + j, vs);
    _mm256_storeu_pd(c + j, vc);
  }
  if (j < n) runTwoLanesBoth(a + j, n - j, s + j, c + j);
}

}  // namespace

void sinCosTwoLanes(const double* a, std::size_t n, double* s, double* c, Fallback sinFallback,
                    Fallback cosFallback) {
  runTwoLanesBoth(a, n, s, c);
  patchBoth(a, n, s, c, sinFallback, cosFallback);
}
void sinCosFourLanes(const double* a, std::size_t n, double* s, double* c, Fallback sinFallback,
                     Fallback cosFallback) {
  runFourLanesBoth(a, n, s, c);
  patchBoth(a, n, s, c, sinFallback, cosFallback);
}

double sinOne(double a, Fallback fallback) {
  if (!(std::abs(a) <= kDirectLimit)) return fallback(a);
  return _mm_cvtsd_f64(twoLanes(_mm_set1_pd(a), 0));
}
double cosOne(double a, Fallback fallback) {
  if (!(std::abs(a) <= kDirectLimit)) return fallback(a);
  return _mm_cvtsd_f64(twoLanes(_mm_set1_pd(a), 1));
}
void sinCosOne(double a, double* s, double* c, Fallback sinFallback, Fallback cosFallback) {
  if (!(std::abs(a) <= kDirectLimit)) {
    *s = sinFallback(a);
    *c = cosFallback(a);
    return;
  }
  __m128d vs, vc;
  twoLanes(_mm_set1_pd(a), &vs, &vc);
  *s = _mm_cvtsd_f64(vs);
  *c = _mm_cvtsd_f64(vc);
}
void sinTwoLanes(const double* a, std::size_t n, double* out, Fallback fallback) {
  runTwoLanes(a, n, out, 0, fallback);
}
void cosTwoLanes(const double* a, std::size_t n, double* out, Fallback fallback) {
  runTwoLanes(a, n, out, 1, fallback);
}
void sinFourLanes(const double* a, std::size_t n, double* out, Fallback fallback) {
  runFourLanes(a, n, out, 0, fallback);
}
void cosFourLanes(const double* a, std::size_t n, double* out, Fallback fallback) {
  runFourLanes(a, n, out, 1, fallback);
}
bool hasFourLanes() {
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
}

}  // namespace vector_trig
}  // namespace frep
