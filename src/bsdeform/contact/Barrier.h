// SPDX-License-Identifier: MIT
#pragma once
/// @file Barrier.h
/// The barrier potential of Incremental Potential Contact (IPC; Li et al., "Incremental Potential
/// Contact", ACM TOG 39(4), 2020) on the classified squared distances of Distance.h, with a
/// thickness offset as in Codimensional IPC (Li et al., ACM TOG 40(4), 2021), the edge–edge
/// mollifier (IPC §4.3) and IPC's adaptive barrier stiffness. Formulas: docs/math.md §18.

#include <Eigen/Core>

namespace bsdeform {

using Vector12d = Eigen::Matrix<double, 12, 1>;
using Matrix12d = Eigen::Matrix<double, 12, 12>;

/// What a pair's barrier potential depends on besides the positions.
struct BarrierParameters {
  double offset = 0.0;     ///< ξ, m: the thickness; contact is at distance ξ, not 0
  double dhat = 1e-3;      ///< d̂, m: the barrier acts for distances d < ξ + d̂
  double stiffness = 1.0;  ///< κ: multiplies b (units: the energy's per m⁴; see initialBarrierStiffness)
};

/// @name The barrier on squared distances
/// b(s) = -(s - ŝ)² ln(s / ŝ) for 0 < s < ŝ, 0 for s ≥ ŝ, +∞ for s ≤ 0, where s = d² - ξ² and
/// ŝ = (ξ + d̂)² - ξ² (barrierSquaredActivation). b is C² at s = ŝ (b, b' vanish there) and its
/// derivatives are 0 outside (0, ŝ).
///@{
double barrier(double s, double sHat);
/// db/ds
double barrierFirstDerivative(double s, double sHat);
/// d²b/ds²
double barrierSecondDerivative(double s, double sHat);
/// ŝ = (ξ + d̂)² - ξ², the s at which the pair's barrier switches on.
double barrierSquaredActivation(const BarrierParameters& bp);
///@}

/// @name The edge–edge mollifier (IPC §4.3)
/// m(x) = -x²/ε_x² + 2x/ε_x for x < ε_x, 1 otherwise, with x = |(a1 - a0) x (b1 - b0)|²: it takes
/// the edge–edge barrier smoothly to 0 as the edges become parallel, where the edge–edge distance
/// is not smooth. m is C¹ at x = ε_x.
///@{
/// ε_x = 1e-3 |a1r - a0r|² |b1r - b0r|² from the REST positions of the edges (IPC's choice of the
/// factor: edges within about 1.8° of parallel, sin² θ < 1e-3, are mollified).
double edgeEdgeMollifierThreshold(const Eigen::Vector3d& a0Rest, const Eigen::Vector3d& a1Rest,
                                  const Eigen::Vector3d& b0Rest, const Eigen::Vector3d& b1Rest);
/// m(x) for a threshold ε_x > 0.
double edgeEdgeMollifier(double x, double threshold);
/// m(x) at the positions, and (when not null) its gradient and Hessian in (a0, a1, b0, b1).
double edgeEdgeMollifier(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& b0,
                         const Eigen::Vector3d& b1, double threshold, Vector12d* grad, Matrix12d* hess);
///@}

/// Which Hessian a pair barrier gives: projected to positive semidefinite (Newton's definite
/// fallback) or the exact one (Newton's exact tangent, tests).
enum class BarrierHessian { ProjectedPsd, Exact };

/// The potential κ b(s) of a point and a triangle, s = d² - ξ² with d² of the class Distance's
/// classifier gives at these positions (IPC's convention: the derivatives are those of that
/// class's formula).
/// @param[out] grad  when not null: its gradient in (p, t0, t1, t2)
/// @param[out] hessPsd  when not null: its Hessian, with negative eigenvalues clamped to 0 unless
///   `hessian` is BarrierHessian::Exact
/// `distanceSquared`, if given, receives d² (pointTriangleDistanceSquared's, bit for bit).
/// @return 0 (outputs zero) when s ≥ ŝ; +∞ (outputs zero) when s ≤ 0, i.e. d ≤ ξ
double pointTriangleBarrier(const Eigen::Vector3d& p, const Eigen::Vector3d& t0, const Eigen::Vector3d& t1,
                            const Eigen::Vector3d& t2, const BarrierParameters& bp, Vector12d* grad,
                            Matrix12d* hessPsd, BarrierHessian hessian = BarrierHessian::ProjectedPsd,
                            double* distanceSquared = nullptr);

/// pointTriangleBarrier for a triangle that does not move (an obstacle's, in a step): the value
/// and d² the same bits, the gradient and Hessian in the point's three coordinates alone, in
/// closed form. With g = ∇d² the Hessian is b'' g gᵀ + b' ∇²d², where ∇²d² is 2 n̂n̂ᵀ (the face
/// class), 2 (I − êêᵀ) (an edge of direction ê) or 2 I (a vertex), and g is an eigenvector of both
/// terms: its eigenvalues are b''|g|² + 2b' along g and 2b' (or 0) across, so the projection to
/// PSD clamps those two numbers, with no eigensolver (docs/math.md §18.2).
double pointStaticTriangleBarrier(const Eigen::Vector3d& p, const Eigen::Vector3d& t0, const Eigen::Vector3d& t1,
                                  const Eigen::Vector3d& t2, const BarrierParameters& bp, Eigen::Vector3d* grad,
                                  Eigen::Matrix3d* hess, BarrierHessian hessian = BarrierHessian::ProjectedPsd,
                                  double* distanceSquared = nullptr);

/// The potential κ m(x) b(s) of two edges (a0 a1) and (b0 b1): as pointTriangleBarrier, times the
/// mollifier with threshold `mollifierThreshold` (edgeEdgeMollifierThreshold of the rest
/// positions). Coordinates ordered (a0, a1, b0, b1).
double edgeEdgeBarrier(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& b0,
                       const Eigen::Vector3d& b1, double mollifierThreshold, const BarrierParameters& bp,
                       Vector12d* grad, Matrix12d* hessPsd, BarrierHessian hessian = BarrierHessian::ProjectedPsd,
                       double* distanceSquared = nullptr);

/// Replaces a symmetric matrix by its projection onto the positive semidefinite cone: V max(Λ, 0) Vᵀ
/// from its eigen-decomposition. A matrix that is already positive semidefinite is left unchanged
/// (bit for bit).
void projectToPsd(Matrix12d& h);
/// The same for the n x n block of `h` at (first, first) (the coordinates
/// that move when the pair's other points are an obstacle's), the rest of `h` set to zero.
void projectBlockToPsd(Matrix12d& h, int first, int n);

/// @name Adaptive barrier stiffness (IPC supplementary §3; ipc-toolkit adaptive_stiffness)
/// These assume IPC's incremental potential E(x) = ½|x - x̃|²_M + h²Ψ(x) + κ Σ b (units kg m²: a
/// mass times a length squared; then κ is in kg/m², since b is in m⁴), SI lengths and masses.
///@{
/// The initial κ: the least-squares balance of the energy's and the barrier's gradients,
/// κ = -∇E·∇B / |∇B|², clamped to [κ_min, 100 κ_min]. κ_min makes the barrier's stiffness across the
/// gap at a tiny gap d0 - ξ = 1e-8 × bboxDiagonal comparable to the mass: κ_min = minStiffnessScale ×
/// averageMass / (4 d0² b''(d0² - ξ², ŝ)) (the second derivative of b(d² - ξ²) in d is
/// 4 d² b'' + 2 b', dominated by the first term there). If that gap is beyond d̂, d0² - ξ² = ŝ / 2.
/// @param bboxDiagonal  m, the diagonal of the scene's bounding box
/// @param dhat  m, d̂
/// @param averageMass  kg, the average of the nodal masses
/// @param gradEnergy  the gradient of the potential without the barrier (kg m, per coordinate)
/// @param gradBarrier  the gradient of Σ b (κ = 1, m³), same length; zero: κ = κ_min (ipc-toolkit
///   takes κ = 1 clamped to the range then)
/// @param[out] maxStiffness  100 κ_min, the cap updateBarrierStiffness keeps to
/// @param minStiffnessScale  IPC's 1e11, an empirical constant tuned for SI scales
/// @param offset  m, ξ
double initialBarrierStiffness(double bboxDiagonal, double dhat, double averageMass,
                               const Eigen::Ref<const Eigen::VectorXd>& gradEnergy,
                               const Eigen::Ref<const Eigen::VectorXd>& gradBarrier, double& maxStiffness,
                               double minStiffnessScale = 1e11, double offset = 0.0);

/// After a Newton iteration: if the smallest gap of any pair was below ε = dhatEpsilonScale ×
/// bboxDiagonal before and after it and has shrunk, the barrier is losing, and κ doubles (at most to
/// maxStiffness). The gaps are d - ξ in m (ipc-toolkit compares d² with ε², which is the same for ξ = 0).
/// @return whether κ changed
bool updateBarrierStiffness(double previousMinDistance, double minDistance, double maxStiffness, double& stiffness,
                            double bboxDiagonal, double dhatEpsilonScale = 1e-9);
///@}

}  // namespace bsdeform
