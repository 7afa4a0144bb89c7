// SPDX-License-Identifier: MIT
#include <catch2/catch.hpp>
#include <memory>

#include "bsdeform/forces/Force.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/dynamics/SimulationState.h"

using namespace bsdeform;

namespace {
ModelParameters params(EnergyModel energy, Integrator integrator) {
  ModelParameters p;
  p.numU = p.numV = 5;
  p.energy = energy;
  p.integrator = integrator;
  p.damping = 0.2;
  if (energy == EnergyModel::Shell) p.timeStep = 0.002;  // SI units: a stiff 1 mm plate
  return p;
}
}  // namespace

TEST_CASE("SimulationState: a restored state goes on with the same bits as the uninterrupted run", "[core]") {
  for (EnergyModel energy : {EnergyModel::Paper, EnergyModel::Shell})
    for (Integrator integrator : {Integrator::Explicit, Integrator::Implicit}) {
      INFO("energy " << int(energy) << ", integrator " << int(integrator));
      const ModelParameters p = params(energy, integrator);
      Simulation sim(p);
      sim.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, 20)));
      const SimulationState atRest = stateOf(sim);
      REQUIRE(sim.advance(7) == Status::Ok);
      const SimulationState middle = stateOf(sim);
      REQUIRE(sim.advance(5) == Status::Ok);
      const SimulationState end = stateOf(sim);
      REQUIRE_FALSE(sameBits(middle, end));

      // back to the middle of the run, then on again: the same end
      restoreState(sim, middle);
      CHECK(sameBits(stateOf(sim), middle));
      REQUIRE(sim.advance(5) == Status::Ok);
      CHECK(sameBits(stateOf(sim), end));

      // back to the start (the start rule still due): the whole run again
      restoreState(sim, atRest);
      CHECK(sameBits(stateOf(sim), atRest));
      CHECK(sim.startPending());
      REQUIRE(sim.advance(12) == Status::Ok);
      CHECK(sameBits(stateOf(sim), end));

      // in a second model built alike (how the viewer's surfaces and bsdeform-run's differ)
      Simulation other(p);
      other.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, 20)));
      restoreState(other, middle);
      REQUIRE(other.advance(5) == Status::Ok);
      CHECK(sameBits(stateOf(other), end));
    }
}

TEST_CASE("SimulationState: a state of another net size is refused and the state is kept", "[core]") {
  Simulation sim(params(EnergyModel::Paper, Integrator::Explicit));
  sim.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, 20)));
  REQUIRE(sim.advance(3) == Status::Ok);
  const SimulationState before = stateOf(sim);
  ModelParameters bigger = params(EnergyModel::Paper, Integrator::Explicit);
  bigger.numU = 6;
  const SimulationState foreign = stateOf(Simulation(bigger));
  CHECK_THROWS_AS(restoreState(sim, foreign), std::invalid_argument);
  CHECK(sameBits(stateOf(sim), before));
  CHECK(bytesOf(before) >= 2 * sizeof(double) * size_t(before.current.size()));
}
