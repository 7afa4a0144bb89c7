// SPDX-License-Identifier: MIT
// Each test program's main; Catch2's implementation is support/CatchRunner.cpp, compiled once.
#include "support/CatchRunner.h"
#include "support/FpTraps.h"

int main(int argc, char* argv[]) {
#ifdef BSDEFORM_TESTS_TRAP_FP_WHOLE_RUN
  // The core tests run only our numerics: in Debug builds a NaN or a division by zero anywhere
  // in them raises SIGFPE. The executables that render or open windows (Coin, Mesa, Qt) trap only
  // inside an FpTrapScope around our own code (support/FpTraps.h says why).
  bsdeform::test::FpTrapScope traps;
#endif
  return bsdeform::test::runCatch(argc, argv);
}
