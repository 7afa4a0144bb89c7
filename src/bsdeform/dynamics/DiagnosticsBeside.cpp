// SPDX-License-Identifier: MIT
#include "bsdeform/dynamics/DiagnosticsBeside.h"

#include "bsdeform/base/HugePages.h"
#include "bsdeform/base/Parallel.h"
#include "bsdeform/dynamics/Simulation.h"

#include <cstdint>
#include <vector>
#if defined(__SSE2__)
#include <emmintrin.h>  // _mm_stream_pd
#endif

namespace bsdeform {

namespace {

// Sub-steps per step up to which begin() uses the background thread: a row costs about one
// explicit sub-step (Diagnostics.h), so beyond this it is under 1/16 of a step and not worth
// two more nets of memory.
constexpr int kBesideMaxSubSteps = 16;

// dst = src with streaming stores where the CPU has them: the lines go to memory without being
// read first and leave this core's caches, so the core that reads them next does not have to
// take them from here, and this core does not wait for that one when it writes them again.
void copyStreaming(const ControlNet& src, ControlNet& dst) {
  const double* s = src.data();
  double* d = dst.data();
  const Eigen::Index n = src.size();
  Eigen::Index i = 0;
#if defined(__SSE2__)
  if (reinterpret_cast<std::uintptr_t>(d) % 16 == 0) {
    for (; i + 2 <= n; i += 2) _mm_stream_pd(d + i, _mm_loadu_pd(s + i));
    _mm_sfence();  // visible before the background thread is told
  }
#endif
  for (; i < n; ++i) d[i] = s[i];
}

}  // namespace

// What a row reads of the model, copied once per model: the job never touches the Simulation.
struct DiagnosticsBeside::Model {
  Model(const Simulation& sim)
      : space(sim.space()), stencil(space, sim.stencil().weights()), rest(sim.rest()) {
    const Simulation::PointMasses m = sim.pointMasses();
    uniform = m.uniform;
    if (m.perPoint) perPoint.assign(m.perPoint, m.perPoint + space.numMoving());
  }
  SplineSpace space;
  StiffnessStencil stencil;  // points to `space`: Model is never copied
  ControlNet rest;
  std::vector<double> perPoint;  ///< empty: every moving point weighs `uniform`
  double uniform = 1.0;
};

// The row's blocks run on the background thread (BackgroundWork) or, when finished before it
// took them, on the caller.
struct PendingDiagnostics::Job {
  const Diagnostics& finish() {
    if (!done) {
      work->finish();
      DiagnosticSums sums = pass->sums();
      sums.velocity += derivedVelocity;
      result = diagnosticsFromSums(sums, model->stencil.weights(), model->perPoint.empty() ? model->uniform : 1.0, dt);
      done = true;
      work.reset();
      pass.reset();
      model.reset();
    }
    return result;
  }

  bool done = false;
  Diagnostics result;
  // until done:
  std::shared_ptr<const DiagnosticsBeside::Model> model;
  std::unique_ptr<DiagnosticPass> pass;
  std::unique_ptr<BackgroundWork> work;  // after `pass`: destroyed (finished) first
  double dt = 1.0;
  double derivedVelocity = 0.0;  ///< the derived points' part of the velocity sum
};

Diagnostics PendingDiagnostics::get() const { return m_job->finish(); }

DiagnosticsBeside::DiagnosticsBeside() = default;

DiagnosticsBeside::~DiagnosticsBeside() { finish(); }

void DiagnosticsBeside::finish() {
  if (!m_job) return;
  m_job->finish();
  m_job.reset();
}

PendingDiagnostics DiagnosticsBeside::begin(const Simulation& sim) {
  finish();  // its blocks read the snapshot
  auto job = std::make_shared<PendingDiagnostics::Job>();
  const bool beside = !sim.shell() && backgroundThreadEnabled() && kernelThreads() == 1 &&
                      sim.parameters().integrator == Integrator::Explicit && sim.subSteps() <= kBesideMaxSubSteps;
  if (!beside) {
    job->result = sim.diagnostics();
    job->done = true;
    return PendingDiagnostics(std::move(job));
  }
  if (!m_model || m_modelSerial != sim.serial()) {
    m_model = std::make_shared<const Model>(sim);
    m_modelSerial = sim.serial();
  }
  for (ControlNet& net : m_snapshot) allocateNet(net, sim.current().rows());
  copyStreaming(sim.current(), m_snapshot[0]);
  copyStreaming(sim.previous(), m_snapshot[1]);
  PendingDiagnostics::Job& j = *job;
  j.model = m_model;
  const Model& m = *m_model;
  j.pass = std::make_unique<DiagnosticPass>(m.space, m.stencil, m_snapshot[0], m.rest, m_snapshot[1],
                                            m.perPoint.empty() ? nullptr : m.perPoint.data());
  j.dt = sim.subStepSize();
  j.derivedVelocity = sim.derivedVelocitySum();
  j.work = std::make_unique<BackgroundWork>(j.pass->blocks(), [&j](int b) { j.pass->computeBlock(b); });
  m_job = job;
  return PendingDiagnostics(std::move(job));
}

}  // namespace bsdeform
