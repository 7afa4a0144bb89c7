// SPDX-License-Identifier: MIT
#pragma once
/// @file Simulation.h
/// The dynamic model (paper eq. 11) \f$M \ddot P + C \dot P + A P = L\f$ on the free control
/// points, integrated with the corrected explicit central-difference scheme (design.md §2, with
/// automatic sub-stepping below the stability limit) or an unconditionally stable implicit
/// scheme (Newmark average acceleration in three-level form, matrix factorised once).
///
/// A Simulation is a model (the spline space, the held points, the mass and the elastic energy,
/// ElasticEnergy.h), a state (current and previous nets, time, status) and a time stepper that
/// advances the state one sub-step (TimeStepper.h, not installed: the paper's and the shell's
/// explicit and implicit schemes, each with its own data).

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bsdeform/dynamics/Diagnostics.h"
#include "bsdeform/dynamics/EdgeMass.h"
#include "bsdeform/energy/ElasticEnergy.h"
#include "bsdeform/forces/Force.h"
#include "bsdeform/dynamics/ImplicitSystem.h"
#include "bsdeform/energy/Shell.h"
#include "bsdeform/dynamics/ArcLength.h"
#include "bsdeform/dynamics/SideSupports.h"
#include "bsdeform/dynamics/StepCosts.h"
#include "bsdeform/spline/SplineSpace.h"
#include "bsdeform/energy/StiffnessStencil.h"
#include "bsdeform/dynamics/TangentMatrix.h"

