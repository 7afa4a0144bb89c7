// SPDX-License-Identifier: MIT
#pragma once
/// @file Distance.h
/// Squared distances between the primitives of barrier contact (docs/math.md §18): a point and a
/// triangle, two segments (edges). Each distance is classified by the features its closest points
/// lie on, as ipc-toolkit does, so that it is one smooth formula within a class (point–point,
/// point–line, point–plane, line–line); each formula comes with its exact gradient and Hessian
/// (hand-derived, fixed size, no allocation: they run once per contact pair and Newton iteration).

#include <Eigen/Core>

namespace bsdeform {

/// Where the closest point of a triangle (t0, t1, t2) to a point p lies: a vertex, the line of an
/// edge (E0 = t0t1, E1 = t1t2, E2 = t2t0), or the plane of the face.
enum class PointTriangleType { P_T0, P_T1, P_T2, P_E0, P_E1, P_E2, P_T };

/// Where the closest points of two segments (a0 a1) and (b0 b1) lie: at endpoints of both, at an
/// endpoint of one and inside the other (the point–line distance), or inside both (the distance of
/// the two lines).
enum class EdgeEdgeType { EA0_EB0, EA0_EB1, EA1_EB0, EA1_EB1, EA_EB0, EA_EB1, EA0_EB, EA1_EB, EA_EB };

/// The class of the point–triangle distance. @pre the triangle is not degenerate
PointTriangleType pointTriangleType(const Eigen::Vector3d& p, const Eigen::Vector3d& t0, const Eigen::Vector3d& t1,
                                    const Eigen::Vector3d& t2);

/// The class of the segment–segment distance. Segments closer to parallel than
/// |(a1 - a0) x (b1 - b0)|² ≤ 1e-20 |a1 - a0|² |b1 - b0|² take an endpoint class (the line–line
/// formula is singular there; the distance is attained at an endpoint of one of them).
/// @pre neither segment is degenerate
EdgeEdgeType edgeEdgeType(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& b0,
                          const Eigen::Vector3d& b1);

/// The squared distances of each class.
double pointPointDistanceSquared(const Eigen::Vector3d& p, const Eigen::Vector3d& q);
/// To the line through e0 and e1.
double pointLineDistanceSquared(const Eigen::Vector3d& p, const Eigen::Vector3d& e0, const Eigen::Vector3d& e1);
/// To the plane through t0, t1, t2.
double pointPlaneDistanceSquared(const Eigen::Vector3d& p, const Eigen::Vector3d& t0, const Eigen::Vector3d& t1,
                                 const Eigen::Vector3d& t2);
/// Between the lines through a0, a1 and b0, b1 (not parallel).
double lineLineDistanceSquared(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& b0,
                               const Eigen::Vector3d& b1);

/// The squared distance of the point and the triangle (by its class).
double pointTriangleDistanceSquared(const Eigen::Vector3d& p, const Eigen::Vector3d& t0, const Eigen::Vector3d& t1,
                                    const Eigen::Vector3d& t2);
double pointTriangleDistanceSquared(const Eigen::Vector3d& p, const Eigen::Vector3d& t0, const Eigen::Vector3d& t1,
                                    const Eigen::Vector3d& t2, PointTriangleType type);
/// The squared distance of the two segments (by its class).
double edgeEdgeDistanceSquared(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& b0,
                               const Eigen::Vector3d& b1);
double edgeEdgeDistanceSquared(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& b0,
                               const Eigen::Vector3d& b1, EdgeEdgeType type);

/// Whether the point is certainly farther than r from the triangle: its distance from the
/// triangle's plane (not for a sliver), or from the triangle's bounding sphere (centroid,
/// farthest corner), exceeds r. Both are lower bounds of the distance, so `true` is never wrong
/// up to rounding, about 10⁻¹⁶ of the coordinates and 10⁻¹³ of |p − t0| (the plane is used where
/// the triangle's angle at t0 has sin above 10⁻³): callers give r a margin. `false` says
/// nothing. Cheaper than a classified distance: a broad phase's last filter.
bool pointTriangleFartherThan(const Eigen::Vector3d& p, const Eigen::Vector3d& t0, const Eigen::Vector3d& t1,
                              const Eigen::Vector3d& t2, double r);
/// Whether the segments are certainly farther than r apart: the distance of their lines (edges
/// not within 10⁻³ rad of parallel), or of their bounding spheres (midpoints, half lengths),
/// exceeds r. As pointTriangleFartherThan.
bool edgeEdgeFartherThan(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& b0,
                         const Eigen::Vector3d& b1, double r);

/// @name Gradients and Hessians of the four formulas
/// Each returns the squared distance and writes its gradient and Hessian with respect to the
/// coordinates of its arguments in the order given (x, y, z of the first point, then the second...).
/// The Hessians are exact and symmetric; they are not positive semidefinite in general. A null
/// `hess` asks for the gradient alone (the same bits as with the Hessian, at a fraction of the cost).
///@{
double pointPointDistanceSquaredDerivatives(const Eigen::Vector3d& p, const Eigen::Vector3d& q,
                                            Eigen::Matrix<double, 6, 1>& grad, Eigen::Matrix<double, 6, 6>* hess);
double pointLineDistanceSquaredDerivatives(const Eigen::Vector3d& p, const Eigen::Vector3d& e0,
                                           const Eigen::Vector3d& e1, Eigen::Matrix<double, 9, 1>& grad,
                                           Eigen::Matrix<double, 9, 9>* hess);
double pointPlaneDistanceSquaredDerivatives(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                                            const Eigen::Vector3d& t1, const Eigen::Vector3d& t2,
                                            Eigen::Matrix<double, 12, 1>& grad, Eigen::Matrix<double, 12, 12>* hess);
/// @pre the lines are not parallel (edgeEdgeType never gives EA_EB for those)
double lineLineDistanceSquaredDerivatives(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1,
                                          const Eigen::Vector3d& b0, const Eigen::Vector3d& b1,
                                          Eigen::Matrix<double, 12, 1>& grad, Eigen::Matrix<double, 12, 12>* hess);
///@}

/// The squared point–triangle distance of the class `type` (pointTriangleDistanceSquared with a
/// class), its gradient and Hessian in the coordinates (p, t0, t1, t2); the rows and columns of
/// points the class does not involve are zero.
double pointTriangleDistanceSquaredDerivatives(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                                               const Eigen::Vector3d& t1, const Eigen::Vector3d& t2,
                                               PointTriangleType type, Eigen::Matrix<double, 12, 1>& grad,
                                               Eigen::Matrix<double, 12, 12>* hess);
/// The squared segment–segment distance of the class `type`, its gradient and Hessian in the
/// coordinates (a0, a1, b0, b1), zero for the points the class does not involve.
double edgeEdgeDistanceSquaredDerivatives(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1,
                                          const Eigen::Vector3d& b0, const Eigen::Vector3d& b1, EdgeEdgeType type,
                                          Eigen::Matrix<double, 12, 1>& grad, Eigen::Matrix<double, 12, 12>* hess);

/// x = |(a1 - a0) x (b1 - b0)|², the quantity the edge–edge mollifier (Barrier.h) smooths, with its
/// gradient and Hessian in (a0, a1, b0, b1).
double edgeEdgeCrossSquaredNormDerivatives(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1,
                                           const Eigen::Vector3d& b0, const Eigen::Vector3d& b1,
                                           Eigen::Matrix<double, 12, 1>& grad, Eigen::Matrix<double, 12, 12>* hess);

}  // namespace bsdeform
