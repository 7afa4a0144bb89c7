// SPDX-License-Identifier: MIT
#pragma once
/// @file Multiversion.h
/// BSDEFORM_MULTIVERSION: compile a kernel for AVX2 and for the baseline x86-64 and pick one at
/// load time (GCC's target_clones). The core is built with -ffp-contract=off, so every clone
/// rounds alike. Private to the core's .cpp files.

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define BSDEFORM_MULTIVERSION __attribute__((target_clones("avx2", "default")))
#else
#define BSDEFORM_MULTIVERSION
#endif
