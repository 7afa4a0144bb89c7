// SPDX-License-Identifier: MIT
#pragma once
/// @file Distance.h
/// Squared distances between the primitives of barrier contact (docs/math.md §18): a point and a
/// triangle, two segments (edges). Each distance is classified by the features its closest points
/// lie on, as ipc-toolkit does, so that it is one smooth formula within a class (point–point,
/// point–line, point–plane, line–line) whose derivatives Distance derivatives give.

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

}  // namespace bsdeform
