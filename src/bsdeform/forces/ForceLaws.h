// SPDX-License-Identifier: MIT
#pragma once
/// @file ForceLaws.h
/// The named force laws of SoForceField as core classes: a spring to an anchor, viscous drag,
/// follower pressure, penalty contact with a plane or a sphere, and gravity. Each validates its
/// parameters (std::invalid_argument naming the parameter and the value) and bounds its share
/// of \f$\lambda_{max}(M^{-1}K)\f$, K being the Jacobian of its load with respect to the moving
/// control points with the sign of a stiffness (\f$K = -\partial L/\partial P\f$).
///
/// \note Densities are per unit *parameter* area (as every DistributedForce): the load of
///       moving point m is \f$L_m = \int_{[0,1]^2} f\, B_m\, du\, dv\f$. In the bounds,
///       \f$r_m = \int B_m \le h_1 h_2\f$ and \f$m_m\f$ is the mass of moving point m, so
///       \f$r_m / m_m \le h_1 h_2 / m_{interior}\f$ for both mass models (NODAL: \f$m_m = m\f$;
///       LUMPED: \f$m_m = \rho r_m\f$, \f$m_{interior} = \rho h_1 h_2\f$).

#include <cmath>
#include <Eigen/Core>
#include <memory>

#include "bsdeform/forces/Force.h"

namespace bsdeform {

/// Zero-length spring from the surface point \f$S(u_0, v_0)\f$ to a fixed anchor a:
/// \f$F = k\,(a - S(u_0, v_0))\f$, a point force (the drag of the mouse).
///
/// Its Jacobian is exactly \f$K = k\,\beta\beta^T \otimes I_3\f$ (\f$\beta_m = B_m(u_0, v_0)\f$
/// summed over the periodic copies of moving point m), a rank-one matrix per coordinate, so the
/// bound inherited from PointForce, \f$k \sum_m \beta_m^2 / m_m\f$, is its exact
/// \f$\lambda_{max}(M^{-1}K)\f$.
class SpringForce : public PointForce {
 public:
  /// @param u0, v0     parameter point in [0,1]^2
  /// @param anchor     anchor point a (world units of the surface), finite
  /// @param stiffness  spring constant k, finite and >= 0
  /// @throws std::invalid_argument naming the parameter and the value
  SpringForce(double u0, double v0, const Eigen::Vector3d& anchor, double stiffness);
  /// A spring whose anchor the caller moves (the viewer's drag: the anchor follows the mouse;
  /// the new position acts from the next evaluation). The anchor must stay finite.
  SpringForce(double u0, double v0, std::shared_ptr<const Eigen::Vector3d> anchor, double stiffness);

  const Eigen::Vector3d& anchor() const { return *m_anchor; }
  double stiffness() const { return m_stiffness; }
  /// A fixed anchor: the potential. A moved one does work on the surface (the user's pull),
  /// which the implicit steppers' energy check counts as work: false.
  bool storedEnergy(const LoadContext& ctx, double& value) const override;

 protected:
  /// K = k I, potential ½ k |a - S|².
  void pointDerivatives(const SurfaceSample& s, Eigen::Matrix3d& Kx, Eigen::Matrix3d& Kv, double& phi) const override;

 private:
  std::shared_ptr<const Eigen::Vector3d> m_anchor;
  double m_stiffness;
  bool m_movable = true;  ///< made with an anchor the caller holds
};

/// Viscous drag on the whole surface: density \f$f = -c\,\dot S\f$ (c per unit parameter area),
/// \f$\dot S\f$ the backward difference \f$(S(t) - S(t - \delta))/\delta\f$ over the sub-step.
///
/// eigenvalueBound() is 0: the load does not depend on the position, only on the velocity, so
/// it has no stiffness. Drag is damping, and centred damping does not move the undamped
/// stability limit \f$\delta^2\lambda < 4\f$. This drag is not centred (the load is evaluated
/// before the step): per mode of frequency \f$\omega\f$ and drag rate
/// \f$\nu = c\,\lambda(M^{-1}G)\f$ (G the Gram matrix) the scheme is stable for
/// \f$\delta^2\omega^2 + 2\delta\nu < 4\f$. The integrator sizes sub-steps by
/// \f$\delta^2\lambda \le 4 s^2\f$ (safety s, default 0.9), which covers the drag term while
/// \f$\delta\,\nu \le 2(1 - s^2)\f$ (0.38 at s = 0.9); dampingRateBound() gives
/// \f$\bar\nu = c\,h_1 h_2 / m_{interior} \ge \nu\f$ to check that. A bound in eigenvalue units
/// would need \f$\delta\f$ (or \f$\lambda\f$), which MassContext does not carry.
class DragForce : public DistributedForce {
 public:
  /// @param coefficient  c, finite and >= 0
  /// @throws std::invalid_argument naming the parameter and the value
  explicit DragForce(double coefficient);

