// SPDX-License-Identifier: MIT
#include "bsdeform/dynamics/SimulationState.h"

#include <cmath>
#include <cstring>
#include <sstream>
#include <stdexcept>
#include <string>

#include "bsdeform/dynamics/Simulation.h"

namespace bsdeform {

SimulationState stateOf(const Simulation& sim) {
  return {sim.current(), sim.previous(), sim.time(), sim.stepCount(), sim.subStepSize(), sim.startPending(),
          forceStatesOf(sim)};
}

std::vector<double> forceStatesOf(const Simulation& sim) {
  std::vector<double> out;
  bool any = false;
  for (const auto& f : sim.forces()) {
    const std::vector<double> s = f->adaptedState();
    out.push_back(double(s.size()));
    out.insert(out.end(), s.begin(), s.end());
    any |= !s.empty();
  }
  if (!any) out.clear();
  return out;
}

void restoreForceStates(const Simulation& sim, const std::vector<double>& states) {
  size_t at = 0;
  for (size_t i = 0; i < sim.forces().size(); ++i) {
    std::vector<double> s;
    if (at < states.size()) {
      const double count = states[at];
      if (!(count >= 0.0) || count != std::floor(count) || count > double(states.size() - at - 1)) {
        std::ostringstream os;
        os << "forceState: force " << i + 1 << "'s count " << count << " (at value " << at + 1 << " of "
           << states.size() << ") is not a whole number of the values that follow";
        throw std::invalid_argument(os.str());
      }
      s.assign(states.begin() + long(at) + 1, states.begin() + long(at) + 1 + long(count));
      at += 1 + size_t(count);
    }
    try {
      sim.forces()[i]->setAdaptedState(s);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("forceState: force " + std::to_string(i + 1) + ": " + e.what());
    }
  }
}

void restoreState(Simulation& sim, const SimulationState& state) {
  // all or nothing: a force state or a net refused leaves the simulation as it was
  const std::vector<double> before = forceStatesOf(sim);
  try {
    restoreForceStates(sim, state.forces);
    // HeldPoints::Check: the held points were taken from a model with this rest net, so they
    // pass the check and are put back as the same bits.
    if (state.startPending) {
      sim.setState(state.current, state.time, state.steps);
    } else {
      // previousStepSize = the sub-step the state was taken at: nothing is rescaled while the
      // model's sub-step is the same, so `previous` comes back bit for bit
      sim.setState(state.current, state.previous, state.time, state.steps, state.subStepSize);
    }
  } catch (...) {
    restoreForceStates(sim, before);
    throw;
  }
}

std::size_t bytesOf(const SimulationState& state) {
  return sizeof(SimulationState) +
         sizeof(double) * (std::size_t(state.current.size() + state.previous.size()) + state.forces.size());
}

namespace {
bool sameBits(const ControlNet& a, const ControlNet& b) {
  return a.rows() == b.rows() && std::memcmp(a.data(), b.data(), sizeof(double) * std::size_t(a.size())) == 0;
}
bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
}  // namespace

bool sameBits(const SimulationState& a, const SimulationState& b) {
  return sameBits(a.current, b.current) && sameBits(a.previous, b.previous) && sameBits(a.time, b.time) &&
         a.steps == b.steps && sameBits(a.subStepSize, b.subStepSize) && a.startPending == b.startPending &&
         a.forces.size() == b.forces.size() &&
         (a.forces.empty() || std::memcmp(a.forces.data(), b.forces.data(), sizeof(double) * a.forces.size()) == 0);
}

}  // namespace bsdeform
