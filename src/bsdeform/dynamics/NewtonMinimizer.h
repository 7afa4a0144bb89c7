// SPDX-License-Identifier: MIT
#pragma once
/// @file NewtonMinimizer.h
/// Not installed. The one Newton solver: backward Euler's step (the minimum of the incremental
/// potential, either energy), SHELL's Newmark step (the minimum of its step potential) and the
/// static solve (the minimum of the total potential, load increment by load increment) all call
/// minimize() with their own evaluation and tangent (docs/math.md §16, "One Newton solver").
///
/// An iteration solves K d = -g with K the tangent at the iterate (the exact one while it is
/// positive definite, else (Options::massRetries) the exact one with more of the mass, else the
/// element Hessians projected to PSD with the loads' Jacobians exact (HessianMode::Projected),
/// with more of the mass added in each attempt, the loads' projected too from the fourth
/// (HessianMode::Definite)), then searches along d (Armijo backtracking on the potential; on the residual's norm
/// when some load has no potential, or where the potential's change is below its rounding). A factorisation is kept while the iterates contract fast
/// with it (chord steps: a gradient and a solve, no assembly and factorisation). Converged when
/// the largest component of an accepted Newton step is below `updateTolerance` (a length:
/// physical units, no rounding floor) or the residual is below its tolerance. Options::quasiNewton
/// replaces the factorisations by L-BFGS directions (docs/math.md §16, "L-BFGS in place of Newton").

#include <Eigen/SparseCore>
#include <functional>
#include <memory>
#include <string>

#include "bsdeform/dynamics/StepCosts.h"
#include "bsdeform/energy/Shell.h"
#include "bsdeform/spline/SplineSpace.h"

namespace bsdeform {

class SparseCholesky;

/// The minimised function at one point.
struct NewtonPoint {
  ControlNet g;            ///< its gradient (the residual), held coordinates zeroed
  double value = 0.0;      ///< its value (valid when `potential`)
  double valueScale = 0.0; ///< the sum of its parts' magnitudes (its rounding is 1e-16 of it)
  double norm = 0.0;       ///< ||g||
  double scale = 0.0;      ///< the size of the forces ||g|| is judged against (the caller's)
  bool potential = true;   ///< every part has a potential (else the search watches ||g||)
};

class NewtonMinimizer {
 public:
  struct Problem {
    /// The point x (also made the problem's current state, for tangent()).
    std::function<void(const ControlNet& x, NewtonPoint& p)> evaluate;
    /// The tangent at the last evaluated point, with `shift` times the mass added.
    std::function<const Eigen::SparseMatrix<double>&(HessianMode mode, double shift)> tangent;
    /// Optional: the last tangent() with `extra` times the mass added, without assembling it
    /// again (see Options::massRetries).
    std::function<const Eigen::SparseMatrix<double>&(double extra)> shiftTangent;
    /// Whether p's residual is below the caller's tolerance (converged).
    std::function<bool(const NewtonPoint& p)> residualSmall;
    /// Optional: the update tolerance at the iterate x (a length), in place of
    /// Options::updateTolerance (the static solve's is relative to the displacement so far).
    std::function<double(const ControlNet& x)> updateTolerance;
    /// Optional: the largest fraction in (0, 1] of the step from x to x + step the search may
    /// try (a barrier's continuous collision check); every trial lies within it.
    std::function<double(const ControlNet& x, const ControlNet& step)> maxStep;
    /// Quasi-Newton only: r := H0⁻¹ r for the constant matrix the L-BFGS recursion starts
    /// from (held coordinates of the result zeroed), in place of the tangent's factorisation.
    std::function<void(ControlNet& r)> precondition;
  };
  struct Options {
    int maxIterations = 30;
    double updateTolerance = 0.0;  ///< a length: converged when an accepted step is below
    double shift = 0.0;            ///< the mass multiple every tangent has (1/h² + c/h; 0: statics)
    /// The first mass multiple added when even the projected tangent is not positive definite
    /// (when `shift` is 0; otherwise 4 shift, 16 shift, ...), and how many times it is tried
    /// (each 4 times the last).
    double firstExtraShift = 0.0;
    int shiftAttempts = 8;
    /// With a shift of its own (the dynamics) and Problem::shiftTangent: where the exact tangent
    /// is not positive definite, the exact tangent with the mass multiple raised 1.25 times up
    /// to this many times, before the projected one (Levenberg–Marquardt's damping on the
    /// inertia the step already has; the exact Hessian's curvature kept).
    int massRetries = 0;
    /// Where the exact tangent was not positive definite, later factorisations of the same
    /// minimize() start from the projected one with a quarter of the last extra shift
    /// (Levenberg–Marquardt's lowering: a free body stays singular near its rigid motions), the
    /// loads' Jacobians exact again (the static solve's: it takes no barrier contact).
    bool rememberShift = false;
    /// Keep a factorisation while the iterates contract fast with it (chord steps); false: a new
    /// one every iteration (a barrier's Hessian changes too fast between iterates for chords).
    bool chordSteps = true;
    /// Without chord steps: the step that confirms convergence reuses the last factorisation.
    /// After a full Newton update on a fresh factorisation of the exact tangent (with the
    /// step's own shift), the next iteration first solves with that factorisation (one solve);
    /// when that direction is below half the update tolerance it is the step, and converged
    /// once the search takes it (it estimates the distance to the minimum as Newton's would,
    /// the matrix having moved by the order of the last update; the half for a barrier's
    /// curvature, which grows near contact). Otherwise the direction is dropped and the tangent factorised anew. Newton
    /// only (not quasiNewton).
    bool keptFactorNearMinimum = false;
    /// L-BFGS (Liu, Bouaziz, Kavan 2017) in place of Newton's factorisations: the direction is
    /// the two-loop recursion over the last `history` pairs of updates and gradient changes,
    /// started from Problem::precondition; the same line search and the same tests. Its step
    /// counts as converged only once a pair has been learnt (the bare H0⁻¹ g can be far too
    /// short where H0 is stiffer than the tangent).
    bool quasiNewton = false;
    int history = 8;
    /// Optional: the factorisations' and solves' wall time is added to it (the caller's
    /// evaluate and tangent time their own parts).
    StepCosts* costs = nullptr;
  };
  struct Outcome {
    bool converged = false;
    int iterations = 0;
    int factorisations = 0;
    std::string failure;  ///< why it stopped, when not converged
  };

  NewtonMinimizer();
  ~NewtonMinimizer();
  NewtonMinimizer(const NewtonMinimizer&) = delete;
  NewtonMinimizer& operator=(const NewtonMinimizer&) = delete;

  /// Minimises from x (updated to the last accepted iterate, `cur` its evaluation); cur must
  /// be evaluated at x on entry.
  Outcome minimize(ControlNet& x, NewtonPoint& cur, const Problem& problem, const Options& options);

 private:
  std::unique_ptr<SparseCholesky> m_solver;  ///< CHOLMOD, its symbolic analysis kept
};

}  // namespace bsdeform
