// SPDX-License-Identifier: MIT
#pragma once
/// @file DiagnosticsBeside.h
/// History rows computed beside the steps: what bsdeform-run's history uses so that a row costs
/// the stepping thread a copy of two nets instead of the row's arithmetic, when a second core is
/// free. Kept out of Simulation (which knows nothing of histories): a DiagnosticsBeside holds
/// its own copies of everything a row reads, so the Simulation may step, be rebuilt or be
/// destroyed while a row is being computed.
///
/// The copy of the current and previous nets is written with streaming stores: the background
/// thread reads the copy, never the nets the steps rewrite, because a core writing cache lines
/// another core has just read waits for them (measured in docs/benchmarks.md, "Runner history":
/// reading the live nets made the 128^2 step 30-45 % slower).

#include <cstdint>
#include <memory>

#include "bsdeform/dynamics/Diagnostics.h"

namespace bsdeform {

class Simulation;

/// A history row being computed beside the caller. Holds its values once finished, even after
/// the Simulation and the DiagnosticsBeside are gone. Use it on the thread that began it.
class PendingDiagnostics {
 public:
  PendingDiagnostics() = default;
  /// Whether this stands for a row (default-constructed: none).
  bool valid() const { return bool(m_job); }
  /// The values: the first call waits for the background thread, running the blocks it has not
  /// taken yet. Precondition: valid().
  Diagnostics get() const;

  struct Job;

 private:
  friend class DiagnosticsBeside;
  explicit PendingDiagnostics(std::shared_ptr<Job> job) : m_job(std::move(job)) {}
  std::shared_ptr<Job> m_job;
};

class DiagnosticsBeside {
 public:
  DiagnosticsBeside();
  /// Finishes the row being computed, if any.
  ~DiagnosticsBeside();
  DiagnosticsBeside(const DiagnosticsBeside&) = delete;
  DiagnosticsBeside& operator=(const DiagnosticsBeside&) = delete;

  /// Begins the row of `sim`'s current state (Simulation::diagnostics(), the same values to the
  /// last bit) on the background thread (Parallel.h) and returns at once; the caller typically
  /// takes the next step before get(). Finishes the row begun before. Computed at once instead
  /// (no copy) when the background thread is disabled, when the kernels already use more than
  /// one thread (kernelThreads()), for the SHELL energy, the implicit scheme and above 16
  /// sub-steps per step (a row then costs little next to a step).
  /// Memory: a copy of the space, the stencil and the rest net per model (made again when `sim`
  /// is another model), and two nets for the copy of the state, allocated once and reused.
  PendingDiagnostics begin(const Simulation& sim);

  struct Model;  ///< copies of what a row reads of a model

 private:
  void finish();

  std::shared_ptr<const Model> m_model;
  std::uint64_t m_modelSerial = 0;
  std::shared_ptr<PendingDiagnostics::Job> m_job;  ///< the row being computed (reads m_snapshot)
  ControlNet m_snapshot[2];
};

}  // namespace bsdeform
