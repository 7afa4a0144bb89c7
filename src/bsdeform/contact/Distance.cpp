// SPDX-License-Identifier: MIT
#include "bsdeform/contact/Distance.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>

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

bool pointTriangleFartherThan(const Eigen::Vector3d& p, const Eigen::Vector3d& t0, const Eigen::Vector3d& t1,
                              const Eigen::Vector3d& t2, double r) {
  const Eigen::Vector3d e1 = t1 - t0, e2 = t2 - t0, n = e1.cross(e2);
  const double h = (p - t0).dot(n), n2 = n.squaredNorm();
  // the plane's distance |h| / |n|, where the triangle is not a sliver (sin² of its angle at t0
  // above 10⁻⁶: the rounded normal's error grows as 1 / sin, here at most about 10⁻¹³ of |p - t0|)
  if (n2 > 1e-6 * e1.squaredNorm() * e2.squaredNorm() && h * h > r * r * n2) return true;
  const Eigen::Vector3d m = (t0 + t1 + t2) / 3.0;
  const double radius2 = std::max({(t0 - m).squaredNorm(), (t1 - m).squaredNorm(), (t2 - m).squaredNorm()});
  const double reach = r + std::sqrt(radius2);
  return (p - m).squaredNorm() > reach * reach;
}

bool edgeEdgeFartherThan(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& b0,
                         const Eigen::Vector3d& b1, double r) {
  const Eigen::Vector3d da = a1 - a0, db = b1 - b0, n = da.cross(db);
  const double la2 = da.squaredNorm(), lb2 = db.squaredNorm(), n2 = n.squaredNorm(), h = (b0 - a0).dot(n);
  // the lines' distance |h| / |n|, where the edges are not near parallel (sin² > 10⁻⁶, as above)
  if (n2 > 1e-6 * la2 * lb2 && h * h > r * r * n2) return true;
  const double reach = r + 0.5 * (std::sqrt(la2) + std::sqrt(lb2));
  return (0.5 * ((a0 + a1) - (b0 + b1))).squaredNorm() > reach * reach;
}

// ---------------------------------------------------------------------------------------------
// Derivatives. Every formula is built from three kinds of scalar of the stencil's N points, each
// a polynomial in vectors U, V, W that are fixed combinations Σ c_i x_i of the points (edge
// vectors, c_i ∈ {-1, 0, 1}): a squared norm |U|², a squared cross product |U x V|² and a triple
// product (U x V)·W. Their gradients and Hessians are closed forms in 3x3 blocks; a quotient rule
// then gives Q / N. Written out by hand rather than with a dual-number type because the blocks
// are few and the Hessian of a bilinear form is constant, so the forward mode's 12x12 products
// per operation would be mostly spent on zeros.

