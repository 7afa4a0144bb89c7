// SPDX-License-Identifier: MIT
#pragma once
/// @file Force.h
/// External forces and their load vectors \f$L_k = \int f\, B_k\, du\, dv\f$ (paper §4.1–4.2;
/// f is the force density, the paper's \f$-\nabla\mathcal{P}\f$).

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "bsdeform/spline/SplineSpace.h"

namespace bsdeform {

/// What a force may depend on. Forces depending on nothing are summed once into a constant
/// load; those of time alone are evaluated at the ends of each step (interpolated between them
/// at the explicit scheme's sub-steps); all others are re-evaluated before every (sub-)step at
/// O(N1 N2) cost.
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
  /// The rest net whatever the model (geometry at rest: which parts of a surface are neighbours
  /// for its self-contact, the edge–edge mollifier's thresholds); null: the first state a force
  /// sees stands for it.
  const ControlNet* restShape = nullptr;
  /// The model's mass per unit area of the load's measure: rho t per unit rest area (SHELL),
  /// m / (h1 h2) or rho per unit parameter area (the paper's NODAL or LUMPED mass). Forces that
  /// scale with the mass (gravity, contact's caps) read it here, so that a model rebuilt with a
  /// new thickness, density or mass keeps its forces (Simulation::loadContext fills it).
  double massPerArea = 1.0;
  /// The rest surface's area (world units; 1 when it is degenerate or not known).
  double restArea = 1.0;
};

/// What a force needs to bound its share of \f$\lambda_{max}(M^{-1} K)\f$, K being the
/// Jacobian of its load with respect to the moving control points.
struct MassContext {
  const SplineSpace& space;
  double interiorMass;                     ///< mass of a moving point whose B-spline lies inside
  std::function<double(int, int)> massAt;  ///< mass of net point (i, j) (net layers), moving or derived
  double restArea = 1.0;                   ///< as LoadContext::restArea
};

