// SPDX-License-Identifier: MIT
// The kernels' thread pool (bsdeform/Parallel.h): every part runs exactly once, whichever thread
// takes it, for back-to-back jobs (the pool's spinning hand-over) and for calls from several
// threads at once (one of them gets the pool, the others run their parts themselves).
#include <atomic>
#include <catch2/catch.hpp>
#include <thread>
#include <vector>

#include "bsdeform/Parallel.h"

using namespace bsdeform;

TEST_CASE("Parallel: every part runs once, job after job and from several threads", "[core]") {
  const int threads = kernelThreads();
  for (int t : {1, 2, 3}) {
    setKernelThreads(t);
    INFO(t << " threads");
    auto jobs = [](int seed, int count) {
      bool ok = true;
      for (int j = 0; j < count; ++j) {
        const int parts = 1 + (seed + j) % 9;
        std::vector<std::atomic<int>> runs(static_cast<size_t>(parts));
        for (auto& r : runs) r = 0;
        runParts(parts, [&](int p) { runs[size_t(p)].fetch_add(1); });
        for (auto& r : runs) ok &= r.load() == 1;
      }
      return ok;
    };
    CHECK(jobs(0, 2000));
    bool okA = false, okB = false;
    std::thread other([&] { okB = jobs(5, 500); });
    okA = jobs(3, 500);
    other.join();
    CHECK(okA);
    CHECK(okB);
    // a part that starts a job of its own runs that job on its own thread
    std::atomic<int> inner{0};
    runParts(4, [&](int) { runParts(3, [&](int) { inner.fetch_add(1); }); });
    CHECK(inner.load() == 12);
  }
  setKernelThreads(threads);
}
