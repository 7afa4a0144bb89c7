// SPDX-License-Identifier: MIT
#pragma once
// One interface over the closest-point libraries compared in bench_closest.cpp, so the same
// meshes and queries drive each of them. Each index keeps its own double copy of the mesh and
// finishes every hit with bsdeform::closestPointOnTriangle (the feature is needed for the
// pseudo-normal), so the figures compare the hierarchies, not two point-triangle routines.

#include <memory>
#include <string>
#include <vector>

#include "bsdeform/contact/ClosestPointOnTriangle.h"
#include "bsdeform/contact/TriangleTree.h"

namespace closestbench {

struct Hit {
  Eigen::Vector3d point;
  double distance = 0.0;
  int triangle = -1;
  bsdeform::TriangleFeature feature = bsdeform::TriangleFeature::Face;
};

class ClosestIndex {
 public:
  virtual ~ClosestIndex() = default;
  virtual void build(const bsdeform::TriangleMesh& mesh) = 0;
  /// New positions, same triangles.
  virtual void update(const std::vector<Eigen::Vector3d>& vertices) = 0;
  virtual bool closest(const Eigen::Vector3d& q, double maxDistance, Hit& hit) const = 0;
};

/// Embree 3: `refit` = two-level scene (RTC_BUILD_QUALITY_LOW, dynamic) with a
/// RTC_BUILD_QUALITY_REFIT geometry, so update() refits; otherwise the default MEDIUM build and
/// update() rebuilds. One build thread.
std::unique_ptr<ClosestIndex> makeEmbreeIndex(bool refit);

enum class CgalQuery {
  SphereHint,  ///< closest_point_and_primitive with a hint at maxDistance from the query (no KD-tree)
  KdHint,      ///< closest_point_and_primitive with the KD-tree hint (accelerate_distance_queries)
  SphereTest,  ///< do_intersect(Sphere_3) first, then the KD-tree hinted query
};
/// CGAL 5 AABB_tree over Simple_cartesian<double> triangles; update() rebuilds (CGAL has no refit).
std::unique_ptr<ClosestIndex> makeCgalIndex(CgalQuery mode);
bool haveCgal();

}  // namespace closestbench