/// Where a force adds its Jacobian: 3 x 3 blocks between net points (full-net indices, held
/// points included; the receiver folds them onto the unknowns and drops held ones).
class JacobianSink {
 public:
  virtual ~JacobianSink() = default;
  /// Adds B to the block of rows of net point p and columns of net point q.
  virtual void add(Eigen::Index p, Eigen::Index q, const Eigen::Matrix3d& B) = 0;
  /// The same for a force whose whole Jacobian is symmetric and that adds every block, (q, p)
  /// as well as (p, q): a receiver that keeps one triangle can skip the symmetrisation.
  virtual void addSymmetric(Eigen::Index p, Eigen::Index q, const Eigen::Matrix3d& B) { add(p, q, B); }
  /// Whether the receiver asks for a positive semi-definite Jacobian where a force can make its
  /// own so (barrier contact: each pair's Hessian projected): the Newton matrix once the exact
  /// one was not positive definite. false: the exact Jacobian, Newton's first try (a barrier's
  /// pairs are not convex across their distance gradient, and projecting them where the whole
  /// matrix needs no projection slows Newton to a crawl along a sliding contact).
  bool wantsDefinite = false;
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
  /// Whether addJacobian() gives this force's derivatives. Forces that depend on the position or
  /// the velocity and have none are evaluated at every Newton iterate without them (EXPRESSION).
  virtual bool hasJacobian() const { return false; }
  /// Adds \f$K = -\partial L/\partial x - s\,\partial L/\partial v\f$ at the state of `ctx`: the
  /// stiffness of the load with respect to the control points, plus `velocityScale` s times its
  /// damping (the velocity the force sees is (current - previous) / stepSize, so an implicit
  /// step whose velocity is (x - previous) / stepSize passes s = 1 / stepSize). Blocks between
  /// net points. A follower load's non-symmetric K is given whole; the solver symmetrises it.
  virtual void addJacobian(const LoadContext& ctx, double velocityScale, JacobianSink& sink) const {
    (void)ctx;
    (void)velocityScale;
    (void)sink;
  }
  /// The force's potential \f$\Phi\f$ at the state of `ctx`, with \f$L = -\partial\Phi/\partial x\f$ (for a
  /// velocity-dependent force, the incremental potential of the step: the velocity is
  /// (x - previous) / stepSize); false when it has none (a follower pressure). Constant loads are
  /// left to the caller (\f$-L\cdot x\f$). Only differences of it matter (line searches).
  virtual bool potential(const LoadContext& ctx, double& value) const {
    (void)ctx;
    value = 0.0;
    return false;
  }
  /// The largest fraction t in (0, 1] of the move from the state of `ctx` (ctx.current) to the
  /// full net `to` over which the force stays finite (barrier contact: no pair crosses); 1 for
  /// forces without a barrier. The implicit step's line search never tries beyond it.
  virtual double admissibleFraction(const LoadContext& ctx, const ControlNet& to) const {
    (void)ctx;
    (void)to;
    return 1.0;
  }
  /// Moves what the force sweeps within a step (obstacles that moved since the last step, from
  /// where the surface last saw them toward their poses now) as far as it can without anything
  /// crossing while the surface stays at the state of `ctx`; returns the fraction of that move
  /// still to go (0: none, or all done). The implicit step alternates it with Newton solves
  /// until it is 0.
  virtual double advanceObstacles(const LoadContext& ctx) const {
    (void)ctx;
    return 0.0;
  }
  /// The largest fraction t in [0, 1] of a joint move that nothing crosses: the surface from the
  /// state of `ctx` to the full net `to` while every obstacle still short of its pose (see
  /// advanceObstacles()) moves toward it by `obstacleFraction` of what it has left. A move of the
  /// surface alone (admissibleFraction()) for forces that sweep nothing.
  virtual double jointAdvanceFraction(const LoadContext& ctx, const ControlNet& to, double obstacleFraction) const {
    (void)obstacleFraction;
    return admissibleFraction(ctx, to);
  }
  /// Moves every obstacle still short of its pose by `fraction` of what it has left (a fraction
  /// jointAdvanceFraction() allowed, with the surface moved along); returns the fraction of the
  /// step's move still to go, as advanceObstacles().
  virtual double advanceObstaclesBy(const LoadContext& ctx, double fraction) const {
    (void)ctx;
    (void)fraction;
    return 0.0;
  }
  /// Whether admissibleFraction() can be below 1 (the implicit step then checks every trial).
  virtual bool limitsSteps() const { return false; }
  /// Called by the implicit steppers at the start of every step, at the step's start state:
  /// adapts what is adapted between steps (a barrier's stiffness), and returns why the state is
  /// not admissible (a surface that starts inside an obstacle), empty when it is.
  virtual std::string beginStep(const LoadContext& ctx) const {
    (void)ctx;
    return std::string();
  }
  /// Why only BACKWARD_EULER can take this force (it needs the line search that admissibleFraction()
  /// bounds), or null when every integrator can.
  virtual const char* backwardEulerOnly() const { return nullptr; }
  /// What the force adapts between steps (a barrier's stiffness), so that a saved and resumed run
  /// takes the same steps as one that went on (SimulationState): empty while nothing is adapted.
  virtual std::vector<double> adaptedState() const { return {}; }
  /// Puts back what adaptedState() gave; empty: the state the force was made with.
  /// @throws std::invalid_argument naming what is wrong with `state`
  virtual void setAdaptedState(const std::vector<double>& state) const {
    if (!state.empty()) throw std::invalid_argument("this force adapts nothing between steps, yet was given a state");
  }
  /// Rounds what adaptedState() gives in place with `round` (Simulation::setStateRounding()),
  /// so that it equals what a file holding it gives back; nothing else changes.
  virtual void roundAdaptedState(double (*round)(double)) const { (void)round; }

