// SPDX-License-Identifier: MIT
#pragma once
/// @file ImplicitSystem.h
/// The linear system of the implicit scheme (Simulation.h, docs/math.md §6):
/// \f[ K P^+ = b, \qquad K = D + \tfrac14 A_{act}, \f]
/// D the diagonal \f$M/\Delta t^2 + C/(2\Delta t)\f$ per moving point, \f$A_{act}\f$ the moving
/// block A_II with the rows and columns of pinned points removed (their coupling is in the
/// right-hand side; a pinned row of K is its diagonal D alone). K is constant, symmetric
/// positive definite (A_II is semi-definite and D > 0), shared by x, y and z.
///
/// Two solvers (docs/benchmarks.md, "Implicit at scale", has the measurements behind them):
///  - Direct: CHOLMOD's supernodal Cholesky, factorised once at construction; exact to
///    rounding, any conditioning, but its factor grows like N log N and its cost like N^1.5
///    (3.3 GB of factor for a 1024^2 bicubic net).
///  - ConjugateGradient: matrix-free CG, K applied with the stiffness stencil (O(N) memory,
///    nothing to factorise), Jacobi-scaled; it stops at a relative residual
///    \f$\|r_c\| \le \mathrm{tol}\,\|b_c\|\f$ in every coordinate c. Its iteration count grows
///    like \f$\sqrt{\kappa(K)}\f$, \f$\kappa \le (\max D + \lambda_{max}(A)/4) / \min D\f$.
///  - Multigrid: the same CG, preconditioned by a multigrid V-cycle (Multigrid.h) instead of
///    Jacobi: a few times the work per iteration, and an iteration count that grows slowly
///    with the net instead of like sqrt(kappa).

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <vector>

#include "bsdeform/spline/SplineSpace.h"
#include "bsdeform/energy/StiffnessStencil.h"

namespace bsdeform {

class MultigridPreconditioner;
class SparseCholesky;

enum class LinearSolver {
  Automatic,          ///< Direct for small nets (at most kAutomaticDirectPoints moving points:
                      ///< exact, and factorised in well under 0.1 s) and for ill-conditioned
                      ///< systems (predicted CG iterations above kAutomaticIterationLimit) of at
                      ///< most kAutomaticFactorPoints moving points; Multigrid for larger
                      ///< ill-conditioned ones and where Jacobi-CG would need more than
                      ///< kAutomaticMultigridIterations iterations, ConjugateGradient below
  Direct,             ///< CHOLMOD supernodal Cholesky, factorised once
  ConjugateGradient,  ///< matrix-free Jacobi-preconditioned conjugate gradients on the stencil
  Multigrid,          ///< matrix-free conjugate gradients preconditioned by a multigrid V-cycle
};

/// Automatic picks CG when \f$\tfrac12\sqrt{\kappa}\,\ln(2/\mathrm{tol})\f$ (the CG/Chebyshev
/// bound on iterations for the bound on kappa) is at most this: about where one CG solve costs
/// what one CHOLMOD solve costs (docs/benchmarks.md).
constexpr double kAutomaticIterationLimit = 300.0;
/// Automatic preconditions CG with multigrid above this many predicted Jacobi-CG iterations: a
/// multigrid iteration costs about 8 Jacobi ones and 4-6 of them reach 1e-10 at every size
/// measured with nodal mass (docs/benchmarks.md): equal at 256^2 (31 Jacobi iterations, 37
/// predicted), multigrid 1.25x faster at 512^2 (64, 71 predicted).
constexpr double kAutomaticMultigridIterations = 50.0;
/// Automatic factorises ill-conditioned systems up to this many moving points (300^2: CHOLMOD
/// takes about 6 s; at 512^2 46 s and 1.1 GB for a step no faster than multigrid's,
/// docs/benchmarks.md).
constexpr Eigen::Index kAutomaticFactorPoints = 90000;
/// Automatic factorises nets up to this many moving points (64^2: 0.06 s, docs/benchmarks.md).
constexpr Eigen::Index kAutomaticDirectPoints = 4096;

class ImplicitSystem {
 public:
  /// @param massTerm D per moving point (numMoving, order of SplineSpace::movingToNet), > 0
  /// @param pinned   moving-point numbers held by pins (rows/columns that leave A)
  /// @param tolerance CG's relative residual per coordinate, in (0, 1)
  /// @param maxIterations CG gives up after this many iterations (solve() returns false)
  /// @param coupling off-diagonal entries (moving-point numbers) added to D: a mass matrix that
  ///        is not diagonal next to SIMPLY_SUPPORTED and BUILT_IN sides (EdgeMass), symmetric;
  ///        entries in pinned rows or columns are left out
  /// @param kappaEstimate if > 0, the condition number Automatic chooses by (and
  ///        conditionBound() reports) instead of the diagonal formula, which a coupling makes
  ///        far too pessimistic (Simulation passes kappa(M^-1 K), M the mass with its coupling)
  /// @throws std::runtime_error if the direct factorisation fails
  ImplicitSystem(const SplineSpace& space, const StiffnessStencil& stencil, const Eigen::VectorXd& massTerm,
                 const std::vector<Eigen::Index>& pinned, LinearSolver kind, double tolerance, int maxIterations,
                 std::vector<Eigen::Triplet<double>> coupling = {}, double kappaEstimate = 0.0);
  ~ImplicitSystem();
  ImplicitSystem(const ImplicitSystem&) = delete;
  ImplicitSystem& operator=(const ImplicitSystem&) = delete;

