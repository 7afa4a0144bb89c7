// SPDX-License-Identifier: MIT
#include "bsdeform/contact/Friction.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "bsdeform/contact/Distance.h"

namespace bsdeform {

double smoothFrictionF0(double y, double epsilon) {
  if (y >= epsilon) return y;
  return y * y * (1.0 / epsilon - y / (3.0 * epsilon * epsilon)) + epsilon / 3.0;
}

double smoothFrictionF1(double y, double epsilon) {
  if (y >= epsilon) return 1.0;
  return y * (2.0 / epsilon - y / (epsilon * epsilon));
}

double smoothFrictionF1OverY(double y, double epsilon) {
  if (y >= epsilon) return 1.0 / y;
  return 2.0 / epsilon - y / (epsilon * epsilon);
}

double smoothFrictionHessianTerm(double y, double epsilon) {
  if (y >= epsilon) return -1.0 / (y * y * y);
  if (y <= 0.0) return 0.0;  // multiplies u uᵀ = 0
  return -1.0 / (epsilon * epsilon * y);
}

namespace {

/// An orthonormal basis of the plane normal to n (unit).
Eigen::Matrix<double, 3, 2> planeBasis(const Eigen::Vector3d& n) {
  Eigen::Index k = 0;
  n.cwiseAbs().minCoeff(&k);  // the axis least aligned with n
  const Eigen::Vector3d t1 = n.cross(Eigen::Vector3d::Unit(k)).normalized();
  Eigen::Matrix<double, 3, 2> T;
  T.col(0) = t1;
  T.col(1) = n.cross(t1);
  return T;
}

double clamp01(double x) { return std::clamp(x, 0.0, 1.0); }

/// The parameter of the point of the line e0 + a (e1 - e0) closest to p.
double lineParameter(const Eigen::Vector3d& p, const Eigen::Vector3d& e0, const Eigen::Vector3d& e1) {
  const Eigen::Vector3d e = e1 - e0;
  return clamp01((p - e0).dot(e) / e.squaredNorm());
}

/// The basis normal to the direction from the second closest point to the first, `fallback` (not
/// necessarily unit) when they coincide.
void setBasis(const Eigen::Vector3d& difference, const Eigen::Vector3d& fallback, FrictionPair& pair) {
  const double d = difference.norm();
  const Eigen::Vector3d n = d > 0.0 ? Eigen::Vector3d(difference / d) : Eigen::Vector3d(fallback.normalized());
  pair.basis = planeBasis(n);
}

}  // namespace

void pointTriangleFrame(const Eigen::Vector3d& p, const Eigen::Vector3d& t0, const Eigen::Vector3d& t1,
                        const Eigen::Vector3d& t2, FrictionPair& pair) {
  double b0 = 0.0, b1 = 0.0, b2 = 0.0;  // barycentric coordinates of the closest point
  switch (pointTriangleType(p, t0, t1, t2)) {
    case PointTriangleType::P_T0: b0 = 1.0; break;
    case PointTriangleType::P_T1: b1 = 1.0; break;
    case PointTriangleType::P_T2: b2 = 1.0; break;
    case PointTriangleType::P_E0: b1 = lineParameter(p, t0, t1), b0 = 1.0 - b1; break;
    case PointTriangleType::P_E1: b2 = lineParameter(p, t1, t2), b1 = 1.0 - b2; break;
    case PointTriangleType::P_E2: b0 = lineParameter(p, t2, t0), b2 = 1.0 - b0; break;
    case PointTriangleType::P_T: {
      const Eigen::Vector3d e1 = t1 - t0, e2 = t2 - t0, q = p - t0;
      Eigen::Matrix2d A;
      A << e1.dot(e1), e1.dot(e2), e1.dot(e2), e2.dot(e2);
      const Eigen::Vector2d st = A.inverse() * Eigen::Vector2d(e1.dot(q), e2.dot(q));
      b1 = st.x(), b2 = st.y(), b0 = 1.0 - b1 - b2;
      break;
    }
  }
  pair.coefficient = {1.0, -b0, -b1, -b2};
  pair.split = 1;
  setBasis(p - (b0 * t0 + b1 * t1 + b2 * t2), (t1 - t0).cross(t2 - t0), pair);
}

void edgeEdgeFrame(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& b0,
                   const Eigen::Vector3d& b1, FrictionPair& pair) {
  double alpha = 0.0, beta = 0.0;  // a0 + α (a1 - a0) and b0 + β (b1 - b0)
  switch (edgeEdgeType(a0, a1, b0, b1)) {
    case EdgeEdgeType::EA0_EB0: break;
    case EdgeEdgeType::EA0_EB1: beta = 1.0; break;
    case EdgeEdgeType::EA1_EB0: alpha = 1.0; break;
    case EdgeEdgeType::EA1_EB1: alpha = beta = 1.0; break;
    case EdgeEdgeType::EA_EB0: alpha = lineParameter(b0, a0, a1); break;
    case EdgeEdgeType::EA_EB1: alpha = lineParameter(b1, a0, a1), beta = 1.0; break;
    case EdgeEdgeType::EA0_EB: beta = lineParameter(a0, b0, b1); break;
    case EdgeEdgeType::EA1_EB: alpha = 1.0, beta = lineParameter(a1, b0, b1); break;
    case EdgeEdgeType::EA_EB: {
      const Eigen::Vector3d da = a1 - a0, db = b1 - b0, w = b0 - a0;
      Eigen::Matrix2d A;
      A << da.dot(da), -da.dot(db), -da.dot(db), db.dot(db);
      const Eigen::Vector2d ab = A.inverse() * Eigen::Vector2d(da.dot(w), -db.dot(w));
      alpha = clamp01(ab.x()), beta = clamp01(ab.y());
      break;
    }
  }
  pair.coefficient = {1.0 - alpha, alpha, -(1.0 - beta), -beta};
  pair.split = 2;
  setBasis((a0 + alpha * (a1 - a0)) - (b0 + beta * (b1 - b0)), (a1 - a0).cross(b1 - b0), pair);
}

double frictionPotential(const FrictionPair& pair, const Eigen::Vector3d& r, double mu, double epsilon,
                         Eigen::Vector3d* grad, Eigen::Matrix3d* hess) {
  const double scale = mu * pair.normalForce;
  const Eigen::Vector2d u = pair.basis.transpose() * r;
  const double y = u.norm();
  if (grad) *grad = scale * smoothFrictionF1OverY(y, epsilon) * (pair.basis * u);
  if (hess) {
    const Eigen::Matrix2d inner = smoothFrictionF1OverY(y, epsilon) * Eigen::Matrix2d::Identity() +
                                  smoothFrictionHessianTerm(y, epsilon) * (u * u.transpose());
    *hess = scale * pair.basis * inner * pair.basis.transpose();
  }
  return scale * smoothFrictionF0(y, epsilon);
}

}  // namespace bsdeform