namespace bsdeform {

class MassMatrix;
class TimeStepper;
class StepperModel;

enum class Integrator {
  Explicit,  ///< central differences (eq. 12, corrected), sub-stepped below the stability limit
  Implicit,  ///< Newmark beta = 1/4, gamma = 1/2 in displacement form; see ImplicitSystem.h
  /// Either energy: backward Euler as the minimisation of the incremental potential, every force
  /// inside the Newton system (its Jacobian), a line search on the potential; first order,
  /// dissipative: the total energy never rises without work done (checked). For cloth.
  BackwardEuler,
};

/// How BACKWARD_EULER finds each step's minimum.
enum class NonlinearSolver {
  /// Newton: the tangent (element Hessians, the forces' Jacobians) assembled and factorised
  /// (CHOLMOD) at the iterates; a few iterations a step.
  Newton,
  /// L-BFGS (Liu, Bouaziz, Kavan 2017): no tangent within the steps; directions from the last
  /// gradients and one matrix factorised per model and time step, the mass over h² plus the
  /// rest tangent made isotropic (docs/math.md §16). More iterations, each a gradient and a
  /// triangular solve.
  LBFGS,
};

enum class MassModel {
  Nodal,   ///< the paper's M = m I, C = c I (mass, damping per control point)
  Lumped,  ///< M = rho h1 h2 I, C = c h1 h2 I (mass, damping per unit parameter area)
};

/// What the elastic energy measures.
enum class ElasticReference {
  Rest,      ///< energy of the displacement S - S_rest: any rest net is an equilibrium
  Absolute,  ///< the paper's energy of S itself; equal to Rest for the Greville plane
};

/// Which elastic energy the model has.
enum class EnergyModel {
  Paper,  ///< the paper's eq. 7: quadratic in the positions, weights omega (the default)
  Shell,  ///< the Kirchhoff–Love thin shell of a St. Venant–Kirchhoff or neo-Hookean material (Shell.h)
};

/// How the scheme starts from a state at rest (the net one (sub-)step delta before t = 0).
enum class StartRule {
  Paper,        ///< P(-delta) = P(0): the paper's start, first order against a release from rest
  SecondOrder,  ///< P(-delta) = P(0) + delta^2/2 M^-1 (L - (A P(0) - c0)): consistent to O(delta^3)
};

enum class Status {
  Ok,
  NonFinite,  ///< a step produced NaN or infinity; the last finite state is kept
  Diverged,   ///< a coordinate exceeded the divergence limit; the last state is kept
  Refused,    ///< the step cannot be taken as asked (see Simulation::refusal()); nothing changed
};

/// Everything that defines a model. Defaults are the paper's §5 settings, except the start.
struct ModelParameters {
  int degreeU = 3, degreeV = 3;  ///< n1, n2 in 1..7
  int numU = 5, numV = 5;        ///< N1, N2 inner control points, 1..65536, N1 N2 <= 2^22
  Boundaries boundaries;         ///< each side CLAMPED (the paper), FREE or PERIODIC
  /// Pinned parameter points (u, v) in [0,1]^2: each holds the (n1+1)(n2+1) control points of
  /// the knot span containing it (spans half-open, the last closed at 1), so S(u, v) stays at
  /// its rest position.
  std::vector<Eigen::Vector2d> pins;
  /// SHELL only: single coordinates held at their rest values, each (net row of a moving
  /// control point, axis 0..2): rollers, and the symmetry conditions that remove a free body's
  /// rigid motions without a reaction (a point on a symmetry plane keeps its coordinate normal
  /// to it). Honoured by both time steppers and the static solver; not with SIMPLY_SUPPORTED or
  /// BUILT_IN sides (their mass is not diagonal).
  struct HeldCoordinate {
    Eigen::Index point = 0;
    int axis = 0;
  };
  std::vector<HeldCoordinate> heldCoordinates;
  /// SHELL: per side (uMin, uMax, vMin, vMax), a support that
  /// holds chosen world components of the edge curve (a diaphragm, a roller) or a symmetry
  /// plane through it (SideSupports.h); such a side is FREE in `boundaries`. BACKWARD_EULER and
  /// IMPLICIT take them; EXPLICIT refuses a model with one (Status::Refused, saying so).
  SideSupports sideSupports;
  /// SHELL: the world components the pins hold (bit 0 x,
  /// 1 y, 2 z; 7 all, the default). EXPLICIT refuses pins holding fewer.
  unsigned pinComponents = 7;
  Weights weights;               ///< omega_10 .. omega_02
  MassModel massModel = MassModel::Nodal;
  double mass = 1.0;     ///< m (> 0): per control point (Nodal) or per unit area (Lumped)
  double damping = 0.5;  ///< c (>= 0): same units convention as mass
  double timeStep = 0.1;  ///< Delta t (> 0) of one step()
  Integrator integrator = Integrator::Explicit;
  ElasticReference reference = ElasticReference::Rest;
  StartRule start = StartRule::SecondOrder;
  bool autoSubstep = true;        ///< explicit only: split Delta t to stay below the limit
  double stabilitySafety = 0.9;   ///< sub-step <= safety * stability limit, in (0, 1]
  double divergenceLimit = 1e6;   ///< |coordinate| > limit * (1 + max |rest coordinate|) stops
  /// Explicit: a step that needs more sub-steps than this is refused (Status::Refused) instead
  /// of running for minutes; >= 1.
  int maxSubSteps = 10000;
  /// Implicit only: how the constant system is solved (ImplicitSystem.h).
  LinearSolver implicitSolver = LinearSolver::Automatic;
  /// Implicit with conjugate gradients: relative residual per coordinate, in (0, 1).
  double solverTolerance = 1e-10;
  /// Implicit with conjugate gradients: a solve that needs more iterations fails the step.
  int maxSolverIterations = 10000;
  /// The elastic energy. SHELL ignores `weights`, `massModel` and `mass`: its mass is
  /// material.density x material.thickness per unit rest area (lumped), `damping` is a
  /// mass-proportional rate (1/s), and loads are densities per unit rest area (LoadContext).
  EnergyModel energy = EnergyModel::Paper;
  ShellMaterial material;  ///< SHELL only
  /// SHELL, implicit and static: Newton stops when the residual, relative to the forces it
  /// balances, is below this; in (0, 1).
  double newtonTolerance = 1e-8;
  /// SHELL, implicit: a step whose Newton iteration needs more iterations fails (reported,
  /// the last valid state kept); static: per load increment.
  int maxNewtonIterations = 30;
  /// BACKWARD_EULER: Newton has converged when its largest update, divided by the time
  /// step, is below this velocity (m/s in SI scenes); > 0. The residual criterion above also
  /// ends it.
  double newtonVelocityTolerance = 1e-4;
  /// BACKWARD_EULER: Newton's method or L-BFGS (NonlinearSolver). L-BFGS starts from each
  /// step's first tangent instead of the isotropic matrix with a barrier contact, supports per
  /// component or symmetry sides.
  NonlinearSolver nonlinearSolver = NonlinearSolver::Newton;
};

/// Simulation::solveStatic(): the equilibrium found and how.
struct StaticResult {
  ControlNet net;          ///< the full net at equilibrium (held and derived points included)
  /// ||A P - c0 - L(P)|| / (||A|| ||P - P_rest|| + ||L(P)|| + ||c0||) on the unpinned
  /// unknowns: the normwise backward error
  double residual = 0.0;
  int loadIterations = 1;  ///< fixed-point iterations (1 when no load depends on the position)
  std::string method;      ///< "CHOLMOD Cholesky", "multigrid-preconditioned CG", "Jacobi-preconditioned CG" or "Newton (CHOLMOD)"
  /// One equilibrium per load increment (loadSteps of them, the last being `net`): the load
  /// factor, the net and its residual, and the iterations it took (Newton's for SHELL, the
  /// fixed point's for the paper's model).
  struct Increment {
    double loadFactor = 1.0;
    ControlNet net;
    double residual = 0.0;
    int iterations = 0;
  };
  std::vector<Increment> increments;
};

/// What setState() does with held points (clamped layers, pins) that differ from the rest net.
enum class HeldPoints {
  Check,  ///< they must equal the rest net's to 1e-12 (relative), else std::invalid_argument
  Reset,  ///< they are set to the rest net's (a model edit that holds new points)
};

class Simulation {
 public:
  /// Rest and initial state: the Greville plane S(u,v) = (u, v, 0).
  /// @throws std::invalid_argument naming the parameter and the value, also for a periodic
  ///         direction (the plane does not close: give a rest net)
  explicit Simulation(const ModelParameters& params);
  /// Rest and initial state given as a full net of (N1 + 2 n1) x (N2 + 2 n2) points. In a
  /// periodic direction the last n layers are set from the first n (see seamMismatch()).
  Simulation(const ModelParameters& params, const ControlNet& rest);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  const ModelParameters& parameters() const { return m_params; }
  const SplineSpace& space() const { return m_space; }
  const StiffnessStencil& stencil() const { return m_stencil; }