  double coefficient() const { return m_coefficient; }
  /// \f$\bar\nu = c\,h_1 h_2 / m_{interior}\f$: Gershgorin bound of \f$\lambda_{max}(M^{-1} c\,G)\f$.
  double dampingRateBound(const MassContext& ctx) const;

 protected:
  /// K_v = c I; the step's potential ½ c δ |Ṡ|² (Rayleigh's dissipation over the step).
  void densityDerivatives(const SurfaceSample& s, Eigen::Matrix3d& Kx, Eigen::Matrix3d& Kv, double& phi) const override;

 private:
  double m_coefficient;
};

/// Follower pressure: density \f$f = p\,\hat n(u, v)\f$ along the current unit normal
/// \f$\hat n = S_u \times S_v / |S_u \times S_v|\f$, per unit parameter area.
///
/// Its Jacobian is not symmetric (a follower load): with \f$N = S_u \times S_v\f$,
/// \f$\partial \hat n / \partial P_n = (I - \hat n \hat n^T)\,
/// (\beta_{n,v} [S_u]_\times - \beta_{n,u} [S_v]_\times) / |N|\f$, which is O(p/h) and depends on
/// the current shape. eigenvalueBound() bounds the spectral radius of \f$M^{-1}K\f$ by its
/// norm in \f$\|x\| = \max_m |x_m|\f$: with \f$\sum_n |\beta_{n,u}| \le 2/h_1\f$,
/// \f$\sum_n |\beta_{n,v}| \le 2/h_2\f$ and
/// \f$|N| \ge \sigma \max(|S_u|, |S_v|)\f$,
/// \f[ \rho(M^{-1}K) \le \frac{2|p|\,(h_1 + h_2)}{\sigma\, m_{interior}}, \f]
/// where \f$\sigma\f$ (`minStretch`) is a lower bound of \f$\min(|S_u|, |S_v|)\sin\theta\f$ over
/// the surface (\f$\theta\f$ the angle between \f$S_u\f$ and \f$S_v\f$). The Greville plane of
/// the unit square has \f$\sigma = 1\f$, and so does any graph \f$(u, v, z(u, v))\f$ over it.
/// A surface compressed below that (\f$\sigma < 1\f$) needs the smaller value for the bound to
/// hold. On a flat sheet the Jacobian is nilpotent (out-of-plane motion tilts the normal,
/// in-plane motion does not), so its eigenvalues are 0 there; the bound is the norm, not the
/// eigenvalue.
class PressureForce : public DistributedForce {
 public:
  /// @param pressure    p (force per unit parameter area), finite; negative pulls inwards
  /// @param minStretch  \f$\sigma\f$ of the bound above, finite and > 0 (1 by default)
  /// @throws std::invalid_argument naming the parameter and the value
  explicit PressureForce(double pressure, double minStretch = 1.0);

  double pressure() const { return m_pressure; }
  double minStretch() const { return m_minStretch; }
  /// \f$2|p|(h_1 + h_2) / (\sigma\, m_{interior})\f$, see the class documentation.
  double eigenvalueBound(const MassContext& ctx) const override;
  /// The exact, non-symmetric Jacobian: per unit rest area (SHELL) the load is
  /// \f$\int p\,(S_u \times S_v)\,B_k\f$, so \f$K_{km} = -p\int B_k(B_{m,v}[S_u]_\times -
  /// B_{m,u}[S_v]_\times)\f$; per parameter area \f$\hat n\f$'s derivative
  /// \f$(I - \hat n\hat n^T)/|N|\f$ enters too. No potential (a follower load): the Newton
  /// matrix takes the symmetric part (Simulation's tangent), the residual the exact load.
  bool hasJacobian() const override { return true; }
  void addJacobian(const LoadContext& ctx, double velocityScale, JacobianSink& sink) const override;
  bool potential(const LoadContext&, double& value) const override {
    value = 0.0;
    return false;
  }

 private:
  double m_pressure;
  double m_minStretch;
};

/// Penalty contact with the half-space on the negative side of a plane through c with unit
/// normal \f$\hat n\f$ (the positive side is free): with depth \f$d = -(S - c)\cdot\hat n\f$,
/// density \f$f = k\,\max(d, 0)\,\hat n\f$ per unit parameter area.
///
/// \f$-\partial f/\partial S = k\,\hat n\hat n^T\f$ where penetrating, else 0, so
/// \f$0 \le K \le k\,G \otimes I_3\f$ and the bound inherited from DistributedForce,
/// \f$k\,h_1 h_2 / m_{interior}\f$ (Gershgorin on \f$M^{-1}kG\f$), holds.
class PlaneContactForce : public DistributedForce {
 public:
  /// @param point      c, a point on the plane, finite
  /// @param normal     plane normal (normalised here), finite and non-zero
  /// @param stiffness  k (force per unit parameter area and unit depth), finite and >= 0
  /// @throws std::invalid_argument naming the parameter and the value
  PlaneContactForce(const Eigen::Vector3d& point, const Eigen::Vector3d& normal, double stiffness);

