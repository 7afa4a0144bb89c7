// SPDX-License-Identifier: MIT
#pragma once
/// @file TriangleTree.h
/// Closest points on a triangle mesh through a bounding-volume hierarchy: the query behind
/// contact with obstacles of any shape (docs/math.md, contact). World coordinates throughout.

#include <Eigen/Core>
#include <cstdint>
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
///
/// Built on Embree 3's BVH and point queries (docs/benchmarks.md, "Closest-point queries: CGAL vs
/// Embree"); the hierarchy culls in single precision with a widened radius, the closest point and
/// the distances are computed in double, so answers equal a brute-force search in double.
/// \note Zero area means twice the area at most 1e-12 times the squared diagonal of the box of
/// the mesh's vertices; coordinates beyond 1e30 count as non-finite (the hierarchy keeps floats).
/// Vertices at the same position are one vertex for the pseudo-normals (a triangle soup, as
/// SoCallbackAction gives it, signs like the indexed mesh); this welding is decided when the tree
/// is built. The sign is right for closed, consistently wound, manifold meshes (Baerentzen and
/// Aanaes, Signed distance computation using the angle weighted pseudonormal, IEEE TVCG 2005);
/// an open mesh gives the side of its faces' normals.
class TriangleTree {
 public:
  explicit TriangleTree(TriangleMesh mesh);
  ~TriangleTree();
  TriangleTree(const TriangleTree&) = delete;
  TriangleTree& operator=(const TriangleTree&) = delete;

  /// Moves the vertices (same count and triangles) and refits or rebuilds the hierarchy.
  /// Refits the hierarchy (1/9 to 1/15 of a rebuild) and recomputes the pseudo-normals (the
  /// whole update: a third to a half of a rebuild); rebuilds when the set of kept triangles
  /// changes (one became degenerate or non-finite, or valid again), so the answers are always
  /// those of a tree built from scratch on the moved mesh.
  /// @throws std::invalid_argument when the vertex count differs
  void update(const std::vector<Eigen::Vector3d>& vertices);

  /// The closest point within `maxDistance` of `query` (false when there is none, the mesh is
  /// empty, the query is not finite or maxDistance is negative or NaN; infinity searches the
  /// whole mesh). Thread-safe for concurrent queries (not concurrently with update()).
  bool closest(const Eigen::Vector3d& query, double maxDistance, ClosestHit& hit) const;

  /// The same search started from a guess: when `hint` is a kept triangle, the distance to it
  /// bounds the search radius, which makes the query several times cheaper when the guess is
  /// the previous answer for a point that moved little. The answer is the one without the hint
  /// (the same closest point, normal and distances; of two triangles at exactly the same
  /// distance either may be named). On return `hint` holds the triangle found, or -1.
  bool closest(const Eigen::Vector3d& query, double maxDistance, ClosestHit& hit, int& hint) const;

  const TriangleMesh& mesh() const;  ///< all vertices as given, the kept triangles
  int droppedTriangles() const;
  /// How many times update() moved the vertices (answers depend on the tree and this number).
  std::uint64_t version() const;
  int triangleCount() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> m;
};

}  // namespace bsdeform