  /// Forces act from the next step on. Adding or removing may change the sub-step count.
  void addForce(std::shared_ptr<const Force> force);
  bool removeForce(const Force* force);
  void clearForces();
  const std::vector<std::shared_ptr<const Force>>& forces() const { return m_forces; }

  /// Advances by one Delta t (sub-steps inside). Does nothing once the status is not Ok.
  Status step();
  /// Advances by `steps` Delta t; stops early on failure.
  Status advance(long steps);
  /// Back to the rest state at t = 0, status Ok; the forces forget what they adapted.
  void reset();
  /// Sets the state (e.g. read back from a file). `previous` is the net one step of size
  /// `previousStepSize` before `current` (0: the current sub-step size); it is rescaled to the
  /// current sub-step keeping the velocity. Held points (clamped layers, pins in the components
  /// they hold: ModelParameters::pinComponents) are set to the rest values exactly, after the
  /// check `held` asks for. Periodic copies: the first n layers win.
  /// @throws std::invalid_argument for wrong sizes, NaN, or (Check) changed held points
  void setState(const ControlNet& current, const ControlNet& previous, double time, long steps,
                double previousStepSize = 0.0, HeldPoints held = HeldPoints::Check);
  /// A CLAMPED side moved by a prescribed map (SHELL, BACKWARD_EULER: a sheet twisted by
  /// turning one edge). From the next step on, the n layers side `side` (0 u = 0, 1 u = 1,
  /// 2 v = 0, 3 v = 1) holds are held at `map` applied to their rest positions: reached at the end
  /// of that step (a step retaken in pieces moves them linearly over its pieces), the move checked
  /// first by every barrier's continuous collision check (a move that would cross is refused
  /// as the step's failure). The sides next to a moved side must be FREE or PERIODIC, or moved
  /// by the same map (else the step is refused, see refusal()). A state given to setState() may
  /// hold a moved side's layers anywhere (they move from there to the map at the next step).
  /// @throws std::invalid_argument naming the side when it is not CLAMPED, and for a map that is
  ///         not finite
  void setSideMotion(int side, const Eigen::Matrix3d& linear, const Eigen::Vector3d& offset);
  /// The side held at rest again, and no longer moved: reached at the end of the next step.
  void clearSideMotion(int side);
  /// Whether setSideMotion() moves `side`.
  bool sideMoved(int side) const { return m_sideMoved[size_t(side)]; }
  /// Sets the state released from rest at `current` (velocity zero; the start rule applies).
  void setState(const ControlNet& current, double time, long steps, HeldPoints held = HeldPoints::Check);
  /// Rounds the state after every step with `round` (the current and previous nets, the clock,
  /// what the forces adapt: Force::roundAdaptedState()), held points then put back exactly as
  /// setState() puts them; the clock lands on the rounded end of each step. Given the rounding of a file format (the nodes give snap15, what a
  /// scene keeps of a double), a run resumed from a written state starts from the bits the run
  /// that wrote it goes on from, and takes the same steps bit for bit. Null (the default): the
  /// state is kept as the steps leave it.
  void setStateRounding(double (*round)(double));
  /// Largest coordinate difference between the first and last n layers of a periodic direction
  /// in the nets given to the constructor and setState() (the first were used); 0 if none.
  double seamMismatch() const { return m_seamMismatch; }

