// SPDX-License-Identifier: MIT
#include "bsdeform/base/Parallel.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <dlfcn.h>

#if defined(__linux__)
#include <sched.h>
#include <time.h>
#endif

namespace bsdeform {

namespace {

// CPUs this process may run on (its affinity mask: `taskset -c 1` gives 1).
int availableCpus() {
#if defined(__linux__)
  cpu_set_t set;
  if (sched_getaffinity(0, sizeof(set), &set) == 0) return CPU_COUNT(&set);
#endif
  return int(std::thread::hardware_concurrency());
}

int defaultThreads() {
  if (const char* env = std::getenv("BSDEFORM_THREADS")) {
    char* end = nullptr;
    const long n = std::strtol(env, &end, 10);
    if (end != env && *end == '\0' && n >= 1) return int(std::min(n, 64L));
  }
  return std::clamp(availableCpus(), 1, 64);  // see Parallel.h
}

std::atomic<int> g_threads{defaultThreads()};

// Spins for up to kSpinTime until done() holds; false if it did not. Waking a sleeping thread
// costs tens of microseconds on this project's VM (measured: a 128^2 explicit sub-step of
// 120 us took 111 us on two threads that slept between sub-steps), more than the work saved on
// small nets; consecutive sub-steps come within a few microseconds, so a short spin catches
// them. Idle threads still sleep: a shared machine loses at most kSpinTime per job.
template <typename Done>
bool spinUntil(Done&& done) {
  constexpr auto kSpinTime = std::chrono::microseconds(200);
  const auto start = std::chrono::steady_clock::now();
  for (int i = 1;; ++i) {
    if (done()) return true;
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
    if (i % 64 == 0 && std::chrono::steady_clock::now() - start > kSpinTime) return done();
  }
}

// When the other cores are busy (a shared machine), a thread that took a part may be
// descheduled and the caller waits for it far longer than the part takes: measured, the 128^2
// step then took 1.45x its one-thread time. After such a wait the next jobs run on the caller
// alone, 16 of them, twice as many after every further such wait (up to 4096), halved again by
// every job without. Only the time changes: the results are the same bits.
class Backoff {
 public:
  /// Whether the next job runs on its caller alone (and counts it).
  bool serial() {
    if (m_serial == 0) return false;
    --m_serial;
    return true;
  }
  /// After a job that was handed out: whether its caller waited far too long.
  void report(bool slow) {
    if (slow) {
      m_length = std::min(m_length == 0 ? 16 : 2 * m_length, 4096);
      m_serial = m_length;
    } else {
      m_length /= 2;  // a machine that stays busy fails again soon: come back down slowly
    }
  }
  void reset() { m_length = m_serial = 0; }

 private:
  int m_length = 0;  // serial jobs after the last slow one (0: none)
  int m_serial = 0;  // serial jobs still to run
};

// The kernels' threads are TBB's (oneTBB, already in the process through Embree): one arena
// per thread count, so a job never uses more than kernelThreads() threads, the caller included.
// Each part is one task (simple partitioner, grain 1): a part's result does not depend on the
// thread that runs it.
class Kernels {
 public:
  void run(int parts, int threads, const std::function<void(int)>& fn) {
    bool serial;
    {
      std::lock_guard<std::mutex> lock(m_mutex);
      serial = m_backoff.serial();
    }
    if (serial) {  // after a long wait for a descheduled thread: see Backoff
      for (int p = 0; p < parts; ++p) fn(p);
      return;
    }
    const std::thread::id caller = std::this_thread::get_id();
    int ownParts = 0;
    std::chrono::steady_clock::duration ownTime{};
    std::chrono::steady_clock::time_point ownEnd{};
    const auto body = [&](const tbb::blocked_range<int>& r) {
      const bool own = std::this_thread::get_id() == caller;
      const auto start = own ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point{};
      for (int p = r.begin(); p != r.end(); ++p) fn(p);
      if (own) {
        ownEnd = std::chrono::steady_clock::now();
        ownTime += ownEnd - start;
        ownParts += r.size();
      }
    };
    arena(threads).execute(
        [&] { tbb::parallel_for(tbb::blocked_range<int>(0, parts, 1), body, tbb::simple_partitioner()); });
    if (ownParts > 0) {
      const auto waited = std::chrono::steady_clock::now() - ownEnd;
      std::lock_guard<std::mutex> lock(m_mutex);
      m_backoff.report(waited > 2 * (ownTime / ownParts) + std::chrono::microseconds(20));
    }
  }

