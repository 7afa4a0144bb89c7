// SPDX-License-Identifier: MIT
// SHELL's BACKWARD_EULER step (TimeStepper.h, docs/math.md §16): the incremental potential
// minimised by Newton with every force inside. Its energy never rises without forcing, it
// converges at first order in the time step, forces act at the new state (a penalty plane holds
// a falling sheet without energy creeping in), the drag spring moves a sheet, and the results
// are bit-identical for one and two threads. The tangent it factorises (TangentMatrix, folded
// through periodic and derived sides) is checked against the Hessian product.
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <random>

#include "../support/Cotton.h"
#include "../support/TangentCheck.h"
#include "../support/ThreadSettings.h"
#include "bsdeform/forces/ForceLaws.h"
#include "bsdeform/base/Parallel.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/dynamics/TangentMatrix.h"

using namespace bsdeform;

namespace {
ModelParameters sheet(Integrator integrator, double dt, Boundaries b = Boundaries{Boundary::Free, Boundary::Free,
                                                                                Boundary::Free,
                                                                                Boundary::SimplySupported}) {
  ModelParameters p;
  p.numU = p.numV = 6;
  p.boundaries = b;
  p.energy = EnergyModel::Shell;
  p.material = ShellMaterial{1.0e4, 0.3, 0.005, 200.0};
  p.damping = 0.0;
  p.integrator = integrator;
  p.timeStep = dt;
  p.newtonVelocityTolerance = 1e-9;
  return p;
}

// A 12² cotton curtain hinged at its top (v = 1), released horizontal, Δt = 0.02.
ModelParameters cottonCurtain() {
  ModelParameters p;
  p.numU = p.numV = 12;
  p.boundaries = Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::SimplySupported};
  p.energy = EnergyModel::Shell;
  p.material = test::kCotton;
  p.damping = 0.5;
  p.timeStep = 0.02;
  return p;
}

ControlNet bent(const Simulation& sim) {
  ControlNet net = sim.rest();
  for (Eigen::Index r = 0; r < net.rows(); ++r) {
    const double v = sim.rest()(r, 1);
    net(r, 2) += 0.05 * (1 - v) * (1 - v);
  }
  sim.space().completeNet(net, &sim.rest());
  return net;
}

/// Kinetic + strain energy, minus the work potential of a constant load L (-L . x).
double mechanicalEnergy(const Simulation& sim, const ControlNet& load) {
  const ControlNet x = sim.space().gatherMoving(sim.current());
  return sim.kineticEnergy() + sim.strainEnergy().total - (load.array() * x.array()).sum();
}
}  // namespace

TEST_CASE("TangentMatrix: the folded tangent equals the energy's Hessian product on the unknowns", "[shell]") {
  using B = Boundary;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> X(-1.0, 1.0);
  for (const Boundaries& b : {Boundaries{B::Free, B::Free, B::Free, B::Free},
                              Boundaries{B::Periodic, B::Periodic, B::SimplySupported, B::BuiltIn},
                              Boundaries{B::SimplySupported, B::Clamped, B::Periodic, B::Periodic}}) {
    const SplineSpace s(3, 3, 5, 6, b);
    ControlNet rest = ControlNet::Zero(s.netSize(), 3);
    for (int i = 0; i < s.netRows(); ++i)
      for (int j = 0; j < s.netCols(); ++j) {
        const double u = double(i) / (s.netRows() - 1), v = double(j) / (s.netCols() - 1);
        rest.row(Eigen::Index(i) * s.netCols() + j) << std::cos(2.0 * u) + 0.2 * v, v + 0.1 * u, std::sin(2.0 * u);
      }
    const ShellModelEnergy energy(s, rest, ShellMaterial{1e5, 0.3, 0.01, 100.0});
    ControlNet x = s.gatherMoving(rest);
    for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] += 0.05 * X(rng);
    ControlNet net = rest;
    s.scatterMoving(x, net);
    s.completeNet(net, &rest);
    TangentMatrix K(s, energy.foldStart(), energy.foldEntries());
    energy.shell().elementHessians(net, HessianMode::Exact, s.periodicU(),
                                   [&](int e1, int e2, const double* Ke) { K.addElement(e1, e2, Ke, 1.0); });
    ControlNet d(x.rows(), 3);
    for (Eigen::Index i = 0; i < d.size(); ++i) d.data()[i] = X(rng);
    ControlNet Hd;
    energy.hessianProduct(net, d, Hd);
    CHECK(test::tangentProductError(K, d, Hd) <= 1e-10 * Hd.cwiseAbs().maxCoeff());
    CHECK(Hd.cwiseAbs().maxCoeff() > 0.0);
  }
}

