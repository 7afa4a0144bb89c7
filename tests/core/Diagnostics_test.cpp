// SPDX-License-Identifier: MIT
// The one-pass diagnostics of a history row (Simulation::diagnostics(), Diagnostics.h) against
// the functions that compute each value on its own (deformationNorm(), kineticEnergy(),
// strainEnergy(): five stencils applied to the displacement).
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <atomic>
#include <chrono>
#include <memory>
#include <random>
#include <thread>

#include "../support/ThreadSettings.h"
#include "bsdeform/dynamics/DiagnosticsBeside.h"
#include "bsdeform/base/Parallel.h"
#include "bsdeform/dynamics/Simulation.h"

using namespace bsdeform;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A rest net that closes in the periodic directions (tube, ring, torus), else the plane.
ControlNet restNet(const SplineSpace& s) {
  ControlNet net(s.netSize(), 3);
  const int Mu = s.numU() + s.degreeU(), Mv = s.numV() + s.degreeV();
  for (int k1 = -s.degreeU(); k1 < Mu; ++k1)
    for (int k2 = -s.degreeV(); k2 < Mv; ++k2) {
      const double a = 2 * kPi * k1 / Mu, b = 2 * kPi * k2 / Mv, gu = s.grevilleU(k1), gv = s.grevilleV(k2);
      Eigen::Vector3d p(gu, gv, 0.0);
      if (s.periodicU() && s.periodicV())
        p << (1 + 0.35 * std::cos(b)) * std::cos(a), (1 + 0.35 * std::cos(b)) * std::sin(a), 0.35 * std::sin(b);
      else if (s.periodicU())
        p << std::cos(a), std::sin(a), gv;
      else if (s.periodicV())
        p << gu, std::cos(b), std::sin(b);
      net.row(s.netIndex(k1, k2)) = p.transpose();
    }
  return net;
}

// |a - b| <= tol |b| for every value of the row.
void checkClose(const Diagnostics& d, const Simulation& sim, double tol) {
  const StrainEnergy e = sim.strainEnergy();
  const double norm = sim.deformationNorm(), kinetic = sim.kineticEnergy();
  auto close = [tol](double a, double b) { return std::abs(a - b) <= tol * std::abs(b); };
  INFO("norm " << d.norm << " / " << norm << ", kinetic " << d.kinetic << " / " << kinetic);
  CHECK(close(d.norm, norm));
  CHECK(close(d.kinetic, kinetic));
  INFO("strain " << d.strain.total << " / " << e.total << ": w10 " << d.strain.w10 << " / " << e.w10 << ", w01 "
                 << d.strain.w01 << " / " << e.w01 << ", w11 " << d.strain.w11 << " / " << e.w11 << ", w20 "
                 << d.strain.w20 << " / " << e.w20 << ", w02 " << d.strain.w02 << " / " << e.w02);
  CHECK(close(d.strain.w10, e.w10));
  CHECK(close(d.strain.w01, e.w01));
  CHECK(close(d.strain.w11, e.w11));
  CHECK(close(d.strain.w20, e.w20));
  CHECK(close(d.strain.w02, e.w02));
  CHECK(close(d.strain.total, e.total));
}

}  // namespace