  const Eigen::Vector3d& point() const { return m_point; }
  /// The unit normal.
  const Eigen::Vector3d& normal() const { return m_normal; }
  double stiffness() const { return m_stiffness; }

 protected:
  /// K = k n nᵀ where penetrating; potential ½ k max(d, 0)².
  void densityDerivatives(const SurfaceSample& s, Eigen::Matrix3d& Kx, Eigen::Matrix3d& Kv, double& phi) const override;

 private:
  Eigen::Vector3d m_point, m_normal;
  double m_stiffness;
};

/// Penalty contact with a solid sphere (centre c, radius r): with \f$d = S - c\f$, density
/// \f$f = k\,(r - |d|)\,d/|d|\f$ inside the sphere (pushing out along the radius), else 0; 0 at
/// the centre itself, where the direction is undefined.
///
/// Inside, \f$-\partial f/\partial S = k\,\hat d\hat d^T - k\,(r/|d| - 1)(I - \hat d\hat d^T)
/// \le k I\f$ (the tangential part is negative), so \f$K \le k\,G \otimes I_3\f$ and the bound
/// inherited from DistributedForce, \f$k\,h_1 h_2 / m_{interior}\f$, holds for the largest
/// eigenvalue (the negative tangential stiffness is a physical instability near the centre, not
/// a step-size limit).
class SphereContactForce : public DistributedForce {
 public:
  /// @param center     c, finite
  /// @param radius     r, finite and >= 0
  /// @param stiffness  k (force per unit parameter area and unit depth), finite and >= 0
  /// @throws std::invalid_argument naming the parameter and the value
  SphereContactForce(const Eigen::Vector3d& center, double radius, double stiffness);

  const Eigen::Vector3d& center() const { return m_center; }
  double radius() const { return m_radius; }
  double stiffness() const { return m_stiffness; }

 protected:
  /// Inside: K = k d̂d̂ᵀ - k (r/|d| - 1)(I - d̂d̂ᵀ); potential ½ k (r - |d|)².
  void densityDerivatives(const SurfaceSample& s, Eigen::Matrix3d& Kx, Eigen::Matrix3d& Kv, double& phi) const override;

 private:
  Eigen::Vector3d m_center;
  double m_radius, m_stiffness;
};

/// Gravity: the constant density \f$f = \rho\,g\f$ on the whole surface, \f$\rho\f$ the mass per
/// unit area of the load's measure — \f$m/(h_1 h_2)\f$ per unit parameter area for the NODAL model
/// (m per control point), \f$\rho\f$ itself for LUMPED, \f$\rho t\f$ per unit rest area for SHELL —
/// and g the acceleration. With LUMPED mass every moving point gets exactly \f$M^{-1}L = g\f$.
/// Constant, so eigenvalueBound() is 0.
///
/// Built from g alone, it takes \f$\rho\f$ from the model it acts on
/// (LoadContext::massPerArea) at every evaluation: a model rebuilt with another thickness,
/// density or mass keeps the same force (what the nodes do). Built with a density, it keeps that
/// one.
class GravityForce : public DistributedForce {
 public:
  /// @param acceleration  g, finite; \f$\rho\f$ is the model's (LoadContext::massPerArea)
  /// @throws std::invalid_argument naming the parameter and the value
  explicit GravityForce(const Eigen::Vector3d& acceleration);
  /// @param massDensity   \f$\rho\f$, finite and >= 0, whatever the model's
  /// @param acceleration  g, finite
  /// @throws std::invalid_argument naming the parameter and the value
  GravityForce(double massDensity, const Eigen::Vector3d& acceleration);

  void addLoad(const LoadContext& ctx, ControlNet& load) const override;

  /// The density given to the constructor; NaN where the force takes the model's.
  double massDensity() const { return m_massDensity; }
  /// Whether \f$\rho\f$ is the model's (the constructor without a density).
  bool modelDensity() const { return std::isnan(m_massDensity); }
  const Eigen::Vector3d& acceleration() const { return m_acceleration; }

 private:
  double m_massDensity;
  Eigen::Vector3d m_acceleration;
};

}  // namespace bsdeform