TEST_CASE("TangentMatrix: blocks between points of no common element enter the pattern, which then depends on "
          "the last assembly alone",
          "[shell]") {
  // The energy's element matrices plus symmetric blocks coupling far-apart points (self-contact):
  // the matrix equals the dense sum of the same blocks, and its pattern after an assembly is
  // the elements' plus exactly that assembly's far blocks, whatever came before.
  const SplineSpace s(2, 2, 8, 8, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
  const ControlNet rest = s.grevillePlane();
  const ShellModelEnergy energy(s, rest, ShellMaterial{1e5, 0.3, 0.01, 100.0});
  const Eigen::Index cols = s.netCols();
  Eigen::Matrix3d B;
  B << 2.0, 0.5, -0.25, 0.5, 1.5, 0.125, -0.25, 0.125, 1.0;
  using Far = std::vector<std::pair<Eigen::Index, Eigen::Index>>;
  // net points (2, 2) and (8, 8), (1, 9) and (9, 1): no element holds both of a pair
  const Far first{{2 * cols + 2, 8 * cols + 8}, {1 * cols + 9, 9 * cols + 1}}, second{{2 * cols + 2, 8 * cols + 8}};
  auto assemble = [&](TangentMatrix& K, const Far& far, double scale) {
    K.setZero();
    energy.shell().elementHessians(rest, HessianMode::Exact, true,
                                   [&](int e1, int e2, const double* Ke) { K.addElement(e1, e2, Ke, 1.0); });
    for (const auto& [p, q] : far) {  // both blocks of a symmetric coupling, as a force adds them
      K.addNetBlock(p, q, scale * B);
      K.addNetBlock(q, p, scale * B.transpose());
      K.addNetBlock(p, p, scale * B);
    }
    return K.settlePattern();
  };
  auto dense = [&](const Far& far, double scale) {
    TangentMatrix base(s, energy.foldStart(), energy.foldEntries());
    assemble(base, {}, scale);
    Eigen::MatrixXd D = Eigen::MatrixXd(Eigen::SparseMatrix<double>(base.matrix().selfadjointView<Eigen::Lower>()));
    for (const auto& [p, q] : far) {
      const Eigen::Index f = p, g = q;  // free sides: net point = unknown
      D.block<3, 3>(3 * f, 3 * g) += scale * B;
      D.block<3, 3>(3 * g, 3 * f) += scale * B.transpose();
      D.block<3, 3>(3 * f, 3 * f) += scale * B;
    }
    return D;
  };
  REQUIRE(s.numMoving() == s.netSize());
  TangentMatrix K(s, energy.foldStart(), energy.foldEntries());
  const Eigen::Index baseNonZeros = K.matrix().nonZeros();
  CHECK(assemble(K, first, 1.0));  // the pattern grew
  CHECK(K.matrix().nonZeros() == baseNonZeros + 2 * 9);
  Eigen::MatrixXd full = Eigen::MatrixXd(Eigen::SparseMatrix<double>(K.matrix().selfadjointView<Eigen::Lower>()));
  CHECK((full - dense(first, 1.0)).norm() <= 1e-12 * full.norm());
  CHECK_FALSE(assemble(K, first, 3.0));  // the same far blocks: the same pattern
  full = Eigen::MatrixXd(Eigen::SparseMatrix<double>(K.matrix().selfadjointView<Eigen::Lower>()));
  CHECK((full - dense(first, 3.0)).norm() <= 1e-12 * full.norm());
  CHECK(assemble(K, second, 1.0));  // one far block fewer: the pattern shrinks to this assembly's
  TangentMatrix fresh(s, energy.foldStart(), energy.foldEntries());
  assemble(fresh, second, 1.0);
  CHECK(K.matrix().nonZeros() == baseNonZeros + 9);
  CHECK(K.matrix().nonZeros() == fresh.matrix().nonZeros());
  CHECK(std::equal(K.matrix().innerIndexPtr(), K.matrix().innerIndexPtr() + K.matrix().nonZeros(),
                   fresh.matrix().innerIndexPtr()));
  CHECK(std::equal(K.matrix().valuePtr(), K.matrix().valuePtr() + K.matrix().nonZeros(), fresh.matrix().valuePtr()));
  // grown again from a pattern that held one of the two far blocks: settled twice, it stays
  CHECK(assemble(K, first, 1.0));
  const std::vector<double> settled(K.matrix().valuePtr(), K.matrix().valuePtr() + K.matrix().nonZeros());
  CHECK_FALSE(K.settlePattern());
  CHECK(K.matrix().nonZeros() == baseNonZeros + 2 * 9);
  CHECK(std::equal(settled.begin(), settled.end(), K.matrix().valuePtr()));
  CHECK(assemble(K, {}, 1.0));  // and back to the elements'
  CHECK(K.matrix().nonZeros() == baseNonZeros);
}

TEST_CASE("BACKWARD_EULER: the energy of a free swing never rises, and falls with damping", "[shell]") {
  for (double damping : {0.0, 2.0}) {
    CAPTURE(damping);
    ModelParameters p = sheet(Integrator::BackwardEuler, 4e-3);
    p.damping = damping;
    Simulation sim(p);
    sim.setState(bent(sim), 0.0, 0, HeldPoints::Reset);
    const ControlNet none = ControlNet::Zero(sim.space().numMoving(), 3);
    double last = mechanicalEnergy(sim, none);
    const double e0 = last;
    REQUIRE(e0 > 0.0);
    for (int k = 0; k < 60; ++k) {
      REQUIRE(sim.step() == Status::Ok);
      const double e = mechanicalEnergy(sim, none);
      CHECK(e <= last * (1.0 + 1e-9));
      last = e;
    }
    CHECK(sim.kineticEnergy() > 0.0);  // it moved
    CHECK(last < e0);                  // backward Euler dissipates
  }
}

// [slow]: 35 s under the sanitizers (the Release suite runs it)
TEST_CASE("BACKWARD_EULER converges at first order in the time step", "[shell][slow]") {
  auto finalState = [](double dt) {
    Simulation sim(sheet(Integrator::BackwardEuler, dt));
    sim.setState(bent(sim), 0.0, 0, HeldPoints::Reset);
    sim.advance(long(0.08 / dt + 0.5));
    REQUIRE(sim.status() == Status::Ok);
    return ControlNet(sim.current());
  };
  const ControlNet a = finalState(1e-3), b = finalState(5e-4), c = finalState(2.5e-4);
  const double ratio = (a - b).norm() / (b - c).norm();
  CAPTURE(ratio);
  CHECK(ratio > 1.7);
  CHECK(ratio < 2.4);
}

TEST_CASE("BACKWARD_EULER: forces act at the new state, and a sheet falls onto a penalty plane and rests there",
          "[shell][slow]") {
  ModelParameters p = sheet(Integrator::BackwardEuler, 0.01, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free,
                                                                         Boundary::Free});
  p.damping = 1.0;
  p.timeStep = 0.02;
  Simulation sim(p);
  const double rhoT = p.material.density * p.material.thickness;
  sim.addForce(std::make_shared<GravityForce>(rhoT, Eigen::Vector3d(0, 0, -9.81)));
  // a stiff penalty: explicit load freezing would pump energy in at this step
  sim.addForce(std::make_shared<PlaneContactForce>(Eigen::Vector3d(0, 0, -0.05), Eigen::Vector3d(0, 0, 1), 1e5));
  for (int k = 0; k < 150; ++k) {
    REQUIRE(sim.step() == Status::Ok);
    REQUIRE(sim.current().col(2).maxCoeff() < 0.01);
  }
  // at rest on the plane: penetration of the weight over the stiffness, and no motion left
  const double sink = rhoT * 9.81 / 1e5;
  CHECK(sim.current().col(2).minCoeff() > -0.05 - 3.0 * sink - 1e-4);
  CHECK(sim.kineticEnergy() < 1e-8);
}

