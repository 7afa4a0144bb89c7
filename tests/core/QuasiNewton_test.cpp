// SPDX-License-Identifier: MIT
// BACKWARD_EULER with nonlinearSolver LBFGS (NewtonMinimizer's quasi-Newton direction, the start
// matrix of TimeStepper.cpp): it finds the same minimum as Newton's method to within its
// tolerance, cannot gain energy, takes the paper's quadratic energy in one iteration (its start
// matrix is then that energy's Hessian), and stays bit-identical across thread counts.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <memory>

#include "../support/Cotton.h"
#include "../support/ThreadSettings.h"
#include "bsdeform/base/Parallel.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/forces/ForceLaws.h"

using namespace bsdeform;

namespace {
using test::kCotton;

/// A cotton curtain of n x n inner control points hinged at v = 1, released horizontal.
ModelParameters curtain(int n, NonlinearSolver solver, double velocityTolerance) {
  ModelParameters p;
  p.numU = p.numV = n;
  p.boundaries = Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::SimplySupported};
  p.energy = EnergyModel::Shell;
  p.material = kCotton;
  p.damping = 0.5;
  p.integrator = Integrator::BackwardEuler;
  p.timeStep = 0.02;
  p.nonlinearSolver = solver;
  p.newtonVelocityTolerance = velocityTolerance;
  p.maxNewtonIterations = solver == NonlinearSolver::LBFGS ? 400 : 30;
  return p;
}

std::shared_ptr<const Force> gravity() { return std::make_shared<GravityForce>(Eigen::Vector3d(0, 0, -9.81)); }
}  // namespace

TEST_CASE("LBFGS finds Newton's minimum of a step to within its velocity tolerance", "[shell]") {
  // a state of the swinging curtain (0.1 s in), then one step by each solver
  Simulation start(curtain(8, NonlinearSolver::Newton, 1e-10));
  start.addForce(gravity());
  start.advance(5);
  REQUIRE(start.status() == Status::Ok);
  auto oneStep = [&](NonlinearSolver solver, double tolerance) {
    Simulation sim(curtain(8, solver, tolerance));
    sim.addForce(gravity());
    sim.setState(start.current(), start.previous(), start.time(), 5);
    REQUIRE(sim.step() == Status::Ok);
    return std::make_pair(ControlNet(sim.current()), sim.lastNewtonIterations());
  };
  const ControlNet exact = oneStep(NonlinearSolver::Newton, 1e-11).first;
  const double moved = (exact - start.current()).cwiseAbs().maxCoeff();
  REQUIRE(moved > 1e-3);
  int lastIterations = 0;
  for (double tolerance : {1e-2, 1e-3, 1e-4, 1e-5}) {
    const auto [net, iterations] = oneStep(NonlinearSolver::LBFGS, tolerance);
    const double error = (net - exact).cwiseAbs().maxCoeff();
    const double h = 0.02;
    CAPTURE(tolerance, iterations, error, error / (tolerance * h));
    // Newton's own error at these tolerances is 1.5 to 3 tolerance x h (its last step is taken)
    CHECK(error <= 6.0 * tolerance * h);
    CHECK(iterations >= lastIterations);  // a tighter tolerance never takes fewer
    lastIterations = iterations;
  }
}

TEST_CASE("LBFGS: the energy of a free swing never rises, and falls with damping", "[shell]") {
  for (double damping : {0.0, 2.0}) {
    CAPTURE(damping);
    ModelParameters p = curtain(6, NonlinearSolver::LBFGS, 1e-8);
    p.damping = damping;
    p.timeStep = 0.01;
    Simulation sim(p);
    // released from a bent state with no load: kinetic + strain energy only
    ControlNet net = sim.rest();
    for (Eigen::Index r = 0; r < net.rows(); ++r) net(r, 2) += 0.05 * std::pow(1.0 - sim.rest()(r, 1), 2);
    sim.space().completeNet(net, &sim.rest());
    sim.setState(net, 0.0, 0, HeldPoints::Reset);
    auto energy = [&] { return sim.kineticEnergy() + sim.strainEnergy().total; };
    const double e0 = energy();
    REQUIRE(e0 > 0.0);
    double last = e0;
    for (int k = 0; k < 40; ++k) {
      INFO("step " << k << ": " << sim.statusMessage());
      REQUIRE(sim.step() == Status::Ok);
      const double e = energy();
      CHECK(e <= last * (1.0 + 1e-7));
      last = e;
    }
    CHECK(sim.kineticEnergy() > 0.0);
    CHECK(last < e0);
  }
}

