// SPDX-License-Identifier: MIT
#include "bsdeform/dynamics/NewtonMinimizer.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "bsdeform/dynamics/SparseCholesky.h"

namespace bsdeform {

namespace {
/// Options::massRetries: each retry's mass multiple over the last one's (1.25, five retries: up
/// to 3.05 times the step's own; measured against 1.5 and 2, docs/benchmarks.md).
constexpr double kMassRetryGrowth = 1.25;
/// How many of the projected tangent's attempts (each with more of the mass than the one before:
/// 4 times the multiple in the dynamics, up to 16 times the step's own mass) keep the loads'
/// Jacobians exact (HessianMode::Projected) before they are projected too (HessianMode::Definite).
/// (Where the energy's projection changes nothing, a Projected tangent projects the loads
/// itself: Simulation::tangent.)
constexpr int kExactLoadAttempts = 3;
}  // namespace

NewtonMinimizer::NewtonMinimizer() : m_solver(std::make_unique<SparseCholesky>()) {}
NewtonMinimizer::~NewtonMinimizer() = default;

NewtonMinimizer::Outcome NewtonMinimizer::minimize(ControlNet& x, NewtonPoint& cur, const Problem& problem,
                                                   const Options& options) {
  Outcome out;
  const Eigen::Index n = x.rows();
  NewtonPoint trial;
  bool refactor = true;  // every minimize() starts with a factorisation of its own
  double lastUpdate = 0.0;
  // the last update when it was a full step on an exact factorisation of its own (else 0)
  double lastFull = 0.0;
  bool smallBefore = false;  // quasi-Newton: the last step was below the update tolerance
  double remembered = 0.0;  // the last extra shift that made a factorisation (rememberShift)
  bool exactFactor = false;  // the last factorisation was the exact tangent with the step's own shift
  auto nextShift = [&](double s) { return s > 0.0 ? 4.0 * s : options.firstExtraShift; };
  // L-BFGS (H0: Problem::precondition, else the tangent factorised at the first iterate) and its
  // last pairs (s, y, 1/sᵀy), oldest first
  const bool qn = options.quasiNewton;
  const bool ownStart = qn && !problem.precondition;
  std::vector<ControlNet> pairS, pairY;
  std::vector<double> pairRho;
  auto dot = [](const ControlNet& a, const ControlNet& b) { return (a.array() * b.array()).sum(); };
  // the two-loop recursion: -H⁻¹ g with H⁻¹ the inverse update of H0 by the stored pairs
  auto quasiNewtonStep = [&](const ControlNet& g) {
    const size_t m = pairS.size();
    std::vector<double> a(m);
    ControlNet q = g;
    for (size_t i = m; i-- > 0;) {
      a[i] = pairRho[i] * dot(pairS[i], q);
      q -= a[i] * pairY[i];
    }
    if (ownStart) {
      const CostTimer timer(options.costs ? &options.costs->solve : nullptr);
      const Eigen::VectorXd z = m_solver->solve(Eigen::Map<const Eigen::VectorXd>(q.data(), q.size()));
      q = Eigen::Map<const ControlNet>(z.data(), n, 3);
    } else {
      problem.precondition(q);  // times its own factorisation and solve (the tangent it may build: elastic)
    }
    for (size_t i = 0; i < m; ++i) {
      const double b = pairRho[i] * dot(pairY[i], q);
      q += (a[i] - b) * pairS[i];
    }
    return ControlNet(-q);
  };
  // The numeric factorisation of an assembled tangent (its assembly, the argument, not timed here)
  auto factorise = [&](const Eigen::SparseMatrix<double>& K) {
    const CostTimer timer(options.costs ? &options.costs->factorisation : nullptr);
    return m_solver->factor(K);
  };
  // Factorises the tangent at the current point: exact, then projected, then with more mass.
  auto factor = [&]() {
    // rememberShift: start a quarter of the last extra shift that worked, unless that is
    // below the first one (then the exact tangent again, for Newton's quadratic convergence)
    double extra = options.rememberShift && remembered > 0.0 ? 0.25 * remembered : 0.0;
    if (extra < options.firstExtraShift || options.shift > 0.0) extra = 0.0;
    if (extra == 0.0) {
      exactFactor = false;
      if (factorise(problem.tangent(HessianMode::Exact, options.shift))) {
        remembered = 0.0;
        exactFactor = true;
        return true;
      }
      // then the exact tangent with more of the mass (Levenberg–Marquardt on the inertia), which
      // keeps the Hessian's curvature where the projection would change it at every Gauss point
      // that is not convex (docs/benchmarks.md: fewer iterations on a crumpling cloth)
      if (options.shift > 0.0 && problem.shiftTangent) {
        double multiple = options.shift;
        for (int retry = 0; retry < options.massRetries; ++retry) {
          const double next = kMassRetryGrowth * multiple;
          if (factorise(problem.shiftTangent(next - multiple))) return true;
          multiple = next;
        }
      }
    }
    exactFactor = false;
    double total = options.shift + extra;
    // the energy's Hessians projected at its Gauss points, the loads' Jacobians exact in the first
    // kExactLoadAttempts attempts, then projected too (a barrier's pairs are rarely what keeps
    // the matrix indefinite, and projecting them slows Newton to a crawl along a sliding contact,
    // where more of the mass does not: docs/benchmarks.md)
    for (int attempt = 0; attempt < options.shiftAttempts; ++attempt) {
      const HessianMode mode = attempt < kExactLoadAttempts ? HessianMode::Projected : HessianMode::Definite;
      if (factorise(problem.tangent(mode, total))) {
        remembered = total - options.shift;
        return true;
      }
      // with a shift of its own (the dynamics) the whole mass multiple grows 4 times
      total = options.shift > 0.0 ? 4.0 * total : nextShift(total);
    }
    return false;
  };
  for (; out.iterations < options.maxIterations && std::isfinite(cur.norm);) {
    if (problem.residualSmall(cur)) {
      out.converged = true;
      return out;
    }
    ++out.iterations;
    // The factorisation of an earlier iterate is kept while the iterates contract fast with it;
    // a new one is made when the last update shrank by less than half, or the search refused a
    // kept one's step.
    // a factorisation made for this iteration (quasi-Newton on its own start: only the first,
    // and again after a failed search)
    const double updateTolerance = problem.updateTolerance ? problem.updateTolerance(x) : options.updateTolerance;
    const bool learnt = qn && !pairS.empty();
    // Newton's direction on the factorisation at hand
    auto solveStep = [&]() {
      const CostTimer timer(options.costs ? &options.costs->solve : nullptr);
      const Eigen::VectorXd d = m_solver->solve(-Eigen::Map<const Eigen::VectorXd>(cur.g.data(), cur.g.size()));
      return ControlNet(Eigen::Map<const ControlNet>(d.data(), n, 3));
    };
    bool fresh = qn ? ownStart && refactor : refactor || !options.chordSteps;
    ControlNet step;
    bool solved = false;
    // keptFactorNearMinimum: after a full step on a fresh exact factorisation, that
    // factorisation's direction here (one solve) is the step when it is below half the tolerance
    if (fresh && !qn && !refactor && options.keptFactorNearMinimum && lastFull > 0.0) {
      step = solveStep();
      if (step.cwiseAbs().maxCoeff() <= 0.5 * updateTolerance) {
        fresh = false;
        solved = true;
      }
    }
    if (fresh) {
      if (!factor()) {
        out.failure = "the Newton matrix is not positive definite even with the element Hessians projected";
        return out;
      }
      refactor = false;
      ++out.factorisations;
    }
    if (qn)
      step = quasiNewtonStep(cur.g);
    else if (!solved)
      step = solveStep();
    const double slope = (step.array() * cur.g.array()).sum();
    const double stepSize = step.cwiseAbs().maxCoeff();
    // a barrier's bound first (never try a step that crosses), then the backtracking
    double alpha = problem.maxStep ? std::min(1.0, problem.maxStep(x, step)) : 1.0;
    bool accepted = false;
    // at most 30 halvings on the potential; 10 on the residual's norm (a norm that a
    // thousandth of the step does not lower sits on its rounding: a stall, not progress)
    for (int k = 0; k < 30; ++k, alpha *= 0.5) {
      problem.evaluate(x + alpha * step, trial);
      // the potential decides while its change is above its rounding (1e-12 of its parts'
      // magnitudes), the residual's norm below that (near a minimum a full step's change of the
      // potential is rounding, and only the gradient still sees the way)
      const bool resolved = std::abs(trial.value - cur.value) > 1e-12 * std::max(cur.valueScale, trial.valueScale);
      const bool better = cur.potential && trial.potential && resolved
                              ? trial.value <= cur.value + 1e-4 * alpha * slope
                              : trial.norm <= (1.0 - 1e-4 * alpha) * cur.norm;
      if (std::isfinite(trial.norm) && better) {
        accepted = true;
        break;
      }
      if (k >= 10 && !(cur.potential && trial.potential && resolved)) break;
    }
    if (!accepted && !fresh && !qn) {  // the kept factorisation's step: try again with a new one
      refactor = true;
      problem.evaluate(x, cur);
      continue;
    }
    if (!accepted && (learnt || (ownStart && !fresh))) {
      // the learnt pairs misled the search: start again from H0 (its own: made anew here)
      pairS.clear();
      pairY.clear();
      pairRho.clear();
      refactor = ownStart;
      problem.evaluate(x, cur);
      continue;
    }
    if (!accepted) {
      // no decrease along a descent direction: the potential's rounding floor (converged when
      // the step itself is below the tolerance)
      problem.evaluate(x, cur);
      out.converged = !qn && stepSize <= updateTolerance;
      if (!out.converged) out.failure = "the line search found no decrease along the Newton direction";
      return out;
    }
    x += alpha * step;
    if (qn) {  // learn the pair (s, y) where the curvature along s is positive
      ControlNet y = trial.g - cur.g;
      const ControlNet sk = alpha * step;
      const double sy = dot(sk, y);
      if (sy > 1e-10 * sk.norm() * y.norm()) {
        if (int(pairS.size()) == std::max(1, options.history)) {
          pairS.erase(pairS.begin());
          pairY.erase(pairY.begin());
          pairRho.erase(pairRho.begin());
        }
        pairS.push_back(sk);
        pairY.push_back(std::move(y));
        pairRho.push_back(1.0 / sy);
      }
    }
    std::swap(cur, trial);
    // converged when the Newton step is below the tolerance: it estimates the distance to the
    // minimum whether or not the search took all of it (near the minimum the potential's
    // rounding can refuse a full step; far from it a shortened step is no sign of convergence)
    // quasi-Newton: two steps in a row below it, the first with a learnt pair
    // (keptFactorNearMinimum takes a kept factorisation's direction only below half the
    // tolerance: its matrix is the last iterate's, which a barrier near contact can make stiffer
    // than the current one; so such a step always ends here)
    const bool small = stepSize <= updateTolerance;
    if (small && (!qn || smallBefore)) {
      out.converged = true;
      return out;
    }
    smallBefore = small && learnt;
    const double update = alpha * stepSize;
    if (!qn && !fresh && lastUpdate > 0.0 && update > 0.5 * lastUpdate) refactor = true;
    // (keptFactorNearMinimum: only after Newton's own full step, on the exact tangent, is the next
    // direction that small where the minimum is near: a damped or projected matrix's converge
    // linearly, a shortened step was far from it)
    lastFull = fresh && alpha == 1.0 && exactFactor ? update : 0.0;
    lastUpdate = update;
  }
  if (!std::isfinite(cur.norm)) {
    out.failure = "the residual is not finite";
  } else if (problem.residualSmall(cur)) {
    out.converged = true;
  } else {
    std::ostringstream os;
    os << "no convergence in " << out.iterations << " iterations";
    out.failure = os.str();
  }
  return out;
}

}  // namespace bsdeform