TEST_CASE("Diagnostics: one pass equals the per-term functions for every boundary, degree and mass model",
          "[core]") {
  using B = Boundary;
  struct Case {
    Boundaries bc;
    int n1, n2, N1, N2;
    MassModel mass;
    bool pins;
  };
  const Boundaries clamped, allFree{B::Free, B::Free, B::Free, B::Free}, mixed{B::Free, B::Clamped, B::Clamped, B::Free},
      tube{B::Periodic, B::Periodic, B::Free, B::Clamped}, ring{B::Clamped, B::Free, B::Periodic, B::Periodic},
      torus{B::Periodic, B::Periodic, B::Periodic, B::Periodic},
      supported{B::SimplySupported, B::SimplySupported, B::SimplySupported, B::SimplySupported},
      builtIn{B::BuiltIn, B::BuiltIn, B::BuiltIn, B::BuiltIn}, edges{B::SimplySupported, B::BuiltIn, B::Free, B::Clamped},
      hinged{B::BuiltIn, B::SimplySupported, B::Periodic, B::Periodic};
  const Case cases[] = {
      {supported, 3, 3, 10, 9, MassModel::Nodal, true},  {builtIn, 4, 3, 9, 10, MassModel::Lumped, false},
      {edges, 5, 2, 8, 9, MassModel::Lumped, true},      {hinged, 3, 3, 9, 10, MassModel::Nodal, false},
      {builtIn, 3, 5, 2, 1, MassModel::Nodal, false},
      {clamped, 3, 3, 12, 10, MassModel::Nodal, false}, {clamped, 1, 1, 9, 7, MassModel::Nodal, false},
      {clamped, 2, 5, 8, 13, MassModel::Lumped, true},  {clamped, 7, 4, 15, 11, MassModel::Nodal, false},
      {allFree, 3, 3, 10, 10, MassModel::Lumped, false}, {allFree, 2, 1, 6, 9, MassModel::Nodal, true},
      {mixed, 4, 2, 9, 8, MassModel::Lumped, true},      {tube, 3, 3, 12, 9, MassModel::Nodal, false},
      {tube, 2, 4, 9, 8, MassModel::Lumped, true},       {ring, 3, 2, 10, 11, MassModel::Lumped, false},
      {torus, 3, 3, 11, 12, MassModel::Nodal, false},    {torus, 1, 2, 5, 6, MassModel::Nodal, true},
      {tube, 3, 3, 2, 8, MassModel::Nodal, false},  // 5 moving rows < 2 n1 + 1: the per-term path
      {clamped, 3, 3, 1, 1, MassModel::Nodal, false},   {allFree, 2, 2, 1, 2, MassModel::Lumped, false},
  };
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (const Case& c : cases) {
    ModelParameters p;
    p.degreeU = c.n1;
    p.degreeV = c.n2;
    p.numU = c.N1;
    p.numV = c.N2;
    p.boundaries = c.bc;
    p.massModel = c.mass;
    p.weights = Weights{0.13, 0.07, 0.011, 0.023, 0.017};
    p.timeStep = 0.05;
    if (c.pins) p.pins = {Eigen::Vector2d(0.3, 0.6), Eigen::Vector2d(1.0, 0.0)};
    const SplineSpace s(c.n1, c.n2, c.N1, c.N2, c.bc);
    INFO("degrees (" << c.n1 << ", " << c.n2 << "), " << c.N1 << " x " << c.N2 << ", boundaries "
                     << boundaryName(c.bc.uMin) << "/" << boundaryName(c.bc.uMax) << "/" << boundaryName(c.bc.vMin)
                     << "/" << boundaryName(c.bc.vMax) << (c.mass == MassModel::Lumped ? ", lumped" : ", nodal")
                     << (c.pins ? ", pins" : ""));
    for (ElasticReference ref : {ElasticReference::Rest, ElasticReference::Absolute}) {
      p.reference = ref;
      Simulation sim(p, restNet(s));
      // at rest: all zero, exactly
      const Diagnostics rest = sim.diagnostics();
      CHECK(rest.norm == 0.0);
      CHECK(rest.kinetic == 0.0);
      CHECK(rest.strain.total == 0.0);
      // a rough state (random displacement and velocity of every moving point): no cancellation
      ControlNet current = sim.rest(), previous = sim.rest();
      for (Eigen::Index m = 0; m < s.numMoving(); ++m) {
        const Eigen::Index r = s.movingToNet(m);
        const Eigen::RowVector3d d(unit(rng), unit(rng), unit(rng)), v(unit(rng), unit(rng), unit(rng));
        current.row(r) += 0.1 * d;
        previous.row(r) += 0.1 * d - 0.01 * v;
      }
      s.refreshPeriodicCopies(current);
      s.refreshPeriodicCopies(previous);
      sim.setState(current, previous, 0.5, 7, 0.0, HeldPoints::Reset);
      checkClose(sim.diagnostics(), sim, 1e-12);
      // a smooth state: a few steps under a region load and a point load
      Simulation run(p, restNet(s));
      run.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0.3, -0.2, 5.0), ParamRect{0.2, 0.7, 0.3, 0.9}));
      run.addForce(std::make_shared<PointForce>(0.61, 0.27, Eigen::Vector3d(0.0, 0.4, -1.0)));
      run.advance(5);
      REQUIRE(run.status() == Status::Ok);
      checkClose(run.diagnostics(), run, 1e-12);
    }
  }
}