TEST_CASE("BACKWARD_EULER: the drag spring at the model's stiffness moves a SHELL sheet", "[shell]") {
  ModelParameters p = sheet(Integrator::BackwardEuler, 0.02);
  p.damping = 2.0;
  Simulation sim(p);
  REQUIRE(sim.dragStiffness() > 0.0);
  const Eigen::Vector3d start = sim.evaluate(0.5, 0.2).position;
  auto anchor = std::make_shared<Eigen::Vector3d>(start + Eigen::Vector3d(0, 0, 0.1));
  sim.addForce(std::make_shared<SpringForce>(0.5, 0.2, anchor, sim.dragStiffness()));
  sim.advance(50);
  CAPTURE(sim.statusMessage());
  REQUIRE(sim.status() == Status::Ok);
  const double lifted = sim.evaluate(0.5, 0.2).position.z() - start.z();
  CAPTURE(lifted);
  CHECK(lifted > 0.05);  // towards the mouse, a good part of the 0.1 it asks
  CHECK(lifted < 0.1 + 1e-9);
}

TEST_CASE("BACKWARD_EULER: a drag spring whose anchor the user moves does work and is no blow-up", "[shell]") {
  // the viewer's drag: the anchor follows the mouse, and what the spring stores at one anchor is
  // not what it stored at the last; the energy the pull puts in is work, not a blow-up
  ModelParameters p = sheet(Integrator::BackwardEuler, 0.02);
  p.damping = 0.1;
  Simulation sim(p);
  const Eigen::Vector3d start = sim.evaluate(0.5, 0.2).position;
  auto anchor = std::make_shared<Eigen::Vector3d>(start);
  sim.addForce(std::make_shared<SpringForce>(0.5, 0.2, anchor, sim.dragStiffness()));
  for (int k = 1; k <= 60; ++k) {
    *anchor = start + Eigen::Vector3d(0.0, 0.0, 0.5 * std::sin(0.2 * k));  // a quick pull up and down
    REQUIRE(sim.step() == Status::Ok);
  }
  CAPTURE(sim.statusMessage());
  CHECK(sim.kineticEnergy() > 1e-6);  // the pull moved it
}