  /// Whether the state is released from rest (after construction, reset() or the
  /// release-from-rest setState()): the start rule applies at the next step.
  bool startPending() const { return m_startPending; }
  const ControlNet& current() const { return m_current; }
  /// The net one sub-step before current().
  const ControlNet& previous() const { return m_previous; }
  const ControlNet& rest() const { return m_rest; }
  double time() const { return m_time; }
  long stepCount() const { return m_steps; }

  /// Upper bound of lambda_max(M^-1 (A_II + force stiffness)).
  double eigenvalueBound() const { return m_lambdaMax; }
  /// Upper bound of lambda_max(A_II) alone (stiffness units), computed once at build.
  double stiffnessEigenvalueBound() const { return m_stencilLambda; }
  /// The stiffness of a spring that drags the surface by one point (the viewer's mouse): the
  /// paper's model, stiffnessEigenvalueBound() (it dominates the surface's own stiffness at the
  /// point); SHELL, the whole sheet's mass times (2 pi 5 Hz)^2: the sheet follows the mouse with
  /// a 5 Hz response whatever its net (N/m in SI scenes).
  double dragStiffness() const;
  /// Upper bound of lambda_max(M^-1 A_II) alone, computed once at build.
  double elasticEigenvalueBound() const { return m_elasticLambda; }
  /// Largest stable explicit step 2 / sqrt(lambda_max) (a lower bound of the true limit).
  double stabilityLimit() const;
  /// Sub-steps per step (1 for the implicit scheme).
  int subSteps() const { return m_subSteps; }
  double subStepSize() const { return m_params.timeStep / m_subSteps; }

  /// Sub-steps a step would need below the stability limit (may exceed maxSubSteps, be huge or
  /// infinite); subSteps() is this number when it is allowed.
  double subStepsNeeded() const { return m_subStepsNeeded; }
  /// Why the next step() would be refused, or "" when it can be taken: it needs more than
  /// maxSubSteps sub-steps, or the clock no longer advances by Delta t at time() (t + Delta t
  /// rounds to t, or off by more than 1e-4 Delta t), or the model has supports the time
  /// steppers do not take (sideSupports, pinComponents: static solve and arc length only).
  std::string refusal() const;

  Status status() const { return m_status; }
  const std::string& statusMessage() const { return m_statusMessage; }

