// SPDX-License-Identifier: MIT
#include "bsdeform/contact/Barrier.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "bsdeform/contact/Distance.h"

namespace bsdeform {

double barrier(double s, double sHat) {
  if (s <= 0.0) return std::numeric_limits<double>::infinity();
  if (s >= sHat) return 0.0;
  const double gap = s - sHat;
  return -gap * gap * std::log(s / sHat);
}

double barrierFirstDerivative(double s, double sHat) {
  if (s <= 0.0 || s >= sHat) return 0.0;
  // d/ds [-(s - ŝ)² ln(s/ŝ)] = -2 (s - ŝ) ln(s/ŝ) - (s - ŝ)²/s = (ŝ - s)(2 ln(s/ŝ) - ŝ/s + 1)
  return (sHat - s) * (2.0 * std::log(s / sHat) - sHat / s + 1.0);
}

double barrierSecondDerivative(double s, double sHat) {
  if (s <= 0.0 || s >= sHat) return 0.0;
  const double r = sHat / s;
  return (r + 2.0) * r - 2.0 * std::log(s / sHat) - 3.0;
}

double barrierSquaredActivation(const BarrierParameters& bp) {
  const double reach = bp.offset + bp.dhat;
  return reach * reach - bp.offset * bp.offset;
}

double edgeEdgeMollifierThreshold(const Eigen::Vector3d& a0Rest, const Eigen::Vector3d& a1Rest,
                                  const Eigen::Vector3d& b0Rest, const Eigen::Vector3d& b1Rest) {
  // IPC §4.3: x / (|ea|² |eb|²) = sin² of the edges' angle; below 1e-3 of that the mollifier acts.
  constexpr double kParallelSinSquared = 1e-3;
  return kParallelSinSquared * (a1Rest - a0Rest).squaredNorm() * (b1Rest - b0Rest).squaredNorm();
}

double edgeEdgeMollifier(double x, double threshold) {
  if (x >= threshold) return 1.0;
  const double r = x / threshold;
  return (2.0 - r) * r;
}

double edgeEdgeMollifier(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& b0,
                         const Eigen::Vector3d& b1, double threshold, Vector12d* grad, Matrix12d* hess) {
  assert(threshold > 0.0 && "edgeEdgeMollifier: the threshold comes from non-degenerate rest edges");
  if (grad) grad->setZero();
  if (hess) hess->setZero();
  const double x = (a1 - a0).cross(b1 - b0).squaredNorm();
  if (x >= threshold) return 1.0;
  const double m = edgeEdgeMollifier(x, threshold);
  if (!grad && !hess) return m;
  Vector12d gx;
  Matrix12d hx;
  edgeEdgeCrossSquaredNormDerivatives(a0, a1, b0, b1, gx, hess ? &hx : nullptr);
  const double inv = 1.0 / threshold;
  const double m1 = 2.0 * inv * (1.0 - x * inv);  // dm/dx
  const double m2 = -2.0 * inv * inv;             // d²m/dx²
  if (grad) *grad = m1 * gx;
  if (hess) *hess = m2 * gx * gx.transpose() + m1 * hx;
  return m;
}

void projectToPsd(Matrix12d& h) {
  if (h.isZero(0.0)) return;  // a pair out of reach: nothing to decompose
  const Eigen::SelfAdjointEigenSolver<Matrix12d> eigen(h);
  if (eigen.eigenvalues().minCoeff() >= 0.0) return;
  const Eigen::Matrix<double, 12, 1> clamped = eigen.eigenvalues().cwiseMax(0.0);
  h = eigen.eigenvectors() * clamped.asDiagonal() * eigen.eigenvectors().transpose();
}

namespace {
template <int N>
void projectFixed(Matrix12d& h, int first) {
  Eigen::Matrix<double, N, N> b = h.block<N, N>(first, first);
  if (!b.isZero(0.0)) {  // else a pair out of reach: nothing to decompose
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> eigen(b);
    if (eigen.eigenvalues().minCoeff() < 0.0)
      b = eigen.eigenvectors() * eigen.eigenvalues().cwiseMax(0.0).asDiagonal() * eigen.eigenvectors().transpose();
  }
  h.setZero();
  h.block<N, N>(first, first) = b;
}
}  // namespace

void projectBlockToPsd(Matrix12d& h, int first, int n) {
  switch (n) {
    case 3: projectFixed<3>(h, first); break;
    case 6: projectFixed<6>(h, first); break;
    case 9: projectFixed<9>(h, first); break;
    default: projectToPsd(h);
  }
}

namespace {

/// The pair's s = d² - ξ² and ŝ; zeroes the outputs (they stay zero outside 0 < s < ŝ).
struct PairState {
  double s = 0.0;
  double sHat = 0.0;
};

PairState startPair(double distanceSquared, const BarrierParameters& bp, Vector12d* grad, Matrix12d* hess) {
  if (grad) grad->setZero();
  if (hess) hess->setZero();
  return {distanceSquared - bp.offset * bp.offset, barrierSquaredActivation(bp)};
}

}  // namespace

double pointTriangleBarrier(const Eigen::Vector3d& p, const Eigen::Vector3d& t0, const Eigen::Vector3d& t1,
                            const Eigen::Vector3d& t2, const BarrierParameters& bp, Vector12d* grad,
                            Matrix12d* hessPsd, BarrierHessian hessian, double* distanceSquared) {
  const PointTriangleType type = pointTriangleType(p, t0, t1, t2);
  const double d2 = pointTriangleDistanceSquared(p, t0, t1, t2, type);
  if (distanceSquared) *distanceSquared = d2;
  const PairState pair = startPair(d2, bp, grad, hessPsd);
  if (pair.s >= pair.sHat) return 0.0;
  if (pair.s <= 0.0) return std::numeric_limits<double>::infinity();
  const double value = bp.stiffness * barrier(pair.s, pair.sHat);
  if (!grad && !hessPsd) return value;
  Vector12d gd;
  Matrix12d hd;
  // the load asks for no Hessian: none of the distance's is formed
  pointTriangleDistanceSquaredDerivatives(p, t0, t1, t2, type, gd, hessPsd ? &hd : nullptr);
  // ds = d(d²): the offset is a constant
  const double b1 = bp.stiffness * barrierFirstDerivative(pair.s, pair.sHat);
  if (grad) *grad = b1 * gd;
  if (hessPsd) {
    *hessPsd = bp.stiffness * barrierSecondDerivative(pair.s, pair.sHat) * gd * gd.transpose() + b1 * hd;
    if (hessian == BarrierHessian::ProjectedPsd) projectToPsd(*hessPsd);
  }
  return value;
}

double pointStaticTriangleBarrier(const Eigen::Vector3d& p, const Eigen::Vector3d& t0, const Eigen::Vector3d& t1,
                                  const Eigen::Vector3d& t2, const BarrierParameters& bp, Eigen::Vector3d* grad,
                                  Eigen::Matrix3d* hess, BarrierHessian hessian, double* distanceSquared) {
  const PointTriangleType type = pointTriangleType(p, t0, t1, t2);
  const double d2 = pointTriangleDistanceSquared(p, t0, t1, t2, type);
  if (distanceSquared) *distanceSquared = d2;
  if (grad) grad->setZero();
  if (hess) hess->setZero();
  const double s = d2 - bp.offset * bp.offset, sHat = barrierSquaredActivation(bp);
  if (s >= sHat) return 0.0;
  if (s <= 0.0) return std::numeric_limits<double>::infinity();
  const double value = bp.stiffness * barrier(s, sHat);
  if (!grad && !hess) return value;
  // g = ∇_p d², and the unit vector e that ∇²d² leaves out (an edge's direction), by class
  Eigen::Vector3d g = Eigen::Vector3d::Zero(), e = Eigen::Vector3d::Zero();  // g: set by every class
  enum { Face, Edge, Vertex } kind = Vertex;
  auto edge = [&](const Eigen::Vector3d& e0, const Eigen::Vector3d& e1) {
    e = (e1 - e0).normalized();
    const Eigen::Vector3d q = p - e0;
    g = 2.0 * (q - q.dot(e) * e);
    kind = Edge;
  };
  switch (type) {
    case PointTriangleType::P_T0: g = 2.0 * (p - t0); break;
    case PointTriangleType::P_T1: g = 2.0 * (p - t1); break;
    case PointTriangleType::P_T2: g = 2.0 * (p - t2); break;
    case PointTriangleType::P_E0: edge(t0, t1); break;
    case PointTriangleType::P_E1: edge(t1, t2); break;
    case PointTriangleType::P_E2: edge(t2, t0); break;
    case PointTriangleType::P_T: {
      const Eigen::Vector3d n = (t1 - t0).cross(t2 - t0);
      g = (2.0 * n.dot(p - t0) / n.squaredNorm()) * n;
      kind = Face;
      break;
    }
  }
  const double b1 = bp.stiffness * barrierFirstDerivative(s, sHat);
  if (grad) *grad = b1 * g;
  if (!hess) return value;
  const double b2 = bp.stiffness * barrierSecondDerivative(s, sHat);
  const double g2 = g.squaredNorm();
  const Eigen::Vector3d u = g / std::sqrt(g2);  // d > ξ ≥ 0: g is not zero
  const Eigen::Matrix3d along = u * u.transpose();
  // across: the directions ∇²d² keeps besides g (none for a face)
  Eigen::Matrix3d across = Eigen::Matrix3d::Zero();
  if (kind == Vertex) across = Eigen::Matrix3d::Identity() - along;
  if (kind == Edge) across = Eigen::Matrix3d::Identity() - e * e.transpose() - along;
  double lambdaAlong = b2 * g2 + 2.0 * b1, lambdaAcross = 2.0 * b1;
  if (hessian == BarrierHessian::ProjectedPsd) {
    lambdaAlong = std::max(lambdaAlong, 0.0);
    lambdaAcross = std::max(lambdaAcross, 0.0);
  }
  *hess = lambdaAlong * along + lambdaAcross * across;
  return value;
}

double edgeEdgeBarrier(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& b0,
                       const Eigen::Vector3d& b1, double mollifierThreshold, const BarrierParameters& bp,
                       Vector12d* grad, Matrix12d* hessPsd, BarrierHessian hessian, double* distanceSquared) {
  const EdgeEdgeType type = edgeEdgeType(a0, a1, b0, b1);
  const double d2 = edgeEdgeDistanceSquared(a0, a1, b0, b1, type);
  if (distanceSquared) *distanceSquared = d2;
  const PairState pair = startPair(d2, bp, grad, hessPsd);
  if (pair.s >= pair.sHat) return 0.0;
  if (pair.s <= 0.0) return std::numeric_limits<double>::infinity();
  const bool wantsDerivatives = grad || hessPsd;
  Vector12d gm;
  Matrix12d hm;
  const double m = edgeEdgeMollifier(a0, a1, b0, b1, mollifierThreshold, wantsDerivatives ? &gm : nullptr,
                                     hessPsd ? &hm : nullptr);
  const double b = barrier(pair.s, pair.sHat);
  const double value = bp.stiffness * m * b;
  if (!wantsDerivatives) return value;
  Vector12d gd;
  Matrix12d hd;
  edgeEdgeDistanceSquaredDerivatives(a0, a1, b0, b1, type, gd, hessPsd ? &hd : nullptr);
  const double b1s = barrierFirstDerivative(pair.s, pair.sHat);
  // ∇(m b) = m b' ∇d² + b ∇m
  if (grad) *grad = bp.stiffness * (m * b1s * gd + b * gm);
  if (hessPsd) {
    // ∇²(m b) = m (b'' ∇d² ∇d²ᵀ + b' ∇²d²) + b' (∇m ∇d²ᵀ + ∇d² ∇mᵀ) + b ∇²m
    const double b2s = barrierSecondDerivative(pair.s, pair.sHat);
    *hessPsd = bp.stiffness * (m * (b2s * gd * gd.transpose() + b1s * hd) +
                               b1s * (gm * gd.transpose() + gd * gm.transpose()) + b * hm);
    if (hessian == BarrierHessian::ProjectedPsd) projectToPsd(*hessPsd);
  }
  return value;
}

double initialBarrierStiffness(double bboxDiagonal, double dhat, double averageMass,
                               const Eigen::Ref<const Eigen::VectorXd>& gradEnergy,
                               const Eigen::Ref<const Eigen::VectorXd>& gradBarrier, double& maxStiffness,
                               double minStiffnessScale, double offset) {
  assert(bboxDiagonal > 0.0 && dhat > 0.0 && averageMass > 0.0 && minStiffnessScale > 0.0 && offset >= 0.0);
  assert(gradEnergy.size() == gradBarrier.size());
  // IPC's constants: the reference gap is 1e-8 of the scene's size, and κ may grow 100-fold from
  // κ_min before updateBarrierStiffness stops doubling it.
  constexpr double kReferenceGapFraction = 1e-8;
  constexpr double kStiffnessRange = 100.0;
  const double offsetSquared = offset * offset;
  const double sHat = barrierSquaredActivation({offset, dhat, 1.0});
  const double d0 = offset + kReferenceGapFraction * bboxDiagonal;
  double s0 = d0 * d0 - offsetSquared;
  // A d̂ below that gap (a tiny d̂ in a huge scene): take the middle of the barrier's range instead.
  if (s0 >= sHat) s0 = 0.5 * sHat;
  const double minStiffness =
      minStiffnessScale * averageMass / (4.0 * (s0 + offsetSquared) * barrierSecondDerivative(s0, sHat));
  maxStiffness = kStiffnessRange * minStiffness;
  double kappa = 0.0;
  const double gb2 = gradBarrier.squaredNorm();
  // The κ that makes ∇E + κ∇B smallest; negative (barrier and energy pulling the same way) clamps.
  if (gb2 > 0.0) kappa = -gradBarrier.dot(gradEnergy) / gb2;
  return std::clamp(kappa, minStiffness, maxStiffness);
}

bool updateBarrierStiffness(double previousMinDistance, double minDistance, double maxStiffness, double& stiffness,
                            double bboxDiagonal, double dhatEpsilonScale) {
  const double epsilon = dhatEpsilonScale * bboxDiagonal;
  if (!(previousMinDistance < epsilon && minDistance < epsilon && minDistance < previousMinDistance)) return false;
  const double doubled = std::min(maxStiffness, 2.0 * stiffness);
  const bool changed = doubled != stiffness;
  stiffness = doubled;
  return changed;
}

}  // namespace bsdeform