 private:
  tbb::task_arena& arena(int threads) {
    std::lock_guard<std::mutex> lock(m_mutex);
    std::unique_ptr<tbb::task_arena>& a = m_arenas[size_t(threads)];
    if (!a) a = std::make_unique<tbb::task_arena>(threads);
    return *a;
  }

  std::mutex m_mutex;  // the arenas' table and the back-off
  std::array<std::unique_ptr<tbb::task_arena>, 65> m_arenas;
  Backoff m_backoff;
};

Kernels& kernels() {
  static Kernels& k = *new Kernels;  // never destroyed: a job during static destruction still finds it
  return k;
}

bool defaultBackground() {
  if (const char* env = std::getenv("BSDEFORM_BACKGROUND")) {
    if (std::strcmp(env, "0") == 0) return false;
    if (std::strcmp(env, "1") == 0) return true;
  }
  return availableCpus() >= 2;
}

std::atomic<bool> g_background{defaultBackground()};

// CPU time of the calling thread (a descheduled thread's wall time would hide why it was late).
std::chrono::nanoseconds threadCpuTime() {
#if defined(__linux__)
  timespec ts;
  if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) == 0)
    return std::chrono::seconds(ts.tv_sec) + std::chrono::nanoseconds(ts.tv_nsec);
#endif
  return std::chrono::steady_clock::now().time_since_epoch();
}

}  // namespace

struct BackgroundWork::Task {
  std::function<void(int)> fn;
  int parts = 0;
  std::atomic<int> next{0};
  std::atomic<int> done{0};    // parts finished, by either thread
  std::atomic<int> beside{0};  // parts the background thread ran
  std::atomic<long long> besideCpu{0};  // its CPU time in them, ns
  std::mutex mutex;            // with `finished`
  std::condition_variable finished;
};

namespace {

// The background thread: takes works in the order they were handed over and runs the parts
// their callers have not taken yet. It is started by the first work and sleeps when idle. The
// one instance is never destroyed (a work finished during static destruction still finds it);
// the thread ends with the process.
class Background {
 public:
  void submit(const std::shared_ptr<BackgroundWork::Task>& task) {
    bool wake = false;
    {
      std::lock_guard<std::mutex> lock(m_mutex);
      if (m_backoff.serial()) return;  // the caller runs every part in finish()
      if (!m_thread.joinable()) {
        try {
          m_thread = std::thread([this] { work(); });
        } catch (const std::system_error&) {
          return;  // no thread to be had: the caller runs every part
        }
      }
      m_queue.push_back(task);
      m_queued.fetch_add(1, std::memory_order_release);
      wake = m_sleeping;
    }
    if (wake) m_wake.notify_one();  // a system call: skipped while the thread spins
  }

  void resetBackoff() {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_backoff.reset();
  }

  // After a finish() that waited `waited` for parts of `perPart` each (Parallel.h).
  void report(std::chrono::nanoseconds waited, std::chrono::nanoseconds perPart) {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_backoff.report(waited > 2 * perPart + std::chrono::microseconds(50));
  }

 private:
  void work() {
    for (;;) {
      std::shared_ptr<BackgroundWork::Task> task;
      // Works come one per step of a run: a short spin catches the next without the system
      // calls of sleeping and waking (docs/benchmarks.md, "Rows beside the steps").
      if (!spinUntil([this] { return m_queued.load(std::memory_order_acquire) > 0; })) {
        std::unique_lock<std::mutex> lock(m_mutex);
        m_sleeping = true;
        m_wake.wait(lock, [this] { return !m_queue.empty(); });
        m_sleeping = false;
      }
      {
        std::lock_guard<std::mutex> lock(m_mutex);
        task = std::move(m_queue.front());
        m_queue.pop_front();
        m_queued.fetch_sub(1, std::memory_order_relaxed);
      }
      BackgroundWork::Task& t = *task;
      for (int p; (p = t.next.fetch_add(1)) < t.parts;) {
        const auto cpu = threadCpuTime();
        t.fn(p);
        t.besideCpu.fetch_add((threadCpuTime() - cpu).count(), std::memory_order_relaxed);
        t.beside.fetch_add(1, std::memory_order_relaxed);
        if (t.done.fetch_add(1, std::memory_order_acq_rel) + 1 == t.parts) {
          std::lock_guard<std::mutex> lock(t.mutex);  // the caller is waiting or will see the count
          t.finished.notify_all();
        }
      }
    }
  }

