// SPDX-License-Identifier: MIT
#pragma once
/// @file StepCosts.h
/// Where a simulation's implicit steps spend their time: wall seconds per phase, accumulated by
/// Simulation::step() until Simulation::resetStepCosts() (the static and arc-length solves'
/// tangents add to elastic and loads too: reset before stepping to read the steps alone).
/// The phases are timed where the time stepper calls them, on its own thread (work they hand to
/// kernel threads is inside them); what no phase names (the line search's vector arithmetic, the
/// energy check, the held rows) is other().

#include "bsdeform/base/CostTimer.h"

namespace bsdeform {

struct StepCosts {
  double total = 0.0;            ///< whole steps (Simulation::step), every scheme
  /// Implicit steps (BACKWARD_EULER, IMPLICIT on SHELL): the elastic energy's value, gradient and
  /// element Hessians with their assembly into the Newton matrix (its mass term included).
  double elastic = 0.0;
  /// The forces' loads, potentials and Jacobians (barrier contact's and friction's terms and
  /// their broad phase among them).
  double loads = 0.0;
  /// The line search's collision-free fractions and the sweeps of moved obstacles (continuous
  /// collision checks with their broad phase): nothing without a barrier.
  double collisionChecks = 0.0;
  /// Numeric factorisations of the Newton matrix, those refused as not positive definite included.
  double factorisation = 0.0;
  double solve = 0.0;            ///< triangular solves with the factorisation
  long steps = 0;                ///< steps taken (each counted once, however often it was cut)
  long iterations = 0;           ///< Newton (or L-BFGS) iterations
  long factorisations = 0;       ///< factorisations that succeeded

  /// The part of `total` that no phase names.
  double other() const { return total - elastic - loads - collisionChecks - factorisation - solve; }
};

}  // namespace bsdeform
