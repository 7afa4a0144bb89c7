// SPDX-License-Identifier: MIT
#pragma once
/// @file FpTraps.h
/// Floating-point traps for the tests, switched on only around our own numerics.
///
/// In Debug builds on glibc, an FpTrapScope makes an invalid operation (a NaN from 0/0, inf - inf,
/// sqrt(-1), ...) or a division by zero raise SIGFPE where it happens, so a NaN in the core fails
/// loudly instead of spreading. Only around our code: Mesa's llvmpipe (and with it Coin's
/// rendering and the Qt viewer) computes with these exceptions masked on purpose and dies of
/// SIGFPE when they trap. The core test executable holds a scope for its whole run (it links
/// neither Coin nor Mesa); the others open one where they step a simulation.

#if !defined(NDEBUG) && defined(__GLIBC__)
#include <fenv.h>
#define BSDEFORM_FP_TRAPS_AVAILABLE 1
#else
#define BSDEFORM_FP_TRAPS_AVAILABLE 0
#endif

namespace bsdeform::test {

/// The exceptions a scope traps (FE_INVALID | FE_DIVBYZERO), 0 where traps are not available
/// (release builds, other C libraries).
#if BSDEFORM_FP_TRAPS_AVAILABLE
inline constexpr int kTrappedFpExceptions = FE_INVALID | FE_DIVBYZERO;
#else
inline constexpr int kTrappedFpExceptions = 0;
#endif

/// The exceptions that trap right now (0 without traps).
inline int enabledFpTraps() {
#if BSDEFORM_FP_TRAPS_AVAILABLE
  return fegetexcept();
#else
  return 0;
#endif
}

/// Enables kTrappedFpExceptions for its lifetime and restores the previous trap mask after.
class FpTrapScope {
 public:
  FpTrapScope() {
#if BSDEFORM_FP_TRAPS_AVAILABLE
    m_previous = fegetexcept();
    // a flag left raised by earlier (untrapped) code must not fire at our first instruction
    feclearexcept(kTrappedFpExceptions);
    feenableexcept(kTrappedFpExceptions);
#endif
  }
  ~FpTrapScope() {
#if BSDEFORM_FP_TRAPS_AVAILABLE
    fedisableexcept(kTrappedFpExceptions & ~m_previous);
#endif
  }
  FpTrapScope(const FpTrapScope&) = delete;
  FpTrapScope& operator=(const FpTrapScope&) = delete;

 private:
  [[maybe_unused]] int m_previous = 0;
};

}  // namespace bsdeform::test
