// SPDX-License-Identifier: MIT
#pragma once
/// @file Force.h
/// External forces and their load vectors \f$L_k = \int f\, B_k\, du\, dv\f$ (paper §4.1–4.2;
/// f is the force density, the paper's \f$-\nabla\mathcal{P}\f$).

#include <Eigen/Core>
#include <functional>
#include <memory>

#include "bsdeform/SplineSpace.h"

namespace bsdeform {

/// What a force may depend on. Forces depending on nothing are summed once into a constant
/// load; all others are re-evaluated before every (sub-)step at O(N1 N2) cost.
enum ForceDependence : unsigned {
  kConstant = 0,
  kDependsOnTime = 1u << 0,
  kDependsOnPosition = 1u << 1,  ///< S(u,v)
  kDependsOnVelocity = 1u << 2,  ///< dS/dt(u,v)
  kDependsOnNormal = 1u << 3,    ///< unit normal at (u,v)
};

/// State of the surface at one parameter point, handed to force callables.
/// Only the members the force asked for (its ForceDependence) are filled in.
struct SurfaceSample {
  double u = 0.0, v = 0.0, t = 0.0;
  double stepSize = 0.0;  ///< the (sub-)step the velocity is measured over (always filled in)
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  double areaElement = 0.0;  ///< |S_u x S_v| of the current surface (filled in with the normal)
};

/// A force callable: force (point force) or force per unit parameter area (distributed force).
using ForceFunction = std::function<Eigen::Vector3d(const SurfaceSample&)>;

/// Everything a force needs to build its load vector.
struct LoadContext {
  const SplineSpace& space;
  const ControlNet& current;   ///< full net at time t
  const ControlNet& previous;  ///< full net at t - stepSize (for velocities)
  double stepSize;             ///< the (sub-)step between previous and current
  double time;
  /// The rest net when densities are per unit rest area (the SHELL model): a distributed load
  /// is then integrated against the rest surface's area element J0 = |S_u x S_v| (and a line
  /// load against its length element); null: per unit parameter area (the paper's model).
  const ControlNet* rest = nullptr;
};

/// What a force needs to bound its share of \f$\lambda_{max}(M^{-1} K)\f$, K being the
/// Jacobian of its load with respect to the moving control points.
struct MassContext {
  const SplineSpace& space;
  double interiorMass;                     ///< mass of a moving point whose B-spline lies inside
  std::function<double(int, int)> massAt;  ///< mass of net point (i, j) (net layers), moving or derived
};

/// Base class of all forces. Implementations add their contribution to the load of the moving
/// control points (numMoving x 3, order of SplineSpace::movingToNet).
class Force {
 public:
  virtual ~Force() = default;
  /// Bitwise OR of ForceDependence flags.
  virtual unsigned dependence() const = 0;
  /// load += this force's load vector.
  virtual void addLoad(const LoadContext& ctx, ControlNet& load) const = 0;
  /// Upper bound of \f$\lambda_{max}(M^{-1} K)\f$ for this force's load Jacobian K (0 for
  /// forces that do not depend on position). The explicit integrator adds it to the elastic
  /// bound when it sizes sub-steps, so stiff position-dependent forces (springs, penalties)
  /// stay stable.
  virtual double eigenvalueBound(const MassContext& ctx) const {
    (void)ctx;
    return 0.0;
  }
};

/// Fills a SurfaceSample at (u, v) with what `dependence` asks for.
SurfaceSample sampleSurface(const LoadContext& ctx, double u, double v, unsigned dependence);

/// Force concentrated at one parameter point: \f$L_k = F\, B_k(u_0, v_0)\f$ (exact).
class PointForce : public Force {
 public:
  /// Constant force F at (u0, v0). @throws std::invalid_argument for (u,v) outside [0,1]^2 or NaN
  PointForce(double u0, double v0, const Eigen::Vector3d& force);
  /// Force given by a callable of the surface state at (u0, v0), e.g. a spring to an anchor.
  /// @param stiffness bound of |dF/dS| (e.g. the spring constant) for the stability estimate
  PointForce(double u0, double v0, ForceFunction force, unsigned dependence, double stiffness = 0.0);

