// SPDX-License-Identifier: MIT
// The time steppers (TimeStepper.h): the paper's explicit and implicit schemes, the shell's and
// backward Euler, each with the data only it uses. They read and write the state the Simulation
// holds through StepperModel (`s` below), and nothing else of it.
#include "bsdeform/dynamics/TimeStepper.h"
#include "bsdeform/dynamics/MassMatrix.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <functional>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "bsdeform/base/HugePages.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/dynamics/NewtonMinimizer.h"
#include "bsdeform/dynamics/SparseCholesky.h"

namespace bsdeform {

TimeStepper::~TimeStepper() = default;

bool TimeStepper::retakeInPieces(ControlNet& current, ControlNet& previous, const ControlNet& start,
                                 const ControlNet& before, double t, double dt,
                                 const std::function<bool(double, double)>& stepOf, const std::function<void()>& restart,
                                 const std::function<void(const ControlNet&, int)>& finish) {
  if (m_startRefused) {  // smaller pieces start from the same state: the state stays as it was
    current = start;
    previous = before;
    restart();
    return false;
  }
  if (m_blewUp) {
    previous = start;
    restart();
    return false;
  }
  std::string failure = m_solveFailure;
  for (int pieces = 2; pieces <= 16 && current.allFinite(); pieces *= 2) {
    const double h = dt / pieces;
    // the same velocity, over a piece: an affine combination keeps held and derived points
    current = start;
    previous = start - (start - before) / double(pieces);
    restart();
    bool ok = true;
    int iterations = 0;
    for (int k = 0; k < pieces && ok; ++k) {
      ok = stepOf(t + k * h, h);
      iterations += m_newtonIterations;
    }
    // a piece's start is not the step's: a force refusing it (the surface curved too much in
    // the pieces before) fails the step like any other piece's failure, not as bad input
    m_startRefused = false;
    if (ok) {
      finish(start, pieces);
      m_newtonIterations = iterations;
      m_solveFailure.clear();
      return true;
    }
    failure = m_solveFailure + " (the step cut into " + std::to_string(pieces) + " pieces)";
    if (m_blewUp) break;  // a piece blew up: smaller ones would start the energy check afresh
  }
  m_solveFailure = failure;
  previous = start;  // step() keeps it: the last valid state
  restart();
  return false;
}

bool TimeStepper::blowUp(double energy) {
  std::ostringstream os;
  os << "the total energy rose from " << m_reference.energy << " to " << energy << " J where the loads did "
     << m_reference.work << " J of work (a blow-up)";
  m_solveFailure = os.str();
  m_reference.valid = false;
  m_blewUp = true;
  return false;
}

namespace {
/// Splits the loads for an implicit step: the constant ones (in `load` already) and those that
/// depend on time only, evaluated at `ctx` and added to `load` (they stay fixed within the
/// step); the others, which depend on the state, in `stateForces` (evaluated at every iterate).
void splitLoads(const std::vector<std::shared_ptr<const Force>>& forces, const LoadContext& ctx, ControlNet& load,
                std::vector<const Force*>& stateForces) {
  stateForces.clear();
  for (const auto& f : forces) {
    const unsigned dep = f->dependence();
    if (dep == kConstant) continue;
    if (dep & (kDependsOnPosition | kDependsOnVelocity | kDependsOnNormal))
      stateForces.push_back(f.get());
    else
      f->addLoad(ctx, load);
  }
}

}  // namespace

bool PaperExplicitStepper::subStep(double t) {
  StepperModel& s = m_model;
  const ControlNet& load = s.effectiveLoad(t);
  const double dt = s.subStepSize(), m = s.massPerPoint(), c = s.dampingPerPoint();
  const double g = 2.0 * m + dt * c;
  const double alpha = 2.0 * dt * dt / g, gamma = (2.0 * m - dt * c) / g;
  // Lumped mass next to a free edge: alpha = 2 dt^2 / (s (2m + dt c)) for the point's mass
  // ratio s (damping scales alike, so gamma does not change).
  std::function<double(int, int)> scale;
  StiffnessStencil::BandSolve bandSolve;
  if (s.edgeMass()) {
    // the band's residuals through m M^-1 (EdgeMass: blocks at the source layers)
    if (!m_bandPlan)
      m_bandPlan = std::make_unique<EdgeMass::BandPlan>(s.edgeMass()->bandPlan(s.stencil().bandPoints(), m));
    bandSolve = [plan = m_bandPlan.get()](size_t k0, size_t k1, const Eigen::RowVector3d* r, Eigen::RowVector3d* out) {
      for (size_t k = k0; k < k1; ++k) {
        Eigen::RowVector3d acc = Eigen::RowVector3d::Zero();
        for (int e = plan->start[k]; e < plan->start[k + 1]; ++e) {
          const auto& entry = plan->entries[size_t(e)];
          assert(size_t(entry.first) >= k0 && size_t(entry.first) < k1);
          acc += entry.second * r[size_t(entry.first) - k0];
        }
        out[k - k0] = acc;
      }
    };
  } else if (!s.hasUniformMass()) {
    scale = [&s, m](int i, int j) { return m / s.massAt(i, j); };
  }
  // The new state overwrites the previous one (same buffer); held points are equal in both.
  const bool ok = s.stencil().centralDifferenceUpdate(s.current(), s.previous(), load, alpha, gamma,
                                                      s.divergenceLimit(),
                                                    scale, bandSolve);
  s.holdPins(s.previous());
  s.space().completeNet(s.previous(), &s.rest());
  s.current().swap(s.previous());
  return ok;
}

PaperImplicitStepper::PaperImplicitStepper(StepperModel& model) : TimeStepper(model) {
  StepperModel& s = m_model;
  // K = M/dt^2 + C/(2dt) + A_act/4 (docs/math.md §6); a lumped mass (and damping) is smaller
  // next to a free edge
  const double dt = s.params().timeStep, m = s.massPerPoint(), c = s.dampingPerPoint();
  Eigen::VectorXd massTerm;
  const double factor = 1.0 / (dt * dt) + (c / m) / (2.0 * dt);
  std::vector<Eigen::Triplet<double>> coupling;
  double kappa = 0.0;
  if (s.hasUniformMass()) {
    massTerm = Eigen::VectorXd::Constant(s.space().numMoving(), m / (dt * dt) + c / (2.0 * dt));
  } else if (s.edgeMass()) {
    massTerm.resize(s.space().numMoving());
    for (Eigen::Index f = 0; f < s.space().numMoving(); ++f) {
      const Eigen::Index r = s.space().movingToNet(f);
      massTerm[f] = factor * s.edgeMass()->diagonal(int(r / s.space().netCols()), int(r % s.space().netCols()));
    }
    coupling = s.edgeMass()->offDiagonal(factor);
    // the generalised eigenvalues of (K, M) lie in [factor, factor + lambda_max(M^-1 A)/4]:
    // kappa(M^-1 K), what Jacobi-CG meets in practice; the diagonal formula is far too
    // pessimistic with the coupling (docs/benchmarks.md, "Why the code is as it is")
    kappa = 1.0 + s.elasticLambda() / (4.0 * factor);
  } else {
    massTerm = s.massMoving() * factor;
  }
  m_implicit = std::make_unique<ImplicitSystem>(s.space(), s.stencil(), massTerm, s.pinnedMoving(),
                                                s.params().implicitSolver,
                                                s.params().solverTolerance, s.params().maxSolverIterations,
                                                std::move(coupling), kappa);
}

bool PaperImplicitStepper::subStep(double t) {
  StepperModel& s = m_model;
  const ControlNet& load = s.effectiveLoad(t);
  const double dt = s.params().timeStep, m = s.massPerPoint(), c = s.dampingPerPoint();
  // Newmark (docs/math.md §6) for the increment d = P+ - P: with K = M/dt^2 + C/(2dt) + A_II/4,
  //   K d = L - (A_II V + A_IB P_B) + (M/dt^2 - C/(2dt)) (P - P-),   V = P + (P- - P)/4,
  // where A_II V + A_IB P_B is the stencil applied to the whole net V (its held points are
  // their rest values exactly): no matrix, and a state at rest gives d = 0 exactly.
  allocateNet(m_scratch, s.current().rows());
  m_scratch = s.current() + 0.25 * (s.previous() - s.current());
  ControlNet rhs;
  s.stencil().applyMoving(m_scratch, rhs);
  const ControlNet velocity = s.space().gatherMoving(s.current()) - s.space().gatherMoving(s.previous());  // P - P-
  if (s.hasUniformMass()) {
    rhs = load - rhs + (m / (dt * dt) - c / (2.0 * dt)) * velocity;
  } else if (s.edgeMass()) {
    ControlNet Mv;
    s.edgeMass()->apply(velocity, Mv);
    rhs = load - rhs + (1.0 / (dt * dt) - (c / m) / (2.0 * dt)) * Mv;
  } else {
    const double cm = c / m;
    rhs = load - rhs + (1.0 / (dt * dt) - cm / (2.0 * dt)) * (s.massMoving().asDiagonal() * velocity);
  }
  for (Eigen::Index f : m_implicit->pinned()) rhs.row(f).setZero();  // pinned rows of K are D: d = 0
  // CG starts from the constant-velocity prediction d = P - P-.
  ControlNet next = velocity;
  const bool solved = m_implicit->solve(rhs, next);
  next += s.space().gatherMoving(s.current());
  bool ok = solved;
  for (Eigen::Index i = 0; i < next.size(); ++i) ok &= std::abs(next.data()[i]) <= s.divergenceLimit();
  s.space().scatterMoving(next, s.previous());
  if (s.hasPins() || s.space().hasDerived()) {
    s.holdPins(s.previous());
    s.space().completeNet(s.previous(), &s.rest());
  }
  s.current().swap(s.previous());
  if (!solved && next.allFinite()) {
    std::ostringstream os;
    os << "conjugate gradients stopped at relative residual " << m_implicit->lastResidual() << " after "
       << m_implicit->lastIterations() << " iterations (solverTolerance " << s.params().solverTolerance
       << ", maxSolverIterations " << s.params().maxSolverIterations << ")";
    m_solveFailure = os.str();
  }
  return ok;
}

bool ShellExplicitStepper::subStep(double t) {
  StepperModel& s = m_model;
  const ControlNet& load = s.effectiveLoad(t);
  const double dt = s.subStepSize(), c = s.params().damping;
  // M (P+ - 2P + P-)/dt^2 + c M (P+ - P-)/(2 dt) = L - dW/dP
  const double alpha = dt * dt / (1.0 + 0.5 * c * dt), gamma = (1.0 - 0.5 * c * dt) / (1.0 + 0.5 * c * dt);
  ControlNet a;
  s.elasticGradient(s.current(), a);
  a = load - a;
  s.mass().solve(a);
  bool ok = true;
  for (Eigen::Index f = 0; f < s.space().numMoving(); ++f) {
    const Eigen::Index r = s.space().movingToNet(f);
    if (s.isPinnedRow(r)) continue;
    Eigen::RowVector3d next =
        s.current().row(r) + gamma * (s.current().row(r) - s.previous().row(r)) + alpha * a.row(f);
    for (int k = 0; k < 3; ++k)
      if (s.heldCoordinate(f, k)) next[k] = s.rest()(r, k);
    ok &= next.cwiseAbs().maxCoeff() <= s.divergenceLimit();  // false for NaN
    s.previous().row(r) = next;
  }
  s.space().completeNet(s.previous(), &s.rest());
  s.current().swap(s.previous());
  return ok;
}

// Newmark (average acceleration) in three-level form, the forces averaged as the stiffness term
// of the linear scheme is (docs/math.md §16):
//   M (x - 2P + P-)/dt^2 + c M (x - P-)/(2dt) + (g(x) + 2 g(P) + g(P-))/4 = L(P, t)
// solved for x = P+ by Newton's method, tangent (1/dt^2 + c/(2dt)) M + H(x)/4.
bool ShellImplicitStepper::subStep(double t) {
  StepperModel& s = m_model;
  const double dt = s.params().timeStep;
  const ControlNet start = s.current(), before = s.previous();
  if (stepOf(t, dt)) return true;
  return retakeInPieces(
      s.current(), s.previous(), start, before, t, dt, [this](double ti, double h) { return stepOf(ti, h); },
      [this] { m_cached = false; },
      [this, &s](const ControlNet& begin, int) {
        s.previous() = begin;  // one step before, as the next step expects
        m_cached = false;
      });
}

bool ShellImplicitStepper::stepOf(double t, double dt) {
  StepperModel& s = m_model;
  // constant loads and those that depend on time only, at the start; the others (contact,
  // springs, pressure, drag) at every iterate, at the state V = (x + 2P + P-)/4 moving with
  // (x - P-)/(2 dt): the average the stiffness term takes (docs/math.md §16)
  m_blewUp = false;
  ControlNet load = s.constantLoad();
  std::vector<const Force*> stateForces;
  splitLoads(s.forces(), s.loadContext(s.current(), s.previous(), dt, t), load, stateForces);
  const double c = s.params().damping;
  const double a = 1.0 / (dt * dt) + c / (2.0 * dt), b = 1.0 / (dt * dt) - c / (2.0 * dt);
  const ControlNet P = s.space().gatherMoving(s.current()), Pm = s.space().gatherMoving(s.previous());
  if (!m_cached) {
    s.elasticGradient(s.current(), m_gradCurrent);
    s.elasticGradient(s.previous(), m_gradPrevious);
    m_cached = true;
  }
  const ControlNet fixed = load - 0.5 * m_gradCurrent - 0.25 * m_gradPrevious + b * s.mass().apply(P - Pm);
  const double scale = fixed.norm() + 0.5 * m_gradCurrent.norm() + 0.25 * m_gradPrevious.norm() + 1e-300;
  ControlNet net = s.current();
  ControlNet x = P + (P - Pm);
  ControlNet netV = s.current(), netVPrev = s.current();  // V and V - (x - P-), for the forces
  // The step is the minimum of (a/2)(x - P)ᵀM(x - P) + W(x)/4 - fixed·x + 4 Φ(V(x)) (Φ the
  // state forces' potentials at V = (x + 2P + P-)/4, whose gradient in x is -L(V)): the same
  // Newton solver as backward Euler's and the static solve's (NewtonMinimizer), the search on
  // this potential where every force has one, else on the residual's norm; converged when the
  // residual is below newtonTolerance of the forces or a Newton step is at the positions'
  // rounding (1e-11 of the net's size: stiff membranes under small loads reach this first).
  ControlNet xc;  // xi with the coordinates constrained by supports per component completed
  ControlNet g;   // W's gradient at the last evaluated iterate
  auto evaluate = [&](const ControlNet& xi, NewtonPoint& ev) {
    xc = xi;
    s.completeUnknowns(xc, net);
    std::optional<CostTimer> timer(&s.costs().elastic);
    const double strain = s.energy().energyAndGradient(net, g);
    timer.emplace(&s.costs().loads);
    ControlNet Lv = ControlNet::Zero(xi.rows(), 3);
    ev.potential = true;
    double phi = 0.0;
    if (!stateForces.empty()) {
      netV = 0.25 * (net + 2.0 * s.current() + s.previous());
      netVPrev = netV - (net - s.previous());
      const LoadContext ctx = s.loadContext(netV, netVPrev, 2.0 * dt, t + dt);
      for (const Force* f : stateForces) {
        f->addLoad(ctx, Lv);
        double value = 0.0;
        if (f->potential(ctx, value))
          phi += 4.0 * value;
        else
          ev.potential = false;
      }
    }
    timer.reset();
    const ControlNet dx = xc - P, Mdx = s.mass().apply(dx);
    ev.g = a * Mdx + 0.25 * g - fixed - Lv;
    if (s.components()) s.components()->fold(ev.g);  // onto the free coordinates
    for (Eigen::Index f = 0; f < ev.g.rows(); ++f)
      for (int c = 0; c < 3; ++c)
        if (s.heldCoordinate(f, c)) ev.g(f, c) = 0.0;
    ev.norm = ev.g.norm();
    if (ev.potential) {
      const double inertia = 0.5 * a * (dx.array() * Mdx.array()).sum();
      const double elastic = 0.25 * strain;
      const double work = -(fixed.array() * xc.array()).sum();
      ev.value = inertia + elastic + work + phi;
      ev.valueScale = std::abs(inertia) + std::abs(elastic) + std::abs(work) + std::abs(phi);
    } else {
      ev.value = ev.valueScale = 0.0;
    }
  };
  for (Eigen::Index f = 0; f < x.rows(); ++f)
    for (int c = 0; c < 3; ++c)
      if (s.heldCoordinate(f, c)) x(f, c) = P(f, c);
  // a failed step leaves the rejected state current and the last good one previous (step())
  auto reject = [&]() {
    s.space().scatterMoving(x, s.previous());
    s.space().completeNet(s.previous(), &s.rest());
    s.current().swap(s.previous());
    m_cached = false;
    return false;
  };
  NewtonPoint cur;
  evaluate(x, cur);
  NewtonMinimizer::Problem problem;
  problem.evaluate = evaluate;
  Eigen::SparseMatrix<double> folded;
  problem.tangent = [&](HessianMode mode, double shift) -> const Eigen::SparseMatrix<double>& {
    const LoadContext ctxV = s.loadContext(netV, netVPrev, 2.0 * dt, t + dt);
    return unknownsTangent(s.components(),
                           s.tangent(net, 0.25, shift, mode, stateForces.empty() ? nullptr : &ctxV, 2.0 / dt, 0.25),
                           s.heldMask(), folded);
  };
  problem.residualSmall = [&](const NewtonPoint& p) { return p.norm <= s.params().newtonTolerance * scale; };
  problem.updateTolerance = [](const ControlNet& xi) { return 1e-11 * xi.cwiseAbs().maxCoeff(); };
  NewtonMinimizer::Options options;
  options.maxIterations = s.params().maxNewtonIterations;
  options.shift = a;
  // a new factorisation every iteration, as before: chord steps, counted against
  // maxNewtonIterations, cut more steps into pieces and moved the coarse swinging sheet's
  // trajectory (tests/core/ShellModel_test.cpp) and a Newmark curtain's blow-up
  options.chordSteps = false;
  options.costs = &s.costs();
  if (!m_newton) m_newton = std::make_unique<NewtonMinimizer>();
  const NewtonMinimizer::Outcome outcome = m_newton->minimize(x, cur, problem, options);
  m_newtonIterations = outcome.iterations;
  s.costs().iterations += outcome.iterations;
  s.costs().factorisations += outcome.factorisations;
  if (!outcome.converged) {
    std::ostringstream os;
    os << "Newton's method stopped at relative residual " << cur.norm / scale << " after " << outcome.iterations
       << " iterations (" << outcome.failure << "; newtonTolerance " << s.params().newtonTolerance
       << ", maxNewtonIterations " << s.params().maxNewtonIterations << ")";
    m_solveFailure = os.str();
    return reject();
  }
  // W's gradient at the solution, kept for the next step (the last evaluation was at it, but
  // that is the solver's business)
  xc = x;
  s.completeUnknowns(xc, net);
  s.energy().gradient(net, g);
  if (s.components()) s.components()->complete(x);  // the updates moved the free coordinates only
  bool ok = true;
  for (Eigen::Index i = 0; i < x.size(); ++i) ok &= std::abs(x.data()[i]) <= s.divergenceLimit();
  s.space().scatterMoving(x, s.previous());
  s.holdPins(s.previous());
  s.space().completeNet(s.previous(), &s.rest());
  s.current().swap(s.previous());
  m_gradPrevious.swap(m_gradCurrent);
  m_gradCurrent = g;
  // the energy check: Newmark conserves energy to O(dt²) without damping, so only a rise
  // beyond the reference's own scale (kinetic + elastic + the loads' reach) is a blow-up
  // (the work of the loads that can do work, a wind or a follower pressure, is added to the
  // reference: the trapezoid rule over each step, their load at its two ends)
  if (ok) {
    double energy = 0.0, scaleNow = 0.0;
    ControlNet working;
    BackwardEulerStepper::totalEnergy(s, x, s.current(), s.previous(), dt, (x - P) / dt, t + dt, energy, scaleNow,
                                      &working);
    if (!m_reference.valid) {
      m_reference.start(energy, scaleNow);
    } else {
      m_reference.addWork(0.5 * ((m_workingLoad + working).array() * (x - P).array()).sum());
      const EnergyReference& r = m_reference;
      if (energy > r.energy + r.work + r.scale + r.workScale + 1e-300) return blowUp(energy);
    }
    m_workingLoad = std::move(working);
  }
  return ok;
}

}  // namespace bsdeform

