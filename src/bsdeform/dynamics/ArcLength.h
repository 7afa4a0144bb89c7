// SPDX-License-Identifier: MIT
#pragma once
/// @file ArcLength.h
/// Arc-length continuation (Crisfield 1981, the cylindrical form: the constraint on the
/// displacement increment only): the equilibrium path g(x) = λ F(x) of a structure under a
/// load F scaled by the load factor λ, traced step by step through limit points (where the
/// load passes a maximum: snap-through) and snap-backs (where the displacement turns back),
/// which load control cannot pass (docs/math.md §16, "Arc-length continuation").
///
/// Each step goes a fixed distance Δl in the unknowns: |Δx| = Δl, Δx the step's increment.
/// Predictor along the tangent K⁻¹F, in the direction of the last step's increment (its sign
/// by the angle with it, so the path does not turn back at a limit point); corrector: Newton on
/// R = g − λF with the constraint, solving K δ_R = −R and K δ_F = F and picking δλ from the
/// quadratic |Δx + δ_R + δλ δ_F|² = Δl² (of its two roots the one whose increment makes the
/// smaller angle with the step's increment so far). K is factorised as an LU (SparseLU,
/// pivoting): beyond a limit point it is indefinite. A point is converged when the relative
/// residual is below ArcLengthOptions::tolerance, or a Newton correction (its largest component)
/// below the update tolerance (ArcLengthProblem::updateTolerance, ArcLengthOptions::
/// updateTolerance): the relative residual alone has a rounding floor where large internal
/// forces cancel (a snapped shell near a zero load), and a path relying on it stalls there. A
/// step that does not converge is retried with half the arc length; one cut below
/// ArcLengthOptions::minArcLength ends the path with an error (no step is accepted that does not
/// move). The next step's length aims at 4 iterations (Δl sqrt(4 / I), between half and twice
/// the last, at most ArcLengthOptions::maxArcLength or else 1000 times the first).

#include <Eigen/SparseCore>
#include <functional>
#include <string>
#include <vector>

namespace bsdeform {

struct ArcLengthProblem {
  /// g(x) (the internal force) and F(x) (the load at factor 1), both with held unknowns zeroed.
  std::function<void(const Eigen::VectorXd& x, Eigen::VectorXd& g, Eigen::VectorXd& F)> evaluate;
  /// dg/dx at x (lower triangle or full, symmetric; held unknowns with a unit diagonal).
  std::function<Eigen::SparseMatrix<double>(const Eigen::VectorXd& x)> tangent;
  /// Whether the matrix from tangent() holds only its lower triangle.
  bool lowerOnly = true;
  /// Optional: the length below which a Newton correction's largest component counts as
  /// converged at x (Simulation::solveStaticArcLength: the static Newton's, tolerance times the
  /// largest displacement from rest plus 1e-11 of the surface's size). The larger of it and
  /// ArcLengthOptions::updateTolerance is used.
  std::function<double(const Eigen::VectorXd& x)> updateTolerance;
};

struct ArcLengthOptions {
  int maxSteps = 20;         ///< converged points to find at most
  /// (> 0) the path ends at this load factor: a step that would pass it going up ends at an
  /// equilibrium at exactly this load (Newton at fixed load; past it if that fails to converge)
  double maxLoad = 1.0;
  /// The arc length Δl; 0: the length of the linear response to a load factor of
  /// maxLoad / maxSteps (so that a linear structure reaches maxLoad in maxSteps steps).
  double arcLength = 0.0;
  /// The longest arc length a step may grow to; 0: 1000 times the first. A cap of the first
  /// length keeps the points evenly spaced along the path (e.g. to compare it with a table).
  double maxArcLength = 0.0;
  double tolerance = 1e-8;   ///< relative residual |g − λF| / (|g| + |λF|)
  /// or a Newton correction below this length (largest component); see also
  /// ArcLengthProblem::updateTolerance
  double updateTolerance = 0.0;
  int maxIterations = 25;    ///< per step, before the step is retried shorter
  int maxCuts = 12;          ///< halvings of the arc length in one step before giving up
  /// A step cut below this arc length ends the path with an error (a stall: the corrector
  /// converges only on steps that do not move); 0: 1e-4 times the first arc length.
  double minArcLength = 0.0;
};

struct ArcLengthPoint {
  double loadFactor = 0.0;
  Eigen::VectorXd x;
  double residual = 0.0;  ///< relative, as ArcLengthOptions::tolerance
  int iterations = 0;
};

/// The path from x0 (an equilibrium at λ = 0) for at most options.maxSteps steps or until the
/// load factor reaches options.maxLoad (the last point then at exactly it, see there). `each`, when given, is called with every converged point.
/// @throws std::runtime_error naming the step and the load factor reached when a step does not
///         converge even at 2^-maxCuts of the arc length or at minArcLength (the path stalls),
///         or the tangent cannot be factorised; the points before it have gone to `each`
std::vector<ArcLengthPoint> arcLengthPath(const Eigen::VectorXd& x0, const ArcLengthProblem& problem,
                                          const ArcLengthOptions& options,
                                          const std::function<void(const ArcLengthPoint&)>& each = {});

}  // namespace bsdeform