  /// The paper's eq. 15: ||P_I - P0_I|| over the moving control points (each periodic point once).
  double deformationNorm() const;
  /// 1/2 v^T M v with v = (P(t) - P(t - dt_sub)) / dt_sub on the moving points.
  double kineticEnergy() const;
  /// 1/2 D^T A_II D with D = P - P_rest, total and per weight term.
  StrainEnergy strainEnergy() const;
  /// deformationNorm(), kineticEnergy() and strainEnergy() together, in one pass over the nets
  /// (Diagnostics.h): what a history row records. Equal to the three to rounding (1e-12
  /// relative, tested; the bending terms of large smooth states are ill-conditioned sums).
  Diagnostics diagnostics() const;
  /// The masses a diagnostics pass weighs the velocities with (Diagnostics.h).
  struct PointMasses {
    const double* perPoint = nullptr;  ///< per moving point (order of movingToNet), or null:
    double uniform = 1.0;              ///< every moving point has this mass
  };
  PointMasses pointMasses() const;
  /// sum W |current - previous|^2 over the points derived next to SIMPLY_SUPPORTED and BUILT_IN
  /// sides (their part of the kinetic energy's sum; 0 without them).
  double derivedVelocitySum() const { return derivedVelocitySum(m_current, m_previous); }
  /// A number no other Simulation of this process has had: tells a model from one built later
  /// at the same address (DiagnosticsBeside keeps copies per model).
  std::uint64_t serial() const { return m_serial; }
  /// Load vector L (numMoving x 3, order of SplineSpace::movingToNet) of all forces at the
  /// current state and time.
  ControlNet loadVector() const;
  /// Static equilibrium for the current loads: solves A_II P_I = L + c0 - A_IB P_B directly
  /// (pinned points held).
  /// @throws std::runtime_error if A_II is singular (all weights zero, or a free surface with
  ///         nothing holding it)
  ControlNet staticSolution() const;
  /// The paper's static problem (eq. 10) as a user feature: the equilibrium A P = L + c0 of the
  /// loads at time 0 with zero velocity, for nets of any size (CHOLMOD up to
  /// kAutomaticDirectPoints unknowns, multigrid-preconditioned CG above, each followed by
  /// defect correction with the stencil to `tolerance`). Loads that depend on the position
  /// (pressure, contact, springs) are evaluated at the solution by fixed-point iteration
  /// until the relative residual is below `tolerance`. The state is left alone.
  /// @throws std::runtime_error naming the free motions when nothing holds the surface (all
  ///         sides FREE and no pin: translations; only hinges: rotations about them), or when
  ///         the fixed point does not converge in `maxLoadIterations`
  /// @param solver Automatic: CHOLMOD up to kAutomaticDirectPoints unknowns, multigrid-
  ///        preconditioned CG above (docs/benchmarks.md, "Engineering edges and the static
  ///        problem")
  /// `loadSteps` >= 1: the loads are applied in that many equal increments, each equilibrium
  /// kept in StaticResult::increments (a load-displacement curve). For SHELL the equilibria are
  /// found by Newton's method with a line search from the previous one (the tangent projected
  /// to positive semidefinite where it is indefinite, and shifted by a multiple of the mass
  /// where nothing holds the surface), `maxLoadIterations` Newton iterations per increment.
  StaticResult solveStatic(double tolerance = 1e-10, int maxLoadIterations = 100,
                           LinearSolver solver = LinearSolver::Automatic, int loadSteps = 1) const;
  /// A rigid motion the held and constrained coordinates leave free (to first order) and
  /// `load` (on the unknowns) does work on, named ("the translation along y is free ..."), or
  /// ""; translations only unless `rotations`.
  std::string freeRigidMotionLoaded(const ControlNet& load, bool rotations) const;
  /// Why the static solve and arc length refuse this model, or "": a translation the held and
  /// constrained coordinates leave free (to first order), named, whether `load` (on the unknowns)
  /// does work on it (no equilibrium) or not (a family of them); with the way to hold it.
  std::string freeTranslationRefusal(const ControlNet& load) const;
  /// SHELL: the static equilibrium path by arc-length continuation (ArcLength.h, Crisfield's
  /// cylindrical form) from the rest state, the loads at time 0 scaled by the load factor:
  /// one StaticResult::Increment per converged point (its load factor, net, relative residual
  /// and Newton iterations), through limit points and snap-backs, until the load factor passes
  /// options.maxLoad or options.maxSteps points were found; `each` called with every point.
  /// The corrector's tangent is the elastic one (the loads' Jacobians left out: exact for loads
  /// that do not depend on the state).
  /// @throws std::runtime_error for the paper's energy, for a surface nothing holds (naming
  ///         the free motions' cause), or when a step does not converge even much shortened
  StaticResult solveStaticArcLength(const ArcLengthOptions& options,
                                    const std::function<void(const StaticResult::Increment&)>& each = {}) const;

