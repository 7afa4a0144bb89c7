// SPDX-License-Identifier: MIT
#include "bsdeform/Parallel.h"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdlib>
#include <mutex>
#include <thread>
#include <vector>

namespace bsdeform {

namespace {

int defaultThreads() {
  if (const char* env = std::getenv("BSDEFORM_THREADS")) {
    char* end = nullptr;
    const long n = std::strtol(env, &end, 10);
    if (end != env && *end == '\0' && n >= 1) return int(std::min(n, 64L));
  }
  const unsigned hw = std::thread::hardware_concurrency();
  return int(std::clamp(hw, 1u, 2u));
}

std::atomic<int> g_threads{defaultThreads()};

// Workers sleep on a condition variable between jobs: the machine may be shared, so an idle
// worker must not spin. A job's parts are taken from an atomic counter, so a worker that wakes
// late finds them done by the caller and nothing waits for it.
class Pool {
 public:
  ~Pool() {
    {
      std::lock_guard<std::mutex> lock(m_mutex);
      m_stop = true;
    }
    m_wake.notify_all();
    for (std::thread& t : m_workers) t.join();
  }

  // false if another job is running (the caller then runs its parts itself)
  bool run(int parts, int threads, const std::function<void(int)>& fn) {
    std::unique_lock<std::mutex> busy(m_busy, std::try_to_lock);
    if (!busy.owns_lock()) return false;
    while (int(m_workers.size()) < threads - 1) m_workers.emplace_back([this] { work(); });
    {
      std::lock_guard<std::mutex> lock(m_mutex);
      m_fn = &fn;
      m_parts = parts;
      m_next.store(0);
      m_pending = parts;
      m_helpers = threads - 1;
      ++m_generation;
    }
    m_wake.notify_all();
    runAvailable();
    std::unique_lock<std::mutex> lock(m_mutex);
    m_done.wait(lock, [this] { return m_pending == 0 && m_active == 0; });
    m_helpers = 0;  // a worker waking only now must not join a finished job
    m_fn = nullptr;
    return true;
  }

 private:
  void runAvailable() {
    int done = 0;
    for (int p; (p = m_next.fetch_add(1)) < m_parts; ++done) (*m_fn)(p);
    if (done == 0) return;
    std::lock_guard<std::mutex> lock(m_mutex);
    m_pending -= done;
    if (m_pending == 0) m_done.notify_all();
  }

  void work() {
    long seen = 0;
    std::unique_lock<std::mutex> lock(m_mutex);
    for (;;) {
      m_wake.wait(lock, [&] { return m_stop || (m_generation != seen && m_helpers > 0); });
      if (m_stop) return;
      seen = m_generation;
      --m_helpers;  // only as many workers as the job asked for
      ++m_active;
      lock.unlock();
      runAvailable();
      lock.lock();
      if (--m_active == 0 && m_pending == 0) m_done.notify_all();
    }
  }

  std::mutex m_busy;   // one job at a time
  std::mutex m_mutex;  // guards the job's fields below
  std::condition_variable m_wake, m_done;
  std::vector<std::thread> m_workers;
  const std::function<void(int)>* m_fn = nullptr;
  int m_parts = 0;
  std::atomic<int> m_next{0};
  int m_pending = 0;  // parts not finished
  int m_active = 0;   // workers inside runAvailable()
  int m_helpers = 0;  // workers still wanted for this job
  long m_generation = 0;
  bool m_stop = false;
};

Pool& pool() {
  static Pool p;
  return p;
}

}  // namespace

int kernelThreads() { return g_threads.load(std::memory_order_relaxed); }

void setKernelThreads(int threads) { g_threads.store(std::clamp(threads, 1, 64), std::memory_order_relaxed); }

void runParts(int parts, const std::function<void(int)>& fn) {
  const int threads = std::min(kernelThreads(), parts);
  if (threads > 1 && pool().run(parts, threads, fn)) return;
  for (int p = 0; p < parts; ++p) fn(p);
}

}  // namespace bsdeform
