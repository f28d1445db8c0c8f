// sin and cos for every evaluation mode (scalar_math.h). The gyroid and the other lattices
// are sums of products of sines and cosines: glibc's scalar sin took 9.7 ns here, half of
// meshing a gyroid; its vector library (libmvec) takes 2.4 ns a value two at a time with SSE
// (0.8 ns with AVX2, not used: its results differ from the SSE ones in the last bits, and a
// model must evaluate to the same bits on every x86-64 processor). Measured within 3 ulps of
// the scalar functions on 2^20 arguments; glibc documents 4 ulps from the exact value.
#include "frep/scalar_math.h"

#include <algorithm>

#if defined(__x86_64__) && defined(__GLIBC__)
#include <emmintrin.h>
extern "C" __m128d _ZGVbN2v_sin(__m128d);
extern "C" __m128d _ZGVbN2v_cos(__m128d);
#define FREP_LIBMVEC 1
#endif

namespace frep {

namespace {

inline double clampUnit(double v) {
  return std::min(1.0, std::max(-1.0, v));
}  // (NaN stays)

#ifdef FREP_LIBMVEC
template <__m128d (*F)(__m128d)>
inline double one(double a) {
  double r[2];
  _mm_storeu_pd(r, F(_mm_set1_pd(a)));
  return clampUnit(r[0]);
}
template <__m128d (*F)(__m128d)>
inline void many(const double* a, std::size_t n, double* out) {
  std::size_t j = 0;
  for (; j + 2 <= n; j += 2) {
    double r[2];
    _mm_storeu_pd(r, F(_mm_loadu_pd(a + j)));
    out[j] = clampUnit(r[0]);
    out[j + 1] = clampUnit(r[1]);
  }
  if (j < n) out[j] = one<F>(a[j]);
}
#endif

}  // namespace

#ifdef FREP_LIBMVEC
double sin(double a) {
  return one<_ZGVbN2v_sin>(a);
}
double cos(double a) {
  return one<_ZGVbN2v_cos>(a);
}
void sinMany(const double* a, std::size_t n, double* out) {
  many<_ZGVbN2v_sin>(a, n, out);
}
void cosMany(const double* a, std::size_t n, double* out) {
  many<_ZGVbN2v_cos>(a, n, out);
}
#else
double sin(double a) {
  return clampUnit(std::sin(a));
}
double cos(double a) {
  return clampUnit(std::cos(a));
}
void sinMany(const double* a, std::size_t n, double* out) {
  for (std::size_t j = 0; j < n; ++j) out[j] = sin(a[j]);
}
void cosMany(const double* a, std::size_t n, double* out) {
  for (std::size_t j = 0; j < n; ++j) out[j] = cos(a[j]);
}
#endif

}  // namespace frep
