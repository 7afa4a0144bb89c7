// SPDX-License-Identifier: MIT
#pragma once
/// @file TriangleTree.h
/// Closest points on a triangle mesh through a bounding-volume hierarchy: the query behind
/// contact with obstacles of any shape (docs/math.md, contact). World coordinates throughout.

#include <Eigen/Core>
#include <memory>
#include <vector>

namespace bsdeform {

/// Triangles as indices into a vertex array.
struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> triangles;
};

/// The closest point of the mesh to a query point.
struct ClosestHit {
  Eigen::Vector3d point;   ///< closest point on the mesh
  /// Unit normal for the side test at the closest feature: the face normal inside a face, the
  /// angle-weighted pseudo-normal of the vertex or edge on which the closest point lies
  /// (triangle winding gives the outside: counter-clockwise seen from outside, as Coin's shapes).
  Eigen::Vector3d normal;
  double distance = 0.0;   ///< |query - point|
  /// (query - point) . normal sign times distance: negative behind the surface (inside a
  /// closed, consistently wound mesh).
  double signedDistance = 0.0;
  int triangle = -1;       ///< index into the mesh's (kept) triangles
};

/// A bounding-volume hierarchy over a mesh's triangles. Degenerate triangles (zero area) and
/// triangles with a non-finite or out-of-range vertex are dropped at build (counted).
class TriangleTree {
 public:
  explicit TriangleTree(TriangleMesh mesh);
  ~TriangleTree();
  TriangleTree(const TriangleTree&) = delete;
  TriangleTree& operator=(const TriangleTree&) = delete;

  /// Moves the vertices (same count and triangles) and refits or rebuilds the hierarchy.
  /// @throws std::invalid_argument when the vertex count differs
  void update(const std::vector<Eigen::Vector3d>& vertices);

  /// The closest point within `maxDistance` of `query` (false when there is none or the mesh is
  /// empty). Thread-safe for concurrent queries.
  bool closest(const Eigen::Vector3d& query, double maxDistance, ClosestHit& hit) const;

  const TriangleMesh& mesh() const;  ///< the kept triangles
  int droppedTriangles() const;
  int triangleCount() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> m;
};

}  // namespace bsdeform
