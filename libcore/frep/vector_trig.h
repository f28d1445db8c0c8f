// sin and cos of many arguments at once, two lanes (SSE2, every x86-64 processor) or four
// (AVX2 where the processor has it), giving the same bits either way: the reduction by pi/2
// and the polynomials use only IEEE additions, subtractions and multiplications (no fused
// multiply-add: the project builds with -ffp-contract=off and the AVX2 code asks for no FMA),
// each correctly rounded whatever the vector width. glibc's vector library is 2.4 ns a value
// with SSE and its AVX2 variant differs from it in the last bits, so a model would evaluate
// differently on different processors (docs/architecture.md, "Decisions").
//
// Arguments beyond kDirectLimit in magnitude, and non-finite ones, are left to `fallback`
// (scalar_math.cpp passes glibc's SSE functions, the same bits on every x86-64 processor).
#pragma once

#include <cstddef>

namespace frep {
namespace vector_trig {

// The reduction k pi/2 with pi/2 in three parts (33, 33 and 53 bits) is exact in its first two
// products for |k| < 2^20; this bound keeps k under 2^17.
constexpr double kDirectLimit = 1e5;

using Fallback = double (*)(double);

// sin a and cos a: the first lane of the two-lane code with a in both lanes, so the same bits
// as in a batch (the point and gradient modes).
void sinCosOne(double a, double* s, double* c, Fallback sinFallback, Fallback cosFallback);
// s[j] = sin(a[j]) and c[j] = cos(a[j]) for j < n, `width` lanes at a time (2, or 4 where
// widestLanes() allows it); s or c may be null (not wanted), the other's bits are the same
// either way, and the same whatever the width. `a` must be neither `s` nor `c`.
void sinCosLanes(int width, const double* a, std::size_t n, double* s, double* c,
                 Fallback sinFallback, Fallback cosFallback);
// The most lanes this processor runs: 4 (AVX2) or 2.
int widestLanes();

}  // namespace vector_trig
}  // namespace frep