  /// Moving-point numbers held by pins, sorted.
  const std::vector<Eigen::Index>& pinned() const { return m_pinned; }
  /// Direct, ConjugateGradient or Multigrid (Automatic resolved at construction).
  LinearSolver method() const { return m_method; }
  /// Upper bound of the condition number of K (from the stencil's symbol bound).
  double conditionBound() const { return m_kappa; }
  /// \f$\tfrac12\sqrt{\kappa}\ln(2/\mathrm{tol})\f$: what Automatic compares.
  double predictedIterations() const;

  /// Solves K x = b (numMoving x 3). For CG, x holds the initial guess on entry.
  /// @return false if CG did not reach the tolerance within maxIterations (x is its last iterate)
  bool solve(const ControlNet& b, ControlNet& x);
  /// CG iterations of the last solve() (0 for Direct).
  int lastIterations() const { return m_lastIterations; }
  /// Largest relative residual \f$\|r_c\|/\|b_c\|\f$ over the coordinates after the last CG solve.
  double lastResidual() const { return m_lastResidual; }

  /// Non-zeros of the Cholesky factor (CHOLMOD's analysis; 0 for CG).
  double factorNonZeros() const { return m_factorNonZeros; }

  /// y = K x, matrix-free (numMoving x 3).
  void apply(const ControlNet& x, ControlNet& y);
  /// out = b - K x, matrix-free, in one pass after the stencil.
  void residual(const ControlNet& x, const ControlNet& b, ControlNet& out);
  /// Multigrid's smoothing step on the finest level, from zero: with x0 = scale diag(invDiag) b,
  /// out = alpha x0 + beta diag(invDiag) (b - K x0), or out += that when `accumulate`. x0 is
  /// written straight into the stencil's net and recomputed in the one pass after the stencil.
  void smoothingStep(const ControlNet& b, double scale, double alpha, double beta, const Eigen::VectorXd& invDiag,
                     bool accumulate, ControlNet& out);

 private:
  /// diag(K): D + diag(A)/4, and D alone on the pinned rows.
  Eigen::VectorXd diagonal() const;
  /// Allocates m_net (the stencil's argument, held points zero) if it is not yet.
  void ensureNet();
  /// Zeroes the pinned points of m_net and refreshes its periodic copies.
  void zeroPinnedInNet();
  /// Writes x into m_net (the stencil's argument) with its pinned points zeroed.
  void scatterDirection(const ControlNet& x);
  /// From y = A x~ (pinned columns zeroed, the stencil's output): fn(f, c, k, (K x)_k) for every
  /// entry k = 3 f + c in order, with K x = A_act x / 4 + D x (y's pinned rows are zeroed first);
  /// x_k is xAt(f, k).
  template <typename XAt, typename EntryFunction>
  void forEachProductEntry(XAt&& xAt, ControlNet& y, EntryFunction&& fn) const;
  /// From y = A x~ (pinned columns zeroed): y = A_act x / 4 + D x, and the dot x . y per coordinate.
  void finishApply(const ControlNet& x, ControlNet& y, double dot[3]) const;

  const SplineSpace& m_space;
  const StiffnessStencil& m_stencil;
  Eigen::VectorXd m_mass;          ///< D
  std::vector<Eigen::Triplet<double>> m_coupling;  ///< off-diagonal part of D (pins left out)
  Eigen::VectorXd m_inverseDiag;   ///< 1 / diag(K) (empty when diag(K) is constant: no scaling)
  std::vector<Eigen::Index> m_pinned;
  std::vector<Eigen::Index> m_pinnedNet;  ///< their net rows
  LinearSolver m_method;
  double m_tolerance;
  int m_maxIterations;
  double m_kappa = 1.0;
  double m_factorNonZeros = 0.0;
  std::unique_ptr<SparseCholesky> m_factor;  ///< Direct: CHOLMOD's factorisation of K
  std::unique_ptr<MultigridPreconditioner> m_multigrid;
  ControlNet m_net;  ///< scratch full net for the stencil (held points stay zero)
  ControlNet m_r, m_z, m_p, m_q, m_smooth;
  int m_lastIterations = 0;
  double m_lastResidual = 0.0;
};

}  // namespace bsdeform