namespace bsdeform {

/// L-BFGS's H0 over the unknowns (one scalar matrix for x, y and z): shift M + K̄ with K̄_fg the
/// mean of the diagonal entries of the rest tangent's 3 × 3 block (f, g), held coordinates left
/// out. K̄ is positive semi-definite when the tangent is (aᵀ K̄ a = ⅓ Σ_c (a ⊗ e_c)ᵀ K (a ⊗ e_c)),
/// and unlike the tangent it does not change when the surface turns: the stiffness of the
/// membrane in every direction, the projective-dynamics matrix of Liu, Bouaziz, Kavan (2017).
struct BackwardEulerStepper::QuasiNewtonStart {
  SparseCholesky solver;                 ///< H0's factorisation (its pattern is the same for every shift)
  Eigen::SparseMatrix<double> restPart;  ///< K̄, lower triangle
  double shift = -1.0;                    ///< the mass multiple solver was made with
};

BackwardEulerStepper::BackwardEulerStepper(StepperModel& model) : TimeStepper(model) {}
BackwardEulerStepper::~BackwardEulerStepper() = default;

void BackwardEulerStepper::precondition(ControlNet& r, double h) {
  StepperModel& s = m_model;
  const double shift = 1.0 / (h * h) + s.dampingRatio() / h;
  if (!m_start) {
    m_start = std::make_unique<QuasiNewtonStart>();
    const Eigen::SparseMatrix<double>& K = s.tangent(s.rest(), 1.0, 0.0, HessianMode::Exact, nullptr);
    const Eigen::Index n = s.space().numMoving();
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(size_t(K.nonZeros() / 3 + n));
    for (Eigen::Index c = 0; c < K.outerSize(); ++c)
      for (Eigen::SparseMatrix<double>::InnerIterator it(K, c); it; ++it)
        if (it.row() % 3 == c % 3 && !s.heldMask()[size_t(it.row())] && !s.heldMask()[size_t(c)])
          entries.emplace_back(it.row() / 3, c / 3, it.value() / 3.0);
    m_start->restPart.resize(n, n);
    m_start->restPart.setFromTriplets(entries.begin(), entries.end());
  }
  if (m_start->shift != shift) {
    const Eigen::SparseMatrix<double> H0 =
        m_start->restPart + shift * Eigen::SparseMatrix<double>(s.mass().matrix().triangularView<Eigen::Lower>());
    const CostTimer timer(&s.costs().factorisation);
    ++s.costs().factorisations;
    if (!m_start->solver.factor(H0))
      throw std::runtime_error("BACKWARD_EULER with LBFGS: the start matrix is not positive definite");
    m_start->shift = shift;
  }
  const CostTimer timer(&s.costs().solve);
  const Eigen::MatrixXd z = m_start->solver.solve(Eigen::MatrixXd(r));
  r = z;
  for (Eigen::Index f = 0; f < r.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      if (s.heldCoordinate(f, k)) r(f, k) = 0.0;
}

void BackwardEulerStepper::totalEnergy(const StepperModel& s, const ControlNet& x, const ControlNet& net,
                                      const ControlNet& previousNet, double h, const ControlNet& v, double t,
                                      double& energy, double& scale, ControlNet* working) {
  const double kinetic = s.mass().kineticEnergy(v);
  const double elastic = s.energy().energy(net);
  const ControlNet fixedLoad = s.forcesConstantLoad();
  double loads = -(fixedLoad.array() * x.array()).sum();
  const LoadContext ctx = s.loadContext(net, previousNet, h, t);
  if (working) *working = ControlNet::Zero(x.rows(), 3);
  for (const auto& f : s.forces()) {
    if (f->dependence() == kConstant) continue;
    double stored = 0.0;
    if (f->storedEnergy(ctx, stored))
      loads += stored;
    else if (working)  // it can do work: counted as work by the caller
      f->addLoad(ctx, *working);
  }
  energy = kinetic + elastic + loads;
  // plus the work the constant loads can do over the surface's own size (a sheet at z = 0
  // under gravity stores nothing, yet falls)
  const double extent = (net.colwise().maxCoeff() - net.colwise().minCoeff()).norm();
  // and a floor below which a change is rounding (a strip at rest under no load moves its
  // energy between 1e-17 and 1e-16): SHELL, the membrane energy of a uniform strain of 1.4e-4
  // (1e-8 E t A); the paper's model, 1e-8 lambda_max(A_II) extent^2 alike
  double floor = 0.0;
  if (s.shell()) {
    const ShellMaterial& m = s.params().material;
    floor = 1e-8 * m.youngsModulus * m.thickness * s.shell()->restArea();
  } else {
    floor = 1e-8 * s.stencil().eigenvalueBound() * extent * extent;
  }
  scale = kinetic + std::abs(elastic) + std::abs(loads) + fixedLoad.cwiseAbs().sum() * extent + floor;
}

bool BackwardEulerStepper::subStep(double t) {
  StepperModel& s = m_model;
  const double dt = s.params().timeStep;
  const ControlNet start = s.current(), before = s.previous();
  m_stepStart = t;
  m_stepLength = dt;
  m_stepFrom = start;
  if (stepOf(t, dt)) return true;
  return retakeInPieces(
      s.current(), s.previous(), start, before, t, dt, [this](double ti, double h) { return stepOf(ti, h); }, [] {},
      [&s](const ControlNet&, int pieces) {
        // one step before, with the velocity of the last piece
        s.previous() = s.current() - double(pieces) * (s.current() - s.previous());
        s.space().completeNet(s.previous(), &s.rest());
      });
}

bool BackwardEulerStepper::stepOf(double t, double h) {
  StepperModel& s = m_model;
  const SplineSpace& sp = s.space();
  const double c = s.dampingRatio(), tNew = t + h;
  const MassMatrix& mass = s.mass();
  // Sides moved by a prescribed map: their held layers go where the map puts them at the end of
  // this step (of this piece: the fraction of the whole step's move its end has reached); the
  // move is checked below against the barriers' CCD before anything is solved
  ControlNet heldBefore;
  const bool heldMoves = s.heldRowsMoved(s.current());
  if (heldMoves) {
    heldBefore = s.current();
    const double alpha = m_stepLength > 0.0 ? (tNew - m_stepStart) / m_stepLength : 1.0;
    s.placeHeldRows(m_stepFrom, alpha >= 1.0 - 1e-12 ? 1.0 : alpha, s.current());
  }
  const ControlNet P = sp.gatherMoving(s.current()), Pm = sp.gatherMoving(s.previous());
  const ControlNet xhat = 2.0 * P - Pm;  // P + h v
  const ControlNet startNet = s.current();
  m_blewUp = false;
  // the constant loads and those that depend on time only are fixed within the step (their
  // potential -L·x); the others are evaluated at every iterate
  ControlNet fixedLoad = s.forcesConstantLoad();
  std::vector<const Force*> stateForces;
  splitLoads(s.forces(), s.loadContext(startNet, startNet, h, tNew), fixedLoad, stateForces);
  // forces with a state between steps (a barrier's stiffness) adapt it, and refuse a start state
  // they cannot take (a surface inside an obstacle)
  bool barrier = false;
  {
    // (a barrier knows the step by the net it starts from: the one before the held layers moved)
    const LoadContext startCtx = s.loadContext(heldMoves ? heldBefore : startNet, startNet, h, tNew);
    for (const Force* f : stateForces) {
      if (std::string why = f->beginStep(startCtx); !why.empty()) {
        if (heldMoves) s.current() = heldBefore;
        m_solveFailure = why;
        m_startRefused = true;
        return false;
      }
      barrier |= f->limitsSteps();
    }
    if (heldMoves && barrier) {
      double fraction = 1.0;
      for (const Force* f : stateForces) fraction = std::min(fraction, f->admissibleFraction(startCtx, startNet));
      if (fraction < 1.0) {
        s.current() = heldBefore;
        std::ostringstream os;
        os << "a moved side's layers would cross an obstacle or the surface itself within this step (CCD allows "
           << fraction << " of their move): move it more slowly, or take smaller steps";
        m_solveFailure = os.str();
        return false;
      }
    }
  }
  if (heldMoves) m_reference.valid = false;  // the moved side does work: no energy check this step
  if (!m_reference.valid && !heldMoves) {
    double energy = 0.0, scale = 0.0;
    totalEnergy(s, P, s.current(), s.previous(), h, (P - Pm) / h, t, energy, scale);
    m_reference.start(energy, scale);
  }
  ControlNet net = s.current();
  auto held = [&](Eigen::Index f, int k) { return s.heldCoordinate(f, k); };
  // E(x) and its gradient; `potential` false when a load has none (the line search then
  // watches the residual)
  ControlNet gW, L, Mdx, Mdn;
  ControlNet xc;  // x with the coordinates constrained by supports per component completed
  auto evaluate = [&](const ControlNet& x, NewtonPoint& ev) {
    xc = x;
    s.completeUnknowns(xc, net);
    const LoadContext ctx = s.loadContext(net, startNet, h, tNew);
    std::optional<CostTimer> timer(&s.costs().elastic);
    const double elastic = s.energy().energyAndGradient(net, gW);
    timer.emplace(&s.costs().loads);
    L = fixedLoad;
    ev.potential = true;
    double phi = -(fixedLoad.array() * xc.array()).sum();
    for (const Force* f : stateForces) {
      f->addLoad(ctx, L);
      double value = 0.0;
      if (f->potential(ctx, value))
        phi += value;
      else
        ev.potential = false;
    }
    timer.reset();
    const ControlNet dx = xc - xhat, dn = xc - P;
    Mdx = mass.apply(dx);
    Mdn = mass.apply(dn);
    ev.g = Mdx / (h * h) + (c / h) * Mdn + gW - L;
    if (s.components()) s.components()->fold(ev.g);  // onto the free coordinates
    for (Eigen::Index f = 0; f < ev.g.rows(); ++f)
      for (int k = 0; k < 3; ++k)
        if (held(f, k)) ev.g(f, k) = 0.0;
    ev.norm = ev.g.norm();
    // the potential only where the line search watches it (every load has one)
    if (ev.potential) {
      const double inertia = 0.5 * (dx.array() * Mdx.array()).sum() / (h * h);
      const double damping = 0.5 * (c / h) * (dn.array() * Mdn.array()).sum();
      ev.value = inertia + damping + elastic + phi;
      ev.valueScale = std::abs(inertia) + std::abs(damping) + std::abs(elastic) + std::abs(phi) +
                      (fixedLoad.array() * xc.array()).abs().sum();
    } else {
      ev.value = ev.valueScale = 0.0;
    }
  };
  ControlNet x = xhat;
  for (Eigen::Index f = 0; f < x.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      if (held(f, k)) x(f, k) = P(f, k);
  // The move from `from` (unknowns) by `step` as full nets (fromNet to toNet), and the context
  // of its start.
  ControlNet fromNet = startNet, toNet = startNet, xs;
  auto moveContext = [&](const ControlNet& from, const ControlNet& step) {
    xs = from;
    s.completeUnknowns(xs, fromNet);
    xs = from + step;
    s.completeUnknowns(xs, toNet);
    return s.loadContext(fromNet, startNet, h, tNew);
  };
  // The largest fraction of the move from `from` by `step` that no barrier refuses.
  auto admissible = [&](const ControlNet& from, const ControlNet& step) {
    const CostTimer timer(&s.costs().collisionChecks);
    const LoadContext ctx = moveContext(from, step);
    double fraction = 1.0;
    for (const Force* f : stateForces) fraction = std::min(fraction, f->admissibleFraction(ctx, toNet));
    return fraction;
  };
  // Obstacles that moved since the last step are swept toward their poses as far as nothing
  // crosses, the surface held where it is; then, after each Newton solve, further (below)
  auto advanceObstacles = [&](const ControlNet& at) {
    const CostTimer timer(&s.costs().collisionChecks);
    xs = at;
    s.completeUnknowns(xs, fromNet);
    const LoadContext ctx = s.loadContext(fromNet, startNet, h, tNew);
    double remaining = 0.0;
    for (const Force* f : stateForces) remaining = std::max(remaining, f->advanceObstacles(ctx));
    return remaining;
  };
  double sweepRemaining = barrier ? advanceObstacles(P) : 0.0;
  // with a barrier the first iterate is the prediction cut to where nothing crosses
  if (barrier) x = P + admissible(P, x - P) * (x - P);
  NewtonPoint cur;
  evaluate(x, cur);
  const double forceScale = (fixedLoad.norm() + gW.norm() + Mdx.norm() / (h * h)) + 1e-300;
  const double massShift = 1.0 / (h * h) + c / h;
  auto reject = [&]() {
    sp.scatterMoving(x, s.previous());
    sp.completeNet(s.previous(), &s.rest());
    s.current().swap(s.previous());
    m_reference.valid = false;
    return false;
  };
  // The exact tangent while it is positive definite (the mass term M/h² usually makes it so),
  // else the exact one with up to 3.05 times the mass multiple (problem.shiftTangent), else the
  // element Hessians projected, then more of the mass (a force's Jacobian, a sphere's
  // tangential part, can still be indefinite), the barrier's pairs projected too beyond 16 times
  // the mass (NewtonMinimizer); each step starts with a factorisation of its own
  // (NewtonMinimizer), so that a run resumed from a saved state takes the same iterates.
  NewtonMinimizer::Problem problem;
  problem.evaluate = evaluate;
  Eigen::SparseMatrix<double> folded;
  problem.tangent = [&](HessianMode mode, double shift) -> const Eigen::SparseMatrix<double>& {
    const LoadContext ctx = s.loadContext(net, startNet, h, tNew);
    return unknownsTangent(s.components(), s.tangent(net, 1.0, shift, mode, &ctx, 1.0 / h), s.heldMask(), folded);
  };
  problem.shiftTangent = [&](double extra) -> const Eigen::SparseMatrix<double>& {
    return unknownsTangent(s.components(), s.shiftTangent(extra), s.heldMask(), folded);
  };
  problem.residualSmall = [&](const NewtonPoint& p) { return p.norm <= s.params().newtonTolerance * forceScale; };
  if (barrier) problem.maxStep = admissible;
  NewtonMinimizer::Options options;
  options.maxIterations = s.params().maxNewtonIterations;
  options.updateTolerance = s.params().newtonVelocityTolerance * h;
  options.shift = massShift;
  options.chordSteps = !barrier;
  options.keptFactorNearMinimum = barrier;
  options.massRetries = 5;
  if (s.params().nonlinearSolver == NonlinearSolver::LBFGS) {
    options.quasiNewton = true;
    options.maxIterations = 10 * s.params().maxNewtonIterations;  // each about a tenth of Newton's
    // H0: the isotropic matrix of the model, factorised once; with a barrier (whose stiffness
    // the isotropic matrix knows nothing of) or supports per component (whose folded unknowns
    // it does not describe), the step's first tangent
    if (!barrier && !s.components()) problem.precondition = [this, h](ControlNet& r) { precondition(r, h); };
  }
  options.costs = &s.costs();
  if (!m_newton) m_newton = std::make_unique<NewtonMinimizer>();
  NewtonMinimizer::Outcome outcome = m_newton->minimize(x, cur, problem, options);
  m_newtonIterations = outcome.iterations;
  m_factorisations += outcome.factorisations;
  s.costs().iterations += outcome.iterations;
  s.costs().factorisations += outcome.factorisations;
  // a swept obstacle: moved on as far as it goes with the surface where Newton left it, then
  // Newton again, until it is where it is to be (each pass it closes at least 90 % of the gap the
  // surface leaves it; a surface held in its way stops it short)
  // From the second pass on, the last pass predicts the next (a secant: the surface moved Δx
  // while the obstacles closed ΔR of their move): the obstacles go up to kPassGrowth ΔR further,
  // or the rest of the way, with the surface moved along by as many Δx, both as far as nothing
  // crosses (a pushed sheet moves with what pushes it; without this, each pass gains only what
  // the barrier's gap gives, a fraction of dhat); Newton then corrects.
  constexpr int kSweepPasses = 200;
  constexpr double kPassGrowth = 4.0;
  ControlNet passStart;      // the unknowns before the last pass (its joint move and its solve)
  double passAdvance = 0.0;  // the step's move its obstacles made in that pass
  auto jointAdvance = [&](const ControlNet& from, const ControlNet& step, double obstacleFraction) {
    const CostTimer timer(&s.costs().collisionChecks);
    const LoadContext ctx = moveContext(from, step);
    double fraction = 1.0;
    for (const Force* f : stateForces)
      fraction = std::min(fraction, f->jointAdvanceFraction(ctx, toNet, obstacleFraction));
    if (fraction <= 0.0) return;
    for (const Force* f : stateForces) f->advanceObstaclesBy(ctx, fraction * obstacleFraction);
    x += fraction * step;
  };
  for (int pass = 0; outcome.converged && sweepRemaining > 0.0; ++pass) {
    if (pass == kSweepPasses) {
      std::ostringstream os;
      os << "an obstacle that moved since the last step could not be brought to its pose in " << kSweepPasses
         << " passes (" << sweepRemaining << " of its move left): the surface is held in its way";
      m_solveFailure = os.str();
      return reject();
    }
    if (s.components()) s.components()->complete(x);
    const ControlNet before = x;
    const double remainingBefore = sweepRemaining;
    if (passAdvance > 0.0) {  // (x and passStart complete: so is x + τ step, supports being affine)
      const double obstacleFraction = std::min(1.0, kPassGrowth * passAdvance / sweepRemaining);
      const ControlNet step = (obstacleFraction * sweepRemaining / passAdvance) * (x - passStart);
      jointAdvance(x, step, obstacleFraction);
    }
    sweepRemaining = advanceObstacles(x);
    evaluate(x, cur);  // the obstacle moved: a new potential
    const NewtonMinimizer::Outcome more = m_newton->minimize(x, cur, problem, options);
    passStart = before;
    passAdvance = remainingBefore - sweepRemaining;
    outcome.converged = more.converged;
    outcome.failure = more.failure;
    m_newtonIterations += more.iterations;
    m_factorisations += more.factorisations;
    s.costs().iterations += more.iterations;
    s.costs().factorisations += more.factorisations;
  }
  if (s.components()) s.components()->complete(x);  // the updates moved the free coordinates only
  if (!outcome.converged) {
    std::ostringstream os;
    os << (options.quasiNewton ? "L-BFGS" : "Newton's method") << " did not converge in " << m_newtonIterations << " iterations (" << outcome.failure
       << "; residual " << cur.norm / forceScale << " of the forces, newtonTolerance " << s.params().newtonTolerance
       << ", newtonVelocityTolerance " << s.params().newtonVelocityTolerance << ", maxNewtonIterations "
       << s.params().maxNewtonIterations
       << (options.quasiNewton ? ", LBFGS: 10 x maxNewtonIterations iterations" : "") << ")";
    m_solveFailure = os.str();
    return reject();
  }
  bool ok = true;
  for (Eigen::Index i = 0; i < x.size(); ++i) ok &= std::abs(x.data()[i]) <= s.divergenceLimit();
  sp.scatterMoving(x, s.previous());
  s.holdPins(s.previous());
  s.copyHeldRows(startNet, s.previous());
  sp.completeNet(s.previous(), &s.rest());
  s.current().swap(s.previous());
  if (ok && m_reference.valid) {
    // backward Euler's own balance: E(end) - E(start) <= L(end)·(x - P) for the loads that do
    // work, as the step applies them (the rest dissipates), summed since the reference
    double energy = 0.0, scale = 0.0;
    ControlNet working;
    totalEnergy(s, x, s.current(), s.previous(), h, (x - P) / h, tNew, energy, scale, &working);
    m_reference.addWork((working.array() * (x - P).array()).sum());
    const EnergyReference& r = m_reference;
    if (energy > r.energy + r.work + 1e-2 * std::max({r.scale, scale, r.workScale}) + 1e-300) return blowUp(energy);
  }
  return ok;
}

}  // namespace bsdeform
