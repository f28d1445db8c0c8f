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

// sin a (cos a) alone: the first lane of the two-lane code with a in both lanes, so the same
// bits as in a batch (the point and gradient modes).
double sinOne(double a, Fallback fallback);
double cosOne(double a, Fallback fallback);
// Both at once (the gradient mode needs both): one lane each, the same bits as above.
void sinCosOne(double a, double* s, double* c, Fallback sinFallback, Fallback cosFallback);
// out[j] = sin(a[j]) (cos) for j < n, two lanes at a time.
void sinTwoLanes(const double* a, std::size_t n, double* out, Fallback fallback);
void cosTwoLanes(const double* a, std::size_t n, double* out, Fallback fallback);
// The same four lanes at a time; only where hasFourLanes().
void sinFourLanes(const double* a, std::size_t n, double* out, Fallback fallback);
void cosFourLanes(const double* a, std::size_t n, double* out, Fallback fallback);
bool hasFourLanes();
// s[j] = sin(a[j]) and c[j] = cos(a[j]) in one pass, the same bits as the two apart (the
// lattices take both of the same argument). `a` must be neither `s` nor `c`.
void sinCosTwoLanes(const double* a, std::size_t n, double* s, double* c, Fallback sinFallback,
                    Fallback cosFallback);
void sinCosFourLanes(const double* a, std::size_t n, double* s, double* c, Fallback sinFallback,
                     Fallback cosFallback);

}  // namespace vector_trig
}  // namespace frep
