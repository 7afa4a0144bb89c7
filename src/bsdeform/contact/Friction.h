// SPDX-License-Identifier: MIT
#pragma once
/// @file Friction.h
/// Lagged smooth friction of Incremental Potential Contact (Li et al. 2020, §5; ipc-toolkit's
/// friction module as the specification), on the pairs of Barrier.h: at the start of a step each
/// contact pair within the barrier's reach is frozen as a FrictionPair (its closest points'
/// coefficients, the tangent plane there and the normal force the barrier exerts); during the step
/// the pair's friction is a convex potential of the relative tangential displacement u over the step,
/// D = μ λ f0(|u|), whose force is the Coulomb force μ λ opposing the slip once |u| ≥ ε_v h, and
/// grows linearly from 0 below it (static friction smoothed over the velocity ε_v). docs/math.md §18.3.

#include <Eigen/Core>
#include <array>

namespace bsdeform {

/// @name IPC's smoothing of the slip (ε = ε_v h, a displacement)
/// f0(y) = -y³/(3ε²) + y²/ε + ε/3 for y < ε, y otherwise (C², f0' = f1);
/// f1(y) = -y²/ε² + 2y/ε for y < ε, 1 otherwise (the friction force over μλ).
///@{
double smoothFrictionF0(double y, double epsilon);
double smoothFrictionF1(double y, double epsilon);
/// f1(y) / y, finite at y = 0 (2/ε there).
double smoothFrictionF1OverY(double y, double epsilon);
/// (f1'(y) y - f1(y)) / y³: -1/(ε² y) below ε (its product with |u|² vanishes at 0), -1/y³ above.
/// The 2×2 Hessian of f0(|u|) in u is f1/y I + this × u uᵀ, positive semidefinite everywhere.
double smoothFrictionHessianTerm(double y, double epsilon);
///@}

/// One pair's friction, frozen at the start of a step. The pair's points are up to four (a point
/// and a triangle, two edges); `coefficient` weighs each point's displacement in the relative
/// displacement of the two closest points (first primitive minus second): r = Σ_k c_k Δx_k.
struct FrictionPair {
  std::array<Eigen::Index, 4> vertex{};  ///< the caller's indices of the points (-1: one that does not move)
  std::array<double, 4> coefficient{};
  int split = 1;                    ///< points [0, split) belong to the first primitive
  Eigen::Matrix<double, 3, 2> basis;  ///< orthonormal, spans the plane normal to the pair's normal
  double normalForce = 0.0;         ///< λ, newtons (the barrier's force on the pair)
  /// The part of r from points that do not move with the unknowns (a moving obstacle's, over the
  /// whole step): r = slip + Σ over the moving points
  Eigen::Vector3d slip = Eigen::Vector3d::Zero();
};

/// The closest points of a point p and the triangle (t0, t1, t2): coefficients (1, -β0, -β1, -β2)
/// with β the closest point's barycentric coordinates, and the tangent basis of the plane normal
/// to the line between them (the triangle's plane when the closest point is inside it).
/// @pre p is not on the triangle; the triangle is not degenerate
void pointTriangleFrame(const Eigen::Vector3d& p, const Eigen::Vector3d& t0, const Eigen::Vector3d& t1,
                        const Eigen::Vector3d& t2, FrictionPair& pair);
/// The same for two segments: coefficients (1 - α, α, -(1 - β), -β) with α, β the parameters of
/// the closest points on (a0 a1) and (b0 b1) (of the class Distance.h gives the pair).
void edgeEdgeFrame(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& b0,
                   const Eigen::Vector3d& b1, FrictionPair& pair);

/// The friction potential of a frozen pair at the relative displacement r (world, m) over the step:
/// D = μ λ f0(|Tᵀ r|). When asked: its gradient in r (3) and its Hessian in r (3×3, positive
/// semidefinite); those in the points' coordinates are c_k times and c_k c_l times them.
double frictionPotential(const FrictionPair& pair, const Eigen::Vector3d& r, double mu, double epsilon,
                         Eigen::Vector3d* grad, Eigen::Matrix3d* hess);

}  // namespace bsdeform