  std::mutex m_mutex;
  std::condition_variable m_wake;
  std::deque<std::shared_ptr<BackgroundWork::Task>> m_queue;
  std::thread m_thread;
  std::atomic<int> m_queued{0};  // works in m_queue, read while spinning
  bool m_sleeping = false;
  Backoff m_backoff;
};

Background& background() {
  static Background& b = *new Background;  // never destroyed: see above
  return b;
}

}  // namespace

bool backgroundThreadEnabled() { return g_background.load(std::memory_order_relaxed); }

void setBackgroundThreadEnabled(bool enabled) {
  g_background.store(enabled, std::memory_order_relaxed);
  background().resetBackoff();
}

BackgroundWork::BackgroundWork(int parts, std::function<void(int)> fn) : m_task(std::make_shared<Task>()) {
  m_task->fn = std::move(fn);
  m_task->parts = std::max(parts, 0);
  if (m_task->parts > 0 && backgroundThreadEnabled()) background().submit(m_task);
}

BackgroundWork::~BackgroundWork() { finish(); }

void BackgroundWork::finish() {
  if (m_finished) return;
  m_finished = true;
  Task& t = *m_task;
  const auto start = std::chrono::steady_clock::now();
  int own = 0;
  for (int p; (p = t.next.fetch_add(1)) < t.parts; ++own) t.fn(p);
  if (own > 0) t.done.fetch_add(own, std::memory_order_acq_rel);
  const auto ownEnd = std::chrono::steady_clock::now();
  auto finished = [&t] { return t.done.load(std::memory_order_acquire) == t.parts; };
  if (!spinUntil(finished)) {
    std::unique_lock<std::mutex> lock(t.mutex);
    t.finished.wait(lock, finished);
  }
  const int beside = t.beside.load(std::memory_order_relaxed);
  if (beside == 0) return;  // nothing was waited for
  const auto waited = std::chrono::steady_clock::now() - ownEnd;
  const auto perPart = own > 0 ? std::chrono::nanoseconds(ownEnd - start) / own
                               : std::chrono::nanoseconds(t.besideCpu.load(std::memory_order_relaxed) / beside);
  background().report(std::chrono::duration_cast<std::chrono::nanoseconds>(waited), perPart);
}

int BackgroundWork::partsRunBeside() const { return m_task->beside.load(std::memory_order_relaxed); }

