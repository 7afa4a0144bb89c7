// SPDX-License-Identifier: MIT
#pragma once
/// @file Multiversion.h
/// BSDEFORM_MULTIVERSION: compile a kernel for AVX2 and for the baseline x86-64 and pick one at
/// load time (GCC's target_clones). The core is built with -ffp-contract=off, so every clone
/// rounds alike. Private to the core's .cpp files.
///
/// simd::v4: four doubles, written with GCC/Clang vector extensions so that row kernels vectorise
/// for certain (AVX2 in the avx2 clone, two SSE2 registers in the default one). The helpers are
/// forced inline so that each CPU-specific clone compiles them for its own ISA.

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define BSDEFORM_MULTIVERSION __attribute__((target_clones("avx2", "default")))
#else
#define BSDEFORM_MULTIVERSION
#endif

#define BSDEFORM_INLINE inline __attribute__((always_inline))

namespace bsdeform::simd {
typedef double v4 __attribute__((vector_size(32), aligned(8), may_alias));
typedef long long v4i __attribute__((vector_size(32)));
BSDEFORM_INLINE v4 load4(const double* p) { return *reinterpret_cast<const v4*>(p); }
BSDEFORM_INLINE void store4(double* p, v4 x) { *reinterpret_cast<v4*>(p) = x; }
BSDEFORM_INLINE v4 splat(double x) { return v4{x, x, x, x}; }
}  // namespace bsdeform::simd