namespace {

template <int N>
using Coefficients = std::array<double, N>;
template <int N>
using Gradient = Eigen::Matrix<double, 3 * N, 1>;
template <int N>
using Hessian = Eigen::Matrix<double, 3 * N, 3 * N>;

/// A scalar of the stencil with its gradient and, when `withHessian`, its Hessian in the 3N
/// coordinates (a gradient alone skips every Hessian product: the gradient's are the same
/// operations either way, so the same bits).
template <int N>
struct Jet {
  double value = 0.0;
  Gradient<N> grad;
  Hessian<N> hess;
};

/// [a]x, the matrix of v -> a x v.
Eigen::Matrix3d crossMatrix(const Eigen::Vector3d& a) {
  Eigen::Matrix3d m;
  m << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return m;
}

/// |E|² for E = Σ α_i x_i.
template <int N>
Jet<N> squaredNormJet(const Coefficients<N>& alpha, const Eigen::Vector3d& e, bool withHessian) {
  Jet<N> j;
  j.value = e.squaredNorm();
  for (int i = 0; i < N; ++i) {
    j.grad.template segment<3>(3 * i) = 2.0 * alpha[i] * e;
    for (int k = 0; k < N && withHessian; ++k)
      j.hess.template block<3, 3>(3 * i, 3 * k) = 2.0 * alpha[i] * alpha[k] * Eigen::Matrix3d::Identity();
  }
  return j;
}

/// |U x V|² for U = Σ α_i x_i, V = Σ β_i x_i. With c = U x V and its Jacobian J (block i:
/// -α_i [V]x + β_i [U]x), the gradient is 2 Jᵀc and the Hessian 2 JᵀJ + 2 Σ_k c_k ∇²c_k, where
/// the last sum is the (constant) Hessian of the bilinear form c·(U x V) with c held fixed.
template <int N>
Jet<N> crossSquaredNormJet(const Coefficients<N>& alpha, const Coefficients<N>& beta, const Eigen::Vector3d& u,
                           const Eigen::Vector3d& v, bool withHessian) {
  const Eigen::Vector3d c = u.cross(v);
  const Eigen::Matrix3d cu = crossMatrix(u), cv = crossMatrix(v), cc = crossMatrix(c);
  Eigen::Matrix<double, 3, 3 * N> jac;
  for (int i = 0; i < N; ++i) jac.template block<3, 3>(0, 3 * i) = beta[i] * cu - alpha[i] * cv;
  Jet<N> j;
  j.value = c.squaredNorm();
  j.grad = 2.0 * jac.transpose() * c;
  if (!withHessian) return j;
  j.hess = 2.0 * jac.transpose() * jac;
  for (int i = 0; i < N; ++i)
    for (int k = 0; k < N; ++k)
      j.hess.template block<3, 3>(3 * i, 3 * k) += 2.0 * (beta[i] * alpha[k] - alpha[i] * beta[k]) * cc;
  return j;
}

/// (U x V)·W for U, V, W combinations of the points with coefficients α, β, γ. Trilinear: the
/// mixed second derivatives are ∂²/∂U∂V = -[W]x, ∂²/∂V∂W = -[U]x, ∂²/∂W∂U = -[V]x.
template <int N>
Jet<N> tripleProductJet(const Coefficients<N>& alpha, const Coefficients<N>& beta, const Coefficients<N>& gamma,
                        const Eigen::Vector3d& u, const Eigen::Vector3d& v, const Eigen::Vector3d& w,
                        bool withHessian) {
  const Eigen::Vector3d vw = v.cross(w), wu = w.cross(u), uv = u.cross(v);
  const Eigen::Matrix3d cu = crossMatrix(u), cv = crossMatrix(v), cw = crossMatrix(w);
  Jet<N> j;
  j.value = uv.dot(w);
  for (int i = 0; i < N; ++i) {
    j.grad.template segment<3>(3 * i) = alpha[i] * vw + beta[i] * wu + gamma[i] * uv;
    for (int k = 0; k < N && withHessian; ++k)
      j.hess.template block<3, 3>(3 * i, 3 * k) = (beta[i] * alpha[k] - alpha[i] * beta[k]) * cw +
                                                  (gamma[i] * beta[k] - beta[i] * gamma[k]) * cu +
                                                  (alpha[i] * gamma[k] - gamma[i] * alpha[k]) * cv;
  }
  return j;
}

/// h² from h.
template <int N>
Jet<N> squareJet(const Jet<N>& h, bool withHessian) {
  Jet<N> j;
  j.value = h.value * h.value;
  j.grad = 2.0 * h.value * h.grad;
  if (withHessian) j.hess = 2.0 * (h.grad * h.grad.transpose() + h.value * h.hess);
  return j;
}

/// Q / D (D > 0) and its derivatives; writes the gradient and the Hessian (unless null),
/// returns the value.
template <int N>
double quotient(const Jet<N>& q, const Jet<N>& d, Gradient<N>& grad, Hessian<N>* hess) {
  const double inv = 1.0 / d.value, value = q.value * inv;
  grad = inv * (q.grad - value * d.grad);
  // ∇²(Q/D) = (∇²Q - value ∇²D - ∇D ∇(Q/D)ᵀ - ∇(Q/D) ∇Dᵀ) / D
  if (hess) *hess = inv * (q.hess - value * d.hess - d.grad * grad.transpose() - grad * d.grad.transpose());
  return value;
}

/// Places the derivatives of a formula of M of the four points into the 12 coordinates: formula
/// point m is stencil point index[m]; the other rows and columns are zero.
template <int M>
void scatter(const Gradient<M>& g, const Hessian<M>& h, const std::array<int, M>& index,
             Eigen::Matrix<double, 12, 1>& grad, Eigen::Matrix<double, 12, 12>* hess) {
  grad.setZero();
  if (hess) hess->setZero();
  for (int m = 0; m < M; ++m) {
    grad.segment<3>(3 * index[m]) = g.template segment<3>(3 * m);
    for (int n = 0; n < M && hess; ++n)
      hess->block<3, 3>(3 * index[m], 3 * index[n]) = h.template block<3, 3>(3 * m, 3 * n);
  }
}

}  // namespace

