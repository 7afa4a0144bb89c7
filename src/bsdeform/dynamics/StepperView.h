// SPDX-License-Identifier: MIT
#pragma once
/// @file StepperView.h
/// Not installed (Simulation's sources). Simulation::StepperView: the StepperModel a Simulation
/// gives its time stepper (StepperModel.h). A nested class reads the Simulation's members
/// without friendship; every function forwards to one member or member function.

#include "bsdeform/dynamics/StepperModel.h"

#include "bsdeform/dynamics/Simulation.h"

namespace bsdeform {

class Simulation::StepperView final : public StepperModel {
 public:
  explicit StepperView(Simulation& s) : m_s(s) {}

  ControlNet& current() override { return m_s.m_current; }
  ControlNet& previous() override { return m_s.m_previous; }

  const SplineSpace& space() const override { return m_s.m_space; }
  const ModelParameters& params() const override { return m_s.m_params; }
  const ControlNet& rest() const override { return m_s.m_rest; }
  const ElasticEnergy& energy() const override { return *m_s.m_energy; }
  const ShellEnergy* shell() const override { return m_s.m_shell; }
  const MassMatrix& mass() const override { return m_s.massMatrix(); }
  double dampingRatio() const override { return m_s.dampingRatio(); }
  const std::vector<std::shared_ptr<const Force>>& forces() const override { return m_s.m_forces; }
  const ControlNet& constantLoad() const override { return m_s.m_constantLoad; }
  ControlNet forcesConstantLoad() const override { return m_s.forcesConstantLoad(); }
  bool heldCoordinate(Eigen::Index f, int axis) const override { return m_s.heldCoordinate(f, axis); }
  const std::vector<char>& heldMask() const override { return m_s.m_heldMask; }
  bool isPinnedRow(Eigen::Index r) const override { return m_s.m_pinMask[size_t(r)] != 0; }
  bool hasPins() const override { return !m_s.m_pinned.empty(); }
  std::vector<Eigen::Index> pinnedMoving() const override { return m_s.pinnedMoving(); }
  const ComponentConstraints* components() const override { return m_s.m_components.get(); }
  double divergenceLimit() const override { return m_s.m_divergenceLimit; }

  const StiffnessStencil& stencil() const override { return m_s.m_stencil; }
  double massPerPoint() const override { return m_s.massPerPoint(); }
  double dampingPerPoint() const override { return m_s.dampingPerPoint(); }
  bool hasUniformMass() const override { return m_s.m_uniformMass; }
  const Eigen::VectorXd& massMoving() const override { return m_s.m_massMoving; }
  double massAt(int i, int j) const override { return m_s.massAt(i, j); }
  const EdgeMass* edgeMass() const override { return m_s.m_edgeMass.get(); }
  double elasticLambda() const override { return m_s.m_elasticLambda; }
  double subStepSize() const override { return m_s.subStepSize(); }

  const ControlNet& effectiveLoad(double t) override { return m_s.effectiveLoad(t); }
  LoadContext loadContext(const ControlNet& current, const ControlNet& previous, double stepSize,
                          double t) const override {
    return m_s.loadContext(current, previous, stepSize, t);
  }
  const Eigen::SparseMatrix<double>& tangent(const ControlNet& net, double scale, double shift, HessianMode mode,
                                             const LoadContext* forces, double velocityScale,
                                             double forceScale) const override {
    return m_s.tangent(net, scale, shift, mode, forces, velocityScale, forceScale);
  }
  const Eigen::SparseMatrix<double>& shiftTangent(double extra) const override { return m_s.shiftTangent(extra); }
  void elasticGradient(const ControlNet& net, ControlNet& out) const override { m_s.m_energy->gradient(net, out); }
  void completeUnknowns(ControlNet& x, ControlNet& net) const override { m_s.completeUnknowns(x, net); }
  void holdPins(ControlNet& net) const override { m_s.holdPins(net); }
  bool heldRowsMoved(const ControlNet& net) const override { return m_s.heldRowsMoved(net); }
  void placeHeldRows(const ControlNet& from, double alpha, ControlNet& net) const override {
    m_s.placeHeldRows(from, alpha, net);
  }
  void copyHeldRows(const ControlNet& from, ControlNet& net) const override { m_s.copyHeldRows(from, net); }
  StepCosts& costs() const override { return m_s.m_costs; }

 private:
  Simulation& m_s;
};

}  // namespace bsdeform
