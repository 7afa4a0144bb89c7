// SPDX-License-Identifier: MIT
// CGAL 5 AABB tree over Simple_cartesian<double> triangles (header-only). Compiled only with
// -DBSDEFORM_BENCH_CGAL=ON and libcgal-dev installed (AABB_tree is GPL-3.0-or-later); otherwise
// this file only says CGAL is absent.
#include "closest_index.h"

#if defined(BSDEFORM_BENCH_CGAL) && __has_include(<CGAL/AABB_tree.h>)
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <cmath>

namespace closestbench {
namespace {

using K = CGAL::Simple_cartesian<double>;
using Triangles = std::vector<K::Triangle_3>;
using Primitive = CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

K::Point_3 toCgal(const Eigen::Vector3d& p) { return K::Point_3(p.x(), p.y(), p.z()); }

class CgalIndex final : public ClosestIndex {
 public:
  explicit CgalIndex(CgalQuery mode) : m_mode(mode) {}

  void build(const bsdeform::TriangleMesh& mesh) override {
    m_triangleIndices = mesh.triangles;
    update(mesh.vertices);
  }

  void update(const std::vector<Eigen::Vector3d>& vertices) override {
    m_vertices = vertices;
    m_cgalTriangles.clear();
    m_cgalTriangles.reserve(m_triangleIndices.size());
    for (const Eigen::Vector3i& t : m_triangleIndices)
      m_cgalTriangles.emplace_back(toCgal(m_vertices[t[0]]), toCgal(m_vertices[t[1]]), toCgal(m_vertices[t[2]]));
    m_tree.rebuild(m_cgalTriangles.begin(), m_cgalTriangles.end());
    if (m_mode == CgalQuery::SphereHint)
      m_tree.do_not_accelerate_distance_queries();
    else
      m_tree.accelerate_distance_queries();  // the KD-tree now, not lazily in the first query
  }

  bool closest(const Eigen::Vector3d& q, double maxDistance, Hit& hit) const override {
    const K::Point_3 cq = toCgal(q);
    Tree::Point_and_primitive_id found;
    if (m_mode == CgalQuery::SphereHint) {
      // The traversal keeps the hint unless it finds something strictly closer and prunes every
      // box farther than the hint: a hint at maxDistance is a search radius.
      const Tree::Point_and_primitive_id hint(K::Point_3(q.x() + maxDistance, q.y(), q.z()), m_cgalTriangles.begin());
      found = m_tree.closest_point_and_primitive(cq, hint);
      if (found.first == hint.first) return false;
    } else {
      if (m_mode == CgalQuery::SphereTest &&
          !m_tree.do_intersect(K::Sphere_3(cq, maxDistance * maxDistance)))
        return false;
      found = m_tree.closest_point_and_primitive(cq);
    }
    const int t = int(found.second - m_cgalTriangles.begin());
    const Eigen::Vector3i& f = m_triangleIndices[t];
    const bsdeform::TrianglePoint p =
        bsdeform::closestPointOnTriangle(q, m_vertices[f[0]], m_vertices[f[1]], m_vertices[f[2]]);
    const double d = (q - p.point).norm();
    if (d > maxDistance) return false;
    hit.point = p.point;
    hit.feature = p.feature;
    hit.distance = d;
    hit.triangle = t;
    return true;
  }

 private:
  CgalQuery m_mode;
  std::vector<Eigen::Vector3d> m_vertices;
  std::vector<Eigen::Vector3i> m_triangleIndices;
  Triangles m_cgalTriangles;
  Tree m_tree;
};

}  // namespace

std::unique_ptr<ClosestIndex> makeCgalIndex(CgalQuery mode) { return std::make_unique<CgalIndex>(mode); }
bool haveCgal() { return true; }

}  // namespace closestbench

#else

namespace closestbench {
std::unique_ptr<ClosestIndex> makeCgalIndex(CgalQuery) { return nullptr; }
bool haveCgal() { return false; }
}  // namespace closestbench

#endif
