// SPDX-License-Identifier: MIT
#pragma once
/// @file Parallel.h
/// Threads for the kernels that split a net into row blocks (the explicit step, the shell's
/// forces, the history diagnostics): oneTBB's, in an arena per thread count (runParts()); and
/// one background thread for work that runs beside
/// the caller (BackgroundWork: a history row computed while the next step is taken).
///
/// Determinism: callers split their work into parts whose results do not depend on which
/// thread computes them or how many threads there are (each part writes its own rows or its
/// own partial sums, combined afterwards in part order). So a result is bit-identical for any
/// thread count; threads only change the wall time.

#include <functional>
#include <memory>

namespace bsdeform {

/// Threads the kernels may use, including the caller's. Default: the BSDEFORM_THREADS
/// environment variable if it is a number >= 1, else the CPUs this process may run on (its
/// affinity mask; at most 64): a second thread costs nothing measurable when another program
/// keeps its core busy (docs/benchmarks.md, "both cores by default"). Processes that run beside
/// each other (bsdeform-run --sweep, bsdeform.sweep) give their children BSDEFORM_THREADS=1.
int kernelThreads();
/// Sets the number of kernel threads (clamped to 1..64); takes effect at the next call.
void setKernelThreads(int threads);
/// The threads runParts() can have now: kernelThreads(), less any cap that a library put on the
/// process's TBB (a tbb::global_control of max_allowed_parallelism; Embree's devices keep one of
/// their thread count while they live, contact/TriangleTree.cpp).
int effectiveKernelThreads();

/// Runs fn(part) once for every part = 0..parts-1 and returns when all are done: one TBB task
/// per part in an arena of kernelThreads() threads, the caller's included (TBB's worker threads
/// are shared by the whole process; nested calls, and calls from several threads at once, are
/// TBB's to schedule). Runs everything on the caller when there is one thread or one part, and
/// for a while after a job in which the caller waited much longer for a worker than a part
/// takes (the other cores busy elsewhere: 16 jobs, doubling up to 4096 while it repeats).
void runParts(int parts, const std::function<void(int)>& fn);

/// While it lives, OpenMP parallel regions run on their caller alone (max-active-levels 0, set
/// through the OpenMP runtime when one is loaded; restored after). For calls into CHOLMOD: its
/// supernodal factorisation opens parallel regions of a fixed 4 threads (SuiteSparse 5's
/// CHOLMOD_OMP_NUM_THREADS, which OMP_NUM_THREADS does not lower) for loops of a few
/// microseconds, and on two cores their wake-ups cost more than the whole factorisation: 300 000
/// context switches and 5 s of a 12.9 s cloth_on_cube run (docs/benchmarks.md, issue 34). The
/// factor's values do not depend on them. Not for use while another thread runs OpenMP code of
/// its own (the setting is the process's while any SerialOpenMp lives; the last one restores
/// what the first found). Outside any parallel region, the core's own GOMP_parallel
/// (Parallel.cpp, bound ahead of libgomp's) runs such a region's body on the caller directly,
/// without even libgomp's team of one, whose closing barrier made a system call per region
/// (three per supernode).
class SerialOpenMp {
 public:
  SerialOpenMp();
  ~SerialOpenMp();
  SerialOpenMp(const SerialOpenMp&) = delete;
  SerialOpenMp& operator=(const SerialOpenMp&) = delete;
};

/// How many OpenMP parallel regions the core's GOMP_parallel has run on their caller (under a
/// SerialOpenMp): a diagnostic, by which the tests see that CHOLMOD's calls reach it.
long long openMpRegionsRunOnCaller();

/// Whether BackgroundWork hands its parts to a background thread. Default: the
/// BSDEFORM_BACKGROUND environment variable if it is 0 (no) or 1 (yes), else yes when this
/// process may run on two or more CPUs (its affinity mask: not under `taskset -c 1`; a CPU
/// quota of a container is not seen). The caller never waits for the background thread to
/// start (it runs the parts not yet taken itself). What a busy machine can cost: the background
/// thread spins up to 200 us after each work before it sleeps (CPU time, measured in
/// docs/benchmarks.md), and a caller may wait once for a part whose thread was descheduled
/// before the back-off below sets in.
bool backgroundThreadEnabled();
/// Turns the background thread on or off for the next works, and ends a back-off (see below).
void setBackgroundThreadEnabled(bool enabled);

/// fn(part) for part = 0..parts-1, run beside the caller: the constructor hands the parts to the
/// background thread (when enabled) and returns at once; finish() runs on the calling thread
/// the parts the background thread has not taken, waits for the ones it has, and returns when
/// every part has run exactly once. The destructor finishes. Parts may run in any order and on
/// either thread, so they must not depend on each other (write their own results). Works of
/// several threads share the one background thread, first come first served.
/// Back-off, for the whole process: when finish() waited for the background thread more than
/// twice the time of a part plus 50 us (a part's time: the caller's own parts, or the
/// background thread's CPU time per part when the caller ran none), the next 16 works run on
/// their callers only, in finish(); 16 doubles with every further such wait, up to 4096, and
/// halves with every work the background thread helped with and no such wait. Only the time
/// changes.
class BackgroundWork {
 public:
  BackgroundWork(int parts, std::function<void(int)> fn);
  ~BackgroundWork();
  BackgroundWork(const BackgroundWork&) = delete;
  BackgroundWork& operator=(const BackgroundWork&) = delete;
  /// Runs what is left on this thread, waits for the rest; then every part has run. Once.
  void finish();
  /// Parts the background thread ran (for tests and benchmarks; valid after finish()).
  int partsRunBeside() const;

  struct Task;

 private:
  std::shared_ptr<Task> m_task;
  bool m_finished = false;
};

}  // namespace bsdeform
