// SPDX-License-Identifier: MIT
#pragma once
/// @file SimulationState.h
/// Everything a Simulation's motion depends on besides its model: the two nets, the clock and
/// whether the start rule is still due. Taken with stateOf() and put back with restoreState(),
/// the simulation goes on with the same bits as if it had never left that state (the viewer's
/// timeline, bsdeform-run --keep-states).

#include <cstddef>
#include <vector>

#include "bsdeform/spline/SplineSpace.h"

namespace bsdeform {

class Simulation;

struct SimulationState {
  ControlNet current;        ///< Simulation::current(), #net rows by 3
  ControlNet previous;       ///< Simulation::previous(): one sub-step of `subStepSize` before
  double time = 0.0;         ///< Simulation::time()
  long steps = 0;            ///< Simulation::stepCount()
  double subStepSize = 0.0;  ///< the sub-step `previous` is one of (Simulation::subStepSize())
  bool startPending = true;  ///< released from rest: the start rule applies at the next step
  std::vector<double> forces;  ///< forceStatesOf(): what the forces adapt between steps
};

/// What the simulation's forces adapt between steps (Force::adaptedState()), in their order, each
/// as its count followed by its values; empty when no force has any.
std::vector<double> forceStatesOf(const Simulation& sim);
/// Gives each force its part of `states` (forceStatesOf()); a force past the end, or every force
/// when `states` is empty, goes back to the state it was made with.
/// @throws std::invalid_argument naming the problem (a count that runs past the end, a state a
///         force refuses)
void restoreForceStates(const Simulation& sim, const std::vector<double>& states);

/// The state of `sim` now.
SimulationState stateOf(const Simulation& sim);
/// Makes `state` the state of `sim` (a model with nets of the same size): afterwards
/// stateOf(sim) equals `state` bit for bit, and the next steps are those the simulation took
/// from it. The status goes back to Ok.
/// @throws std::invalid_argument as Simulation::setState (a net of another size, NaN, held
///         points that differ from this model's rest net) or restoreForceStates(); the
///         simulation is then as it was
void restoreState(Simulation& sim, const SimulationState& state);
/// Bytes the state holds (both nets and the scalars).
std::size_t bytesOf(const SimulationState& state);
/// Whether `a` and `b` are the same bits (nets, time, steps, sub-step, start rule).
bool sameBits(const SimulationState& a, const SimulationState& b);

}  // namespace bsdeform