  /// For the implicit steppers' energy check: the energy the force stores at the state, when the
  /// rest of its load can only dissipate (damping, friction); false when it can do work on the
  /// surface (a follower pressure, a callable, a load that depends on time). The default: the
  /// potential of a load that depends on the position alone, 0 for one that depends on the
  /// velocity alone (drag dissipates).
  virtual bool storedEnergy(const LoadContext& ctx, double& value) const {
    value = 0.0;
    const unsigned dep = dependence();
    if (dep & kDependsOnTime) return false;
    if (!(dep & (kDependsOnPosition | kDependsOnNormal))) return (dep & kDependsOnVelocity) != 0;
    if (dep & kDependsOnVelocity) return false;
    return potential(ctx, value);
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
  /// A point force F(S, Ṡ) whose derivatives pointDerivatives() gives: \f$K_{pq} = \beta_p \beta_q
  /// (K_x + s K_v)\f$ with \f$\beta\f$ the B-splines at (u0, v0).
  bool hasJacobian() const override { return m_hasPointDerivatives; }
  void addJacobian(const LoadContext& ctx, double velocityScale, JacobianSink& sink) const override;
  bool potential(const LoadContext& ctx, double& value) const override;

 protected:
  /// \f$K_x = -\partial F/\partial S\f$, \f$K_v = -\partial F/\partial\dot S\f$ and the potential
  /// \f$\Phi\f$ (\f$F = -\partial\Phi/\partial S\f$) at the sample; see setHasPointDerivatives().
  virtual void pointDerivatives(const SurfaceSample& sample, Eigen::Matrix3d& Kx, Eigen::Matrix3d& Kv,
                                double& phi) const {
    (void)sample;
    Kx.setZero();
    Kv.setZero();
    phi = 0.0;
  }
  void setHasPointDerivatives() { m_hasPointDerivatives = true; }

 private:
  bool m_hasPointDerivatives = false;
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

  /// The Jacobian of a density whose derivatives densityDerivatives() gives:
  /// \f$\sum_g w_g B_p B_q (K_x + s K_v)\f$ over the same Gauss points as the load.
  bool hasJacobian() const override { return m_hasDensityDerivatives; }
  void addJacobian(const LoadContext& ctx, double velocityScale, JacobianSink& sink) const override;
  /// \f$\int \phi\f$ over the same Gauss points, \f$\phi\f$ from densityDerivatives().
  bool potential(const LoadContext& ctx, double& value) const override;

 protected:
  /// Subclasses whose density depends on the position and velocity only through S(u, v) and
  /// its velocity (not the normal) give \f$K_x = -\partial f/\partial S\f$, \f$K_v = -\partial
  /// f/\partial \dot S\f$ and the potential density \f$\phi\f$ (\f$f = -\partial\phi/\partial S\f$;
  /// for a velocity dependence, the step's: \f$\dot S = (S - S_{prev})/\delta\f$) through these.
  virtual void densityDerivatives(const SurfaceSample& sample, Eigen::Matrix3d& Kx, Eigen::Matrix3d& Kv,
                                  double& phi) const {
    (void)sample;
    Kx.setZero();
    Kv.setZero();
    phi = 0.0;
  }
  /// Declares that densityDerivatives() is implemented.
  void setHasDensityDerivatives() { m_hasDensityDerivatives = true; }
  /// Gauss points of the load's 2-D rule with their weights (area element included) and 1-D
  /// bases (first derivatives evaluated): fn(sample, weight, bu, bv).
  void forEachGaussPoint(
      const LoadContext& ctx, unsigned dependence,
      const std::function<void(const SurfaceSample&, double, const LocalBasis&, const LocalBasis&)>& fn) const;
  /// With physical units (LoadContext::rest), the density is per unit area of the current
  /// surface (a follower pressure) instead of the rest surface's.
  void setPerCurrentArea() { m_perCurrentArea = true; }

 private:
  void addLineLoad(const LoadContext& ctx, ControlNet& load) const;
  bool m_perCurrentArea = false;
  bool m_hasDensityDerivatives = false;
  bool m_isConstant = false;  ///< the density is the constant m_constantDensity
  Eigen::Vector3d m_constantDensity = Eigen::Vector3d::Zero();
  ForceFunction m_density;
  unsigned m_dependence;
  Rect m_rect;
  int m_extraPoints;
  double m_stiffness;
  /// forEachGaussPoint()'s rule (points, 1-D bases, weights with the rest area element), made
  /// at the first call for a space and rest net and kept while they are the same: a callable
  /// load (the flag's wind) is evaluated at every explicit sub-step, and evaluating the rest
  /// surface at 36 points per span each time took a third of the flag's run. Shared by copies;
  /// guarded for forces evaluated from several threads.
  struct GaussPlan;
  struct PlanCache;
  std::shared_ptr<const GaussPlan> gaussPlan(const LoadContext& ctx, int order, bool restArea) const;
  std::shared_ptr<PlanCache> m_plans;
};

}  // namespace bsdeform