TEST_CASE("Diagnostics: one pass and the per-term functions agree with extended precision on a large smooth state",
          "[core]") {
  // 96^2 bicubic after 40 steps of a region load. The bending terms of a smooth state are small
  // differences of large products (coefficients ~ h^-3 of alternating sign): rounding the
  // combined stencil coefficients w G_u G_v (as the per-term functions do) or not (as the one
  // pass does) already moves them by a few 1e-13. Both are checked against the same quadratic
  // form summed in long double (the one pass is the closer), and against each other.
  ModelParameters p;
  p.numU = p.numV = 96;
  p.damping = 1.0;
  Simulation sim(p);
  sim.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, 60), ParamRect{0.3, 0.7, 0.3, 0.7}));
  sim.advance(40);
  REQUIRE(sim.status() == Status::Ok);
  const SplineSpace& s = sim.space();
  const GramRows1D &gu = sim.stencil().gramU(), &gv = sim.stencil().gramV();
  const ControlNet D = sim.current() - sim.rest();
  const int n = 3, N = 96, P[5] = {1, 0, 1, 2, 0}, Q[5] = {0, 1, 1, 0, 2};
  const long double c[5] = {0.5L * p.weights.w10, 0.5L * p.weights.w01, (long double)p.weights.w11,
                            0.5L * p.weights.w20, 0.5L * p.weights.w02};
  long double exact[5] = {0, 0, 0, 0, 0};
  for (int a = 0; a < N; ++a)
    for (int b = 0; b < N; ++b)
      for (int d1 = -n; d1 <= n; ++d1)
        for (int d2 = -n; d2 <= n; ++d2) {
          if (a + d1 < 0 || a + d1 >= N || b + d2 < 0 || b + d2 >= N) continue;  // clamped: D = 0 there
          const Eigen::Index m = s.netIndex(a, b), k = s.netIndex(a + d1, b + d2);
          const long double dd = (long double)D(m, 0) * D(k, 0) + (long double)D(m, 1) * D(k, 1) +
                                 (long double)D(m, 2) * D(k, 2);
          for (int t = 0; t < 5; ++t)
            exact[t] += (long double)gu.entry(P[t], 0, d1) * (long double)gv.entry(Q[t], 0, d2) * dd;
        }
  const Diagnostics d = sim.diagnostics();
  const StrainEnergy e = sim.strainEnergy();
  const double onePass[5] = {d.strain.w10, d.strain.w01, d.strain.w11, d.strain.w20, d.strain.w02};
  const double perTerm[5] = {e.w10, e.w01, e.w11, e.w20, e.w02};
  for (int t = 0; t < 5; ++t) {
    const double ref = double(c[t] * exact[t]);
    INFO("term " << t << ": one pass " << (onePass[t] - ref) / ref << ", per term " << (perTerm[t] - ref) / ref
                 << " relative to the long double sum");
    // measured: one pass within 2e-13 for every term, per term up to 1.4e-12 (w02)
    CHECK(std::abs(onePass[t] - ref) <= 1e-12 * ref);
    CHECK(std::abs(perTerm[t] - ref) <= 3e-12 * ref);
    CHECK(std::abs(onePass[t] - perTerm[t]) <= 3e-12 * perTerm[t]);
  }
  CHECK(std::abs(d.norm - sim.deformationNorm()) <= 1e-14 * d.norm);
  CHECK(std::abs(d.kinetic - sim.kineticEnergy()) <= 1e-13 * d.kinetic);
}