  /// The elastic force on the unknowns at the current state (numMoving x 3, order of
  /// movingToNet): -dW/dP for SHELL (W the shell energy of the net the unknowns complete),
  /// c0 - A P for the paper's model.
  ControlNet elasticForce() const;
  /// The model's elastic energy (ElasticEnergy.h): PaperEnergy or ShellModelEnergy.
  const ElasticEnergy& energy() const { return *m_energy; }
  /// The shell energy (null for the paper's model).
  const ShellEnergy* shell() const { return m_shell; }
  /// The supports per component and SYMMETRY sides (ModelParameters::sideSupports), or null
  /// when no side has one.
  const ComponentConstraints* componentConstraints() const { return m_components.get(); }
  /// SHELL: membrane and bending energy of the current state (zeros for the paper's model).
  ShellEnergies shellEnergies() const;
  /// SHELL, implicit: Newton iterations of the last step.
  int lastNewtonIterations() const;
  /// Where the steps' time went since construction or resetStepCosts(): wall seconds per phase
  /// of the implicit steps (elastic energy, loads, collision checks, factorisation, solve),
  /// Newton iterations and factorisations (StepCosts.h).
  const StepCosts& stepCosts() const { return m_costs; }
  void resetStepCosts() { m_costs = StepCosts(); }

  /// The implicit scheme's linear system (null for the explicit scheme): its method, condition
  /// bound and the last solve's iterations.
  const ImplicitSystem* implicitSystem() const;

  /// Mass per unit rest area, for loads given per area (gravity): rho t (SHELL), m / (h1 h2)
  /// (NODAL: m per point, h1 h2 the parameter area per point) or m (LUMPED, per unit parameter
  /// area).
  double massPerArea() const;
  /// World area of the rest surface (surfaceArea(); computed once).
  double restArea() const;
  /// restArea(), or 1 where the rest surface is degenerate (what LoadContext::restArea holds).
  double usableRestArea() const;
  /// Whether the rest surface is closed (isClosedSurface(); computed once): a closed surface
  /// shows no back faces.
  bool restIsClosed() const;

  /// Mass of net point (i, j) (net layers): m (NODAL) or rho times the exact row sum
  /// \f$\int_{[0,1]^2} B_k\f$ of the Gram matrix (LUMPED; smaller next to a free edge). The
  /// control points derived next to a SIMPLY_SUPPORTED or BUILT_IN side have theirs too: the
  /// mass matrix of the unknowns is then \f$T^T W T\f$ (EdgeMass.h), not this diagonal.
  double massAt(int i, int j) const;
  /// Net rows of the points held by pins (moving points only).
  const std::vector<Eigen::Index>& pinnedRows() const { return m_pinned; }
  /// Whether coordinate `axis` of moving point f (order of movingToNet) is held: by a pin or by
  /// ModelParameters::heldCoordinates.
  bool heldCoordinate(Eigen::Index f, int axis) const { return m_heldMask[size_t(3 * f + axis)] != 0; }

  /// S(u, v) on the current net.
  SurfacePoint evaluate(double u, double v, int order = 1) const { return m_space.evaluate(m_current, u, v, order); }

