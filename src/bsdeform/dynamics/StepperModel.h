// SPDX-License-Identifier: MIT
#pragma once
/// @file StepperModel.h
/// Not installed. What a time stepper (TimeStepper.h) sees of the Simulation it advances, and
/// all it sees: the state it writes (the current and previous nets), the model it reads (the
/// space, the parameters, the elastic energy, the mass, the forces, what is held) and what the
/// Simulation does for it (the loads, the Newton tangent, putting held points back). The
/// Simulation gives it through a nested adapter (Simulation::StepperView); the steppers are not
/// its friends. SOFA's split, in our terms: the ForceField is ElasticEnergy and the forces, the
/// Mass is MassMatrix, the OdeSolver is the stepper, and this is the mechanical state between
/// them (issue 34, item 4).

#include <Eigen/SparseCore>
#include <memory>
#include <vector>

#include "bsdeform/dynamics/StepCosts.h"
#include "bsdeform/energy/Shell.h"
#include "bsdeform/forces/Force.h"
#include "bsdeform/spline/SplineSpace.h"

namespace bsdeform {

class ComponentConstraints;
class EdgeMass;
class ElasticEnergy;
class MassMatrix;
class StiffnessStencil;
struct ModelParameters;

/// The seam between a Simulation and its time stepper: read-only access to the model, write
/// access to the two nets of the state, and the Simulation's own services for a step.
class StepperModel {
 public:
  virtual ~StepperModel() = default;

  // The state: the stepper writes the new state into previous() and swaps the two.
  virtual ControlNet& current() = 0;
  virtual ControlNet& previous() = 0;

  // The model.
  /// The spline space (moving points, held layers, derived layers).
  virtual const SplineSpace& space() const = 0;
  /// The model's parameters (time step, integrator, tolerances, damping, material).
  virtual const ModelParameters& params() const = 0;
  /// The rest net (held points' values, derived layers' completion).
  virtual const ControlNet& rest() const = 0;
  /// The elastic energy (either model).
  virtual const ElasticEnergy& energy() const = 0;
  /// SHELL's energy, null for the paper's model.
  virtual const ShellEnergy* shell() const = 0;
  /// The unknowns' mass (both models; built at the first call for the paper's).
  virtual const MassMatrix& mass() const = 0;
  /// c in the damping matrix C = c M.
  virtual double dampingRatio() const = 0;
  /// The forces, in their order.
  virtual const std::vector<std::shared_ptr<const Force>>& forces() const = 0;
  /// The loads that do not change: the constant forces, plus the paper's c0 (restOffset()).
  virtual const ControlNet& constantLoad() const = 0;
  /// constantLoad() without the paper's c0 (which ElasticEnergy::gradient() has).
  virtual ControlNet forcesConstantLoad() const = 0;
  /// Whether coordinate `axis` of moving point f is held (a pin, a held coordinate, a side).
  virtual bool heldCoordinate(Eigen::Index f, int axis) const = 0;
  /// Per coordinate 3 f + axis of the moving points: held (heldCoordinate()).
  virtual const std::vector<char>& heldMask() const = 0;
  /// Whether net row r is held by a pin.
  virtual bool isPinnedRow(Eigen::Index r) const = 0;
  /// Whether any point is pinned.
  virtual bool hasPins() const = 0;
  /// Moving-point numbers of the pinned points, ascending.
  virtual std::vector<Eigen::Index> pinnedMoving() const = 0;
  /// Supports per component on the unknowns (null without any).
  virtual const ComponentConstraints* components() const = 0;
  /// A coordinate beyond this is a divergence.
  virtual double divergenceLimit() const = 0;

  // The paper's fast paths (its explicit kernel and its implicit scheme's constant system).
  /// The paper's stiffness stencil (its fused explicit kernel, A_II).
  virtual const StiffnessStencil& stencil() const = 0;
  /// The paper's nodal mass m and damping per point.
  virtual double massPerPoint() const = 0;
  virtual double dampingPerPoint() const = 0;
  /// Whether every moving point has massPerPoint() (else massMoving(), or the edge mass).
  virtual bool hasUniformMass() const = 0;
  /// The moving points' masses where they are not uniform.
  virtual const Eigen::VectorXd& massMoving() const = 0;
  /// The mass of net point (i, j) (Simulation::massAt()).
  virtual double massAt(int i, int j) const = 0;
  /// The mass next to sides with derived layers (null without them).
  virtual const EdgeMass* edgeMass() const = 0;
  /// The largest eigenvalue of M⁻¹ A the explicit bound was taken from.
  virtual double elasticLambda() const = 0;
  /// The explicit schemes' sub-step.
  virtual double subStepSize() const = 0;

  // What the Simulation does for the stepper.
  /// The constant load plus the variable forces at the current state and time t (the
  /// Simulation's cache of the loads of time alone).
  virtual const ControlNet& effectiveLoad(double t) = 0;
  /// The context forces build their loads in (with SHELL's rest area element).
  virtual LoadContext loadContext(const ControlNet& current, const ControlNet& previous, double stepSize,
                                  double t) const = 0;
  /// scale H + shift M (+ the forces' Jacobians at `forces`), assembled in the fixed pattern
  /// (Simulation::tangent()).
  virtual const Eigen::SparseMatrix<double>& tangent(const ControlNet& net, double scale, double shift,
                                                     HessianMode mode, const LoadContext* forces = nullptr,
                                                     double velocityScale = 0.0, double forceScale = 1.0) const = 0;
  /// The last tangent() with `extra` times the mass added (Simulation::shiftTangent()).
  virtual const Eigen::SparseMatrix<double>& shiftTangent(double extra) const = 0;
  /// dW/dP on the unknowns.
  virtual void elasticGradient(const ControlNet& net, ControlNet& out) const = 0;
  /// The unknowns x (constrained coordinates completed) into the full net `net`.
  virtual void completeUnknowns(ControlNet& x, ControlNet& net) const = 0;
  /// Pinned rows of `net` back at their rest values.
  virtual void holdPins(ControlNet& net) const = 0;
  /// Sides moved by a map: whether a held row of `net` is not where it is to be; net's held
  /// rows := from's + alpha (target - from's); net's held rows := from's.
  virtual bool heldRowsMoved(const ControlNet& net) const = 0;
  virtual void placeHeldRows(const ControlNet& from, double alpha, ControlNet& net) const = 0;
  virtual void copyHeldRows(const ControlNet& from, ControlNet& net) const = 0;
  /// Where the steps' time goes (Simulation::stepCosts()): the stepper adds its phases.
  virtual StepCosts& costs() const = 0;
};

}  // namespace bsdeform