double pointPointDistanceSquaredDerivatives(const Eigen::Vector3d& p, const Eigen::Vector3d& q,
                                            Eigen::Matrix<double, 6, 1>& grad, Eigen::Matrix<double, 6, 6>* hess) {
  const Eigen::Vector3d r = p - q;
  grad << 2.0 * r, -2.0 * r;
  if (hess) {
    const Eigen::Matrix3d twoI = 2.0 * Eigen::Matrix3d::Identity();
    *hess << twoI, -twoI, -twoI, twoI;
  }
  return r.squaredNorm();
}

double pointLineDistanceSquaredDerivatives(const Eigen::Vector3d& p, const Eigen::Vector3d& e0,
                                           const Eigen::Vector3d& e1, Eigen::Matrix<double, 9, 1>& grad,
                                           Eigen::Matrix<double, 9, 9>* hess) {
  // |(e0 - p) x (e1 - p)|² / |e1 - e0|², points (p, e0, e1)
  const bool h = hess != nullptr;
  const Jet<3> q = crossSquaredNormJet<3>({-1.0, 1.0, 0.0}, {-1.0, 0.0, 1.0}, e0 - p, e1 - p, h);
  const Jet<3> d = squaredNormJet<3>({0.0, -1.0, 1.0}, e1 - e0, h);
  return quotient(q, d, grad, hess);
}

double pointPlaneDistanceSquaredDerivatives(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                                            const Eigen::Vector3d& t1, const Eigen::Vector3d& t2,
                                            Eigen::Matrix<double, 12, 1>& grad, Eigen::Matrix<double, 12, 12>* hess) {
  // ((t1 - t0) x (t2 - t0))·(p - t0) squared over |(t1 - t0) x (t2 - t0)|², points (p, t0, t1, t2)
  const bool wh = hess != nullptr;
  const Coefficients<4> u{0.0, -1.0, 1.0, 0.0}, v{0.0, -1.0, 0.0, 1.0}, w{1.0, -1.0, 0.0, 0.0};
  const Jet<4> h = tripleProductJet<4>(u, v, w, t1 - t0, t2 - t0, p - t0, wh);
  const Jet<4> n = crossSquaredNormJet<4>(u, v, t1 - t0, t2 - t0, wh);
  return quotient(squareJet(h, wh), n, grad, hess);
}

double lineLineDistanceSquaredDerivatives(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1,
                                          const Eigen::Vector3d& b0, const Eigen::Vector3d& b1,
                                          Eigen::Matrix<double, 12, 1>& grad, Eigen::Matrix<double, 12, 12>* hess) {
  // ((a1 - a0) x (b1 - b0))·(b0 - a0) squared over |(a1 - a0) x (b1 - b0)|², points (a0, a1, b0, b1)
  const bool wh = hess != nullptr;
  const Coefficients<4> u{-1.0, 1.0, 0.0, 0.0}, v{0.0, 0.0, -1.0, 1.0}, w{-1.0, 0.0, 1.0, 0.0};
  const Jet<4> h = tripleProductJet<4>(u, v, w, a1 - a0, b1 - b0, b0 - a0, wh);
  const Jet<4> n = crossSquaredNormJet<4>(u, v, a1 - a0, b1 - b0, wh);
  return quotient(squareJet(h, wh), n, grad, hess);
}

double edgeEdgeCrossSquaredNormDerivatives(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1,
                                           const Eigen::Vector3d& b0, const Eigen::Vector3d& b1,
                                           Eigen::Matrix<double, 12, 1>& grad, Eigen::Matrix<double, 12, 12>* hess) {
  const Jet<4> x =
      crossSquaredNormJet<4>({-1.0, 1.0, 0.0, 0.0}, {0.0, 0.0, -1.0, 1.0}, a1 - a0, b1 - b0, hess != nullptr);
  grad = x.grad;
  if (hess) *hess = x.hess;
  return x.value;
}