 private:
  void init();
  void applyStartRule();
  void holdPins(ControlNet& net) const;
  /// Moving-point numbers of the pinned points, ascending.
  std::vector<Eigen::Index> pinnedMoving() const;
  /// Load of all forces on the net `net` at rest (zero velocity) at time t.
  ControlNet loadAt(const ControlNet& net, double t) const;
  /// The context forces build their loads in: for SHELL, with the rest surface's area element.
  LoadContext loadContext(const ControlNet& current, const ControlNet& previous, double stepSize, double t) const;
  /// Free motions of the unloaded model among displacements a + b u + c v (u, v the Greville
  /// coordinates), described for a message; empty if there is none.
  std::string freeMotions() const;
  /// A_II without the pinned rows and columns.
  Eigen::SparseMatrix<double> activeMatrix() const;
  /// A_IB P_B, the coupling to every held point (clamped layers and pins): what the static
  /// solve needs (both schemes apply A to the whole net).
  ControlNet boundaryTerm() const;
  /// c0 = (A P_rest)_moving for ElasticReference::Rest (what makes the rest net an
  /// equilibrium), else 0.
  ControlNet restOffset() const;
  /// m_constantLoad = c0 + the loads of the constant forces, in their order.
  void rebuildConstantLoad();
  void updateSubSteps();
  /// Constant load plus the variable forces evaluated at the current state and time t.
  /// `stepSize`: of the velocity (current - previous) / stepSize the forces see; 0: subStepSize().
  /// With sub-steps, the loads that depend on time alone (a wind expression) are evaluated at
  /// the step's two ends and interpolated linearly in between (an O(Δt²) error, the step's time
  /// resolution; the implicit schemes hold them at one time per step).
  const ControlNet& effectiveLoad(double t, double stepSize = 0.0);
  /// The sum of the loads that depend on time alone, at time t: the last two times asked are
  /// kept (a step's end is the next step's start), for the force list they were made with.
  const ControlNet& timeLoad(double t);
  struct TimeLoadCache {
    double time = 0.0;
    std::uint64_t forces = 0;  ///< m_forcesVersion it was made for (0: empty)
    ControlNet load;
  };
  std::array<TimeLoadCache, 2> m_timeLoads;
  std::uint64_t m_forcesVersion = 1;  ///< counts changes of m_forces
  void fail(Status s, std::string message);
  // SHELL (SimulationShell.cpp)
  void initShell();
  /// scale H + shift M (+ forceScale times the forces' Jacobians at `forces`, their velocity
  /// part times velocityScale, symmetrised) over the unknowns' coordinates (3 f + c), assembled
  /// in place (TangentMatrix: fixed pattern, lower triangle), held coordinates replaced by
  /// identity rows. H: SHELL's T^T H(net) T by elements (`mode`), the paper's constant A_II.
  const Eigen::SparseMatrix<double>& tangent(const ControlNet& net, double scale, double shift, HessianMode mode,
                                             const LoadContext* forces = nullptr, double velocityScale = 0.0,
                                             double forceScale = 1.0) const;
  /// The last tangent() with `extra` times the mass added (held coordinates kept as identity
  /// rows): a larger mass multiple without assembling again. Only after a tangent().
  const Eigen::SparseMatrix<double>& shiftTangent(double extra) const;
  /// dW/dP on the unknowns (numMoving x 3): ShellModelEnergy::gradient().
  void shellGradient(const ControlNet& net, ControlNet& out) const { m_energy->gradient(net, out); }
  void shellUpdateBound();
  /// The nets, held points and forces' adapted states rounded by setStateRounding()'s
  /// function, if any.
  void roundState();
  /// Where the clock lands after the step from m_time: m_time + timeStep, rounded as the state
  /// is (setStateRounding()).
  double stepEnd() const;
  /// Held points at the rest net's values, derived layers, held coordinates (setState()).
  void holdState(ControlNet& cur, ControlNet& prev, HeldPoints held) const;
  StaticResult solveStaticShell(double tolerance, int maxIterations, int loadSteps) const;
  StaticResult solveStaticPaper(double tolerance, int maxLoadIterations, LinearSolver solver, double loadFactor) const;
  /// sum W |current - previous|^2 over the derived points (0 without them).
  double derivedVelocitySum(const ControlNet& current, const ControlNet& previous) const;
  double massPerPoint() const;
  double dampingPerPoint() const;

  ModelParameters m_params;
  SplineSpace m_space;
  StiffnessStencil m_stencil;
  ControlNet m_rest, m_current, m_previous;
  ControlNet m_constantLoad;   ///< c0 (restOffset()) + constant forces
  ControlNet m_load;           ///< scratch
  std::vector<Eigen::Index> m_pinned;  ///< net rows held by pins
  std::vector<char> m_pinMask;         ///< per net row
  std::vector<char> m_heldMask;        ///< per coordinate 3 f + axis of the moving points (pins too)
  double m_seamMismatch = 0.0;
  // restArea(), restIsClosed(): computed when first asked (an area is a quadrature over the
  // whole net), on the thread that owns the simulation
  mutable double m_restArea = -1.0;
  mutable int m_restClosed = -1;
  bool m_uniformMass = true;      ///< every moving point has massPerPoint() (else m_massMoving)
  Eigen::VectorXd m_massMoving;   ///< per moving point, when not uniform
  bool m_startPending = true;  ///< the start rule is applied at the next step
  std::vector<std::shared_ptr<const Force>> m_forces;
  bool m_hasVariableForces = false;
  double m_stencilLambda = 0.0;
  double m_elasticLambda = 0.0;
  double m_lambdaMax = 0.0;
  int m_subSteps = 1;
  double m_subStepsNeeded = 1.0;
  double m_divergenceLimit = 0.0;
  double (*m_stateRounding)(double) = nullptr;  ///< setStateRounding()
  double m_time = 0.0;
  long m_steps = 0;
  Status m_status = Status::Ok;
  std::string m_statusMessage;
  /// The mass of the unknowns next to sides with derived layers (null without them), the
  /// derived points' net rows, and the band's scratch for the explicit step.
  std::unique_ptr<EdgeMass> m_edgeMass;
  std::vector<Eigen::Index> m_derivedRows;
  std::uint64_t m_serial;

