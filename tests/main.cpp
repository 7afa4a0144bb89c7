// SPDX-License-Identifier: MIT
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#if !defined(NDEBUG) && defined(__linux__)
#include <fenv.h>
#endif

int main(int argc, char* argv[]) {
#if !defined(NDEBUG) && defined(__linux__)
  // Debug builds: a NaN or overflow anywhere in the numerics fails loudly.
  feenableexcept(FE_INVALID | FE_DIVBYZERO);
#endif
  return Catch::Session().run(argc, argv);
}
