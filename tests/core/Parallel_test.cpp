// SPDX-License-Identifier: MIT
// The kernels' thread pool (bsdeform/base/Parallel.h): every part runs exactly once, whichever thread
// takes it, for back-to-back jobs (the pool's spinning hand-over) and for calls from several
// threads at once (one of them gets the pool, the others run their parts themselves); and the
// background thread of BackgroundWork.
#include <dlfcn.h>

#include <atomic>
#include <chrono>
#include <catch2/catch.hpp>
#include <thread>
#include <vector>

#include "../support/Skip.h"
#include "../support/ThreadSettings.h"
#include "bsdeform/base/Parallel.h"

using namespace bsdeform;

TEST_CASE("Parallel: every part runs once, job after job and from several threads", "[core]") {
  ThreadSettingsGuard guard;
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
}

TEST_CASE("BackgroundWork: every part runs once, on either thread, work after work", "[core]") {
  ThreadSettingsGuard guard;
  for (bool enabled : {false, true}) {
    setBackgroundThreadEnabled(enabled);
    INFO("background thread " << (enabled ? "on" : "off"));
    bool ok = true;
    long beside = 0;
    for (int w = 0; w < 3000; ++w) {
      const int parts = w % 7;  // 0 parts too
      std::vector<std::atomic<int>> runs(static_cast<size_t>(parts));
      for (auto& r : runs) r = 0;
      BackgroundWork work(parts, [&](int p) { runs[size_t(p)].fetch_add(1); });
      if (w % 3 == 0) work.finish();
      work.finish();  // twice: the second does nothing
      for (auto& r : runs) ok &= r.load() == 1;
      beside += work.partsRunBeside();
    }
    CHECK(ok);
    if (!enabled) CHECK(beside == 0);
  }
  // works from several threads at once share the one background thread
  setBackgroundThreadEnabled(true);
  auto works = [](int count) {
    bool ok = true;
    for (int w = 0; w < count; ++w) {
      std::vector<std::atomic<int>> runs(5);
      for (auto& r : runs) r = 0;
      { BackgroundWork work(5, [&](int p) { runs[size_t(p)].fetch_add(1); }); }  // the destructor finishes
      for (auto& r : runs) ok &= r.load() == 1;
    }
    return ok;
  };
  bool okA = false, okB = false;
  std::thread other([&] { okB = works(800); });
  okA = works(800);
  other.join();
  CHECK(okA);
  CHECK(okB);
}

TEST_CASE("BackgroundWork: the background thread runs parts while the caller goes on", "[core]") {
  ThreadSettingsGuard guard;
  setBackgroundThreadEnabled(true);
  // The caller does not finish until a part has started elsewhere (or 20 s have passed: the
  // background thread gets a time slice even on one CPU), so the parts cannot all be the caller's.
  std::atomic<int> started{0};
  const std::thread::id caller = std::this_thread::get_id();
  std::atomic<int> onOtherThread{0};
  BackgroundWork work(4, [&](int) {
    started.fetch_add(1);
    if (std::this_thread::get_id() != caller) onOtherThread.fetch_add(1);
  });
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (started.load() == 0 && std::chrono::steady_clock::now() < deadline) std::this_thread::yield();
  work.finish();
  CHECK(started.load() == 4);
  CHECK(onOtherThread.load() >= 1);
  CHECK(work.partsRunBeside() == onOtherThread.load());
}

TEST_CASE("BackgroundWork: after a long wait for the background thread the next works run on their callers", "[core]") {
  ThreadSettingsGuard guard;
  setBackgroundThreadEnabled(true);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  // A part that sleeps on the background thread until released 30 ms later: the caller waits
  // far longer than the part's CPU time.
  std::atomic<bool> busy{false}, release{false};
  {
    BackgroundWork slow(1, [&](int) {
      busy = true;
      while (!release) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    });
    while (!busy && std::chrono::steady_clock::now() < deadline) std::this_thread::yield();
    std::thread releaser([&] {
      std::this_thread::sleep_for(std::chrono::milliseconds(30));
      release = true;
    });
    slow.finish();
    releaser.join();
    REQUIRE(slow.partsRunBeside() == 1);
  }
  // backing off: the background thread gets nothing, however long the caller waits
  std::atomic<int> runs{0};
  {
    BackgroundWork next(4, [&](int) { runs.fetch_add(1); });
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    CHECK(runs.load() == 0);
    next.finish();
    CHECK(runs.load() == 4);
    CHECK(next.partsRunBeside() == 0);
  }
  // setBackgroundThreadEnabled() ends the back-off
  setBackgroundThreadEnabled(true);
  std::atomic<int> started{0};
  BackgroundWork again(4, [&](int) { started.fetch_add(1); });
  while (started.load() == 0 && std::chrono::steady_clock::now() < deadline) std::this_thread::yield();
  again.finish();
  CHECK(again.partsRunBeside() >= 1);
}