  std::unique_ptr<ElasticEnergy> m_energy;
  const PaperEnergy* m_paper = nullptr;  ///< m_energy for the paper's model, else null

  /// Net rows of the layers each side holds (CLAMPED: n layers; low-degree SIMPLY_SUPPORTED and
  /// BUILT_IN hold some too), per side; and where those rows are held: m_rest's rows, moved
  /// sides' rows mapped (setSideMotion()).
  std::array<std::vector<Eigen::Index>, 4> m_sideRows;
  std::array<bool, 4> m_sideMoved{};
  std::array<Eigen::Matrix<double, 3, 4>, 4> m_sideMap;
  ControlNet m_heldTarget;
  /// m_heldTarget from m_rest and the moved sides' maps (a corner two moved sides share: the
  /// refusal checks their maps are equal).
  void updateHeldTarget();
  /// Whether some row a side holds is not at m_heldTarget's in `net`.
  bool heldRowsMoved(const ControlNet& net) const;
  /// net's held-layer rows := from's + alpha (m_heldTarget's - from's) (alpha 1: exactly the target's).
  void placeHeldRows(const ControlNet& from, double alpha, ControlNet& net) const;
  /// net's held-layer rows := from's.
  void copyHeldRows(const ControlNet& from, ControlNet& net) const;
  // SHELL
  const ShellModelEnergy* m_shellModel = nullptr;  ///< m_energy for SHELL, else null
  const ShellEnergy* m_shell = nullptr;            ///< its ShellEnergy
  /// The unknowns' mass, both models (MassMatrix.h): the paper's m I, its lumped or edge mass,
  /// the SHELL's T^T W T. The paper's explicit and implicit schemes keep their fast paths
  /// (m_uniformMass, m_massMoving, m_edgeMass); every other scheme reads this.
  mutable std::unique_ptr<MassMatrix> m_mass;
  /// m_mass, built at the first call for the paper's model.
  const MassMatrix& massMatrix() const;
  /// c in C = c M (the damping matrix as a multiple of the mass).
  double dampingRatio() const;
  /// The loads that do not change within a step: m_constantLoad without the paper's c0 (which
  /// ElasticEnergy::gradient() has).
  ControlNet forcesConstantLoad() const { return m_paper ? ControlNet(m_constantLoad - m_paper->restOffset()) : m_constantLoad; }
  mutable Eigen::SparseMatrix<double> m_paperStiffness;  ///< A_II (both triangles), the paper's tangent (first use)
  mutable StepCosts m_costs;  ///< stepCosts(); tangent() adds its assembly's
  mutable std::unique_ptr<TangentMatrix> m_tangent;  ///< the Newton tangent's fixed pattern (first use)
  /// ModelParameters::sideSupports on the unknowns (null without any)
  std::unique_ptr<ComponentConstraints> m_components;
  std::vector<char> m_tangentHeldMask;  ///< m_heldMask without m_components' coordinates (folded later)
  /// The unknowns x (constrained coordinates completed) into the full net `net`.
  void completeUnknowns(ControlNet& x, ControlNet& net) const;
  /// Whether every side is FREE or PERIODIC in the space (supports per component and SYMMETRY
  /// sides are FREE there).
  bool sidesHoldNothing() const;
  /// ... and no coordinate is held or constrained either (pins, held coordinates, supports per
  /// component): the surface is a free body.
  bool holdsNothing() const;
  /// A rigid motion the held and constrained coordinates leave free and `load` does work on
  /// (any free one when `load` is null), named, or "" (freeRigidMotionLoaded()).
  std::string freeRigidMotion(const ControlNet* load, bool rotations) const;
  /// What the scheme sees of this Simulation (StepperModel.h, not installed): a nested adapter
  /// (StepperView.h), made at the first call; the schemes are not friends.
  class StepperView;
  std::unique_ptr<StepperView> m_view;
  StepperModel& stepperView();
  /// The scheme (TimeStepper.h): created by init() and initShell().
  std::unique_ptr<TimeStepper> m_stepper;
};

}  // namespace bsdeform