  unsigned dependence() const override { return m_dependence; }
  void addLoad(const LoadContext& ctx, ControlNet& load) const override;
  /// K = k beta beta^T (beta_m: the B-splines at (u0, v0) of moving point m), so
  /// \f$\lambda(M^{-1}K) = k \sum_m \beta_m^2 / m_m\f$ (exact)
  double eigenvalueBound(const MassContext& ctx) const override;
  double u() const { return m_u; }
  double v() const { return m_v; }

 private:
  double m_u, m_v;
  ForceFunction m_force;
  unsigned m_dependence;
  double m_stiffness;
};

/// A rectangle [u0,u1] x [v0,v1] of the parameter square.
struct ParamRect {
  double u0 = 0.0, u1 = 1.0, v0 = 0.0, v1 = 1.0;
};

/// Force density on a parameter rectangle [u0,u1] x [v0,v1] (the whole square by default),
/// integrated with Gauss–Legendre on every knot span, spans split at the rectangle's edges.
/// A constant density is integrated exactly; smooth densities with `extraPoints` (default 2)
/// more points than the degree needs for the basis alone.
///
/// A constant density f on a rectangle is separable: \f$L_k = f\, l_u(k_1)\, l_v(k_2)\f$ with
/// \f$l_u(k_1) = \int_{u_0}^{u_1} b_{k_1}(u)\, du\f$ (1-D quadratures, the same split spans), so
/// its load costs O(N1 + N2) quadrature and one product per control point instead of
/// (n1+1)(n2+1) quadrature points per knot cell: milliseconds, not seconds, at 2048^2
/// (docs/benchmarks.md, "Why the code is as it is").
///
/// A rectangle of zero width in u (u0 = u1) or in v is a line load: f is then a force per unit
/// length of that parameter line, $L_k = \int f\, B_k(u_0, v)\, \ell(v)\, dv$ (and both zero: a
/// point force f at (u0, v0)). What a unit of area or length is comes from LoadContext::rest:
/// per unit parameter area and length ($\ell = 1$, the paper's model), or per unit area and
/// length of the rest surface ($J_0$, $\ell = |S_v|$ of the rest net: SHELL); a force that
/// follows the current area (pressure) uses the current surface's instead.
class DistributedForce : public Force {
 public:
  using Rect = ParamRect;
  /// Constant density (uniform force when rect is the whole square).
  explicit DistributedForce(const Eigen::Vector3d& density, Rect rect = Rect());
  /// Density as a callable of (u, v, position, velocity, normal, t).
  DistributedForce(ForceFunction density, unsigned dependence, Rect rect = Rect(), int extraPoints = 2,
                   double stiffness = 0.0);

  unsigned dependence() const override { return m_dependence; }
  void addLoad(const LoadContext& ctx, ControlNet& load) const override;
  /// K <= k G (G the Gram matrix over [0,1]^2, k the stiffness per unit area given at
  /// construction); Gershgorin on M^-1 k G: row m sums to k r_m / m_m <= k h1 h2 / m_interior,
  /// since r_m <= h1 h2 (NODAL) and m_m = rho r_m (LUMPED)
  double eigenvalueBound(const MassContext& ctx) const override {
    return m_stiffness * ctx.space.basisU().spacing() * ctx.space.basisV().spacing() / ctx.interiorMass;
  }
  const Rect& rect() const { return m_rect; }
  /// The load of the general quadrature (every point of the 2-D tensor rule through the density
  /// callable), which addLoad() uses for densities that are not constant. For tests: a
  /// constant density's separable load must equal it.
  void addLoadByQuadrature(const LoadContext& ctx, ControlNet& load) const;
  /// Whether the rectangle has zero width in u or v (a line load, or a point).
  bool isLine() const { return m_rect.u0 == m_rect.u1 || m_rect.v0 == m_rect.v1; }

 protected:
  /// With physical units (LoadContext::rest), the density is per unit area of the current
  /// surface (a follower pressure) instead of the rest surface's.
  void setPerCurrentArea() { m_perCurrentArea = true; }

 private:
  void addLineLoad(const LoadContext& ctx, ControlNet& load) const;
  bool m_perCurrentArea = false;
  bool m_isConstant = false;  ///< the density is the constant m_constantDensity
  Eigen::Vector3d m_constantDensity = Eigen::Vector3d::Zero();
  ForceFunction m_density;
  unsigned m_dependence;
  Rect m_rect;
  int m_extraPoints;
  double m_stiffness;
};

}  // namespace bsdeform