TEST_CASE("BACKWARD_EULER is bit-identical for one and two threads", "[shell]") {
  ThreadSettingsGuard guard;
  ControlNet results[2];
  for (int threads : {1, 2}) {
    setKernelThreads(threads);
    ModelParameters p = sheet(Integrator::BackwardEuler, 0.01);
    p.numU = p.numV = 14;
    Simulation sim(p);
    sim.addForce(std::make_shared<GravityForce>(1.0, Eigen::Vector3d(0, 0, -9.81)));
    sim.advance(5);
    REQUIRE(sim.status() == Status::Ok);
    results[threads - 1] = sim.current();
  }
  CHECK((results[0].array() == results[1].array()).all());
}

// [slow]: a minute under the sanitizers (the Release suite runs it)
TEST_CASE("IMPLICIT (Newmark) takes the forces at the iterate: a sheet bouncing on a penalty plane gains no energy",
          "[shell][slow]") {
  for (Integrator integrator : {Integrator::Implicit, Integrator::BackwardEuler}) {
    CAPTURE(integrator == Integrator::Implicit);
    // Newmark's error at an impact falls with the step (the penalty's period is 0.044 s)
    const double dt = integrator == Integrator::Implicit ? 0.0025 : 0.01;
    ModelParameters p = sheet(integrator, dt, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
    p.newtonTolerance = 1e-10;
    Simulation sim(p);
    const double rhoT = p.material.density * p.material.thickness, g = 9.81, k = 2e4, plane = -0.05;
    sim.addForce(std::make_shared<GravityForce>(rhoT, Eigen::Vector3d(0, 0, -g)));
    auto contact = std::make_shared<PlaneContactForce>(Eigen::Vector3d(0, 0, plane), Eigen::Vector3d(0, 0, 1), k);
    sim.addForce(contact);
    // kinetic (of the step's velocity) + strain + gravity's and the penalty's potentials (the
    // sheet's area is 1), the potentials averaged over the step's two states as the kinetic
    // energy is taken between them (what the three-level schemes conserve)
    auto potential = [&](const ControlNet& net) {
      double phi = 0.0;
      const LoadContext ctx{sim.space(), net, net, dt, sim.time(), &sim.rest()};
      REQUIRE(contact->potential(ctx, phi));
      double z = 0.0;
      for (double u = 0.025; u < 1.0; u += 0.05)
        for (double v = 0.025; v < 1.0; v += 0.05) z += 0.0025 * sim.space().evaluate(net, u, v, 0).position.z();
      return sim.shell()->energy(net).total() + rhoT * g * z + phi;
    };
    auto energy = [&] { return sim.kineticEnergy() + 0.5 * (potential(sim.current()) + potential(sim.previous())); };
    const double e0 = energy(), drop = rhoT * g * 0.05;
    double worst = e0;
    bool touched = false;
    for (int s = 0; s < int(0.6 / dt); ++s) {
      REQUIRE(sim.step() == Status::Ok);
      const bool in = std::min(sim.current().col(2).minCoeff(), sim.previous().col(2).minCoeff()) < plane;
      touched |= in;
      // out of contact (in contact the two states the energy is taken between straddle the
      // stiff penalty: a measurement error of O(dt))
      if (!in) worst = std::max(worst, energy());
    }
    CHECK(touched);
    CAPTURE(e0, worst, drop);
    if (integrator == Integrator::BackwardEuler)
      CHECK(worst <= e0 + 1e-9);  // dissipative
    else
      CHECK(worst <= e0 + 0.05 * drop);
  }
}

// [slow]: two minutes under the sanitizers (the Release suite runs it)
TEST_CASE("The implicit steppers report a total energy that rises with no work done as a blow-up", "[shell][slow]") {
  // a cotton curtain hinged at its top, released horizontal, Δt = 0.02: Newmark's energy is not
  // bounded for the stiff membrane at this step (it rose to 3.5 MJ in 2 s and was drawn);
  // backward Euler dissipates and runs through
  ModelParameters p = cottonCurtain();
  const double rhoT = p.material.density * p.material.thickness;
  for (Integrator integrator : {Integrator::Implicit, Integrator::BackwardEuler}) {
    CAPTURE(integrator == Integrator::Implicit);
    p.integrator = integrator;
    Simulation sim(p);
    sim.addForce(std::make_shared<GravityForce>(rhoT, Eigen::Vector3d(0, 0, -9.81)));
    sim.advance(100);
    if (integrator == Integrator::BackwardEuler) {
      CHECK(sim.status() == Status::Ok);
      CHECK(sim.shellEnergies().total() < 0.01);  // a hanging curtain stores millijoules
    } else if (sim.status() != Status::Ok) {
      CHECK(sim.status() == Status::Diverged);
      CHECK(sim.statusMessage().find("total energy rose") != std::string::npos);
      CHECK(sim.shellEnergies().total() < 1.0);  // the last valid state, not the blown-up one
    } else {
      CHECK(sim.shellEnergies().total() < 1.0);  // or it stayed bounded
    }
  }
}

// [slow]: Newmark's 12² run, as above
TEST_CASE("The energy check counts the work of a wind: a blow-up under it is reported, the work itself is not",
          "[shell][slow]") {
  // the curtain above hinged at its top (y = 1) in a gusting wind along +y (a load that depends
  // on time, so it stores no energy and does work): before, a load that can do work switched
  // the check off, and Newmark's curtain blew up to kilojoules unreported (the shipped flag with
  // integrator IMPLICIT: 21 kJ of strain at t = 2, drawn)
  ModelParameters p = cottonCurtain();
  const double rhoT = p.material.density * p.material.thickness;
  auto wind = [](const SurfaceSample& s) { return Eigen::Vector3d(0.0, 2.0 * (1.0 + std::sin(3.0 * s.t)), 0.0); };
  for (Integrator integrator : {Integrator::Implicit, Integrator::BackwardEuler}) {
    CAPTURE(integrator == Integrator::Implicit);
    p.integrator = integrator;
    Simulation sim(p);
    sim.addForce(std::make_shared<GravityForce>(rhoT, Eigen::Vector3d(0, 0, -9.81)));
    sim.addForce(std::make_shared<DistributedForce>(wind, kDependsOnTime));
    sim.advance(100);
    CAPTURE(sim.statusMessage());
    if (integrator == Integrator::BackwardEuler) {
      // the wind blows the curtain out along +y and keeps it swinging: work done, no blow-up
      REQUIRE(sim.status() == Status::Ok);
      Simulation calm(p);
      calm.addForce(std::make_shared<GravityForce>(rhoT, Eigen::Vector3d(0, 0, -9.81)));
      calm.advance(100);
      REQUIRE(calm.status() == Status::Ok);
      CAPTURE(sim.current().col(1).mean(), calm.current().col(1).mean());
      CHECK(sim.current().col(1).mean() > calm.current().col(1).mean() + 0.1);
      CHECK(sim.kineticEnergy() + sim.shellEnergies().total() < 1.0);
    } else if (sim.status() != Status::Ok) {
      CHECK(sim.status() == Status::Diverged);
      CHECK(sim.statusMessage().find("the loads did") != std::string::npos);
      // the last valid state, caught a few steps into the blow-up (the margin is the reference's
      // scale, gravity's reach over the sheet: about 2 J), not the kilojoules it went on to
      CHECK(sim.shellEnergies().total() < 10.0);
    } else {
      CHECK(sim.shellEnergies().total() < 1.0);  // or it stayed bounded
    }
  }
}

TEST_CASE("BACKWARD_EULER: a run resumed from its state takes the same steps, bit for bit", "[shell][slow]") {
  ModelParameters p = sheet(Integrator::BackwardEuler, 0.02, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free,
                                                                         Boundary::Free});
  p.damping = 1.0;
  p.newtonVelocityTolerance = 1e-4;
  const double rhoT = p.material.density * p.material.thickness;
  auto withForces = [&](Simulation& sim) {
    sim.addForce(std::make_shared<GravityForce>(rhoT, Eigen::Vector3d(0, 0, -9.81)));
    sim.addForce(std::make_shared<PlaneContactForce>(Eigen::Vector3d(0, 0, -0.02), Eigen::Vector3d(0.1, 0, 1), 1e5));
  };
  Simulation a(p);
  withForces(a);
  a.advance(15);  // falling, then on the tilted plane
  REQUIRE(a.status() == Status::Ok);
  Simulation b(p);
  withForces(b);
  b.setState(a.current(), a.previous(), a.time(), a.stepCount(), a.subStepSize());
  a.advance(10);
  b.advance(10);
  REQUIRE(a.status() == Status::Ok);
  REQUIRE(b.status() == Status::Ok);
  CHECK(a.current().col(2).minCoeff() < -0.01);  // it reached the plane
  CHECK((a.current().array() == b.current().array()).all());
}

