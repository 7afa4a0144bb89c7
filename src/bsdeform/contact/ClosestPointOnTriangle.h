// SPDX-License-Identifier: MIT
#pragma once
/// @file ClosestPointOnTriangle.h
/// The point of a triangle closest to a point in space, and the feature (face, edge, vertex) it
/// lies on: the exact narrow phase under TriangleTree and the collision forces.

#include <Eigen/Core>

namespace bsdeform {

/// The part of a triangle (a, b, c) a closest point lies on: inside the face, on an edge
/// (endpoints excluded) or at a vertex.
enum class TriangleFeature { Face, EdgeAB, EdgeBC, EdgeCA, VertexA, VertexB, VertexC };

struct TrianglePoint {
  Eigen::Vector3d point;
  TriangleFeature feature = TriangleFeature::Face;
};

/// The closest point of the triangle (a, b, c) to `p`, found by the Voronoi region of `p`
/// (vertex, edge or face region, tested in that order from the dot products of the edges with
/// p - a, p - b, p - c; Ericson, Real-Time Collision Detection, 2005, §5.1.5).
/// @pre the triangle is not degenerate (TriangleTree drops those)
TrianglePoint closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                     const Eigen::Vector3d& c);

}  // namespace bsdeform
