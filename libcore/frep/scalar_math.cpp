// sin and cos for every evaluation mode (scalar_math.h). The gyroid and the other lattices
// are sums of products of sines and cosines: glibc's scalar sin took 9.7 ns here, half of
// meshing a gyroid; its vector library (libmvec) 2.4 ns a value two at a time with SSE (0.8 ns
// with AVX2, but its results differ from the SSE ones in the last bits, and a model must
// evaluate to the same bits on every x86-64 processor). So the lanes run our own
// reduction and polynomials (frep/vector_trig.h), which give the same bits at every width, four
// at a time where the processor has AVX2; libmvec's SSE functions take the arguments beyond
// vector_trig::kDirectLimit. Within 5 ulps of glibc's scalar functions (tests/test_field.cpp).
#include "frep/scalar_math.h"

#include <algorithm>

#if defined(__x86_64__) && defined(__GLIBC__)
#include <emmintrin.h>
extern "C" __m128d _ZGVbN2v_sin(__m128d);
extern "C" __m128d _ZGVbN2v_cos(__m128d);
#define FREP_LIBMVEC 1
#include "frep/vector_trig.h"
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
#endif

}  // namespace

#ifdef FREP_LIBMVEC
void sinCos(double a, double* s, double* c) {
  vector_trig::sinCosOne(a, s, c, one<_ZGVbN2v_sin>, one<_ZGVbN2v_cos>);
}
double sin(double a) {
  double s, c;
  sinCos(a, &s, &c);
  return s;
}
double cos(double a) {
  double s, c;
  sinCos(a, &s, &c);
  return c;
}
void sinCosMany(const double* a, std::size_t n, double* s, double* c) {
  vector_trig::sinCosLanes(vector_trig::widestLanes(), a, n, s, c, one<_ZGVbN2v_sin>,
                           one<_ZGVbN2v_cos>);
}
#else
void sinCosMany(const double* a, std::size_t n, double* s, double* c) {
  for (std::size_t j = 0; j < n; ++j) {
    if (s) s[j] = sin(a[j]);
    if (c) c[j] = cos(a[j]);
  }
}
void sinCos(double a, double* s, double* c) {
  *s = sin(a);
  *c = cos(a);
}
double sin(double a) {
  return clampUnit(std::sin(a));
}
double cos(double a) {
  return clampUnit(std::cos(a));
}
#endif

}  // namespace frep
