// SPDX-License-Identifier: MIT
#pragma once
/// @file ElasticEnergy.h
/// The seam between a model's elastic energy and its time steppers and static solver: what a
/// Simulation asks of an energy, on the unknowns x (the moving control points, order of
/// SplineSpace::movingToNet; the full net is T x + const, T carrying the periodic copies and
/// the layers derived next to SIMPLY_SUPPORTED and BUILT_IN sides).
///
/// Two implementations: PaperEnergy, the paper's eq. 7 (quadratic in the positions, applied by
/// the exact stencil), and ShellModelEnergy, the Kirchhoff–Love thin shell (Shell.h) folded
/// through T. The explicit scheme of the paper's model keeps its fused kernel
/// (StiffnessStencil::centralDifferenceUpdate(), reached through PaperEnergy::stencil()): the
/// force, the update and the divergence check in one pass over the net, bit for bit the paper's
/// scheme. Everything else (the SHELL steppers and static solver, the elastic
/// force, the energies, the stability bound) goes through this interface.

#include <Eigen/Core>
#include <memory>
#include <utility>
#include <vector>

#include "bsdeform/energy/Shell.h"
#include "bsdeform/spline/SplineSpace.h"
#include "bsdeform/energy/StiffnessStencil.h"

namespace bsdeform {

class ElasticEnergy {
 public:
  virtual ~ElasticEnergy();
  /// Whether the gradient is affine in the positions (a constant tangent: the paper's model).
  virtual bool isLinear() const = 0;
  /// W of the full net `net` (periodic copies and derived layers in sync, held points at rest),
  /// zero at the rest net.
  virtual double energy(const ControlNet& net) const = 0;
  /// dW/dx on the unknowns (numMoving x 3): minus the elastic force.
  virtual void gradient(const ControlNet& net, ControlNet& out) const = 0;
  /// gradient() and returns energy() (SHELL: one pass over the Gauss points for both; equal to
  /// energy() up to rounding, the same for every thread count).
  virtual double energyAndGradient(const ControlNet& net, ControlNet& out) const {
    gradient(net, out);
    return energy(net);
  }
  /// H(net) d on the unknowns for a displacement d of the unknowns (numMoving x 3): the exact
  /// directional derivative of gradient().
  virtual void hessianProduct(const ControlNet& net, const ControlNet& d, ControlNet& out) const = 0;
  /// An upper bound of lambda_max(M^-1 H(net)) for the model's mass M: the explicit scheme's
  /// stability limit is 2 / sqrt of it. The paper's is the same at every state.
  virtual double eigenvalueBound(const ControlNet& net) const = 0;

 protected:
  /// The full-net displacement T d of a displacement d of the unknowns (held points zero).
  static void displacementNet(const SplineSpace& space, const ControlNet& d, ControlNet& out);
};

/// The paper's eq. 7, \f$W = \tfrac12 (x - x_r)^T A_{II} (x - x_r) + (x - x_r)^T g_r\f$ with
/// \f$g_r\f$ the gradient at the rest net: zero for ElasticReference::Rest (the rest net is an
/// equilibrium), \f$(A P_{rest})_I\f$ for Absolute (the paper's energy of S itself, less its
/// value at the rest net).
class PaperEnergy final : public ElasticEnergy {
 public:
  /// `massModel`, `mass`: the model's (Simulation.h), for eigenvalueBound(). Keeps references
  /// to `space`, `stencil` and `rest`.
  PaperEnergy(const SplineSpace& space, const StiffnessStencil& stencil, const ControlNet& rest, bool restReference,
              bool lumpedMass, double mass);
  const StiffnessStencil& stencil() const { return m_stencil; }
  /// c0 = (A P_rest)_I for the Rest reference, else zero (numMoving x 3).
  const ControlNet& restOffset() const { return m_c0; }
  /// Whether the model's mass is the same multiple of the identity at every moving point
  /// (NODAL, or LUMPED without FREE sides, and no derived layers): the bound's case.
  bool uniformMass() const { return m_uniformMass; }

  bool isLinear() const override { return true; }
  double energy(const ControlNet& net) const override;
  void gradient(const ControlNet& net, ControlNet& out) const override;
  void hessianProduct(const ControlNet& net, const ControlNet& d, ControlNet& out) const override;
  double eigenvalueBound(const ControlNet& net) const override;

 private:
  const SplineSpace& m_space;
  const StiffnessStencil& m_stencil;
  const ControlNet& m_rest;
  bool m_restReference;
  ControlNet m_c0;
  bool m_uniformMass = true;
  double m_lambda = 0.0;
};

/// The Kirchhoff–Love shell of Shell.h on the unknowns: gradients folded through T
/// (\f$T^T \nabla W\f$), directions spread by T, the mass \f$T^T W T\f$ from the lumped net
/// masses W.
class ShellModelEnergy final : public ElasticEnergy {
 public:
  /// @throws as ShellEnergy. Keeps a reference to `space`.
  ShellModelEnergy(const SplineSpace& space, const ControlNet& rest, const ShellMaterial& material);
  const ShellEnergy& shell() const { return m_shell; }
  /// Lumped mass of every net point, rho t ∫ B_k J0 (W).
  const Eigen::VectorXd& netMass() const { return m_netMass; }
  /// T: net point p is sum over entries [foldStart[p], foldStart[p+1]) of weight x unknown.
  const std::vector<int>& foldStart() const { return m_foldStart; }
  const std::vector<std::pair<Eigen::Index, double>>& foldEntries() const { return m_foldEntries; }

  bool isLinear() const override { return false; }
  double energy(const ControlNet& net) const override { return m_shell.energy(net).total(); }
  void gradient(const ControlNet& net, ControlNet& out) const override;
  double energyAndGradient(const ControlNet& net, ControlNet& out) const override;
  void hessianProduct(const ControlNet& net, const ControlNet& d, ControlNet& out) const override;
  /// Gershgorin on the net points with the lumped masses W (ShellEnergy::eigenvalueBound()).
  double eigenvalueBound(const ControlNet& net) const override { return m_shell.eigenvalueBound(net, m_netMass); }

 private:
  /// out = T^T g for a full-net g.
  void fold(const ControlNet& g, ControlNet& out) const;

  const SplineSpace& m_space;
  ShellEnergy m_shell;
  Eigen::VectorXd m_netMass;
  std::vector<int> m_foldStart;
  std::vector<std::pair<Eigen::Index, double>> m_foldEntries;
  mutable ControlNet m_netScratch[2];
};

}  // namespace bsdeform
