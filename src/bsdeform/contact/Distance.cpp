// SPDX-License-Identifier: MIT
#include "bsdeform/contact/Distance.h"

#include <Eigen/Geometry>
#include <algorithm>

#include "bsdeform/contact/ClosestPointOnTriangle.h"

namespace bsdeform {

PointTriangleType pointTriangleType(const Eigen::Vector3d& p, const Eigen::Vector3d& t0, const Eigen::Vector3d& t1,
                                    const Eigen::Vector3d& t2) {
  switch (closestPointOnTriangle(p, t0, t1, t2).feature) {
    case TriangleFeature::VertexA: return PointTriangleType::P_T0;
    case TriangleFeature::VertexB: return PointTriangleType::P_T1;
    case TriangleFeature::VertexC: return PointTriangleType::P_T2;
    case TriangleFeature::EdgeAB: return PointTriangleType::P_E0;
    case TriangleFeature::EdgeBC: return PointTriangleType::P_E1;
    case TriangleFeature::EdgeCA: return PointTriangleType::P_E2;
    case TriangleFeature::Face: break;
  }
  return PointTriangleType::P_T;
}

EdgeEdgeType edgeEdgeType(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& b0,
                          const Eigen::Vector3d& b1) {
  // The closest points a0 + s (a1 - a0), b0 + t (b1 - b0) of the segments (Ericson, Real-Time
  // Collision Detection, 2005, §5.1.9), then the class from which parameters were clamped.
  const Eigen::Vector3d da = a1 - a0, db = b1 - b0, r = a0 - b0;
  const double a = da.squaredNorm(), e = db.squaredNorm(), f = db.dot(r), c = da.dot(r), b = da.dot(db);
  // |da x db|² = a e - b² (Lagrange), from the cross product: the difference cancels to rounding
  // for near-parallel segments where the cross product stays accurate.
  const double denom = da.cross(db).squaredNorm();
  double s = 0.0;
  if (denom > 1e-20 * a * e) s = std::clamp((b * f - c * e) / denom, 0.0, 1.0);
  double t = (b * s + f) / e;
  if (t <= 0.0) {
    t = 0.0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (t >= 1.0) {
    t = 1.0;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
  const int sClass = s <= 0.0 ? 0 : (s >= 1.0 ? 1 : 2);
  const int tClass = t <= 0.0 ? 0 : (t >= 1.0 ? 1 : 2);
  // A parallel pair never takes the line–line class (its formula divides by |da x db|²).
  if (sClass == 2 && tClass == 2 && denom <= 1e-20 * a * e) return EdgeEdgeType::EA0_EB;
  static constexpr EdgeEdgeType kTable[3][3] = {
      {EdgeEdgeType::EA0_EB0, EdgeEdgeType::EA0_EB1, EdgeEdgeType::EA0_EB},
      {EdgeEdgeType::EA1_EB0, EdgeEdgeType::EA1_EB1, EdgeEdgeType::EA1_EB},
      {EdgeEdgeType::EA_EB0, EdgeEdgeType::EA_EB1, EdgeEdgeType::EA_EB}};
  return kTable[sClass][tClass];
}

double pointPointDistanceSquared(const Eigen::Vector3d& p, const Eigen::Vector3d& q) { return (p - q).squaredNorm(); }

double pointLineDistanceSquared(const Eigen::Vector3d& p, const Eigen::Vector3d& e0, const Eigen::Vector3d& e1) {
  const Eigen::Vector3d d = e1 - e0;
  return (e0 - p).cross(e1 - p).squaredNorm() / d.squaredNorm();
}

double pointPlaneDistanceSquared(const Eigen::Vector3d& p, const Eigen::Vector3d& t0, const Eigen::Vector3d& t1,
                                 const Eigen::Vector3d& t2) {
  const Eigen::Vector3d n = (t1 - t0).cross(t2 - t0);
  const double h = n.dot(p - t0);
  return h * h / n.squaredNorm();
}

double lineLineDistanceSquared(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& b0,
                               const Eigen::Vector3d& b1) {
  const Eigen::Vector3d n = (a1 - a0).cross(b1 - b0);
  const double h = n.dot(b0 - a0);
  return h * h / n.squaredNorm();
}

double pointTriangleDistanceSquared(const Eigen::Vector3d& p, const Eigen::Vector3d& t0, const Eigen::Vector3d& t1,
                                    const Eigen::Vector3d& t2, PointTriangleType type) {
  switch (type) {
    case PointTriangleType::P_T0: return pointPointDistanceSquared(p, t0);
    case PointTriangleType::P_T1: return pointPointDistanceSquared(p, t1);
    case PointTriangleType::P_T2: return pointPointDistanceSquared(p, t2);
    case PointTriangleType::P_E0: return pointLineDistanceSquared(p, t0, t1);
    case PointTriangleType::P_E1: return pointLineDistanceSquared(p, t1, t2);
    case PointTriangleType::P_E2: return pointLineDistanceSquared(p, t2, t0);
    case PointTriangleType::P_T: break;
  }
  return pointPlaneDistanceSquared(p, t0, t1, t2);
}

double pointTriangleDistanceSquared(const Eigen::Vector3d& p, const Eigen::Vector3d& t0, const Eigen::Vector3d& t1,
                                    const Eigen::Vector3d& t2) {
  return pointTriangleDistanceSquared(p, t0, t1, t2, pointTriangleType(p, t0, t1, t2));
}

double edgeEdgeDistanceSquared(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& b0,
                               const Eigen::Vector3d& b1, EdgeEdgeType type) {
  switch (type) {
    case EdgeEdgeType::EA0_EB0: return pointPointDistanceSquared(a0, b0);
    case EdgeEdgeType::EA0_EB1: return pointPointDistanceSquared(a0, b1);
    case EdgeEdgeType::EA1_EB0: return pointPointDistanceSquared(a1, b0);
    case EdgeEdgeType::EA1_EB1: return pointPointDistanceSquared(a1, b1);
    case EdgeEdgeType::EA_EB0: return pointLineDistanceSquared(b0, a0, a1);
    case EdgeEdgeType::EA_EB1: return pointLineDistanceSquared(b1, a0, a1);
    case EdgeEdgeType::EA0_EB: return pointLineDistanceSquared(a0, b0, b1);
    case EdgeEdgeType::EA1_EB: return pointLineDistanceSquared(a1, b0, b1);
    case EdgeEdgeType::EA_EB: break;
  }
  return lineLineDistanceSquared(a0, a1, b0, b1);
}

double edgeEdgeDistanceSquared(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& b0,
                               const Eigen::Vector3d& b1) {
  return edgeEdgeDistanceSquared(a0, a1, b0, b1, edgeEdgeType(a0, a1, b0, b1));
}

}  // namespace bsdeform