namespace {
using RegionEntry = void (*)(void (*)(void*), void*, unsigned, unsigned);

// The OpenMP runtime behind GOMP_parallel (libgomp, which CHOLMOD brings), found at run time so
// that the core does not link an OpenMP runtime of its own: its region entry (the definition
// after the core's own, below) and, from the same library, the levels (from any runtime loaded
// when there is no such entry).
struct OpenMpRuntime {
  RegionEntry parallel = nullptr;
  int (*getLevels)() = nullptr;      ///< omp_get_max_active_levels
  void (*setLevels)(int) = nullptr;  ///< omp_set_max_active_levels
  int (*level)() = nullptr;          ///< omp_get_level: the parallel regions around the caller
  OpenMpRuntime() {
    void* entry = dlvsym(RTLD_NEXT, "GOMP_parallel", "GOMP_4.0");
    if (!entry) entry = dlsym(RTLD_NEXT, "GOMP_parallel");
    parallel = reinterpret_cast<RegionEntry>(entry);
    void* library = nullptr;  // kept open for the process's life
    Dl_info info;
    if (entry && dladdr(entry, &info) && info.dli_fname)
      library = dlopen(info.dli_fname, RTLD_LAZY | RTLD_NOLOAD);
    const auto find = [library](const char* name) { return library ? dlsym(library, name) : dlsym(RTLD_DEFAULT, name); };
    getLevels = reinterpret_cast<int (*)()>(find("omp_get_max_active_levels"));
    setLevels = reinterpret_cast<void (*)(int)>(find("omp_set_max_active_levels"));
    if (!getLevels || !setLevels) getLevels = nullptr, setLevels = nullptr;
    level = reinterpret_cast<int (*)()>(find("omp_get_level"));
  }
};
const OpenMpRuntime& openMpRuntime() {
  static const OpenMpRuntime runtime;
  return runtime;
}
/// SerialOpenMp objects alive on this thread.
thread_local int t_serialOpenMp = 0;
/// SerialOpenMp objects alive in the process, and the levels the first found.
std::mutex g_levelsMutex;
int g_serialGuards = 0;
int g_savedLevels = 0;
std::atomic<long long> g_regionsOnCaller{0};
}  // namespace

/// GCC's entry to an OpenMP parallel region (libgomp's GOMP_parallel, GOMP_4.0), defined here so
/// that the dynamic linker binds CHOLMOD's calls to it (this library comes before libgomp in the
/// lookup order; where it does not, libgomp's own runs and SerialOpenMp's levels still hold).
/// While a SerialOpenMp lives on the calling thread, outside any parallel region, the region's
/// body runs on the caller directly, as the team of one libgomp would make of it then:
/// omp_get_num_threads() 1 and omp_get_thread_num() 0, so each of CHOLMOD's loops takes its whole
/// range. Unlike libgomp's team, the body sees no region around it (omp_get_level() 0,
/// omp_in_parallel() false) and settings it changes outlive it; CHOLMOD's bodies are plain
/// loops. What it saves is the team's set-up and the futex wake of its closing barrier, a system
/// call per region, three per supernode (docs/benchmarks.md, issue 34). Everything else goes on
/// to libgomp's entry.
extern "C" __attribute__((visibility("default"))) void GOMP_parallel(void (*fn)(void*), void* data, unsigned threads,
                                                                   unsigned flags) {
  const OpenMpRuntime& omp = openMpRuntime();
  // no runtime: no team either
  if (!omp.parallel || (t_serialOpenMp > 0 && omp.level && omp.level() == 0)) {
    g_regionsOnCaller.fetch_add(1, std::memory_order_relaxed);
    fn(data);
    return;
  }
  omp.parallel(fn, data, threads, flags);
}

long long openMpRegionsRunOnCaller() { return g_regionsOnCaller.load(std::memory_order_relaxed); }

SerialOpenMp::SerialOpenMp() {
  ++t_serialOpenMp;
  const OpenMpRuntime& omp = openMpRuntime();
  if (!omp.setLevels) return;
  const std::lock_guard<std::mutex> lock(g_levelsMutex);
  if (g_serialGuards++ == 0) {
    g_savedLevels = omp.getLevels();
    omp.setLevels(0);
  }
}

SerialOpenMp::~SerialOpenMp() {
  --t_serialOpenMp;
  const OpenMpRuntime& omp = openMpRuntime();
  if (!omp.setLevels) return;
  const std::lock_guard<std::mutex> lock(g_levelsMutex);
  if (--g_serialGuards == 0) omp.setLevels(g_savedLevels);
}

int kernelThreads() { return g_threads.load(std::memory_order_relaxed); }

void setKernelThreads(int threads) { g_threads.store(std::clamp(threads, 1, 64), std::memory_order_relaxed); }

int effectiveKernelThreads() {
  const size_t cap = tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
  return int(std::min<size_t>(size_t(kernelThreads()), std::max<size_t>(cap, 1)));
}

void runParts(int parts, const std::function<void(int)>& fn) {
  const int threads = std::min(kernelThreads(), parts);
  if (threads > 1)
    kernels().run(parts, threads, fn);
  else
    for (int p = 0; p < parts; ++p) fn(p);
}

}  // namespace bsdeform