TEST_CASE("SerialOpenMp: OpenMP regions run on their caller while it lives, the setting restored after", "[core]") {
  // the core's tests load CHOLMOD and with it an OpenMP runtime; found as the core finds it
  auto get = reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "omp_get_max_active_levels"));
  auto set = reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "omp_set_max_active_levels"));
  if (!get || !set) {
    BSDEFORM_TEST_SKIP("no OpenMP runtime loaded (a CHOLMOD built without OpenMP)");
    return;
  }
  set(3);
  {
    const bsdeform::SerialOpenMp serial;
    CHECK(get() == 0);
    {
      const bsdeform::SerialOpenMp nested;
      CHECK(get() == 0);
    }
    CHECK(get() == 0);
  }
  CHECK(get() == 3);
}

// GCC's entry to a parallel region, which the core defines (Parallel.cpp) ahead of libgomp's
extern "C" void GOMP_parallel(void (*fn)(void*), void* data, unsigned threads, unsigned flags);

namespace {
// What the bodies of the regions below saw: how often they ran, on which thread, in what team.
struct RegionLog {
  int (*teamSize)() = nullptr;
  int (*threadNumber)() = nullptr;
  int (*level)() = nullptr;
  std::atomic<int> runs{0}, onCaller{0}, teamOfOne{0}, outsideRegions{0};
  std::thread::id caller;
  void (*inner)(void*) = nullptr;  // a region to open from within (thread 0 only)
  RegionLog* innerLog = nullptr;
};
void logRegion(void* data) {
  auto& log = *static_cast<RegionLog*>(data);
  log.runs.fetch_add(1);
  if (std::this_thread::get_id() == log.caller) log.onCaller.fetch_add(1);
  if (log.teamSize() == 1 && log.threadNumber() == 0) log.teamOfOne.fetch_add(1);
  if (log.level() == 0) log.outsideRegions.fetch_add(1);
  if (log.inner && log.threadNumber() == 0) {
    const bsdeform::SerialOpenMp serial;
    log.innerLog->caller = std::this_thread::get_id();
    GOMP_parallel(log.inner, log.innerLog, 2, 0);
  }
}
}  // namespace

TEST_CASE("SerialOpenMp: a region's body runs once on its caller, through libgomp in a team or without", "[core]") {
  auto set = reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "omp_set_max_active_levels"));
  auto teamSize = reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "omp_get_num_threads"));
  auto threadNumber = reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "omp_get_thread_num"));
  auto get = reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "omp_get_max_active_levels"));
  auto level = reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "omp_get_level"));
  if (!set || !teamSize || !threadNumber || !get || !level) {
    BSDEFORM_TEST_SKIP("no OpenMP runtime loaded (a CHOLMOD built without OpenMP)");
    return;
  }
  // the dynamic linker's binding (CHOLMOD's calls): the core's entry, exported by this program
  CHECK(dlsym(RTLD_DEFAULT, "GOMP_parallel") == reinterpret_cast<void*>(&GOMP_parallel));
  const int levelsBefore = get();
  set(3);
  const auto fresh = [&](RegionLog& log) {
    log.teamSize = teamSize;
    log.threadNumber = threadNumber;
    log.level = level;
    log.caller = std::this_thread::get_id();
  };
  SECTION("serial: once, on the caller, as a team of one, without libgomp's region") {
    RegionLog log;
    fresh(log);
    {
      const bsdeform::SerialOpenMp serial;
      GOMP_parallel(logRegion, &log, 2, 0);
    }
    CHECK(log.runs.load() == 1);
    CHECK(log.onCaller.load() == 1);
    CHECK(log.teamOfOne.load() == 1);
    // libgomp's region, even of one thread, would count a level (and end with a futex wake)
    CHECK(log.outsideRegions.load() == 1);
  }
  SECTION("without it: libgomp's team, every member once") {
    RegionLog log;
    fresh(log);
    GOMP_parallel(logRegion, &log, 2, 0);
    CHECK(log.runs.load() >= 1);
    CHECK(log.onCaller.load() == 1);
    // a team of two unless the runtime is limited to one thread
    CHECK((log.runs.load() == 2 || log.teamOfOne.load() == 1));
    CHECK(log.outsideRegions.load() == 0);
  }
  SECTION("inside another region: libgomp's team of one, not the outer team's share") {
    RegionLog outer, inner;
    fresh(outer);
    fresh(inner);
    outer.inner = logRegion;
    outer.innerLog = &inner;
    GOMP_parallel(logRegion, &outer, 2, 0);
    CHECK(inner.runs.load() == 1);
    CHECK(inner.onCaller.load() == 1);
    // run directly, omp_get_num_threads() would say the outer team's two and a loop would
    // take half its range
    CHECK(inner.teamOfOne.load() == 1);
    CHECK(inner.outsideRegions.load() == 0);
  }
  set(levelsBefore);
}