double pointTriangleDistanceSquaredDerivatives(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                                               const Eigen::Vector3d& t1, const Eigen::Vector3d& t2,
                                               PointTriangleType type, Eigen::Matrix<double, 12, 1>& grad,
                                               Eigen::Matrix<double, 12, 12>* hess) {
  // Stencil indices: p = 0, t0 = 1, t1 = 2, t2 = 3.
  const std::array<const Eigen::Vector3d*, 4> x{&p, &t0, &t1, &t2};
  switch (type) {
    case PointTriangleType::P_T0:
    case PointTriangleType::P_T1:
    case PointTriangleType::P_T2: {
      const int v = 1 + (static_cast<int>(type) - static_cast<int>(PointTriangleType::P_T0));
      Gradient<2> g;
      Hessian<2> h;
      const double d = pointPointDistanceSquaredDerivatives(p, *x[v], g, hess ? &h : nullptr);
      scatter<2>(g, h, {0, v}, grad, hess);
      return d;
    }
    case PointTriangleType::P_E0:
    case PointTriangleType::P_E1:
    case PointTriangleType::P_E2: {
      // E0 = t0 t1, E1 = t1 t2, E2 = t2 t0
      const int e = static_cast<int>(type) - static_cast<int>(PointTriangleType::P_E0);
      const int i0 = 1 + e, i1 = 1 + (e + 1) % 3;
      Gradient<3> g;
      Hessian<3> h;
      const double d = pointLineDistanceSquaredDerivatives(p, *x[i0], *x[i1], g, hess ? &h : nullptr);
      scatter<3>(g, h, {0, i0, i1}, grad, hess);
      return d;
    }
    case PointTriangleType::P_T: break;
  }
  return pointPlaneDistanceSquaredDerivatives(p, t0, t1, t2, grad, hess);
}

double edgeEdgeDistanceSquaredDerivatives(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1,
                                          const Eigen::Vector3d& b0, const Eigen::Vector3d& b1, EdgeEdgeType type,
                                          Eigen::Matrix<double, 12, 1>& grad, Eigen::Matrix<double, 12, 12>* hess) {
  // Stencil indices: a0 = 0, a1 = 1, b0 = 2, b1 = 3.
  const std::array<const Eigen::Vector3d*, 4> x{&a0, &a1, &b0, &b1};
  int pp[2] = {-1, -1};  // point–point: the two points
  int pl[3] = {-1, -1, -1};  // point–line: the point, then the line's two points
  switch (type) {
    case EdgeEdgeType::EA0_EB0: pp[0] = 0, pp[1] = 2; break;
    case EdgeEdgeType::EA0_EB1: pp[0] = 0, pp[1] = 3; break;
    case EdgeEdgeType::EA1_EB0: pp[0] = 1, pp[1] = 2; break;
    case EdgeEdgeType::EA1_EB1: pp[0] = 1, pp[1] = 3; break;
    case EdgeEdgeType::EA_EB0: pl[0] = 2, pl[1] = 0, pl[2] = 1; break;
    case EdgeEdgeType::EA_EB1: pl[0] = 3, pl[1] = 0, pl[2] = 1; break;
    case EdgeEdgeType::EA0_EB: pl[0] = 0, pl[1] = 2, pl[2] = 3; break;
    case EdgeEdgeType::EA1_EB: pl[0] = 1, pl[1] = 2, pl[2] = 3; break;
    case EdgeEdgeType::EA_EB: return lineLineDistanceSquaredDerivatives(a0, a1, b0, b1, grad, hess);
  }
  if (pp[0] >= 0) {
    Gradient<2> g;
    Hessian<2> h;
    const double d = pointPointDistanceSquaredDerivatives(*x[pp[0]], *x[pp[1]], g, hess ? &h : nullptr);
    scatter<2>(g, h, {pp[0], pp[1]}, grad, hess);
    return d;
  }
  Gradient<3> g;
  Hessian<3> h;
  const double d = pointLineDistanceSquaredDerivatives(*x[pl[0]], *x[pl[1]], *x[pl[2]], g, hess ? &h : nullptr);
  scatter<3>(g, h, {pl[0], pl[1], pl[2]}, grad, hess);
  return d;
}

}  // namespace bsdeform
