// SPDX-License-Identifier: MIT
#pragma once
/// @file Multigrid.h
/// A geometric multigrid V-cycle for the implicit system K = D + A/4 (ImplicitSystem.h), used as
/// the preconditioner of conjugate gradients on large nets.
///
/// K is, up to pins and a non-separable mass, a sum of Kronecker products of 1-D matrices:
/// \f[ \tilde K = \tilde D_u \otimes \tilde D_v + \tfrac14 \sum_{(p,q)} c_{pq}\, G_u^p \otimes G_v^q \f]
/// (StiffnessStencil.h: the five energy terms on the moving layers; \f$\tilde D\f$ is the
/// separable fit \f$D_{ab} \approx d_u(a) d_v(b) / \bar d\f$, exact for nodal mass and for lumped
/// mass of constant density). Coarse spaces are B-spline spaces of twice the knot spacing: a
/// coarse B-spline of degree n is \f$2^{-n} \sum_{k=0}^{n+1} \binom{n+1}{k}\f$ times the fine ones
/// 2j .. 2j+n+1 (knot insertion), so the prolongation P is a Kronecker product of 1-D
/// subdivision matrices and the Galerkin operators \f$P^T \tilde K P\f$ stay sums of Kronecker
/// products of banded 1-D matrices: every level is applied with 1-D passes, O(points). (A
/// periodic direction with an odd number of layers has no coarse space of exactly twice the
/// spacing: its last coarse function overlaps the first, so that level is an approximation;
/// the Galerkin product keeps it symmetric positive definite, which is all CG needs.)
///
/// The finest level is smoothed with the true K (the stencil, pins included; useExactOperator())
/// by a degree-2 Chebyshev polynomial in \f$\mathrm{diag}^{-1} K\f$ on \f$[\lambda/3, \lambda]\f$
/// (\f$[\lambda/8, \lambda]\f$ when a direction is linear),
/// the coarser ones by damped Jacobi (the degree-1 polynomial of the same interval), λ 1.15 times
/// a power-iteration estimate of the largest eigenvalue (the smoothers reduce every mode up to
/// 4/3 λ); the same polynomial before and after the coarse correction keeps the V-cycle
/// symmetric. The coarsest level is solved by a dense Cholesky factorisation. The V-cycle is a
/// symmetric positive definite approximation of \f$K^{-1}\f$: conjugate gradients on K converge
/// with it whatever the pins (they make \f$\tilde K\f$ differ from K by a low-rank term).
/// docs/benchmarks.md ("Implicit at scale") has the measurements behind the choices.
/// The pieces live in the core's own headers: a level's Kronecker operator in MultigridOperator.h,
/// the transfers and Galerkin products in MultigridTransfer.h.

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <vector>

#include "bsdeform/spline/SplineSpace.h"
#include "bsdeform/energy/StiffnessStencil.h"

namespace bsdeform {

/// Preconditioner of the implicit system's conjugate gradients: one V-cycle from zero.
class MultigridPreconditioner {
 public:
  /// @param massTerm D per moving point (order of SplineSpace::movingToNet), > 0
  /// @param weights  the stencil's weights (the five terms)
  MultigridPreconditioner(const SplineSpace& space, const StiffnessStencil& stencil, const Weights& weights,
                          const Eigen::VectorXd& massTerm);
  ~MultigridPreconditioner();
  MultigridPreconditioner(const MultigridPreconditioner&) = delete;
  MultigridPreconditioner& operator=(const MultigridPreconditioner&) = delete;

  /// The finest level's operator: out = K x, or out = b - K x when b is given.
  using Operator = std::function<void(const ControlNet& x, const ControlNet* b, ControlNet& out)>;
  /// A smoothing step from zero, in one pass after the product: with x0 = scale diag^-1 b,
  /// out = alpha x0 + beta diag^-1 (b - K x0), or out += that when `accumulate`.
  using SmoothingStep = std::function<void(const ControlNet& b, double scale, double alpha, double beta,
                                           const Eigen::VectorXd& invDiag, bool accumulate, ControlNet& out)>;
  /// Smooth the finest level with the true operator K and its diagonal instead of K~: what the
  /// conjugate gradients iterate on, pins included. `lambdaBound` is an upper bound of
  /// lambda_max(diag^-1 K) that caps the power-iteration estimate.
  void useExactOperator(Operator op, SmoothingStep step, const Eigen::VectorXd& diagonal, double lambdaBound);
  /// z = B r: one V-cycle from zero (numMoving x 3 each).
  void apply(const ControlNet& r, ControlNet& z);
  /// y = K~ x: the finest level's Kronecker operator (for tests).
  void applyOperator(const ControlNet& x, ControlNet& y);

  /// Number of levels, the finest first; points of level l.
  int levels() const;
  Eigen::Index levelPoints(int level) const;

  struct Level;  ///< one level's operator, smoother, transfers and work vectors (Multigrid.cpp)

 private:
  /// x = one V-cycle for K_level x = r from zero.
  void cycle(int level, const ControlNet& r, ControlNet& x);
  std::vector<std::unique_ptr<Level>> m_levels;
};

}  // namespace bsdeform
