// SPDX-License-Identifier: MIT
#include "bsdeform/dynamics/SimulationState.h"

#include <cstring>

#include "bsdeform/dynamics/Simulation.h"

namespace bsdeform {

SimulationState stateOf(const Simulation& sim) {
  return {sim.current(), sim.previous(), sim.time(), sim.stepCount(), sim.subStepSize(), sim.startPending()};
}

void restoreState(Simulation& sim, const SimulationState& state) {
  // HeldPoints::Check: the held points were taken from a model with this rest net, so they
  // pass the check and are put back as the same bits.
  if (state.startPending) {
    sim.setState(state.current, state.time, state.steps);
  } else {
    // previousStepSize = the sub-step the state was taken at: nothing is rescaled while the
    // model's sub-step is the same, so `previous` comes back bit for bit
    sim.setState(state.current, state.previous, state.time, state.steps, state.subStepSize);
  }
}

std::size_t bytesOf(const SimulationState& state) {
  return sizeof(SimulationState) + sizeof(double) * std::size_t(state.current.size() + state.previous.size());
}

namespace {
bool sameBits(const ControlNet& a, const ControlNet& b) {
  return a.rows() == b.rows() && std::memcmp(a.data(), b.data(), sizeof(double) * std::size_t(a.size())) == 0;
}
bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
}  // namespace

bool sameBits(const SimulationState& a, const SimulationState& b) {
  return sameBits(a.current, b.current) && sameBits(a.previous, b.previous) && sameBits(a.time, b.time) &&
         a.steps == b.steps && sameBits(a.subStepSize, b.subStepSize) && a.startPending == b.startPending;
}

}  // namespace bsdeform