TEST_CASE("Diagnostics: the same bits on one, two and three threads", "[core]") {
  // 75 moving rows: three blocks of rows (32, 32, 11), summed in block order whichever thread
  // computed them.
  using B = Boundary;
  const long minPoints = explicitParallelMinPoints();
  const int threads = kernelThreads();
  for (const Boundaries& bc : {Boundaries{}, Boundaries{B::Free, B::Free, B::Periodic, B::Periodic}}) {
    ModelParameters p;
    p.numU = 75;
    p.numV = 23;
    p.boundaries = bc;
    p.timeStep = 0.01;
    Simulation sim(p, restNet(SplineSpace(p.degreeU, p.degreeV, p.numU, p.numV, bc)));
    sim.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0.3, -0.2, 5.0), ParamRect{0.2, 0.7, 0.3, 0.9}));
    sim.advance(5);
    REQUIRE(sim.status() == Status::Ok);
    setExplicitParallelMinPoints(0);
    Diagnostics d[3];
    for (int t = 1; t <= 3; ++t) {
      setKernelThreads(t);
      d[t - 1] = sim.diagnostics();
    }
    setKernelThreads(threads);
    setExplicitParallelMinPoints(minPoints);
    REQUIRE(d[0].strain.total > 0.0);
    checkClose(d[0], sim, 1e-12);
    for (int t = 1; t < 3; ++t) {
      INFO(t + 1 << " threads");
      CHECK(std::memcmp(&d[0], &d[t], sizeof(Diagnostics)) == 0);
    }
  }
}

