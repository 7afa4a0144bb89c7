// SPDX-License-Identifier: MIT
#pragma once
/// @file TimeStepper.h
/// Not installed. A Simulation is a model (space, held points, mass, energy), a state (current
/// and previous nets, time) and one of these: a time integration scheme with the data only it
/// needs (a factorisation, scratch nets, the forces of the last states), which advances the
/// state by one sub-step. Simulation::step() calls it for every sub-step and handles failure,
/// the clock and the status. A stepper sees the Simulation only through StepperModel (the state,
/// the model, the loads and the tangent; not a friend). Five implementations, chosen by the
/// integrator and the energy:
///   PaperExplicitStepper  the paper's corrected central differences through the stencil's
///                         fused kernel (design.md §2);
///   PaperImplicitStepper  Newmark average acceleration with the constant system (ImplicitSystem);
///   ShellExplicitStepper  central differences with the lumped mass T^T W T;
///   ShellImplicitStepper  three-level Newmark by the one Newton solver (NewtonMinimizer), step
///                         cutting on failure;
///   BackwardEulerStepper  backward Euler as the minimisation of the incremental potential,
///                         either energy (ElasticEnergy, MassMatrix, the forces' Jacobians).

#include <cmath>
#include <functional>
#include <memory>
#include <string>

#include "bsdeform/dynamics/EdgeMass.h"
#include "bsdeform/dynamics/ImplicitSystem.h"
#include "bsdeform/dynamics/NewtonMinimizer.h"
#include "bsdeform/dynamics/StepperModel.h"
#include "bsdeform/spline/SplineSpace.h"

namespace bsdeform {

class TimeStepper {
 public:
  explicit TimeStepper(StepperModel& model) : m_model(model) {}
  virtual ~TimeStepper();
  TimeStepper(const TimeStepper&) = delete;
  TimeStepper& operator=(const TimeStepper&) = delete;
  /// One sub-step from time t. False when the new state is not valid: the rejected state is
  /// then current and the last good one previous (Simulation::step() restores it).
  virtual bool subStep(double t) = 0;
  /// Forgets what it kept of earlier states (a state was set, reset, or a step failed); the
  /// base: the energy check's reference.
  virtual void invalidate() { m_reference.valid = false; }
  /// The state was rounded after a step (Simulation::setStateRounding): what the stepper keeps
  /// of the state it left is no longer the state's.
  virtual void stateRounded() {}
  /// The forces changed (work may be done on the system from now on): the energy check starts
  /// again.
  virtual void forcesChanged() { m_reference.valid = false; }
  /// Newton iterations of the last step (0 for the linear schemes).
  virtual int newtonIterations() const { return 0; }
  /// The implicit scheme's constant system (null for the others).
  virtual const ImplicitSystem* implicitSystem() const { return nullptr; }
  /// Why the last sub-step's solver failed ("" when it did not).
  const std::string& solveFailure() const { return m_solveFailure; }
  /// Whether that failure was a force refusing the state the step starts from (a surface inside
  /// an obstacle's contact offset): bad input, which no smaller step can change.
  bool startRefused() const { return m_startRefused; }
  void clearFailure() {
    m_solveFailure.clear();
    m_startRefused = false;
  }

 protected:
  /// The Newton steppers' step cutting, after stepOf(t, dt) failed from (current, previous) =
  /// (start, before): the step again in 2, 4, 8, 16 equal pieces with the same velocity,
  /// stepOf(t, h) taking one piece (and setting m_newtonIterations), restart() called before
  /// each try (the stepper forgets what it kept of earlier states). On success finish(start,
  /// pieces) sets the previous net the next step expects and m_newtonIterations is the sum over
  /// the pieces; on failure the pieces' failure is reported and previous is start (the last
  /// valid state). Not tried after a blow-up, and not tried smaller after a piece blew up
  /// (m_blewUp: smaller pieces do not cure it, and would start the energy check afresh).
  bool retakeInPieces(ControlNet& current, ControlNet& previous, const ControlNet& start, const ControlNet& before,
                      double t, double dt, const std::function<bool(double, double)>& stepOf,
                      const std::function<void()>& restart,
                      const std::function<void(const ControlNet& start, int pieces)>& finish);

  /// The Newton steppers' energy check: the total energy when it began
  /// (BackwardEulerStepper::totalEnergy()) and its scale, and the work the loads that can do
  /// work have done since and its magnitude.
  struct EnergyReference {
    bool valid = false;
    double energy = 0.0, scale = 0.0, work = 0.0, workScale = 0.0;
    void start(double e, double s) {
      valid = true;
      energy = e;
      scale = s;
      work = workScale = 0.0;
    }
    void addWork(double w) {
      work += w;
      workScale += std::abs(w);
    }
  };
  /// Reports `energy` as a blow-up against m_reference (m_solveFailure, m_blewUp) and forgets
  /// the reference; returns false.
  bool blowUp(double energy);

  StepperModel& m_model;  ///< all the stepper sees of the Simulation (StepperModel.h)
  std::string m_solveFailure;
  int m_newtonIterations = 0;  ///< of the last step (the Newton steppers)
  bool m_blewUp = false;       ///< the last step failed the energy check
  bool m_startRefused = false;  ///< a force refused the last step's start state (startRefused())
  EnergyReference m_reference;  ///< the Newton steppers' energy check
};

class PaperExplicitStepper final : public TimeStepper {
 public:
  using TimeStepper::TimeStepper;
  bool subStep(double t) override;

