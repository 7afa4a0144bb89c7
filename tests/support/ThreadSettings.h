// SPDX-License-Identifier: MIT
#pragma once
// Puts back the core's thread settings (bsdeform/base/Parallel.h, StiffnessStencil.h) when a test
// leaves, passed or not: kernel threads, the split threshold, the background thread (which also
// ends a back-off the test may have started).
#include "bsdeform/base/Parallel.h"
#include "bsdeform/energy/StiffnessStencil.h"

struct ThreadSettingsGuard {
  int threads = bsdeform::kernelThreads();
  long minPoints = bsdeform::explicitParallelMinPoints();
  bool background = bsdeform::backgroundThreadEnabled();
  ~ThreadSettingsGuard() {
    bsdeform::setKernelThreads(threads);
    bsdeform::setExplicitParallelMinPoints(minPoints);
    bsdeform::setBackgroundThreadEnabled(background);
  }
};