TEST_CASE("Diagnostics: a row computed beside the steps has the bits of diagnostics() at its state", "[core]") {
  using B = Boundary;
  ThreadSettingsGuard guard;
  struct Case {
    Boundaries bc;
    MassModel mass;
    bool pins;
    Integrator integrator;
  };
  const Case cases[] = {
      {Boundaries{}, MassModel::Nodal, false, Integrator::Explicit},
      {Boundaries{B::Free, B::Free, B::Periodic, B::Periodic}, MassModel::Lumped, true, Integrator::Explicit},
      {Boundaries{B::Periodic, B::Periodic, B::Free, B::Clamped}, MassModel::Nodal, true, Integrator::Explicit},
      {Boundaries{}, MassModel::Nodal, false, Integrator::Implicit},  // computed at once
  };
  for (const Case& c : cases) {
    ModelParameters p;
    p.numU = 70;  // three blocks of rows
    p.numV = 21;
    p.boundaries = c.bc;
    p.massModel = c.mass;
    p.integrator = c.integrator;
    p.timeStep = 0.01;
    if (c.pins) p.pins = {Eigen::Vector2d(0.4, 0.5)};
    INFO("boundaries " << boundaryName(c.bc.uMin) << "/" << boundaryName(c.bc.uMax) << "/" << boundaryName(c.bc.vMin)
                       << "/" << boundaryName(c.bc.vMax) << (c.integrator == Integrator::Implicit ? ", implicit" : ""));
    auto sim = std::make_unique<Simulation>(p, restNet(SplineSpace(p.degreeU, p.degreeV, p.numU, p.numV, c.bc)));
    sim->addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0.3, -0.2, 5.0), ParamRect{0.2, 0.7, 0.3, 0.9}));
    sim->advance(4);
    REQUIRE(sim->status() == Status::Ok);
    REQUIRE(sim->subSteps() <= 16);  // the background thread's range

    // Background thread on: the row's blocks run there or, at get(), on this thread.
    setBackgroundThreadEnabled(true);
    setKernelThreads(1);
    Diagnostics expected = sim->diagnostics();
    REQUIRE(expected.strain.total > 0.0);
    auto rows = std::make_unique<DiagnosticsBeside>();
    PendingDiagnostics row = rows->begin(*sim);
    sim->advance(3);
    const Diagnostics beside = row.get();
    CHECK(std::memcmp(&beside, &expected, sizeof(Diagnostics)) == 0);
    CHECK(sim->diagnostics().norm != expected.norm);  // the steps changed the state

    // Computed after the steps for certain: the background thread is kept busy by another work
    // until the row is taken, so get() runs every block on this thread from the copy of the state.
    expected = sim->diagnostics();
    {
      setBackgroundThreadEnabled(true);  // ends a back-off a slow get() above may have started
      std::atomic<bool> busy{false}, release{false};
      BackgroundWork blocker(1, [&](int) {
        busy = true;
        while (!release) std::this_thread::sleep_for(std::chrono::milliseconds(1));
      });
      struct Release {  // destroyed before `blocker`: its finish() never waits forever
        std::atomic<bool>& flag;
        ~Release() { flag = true; }
      } releaseOnExit{release};
      const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
      while (!busy && std::chrono::steady_clock::now() < deadline) std::this_thread::yield();
      CHECK(busy);
      row = rows->begin(*sim);
      sim->advance(2);
      const Diagnostics late = row.get();
      release = true;
      blocker.finish();
      CHECK(std::memcmp(&late, &expected, sizeof(Diagnostics)) == 0);
    }
    setBackgroundThreadEnabled(true);  // end the back-off the blocker's long wait started

    // A second row before the first was taken; then the simulation destroyed while a row is
    // computed (it reads only DiagnosticsBeside's copies), and a new model at the same place.
    expected = sim->diagnostics();
    PendingDiagnostics first = rows->begin(*sim);
    PendingDiagnostics second = rows->begin(*sim);
    sim->step();
    const Diagnostics third = sim->diagnostics();
    PendingDiagnostics last = rows->begin(*sim);
    sim.reset();
    const Diagnostics values[3] = {first.get(), second.get(), last.get()};
    CHECK(std::memcmp(&values[0], &expected, sizeof(Diagnostics)) == 0);
    CHECK(std::memcmp(&values[1], &expected, sizeof(Diagnostics)) == 0);
    CHECK(std::memcmp(&values[2], &third, sizeof(Diagnostics)) == 0);
    p.weights.w20 *= 2.0;  // another model: the copies are made again
    sim = std::make_unique<Simulation>(p, restNet(SplineSpace(p.degreeU, p.degreeV, p.numU, p.numV, c.bc)));
    sim->addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0.3, -0.2, 5.0), ParamRect{0.2, 0.7, 0.3, 0.9}));
    sim->advance(4);
    const Diagnostics rebuilt = sim->diagnostics();
    PendingDiagnostics again = rows->begin(*sim);
    PendingDiagnostics pendingAtDestruction = rows->begin(*sim);
    rows.reset();  // finishes the row
    const Diagnostics afterRebuild[2] = {again.get(), pendingAtDestruction.get()};
    CHECK(std::memcmp(&afterRebuild[0], &rebuilt, sizeof(Diagnostics)) == 0);
    CHECK(std::memcmp(&afterRebuild[1], &rebuilt, sizeof(Diagnostics)) == 0);
  }
  // Computed at once: background thread off, or two kernel threads.
  ModelParameters p;
  p.numU = 40;
  p.numV = 33;
  Simulation sim(p);
  sim.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0.0, 0.0, 5.0)));
  sim.advance(3);
  for (int variant = 0; variant < 2; ++variant) {
    setBackgroundThreadEnabled(variant == 1);
    setKernelThreads(variant == 1 ? 2 : 1);
    INFO((variant == 0 ? "background thread off" : "two kernel threads"));
    const Diagnostics expected = sim.diagnostics();
    DiagnosticsBeside beside;
    PendingDiagnostics row = beside.begin(sim);
    sim.step();
    const Diagnostics got = row.get();
    CHECK(std::memcmp(&got, &expected, sizeof(Diagnostics)) == 0);
    CHECK(sim.diagnostics().norm != expected.norm);
  }
}