 private:
  std::unique_ptr<EdgeMass::BandPlan> m_bandPlan;  ///< built at the first step with derived layers
};

class PaperImplicitStepper final : public TimeStepper {
 public:
  /// Builds K = M/dt^2 + C/(2dt) + A_II/4 and its solver.
  explicit PaperImplicitStepper(StepperModel& model);
  bool subStep(double t) override;
  const ImplicitSystem* implicitSystem() const override { return m_implicit.get(); }

 private:
  std::unique_ptr<ImplicitSystem> m_implicit;
  ControlNet m_scratch;  ///< a full net (the stencil's argument)
};

class ShellExplicitStepper final : public TimeStepper {
 public:
  using TimeStepper::TimeStepper;
  bool subStep(double t) override;
};

class ShellImplicitStepper final : public TimeStepper {
 public:
  using TimeStepper::TimeStepper;
  /// One implicit step of Delta t from t; when Newton's method fails, the step is taken again
  /// in 2, 4, ... 16 equal pieces (the velocity kept), so a fast change (a load ramped by the
  /// wall clock, a snap) costs time instead of stopping the run.
  bool subStep(double t) override;
  void invalidate() override {
    m_cached = false;
    TimeStepper::invalidate();
  }
  void stateRounded() override { m_cached = false; }
  int newtonIterations() const override { return m_newtonIterations; }

 private:
  /// One three-level Newmark step of size dt from t (the previous net dt before the current).
  bool stepOf(double t, double dt);

  std::unique_ptr<NewtonMinimizer> m_newton;  ///< the tangent's symbolic factorisation kept
  /// dW/dP at the current and previous state (valid while m_cached).
  ControlNet m_gradCurrent, m_gradPrevious;
  bool m_cached = false;
  /// The energy check (m_reference) starts after the first step since the last change; its
  /// work is the trapezoid rule per step, this the loads that can do work at the last state.
  ControlNet m_workingLoad;
};

/// Backward Euler, both energies, as the minimisation of the incremental potential (docs/math.md
/// §16, "Backward Euler"):
///   E(x) = ½ (x - x̂)ᵀ M (x - x̂) / h² + c/(2h) (x - P)ᵀ M (x - P) + W(x) + Φ(x),
/// x̂ = P + h v, v = (P - P-)/h, Φ the loads' potentials (constant loads: -L·x); its gradient is
/// the residual of M (x - 2P + P-)/h² + c M (x - P)/h + ∇W(x) = L(x, (x - P)/h, t + h), every
/// force evaluated at the iterate; C = c M (Simulation::dampingRatio()), W either energy (the
/// paper's is quadratic: one Newton iteration solves a step without forces that depend on the
/// state). Newton with the element Hessians projected to PSD, the
/// forces' Jacobians inside (symmetrised), a backtracking (Armijo) line search on E (on the
/// residual's norm when a force has no potential); converged when the largest update over h
/// is below newtonVelocityTolerance or the residual below newtonTolerance. A step that does
/// not converge is retaken in 2, 4, ... 16 pieces, then reported. The total energy (kinetic +
/// W + Φ) may not rise above its value when the run (or the last change of forces) began plus
/// the work done since by the loads that can do work (a wind, a follower pressure): a rise is
/// reported as a blow-up. Each step factorises anew (a resumed run is bit-identical); within
/// the step a factorisation is kept while the iterates contract fast with it (chord steps). With
/// `nonlinearSolver` LBFGS the same minimisation by L-BFGS from the isotropic matrix of
/// precondition() (from the step's first tangent with a barrier or supports per component).
class BackwardEulerStepper final : public TimeStepper {
 public:
  explicit BackwardEulerStepper(StepperModel& model);
  ~BackwardEulerStepper() override;
  bool subStep(double t) override;
  int newtonIterations() const override { return m_newtonIterations; }
  /// Factorisations of the Newton matrix since the model was built (fewer than the iterations:
  /// a factorisation is kept while the iterates contract fast with it).
  long factorisations() const { return m_factorisations; }
  /// Total energy (kinetic + elastic + what the loads store, Force::storedEnergy()) of a state
  /// x (its net `net`, the net before it `previousNet`, h apart) with velocity v, and its scale
  /// (the sum of the parts' magnitudes). The loads that can do work instead (a callable, a load
  /// that depends on time, a follower pressure) store nothing; their sum at the state is added
  /// to `working` (over the unknowns) when given, for the work they do (the steppers add it up
  /// for their energy check). Also the Newmark stepper's check.
  static void totalEnergy(const StepperModel& s, const ControlNet& x, const ControlNet& net,
                          const ControlNet& previousNet,
                          double h, const ControlNet& v, double t, double& energy, double& scale,
                          ControlNet* working = nullptr);

 private:
  bool stepOf(double t, double h);

  /// L-BFGS's start matrix H0 (mass shift · M + the rest tangent made isotropic), factorised
  /// once per model and step length (NonlinearSolver::LBFGS)
  void precondition(ControlNet& r, double h);

  std::unique_ptr<NewtonMinimizer> m_newton;  ///< its symbolic factorisation kept
  struct QuasiNewtonStart;
  std::unique_ptr<QuasiNewtonStart> m_start;
  /// The step subStep() takes (its start time and length) and the net it starts from: a step
  /// retaken in pieces moves the held layers of moved sides (Simulation::setSideMotion) linearly
  /// from that net's over its pieces
  double m_stepStart = 0.0, m_stepLength = 0.0;
  ControlNet m_stepFrom;
  long m_factorisations = 0;
};

}  // namespace bsdeform