TEST_CASE("LBFGS takes the paper's quadratic energy in one iteration: its start matrix is the exact one", "[core]") {
  auto run = [](NonlinearSolver solver) {
    ModelParameters p;
    p.numU = p.numV = 7;
    p.integrator = Integrator::BackwardEuler;
    p.timeStep = 0.05;
    p.nonlinearSolver = solver;
    p.newtonVelocityTolerance = 1e-10;
    Simulation sim(p);
    sim.addForce(std::make_shared<GravityForce>(1.0, Eigen::Vector3d(0.1, 0.2, -9.81)));
    int most = 0;
    for (int k = 0; k < 10; ++k) {
      REQUIRE(sim.step() == Status::Ok);
      most = std::max(most, sim.lastNewtonIterations());
    }
    return std::make_pair(ControlNet(sim.current()), most);
  };
  const auto [newton, newtonIterations] = run(NonlinearSolver::Newton);
  const auto [lbfgs, lbfgsIterations] = run(NonlinearSolver::LBFGS);
  CHECK(lbfgsIterations == 1);
  CHECK((lbfgs - newton).cwiseAbs().maxCoeff() <= 1e-10 * newton.cwiseAbs().maxCoeff());
  CHECK(newton.col(2).minCoeff() < -1e-3);  // the load moved it
}

TEST_CASE("LBFGS is bit-identical for one and two threads, and a resumed run takes the same steps", "[shell]") {
  ThreadSettingsGuard guard;
  ControlNet results[2];
  for (int threads : {1, 2}) {
    setKernelThreads(threads);
    Simulation sim(curtain(14, NonlinearSolver::LBFGS, 1e-3));
    sim.addForce(gravity());
    sim.advance(4);
    REQUIRE(sim.status() == Status::Ok);
    results[threads - 1] = sim.current();
  }
  CHECK((results[0].array() == results[1].array()).all());
  // resumed: a new model given the state after 2 steps goes on as the first one did
  Simulation first(curtain(10, NonlinearSolver::LBFGS, 1e-3));
  first.addForce(gravity());
  first.advance(2);
  Simulation resumed(curtain(10, NonlinearSolver::LBFGS, 1e-3));
  resumed.addForce(gravity());
  resumed.setState(first.current(), first.previous(), first.time(), 2);
  first.advance(3);
  resumed.advance(3);
  REQUIRE(first.status() == Status::Ok);
  CHECK((first.current().array() == resumed.current().array()).all());
}

TEST_CASE("LBFGS: the viewer's drag spring at the model's stiffness moves a SHELL sheet as Newton's does", "[shell]") {
  auto drag = [](NonlinearSolver solver) {
    ModelParameters p = curtain(6, solver, 1e-5);
    p.damping = 2.0;
    Simulation sim(p);
    REQUIRE(sim.dragStiffness() > 0.0);
    const Eigen::Vector3d start = sim.evaluate(0.5, 0.2).position;
    auto anchor = std::make_shared<Eigen::Vector3d>(start + Eigen::Vector3d(0, 0, 0.1));
    sim.addForce(std::make_shared<SpringForce>(0.5, 0.2, anchor, sim.dragStiffness()));
    sim.advance(25);
    INFO(sim.statusMessage());
    REQUIRE(sim.status() == Status::Ok);
    return sim.evaluate(0.5, 0.2).position.z() - start.z();
  };
  const double newton = drag(NonlinearSolver::Newton), lbfgs = drag(NonlinearSolver::LBFGS);
  CAPTURE(newton, lbfgs);
  CHECK(lbfgs > 0.05);  // towards the mouse, a good part of the 0.1 it asks
  CHECK(std::abs(lbfgs - newton) <= 1e-3);
}