namespace {
double toFloat(double x) { return double(float(x)); }
}  // namespace

TEST_CASE("setStateRounding: the state is kept rounded and a run resumed from it takes the same steps bit for bit",
          "[core][shell]") {
  // a rounding far coarser than a file's (float), so that a stepper that kept anything of the
  // unrounded state (Newmark's gradients) would part from the resumed run at once
  for (Integrator integrator : {Integrator::Explicit, Integrator::Implicit, Integrator::BackwardEuler}) {
    CAPTURE(int(integrator));
    const ModelParameters p = sheet(integrator, 0.01);
    auto make = [&] {
      auto sim = std::make_unique<Simulation>(p);
      sim->addForce(std::make_shared<GravityForce>(1.0, Eigen::Vector3d(0, 0, -9.81)));
      sim->setStateRounding(&toFloat);
      return sim;
    };
    std::unique_ptr<Simulation> a = make();
    a->setState(bent(*a), 0.0, 0);
    REQUIRE(a->advance(4) == Status::Ok);
    // the moving points rounded (the SIMPLY_SUPPORTED side's held points are at the rest net's
    // values and its derived layers follow their sources, as setState() puts them)
    CHECK(a->time() == toFloat(a->time()));
    Eigen::Index rounded = 0;
    for (Eigen::Index f = 0; f < a->space().numMoving(); ++f)
      for (int c = 0; c < 3; ++c) {
        const Eigen::Index r = a->space().movingToNet(f);
        const bool atRounding = a->current()(r, c) == toFloat(a->current()(r, c));
        const bool atRest = a->current()(r, c) == a->rest()(r, c);
        CHECK((atRounding || atRest));
        rounded += atRounding && !atRest;
      }
    CHECK(rounded > a->space().numMoving());  // the moving points did move, and are rounded
    std::unique_ptr<Simulation> b = make();
    b->setState(a->current(), a->previous(), a->time(), a->stepCount());
    REQUIRE(a->advance(5) == Status::Ok);
    REQUIRE(b->advance(5) == Status::Ok);
    CHECK(a->current() == b->current());
    CHECK(a->previous() == b->previous());
    // without the rounding the same resume is not bit for bit here (what the test could miss)
    std::unique_ptr<Simulation> c = make(), d = make();
    c->setStateRounding(nullptr);
    d->setStateRounding(nullptr);
    c->setState(bent(*c), 0.0, 0);
    REQUIRE(c->advance(4) == Status::Ok);
    d->setState(c->current().unaryExpr(&toFloat), c->previous().unaryExpr(&toFloat), c->time(), c->stepCount(), 0.0,
                HeldPoints::Reset);
    c->advance(5);
    d->advance(5);
    CHECK(c->current() != d->current());
  }
}
