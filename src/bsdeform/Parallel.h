// SPDX-License-Identifier: MIT
#pragma once
/// @file Parallel.h
/// A small persistent thread pool for the kernels that split a net into row blocks (the
/// explicit step, the history diagnostics).
///
/// Determinism: callers split their work into parts whose results do not depend on which
/// thread computes them or how many threads there are (each part writes its own rows or its
/// own partial sums, combined afterwards in part order). So a result is bit-identical for any
/// thread count; threads only change the wall time.

#include <functional>

namespace bsdeform {

/// Threads the kernels may use, including the caller's. Default: the BSDEFORM_THREADS
/// environment variable if it is a number >= 1, else 1. Not more by default: two threads make
/// the explicit step 1.9-2.1x faster from 128^2 on when the second core is idle, but 1.45x
/// slower when other programs keep it busy (measured on this project's shared 2-core VM,
/// docs/benchmarks.md), and a library cannot tell which it will get.
int kernelThreads();
/// Sets the number of kernel threads (clamped to 1..64); takes effect at the next call.
void setKernelThreads(int threads);

/// Runs fn(part) once for every part = 0..parts-1 and returns when all are done. Parts are
/// handed out in order to the calling thread and up to kernelThreads() - 1 pool threads. Runs
/// everything on the caller when there is one thread or one part, when the pool is busy (a
/// call from another thread, or from inside a part), and for a while after a job in which the
/// caller waited much longer for a worker than a part takes (the other cores busy elsewhere:
/// 16 jobs, doubling up to 4096 while it repeats).
void runParts(int parts, const std::function<void(int)>& fn);

}  // namespace bsdeform
