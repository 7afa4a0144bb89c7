// SPDX-License-Identifier: MIT
#include "bsdeform/energy/Shell.h"

#include "bsdeform/base/ParameterError.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "bsdeform/spline/GaussLegendre.h"
#include "bsdeform/base/Multiversion.h"
#include "bsdeform/base/NumberText.h"
#include "bsdeform/base/Parallel.h"

namespace bsdeform {
namespace {

// ---------------------------------------------------------------------------------------------
// Dual numbers a + b ε (ε² = 0): the kernel evaluated on them gives its directional derivative.
struct Dual {
  double a = 0.0, b = 0.0;
  Dual() = default;
  Dual(double x) : a(x) {}  // NOLINT: constants promote
  Dual(double x, double dx) : a(x), b(dx) {}
};
inline Dual operator+(Dual x, Dual y) { return {x.a + y.a, x.b + y.b}; }
inline Dual operator-(Dual x, Dual y) { return {x.a - y.a, x.b - y.b}; }
inline Dual operator-(Dual x) { return {-x.a, -x.b}; }
inline Dual operator*(Dual x, Dual y) { return {x.a * y.a, x.a * y.b + x.b * y.a}; }
inline Dual operator/(Dual x, Dual y) { return {x.a / y.a, (x.b * y.a - x.a * y.b) / (y.a * y.a)}; }
inline Dual& operator+=(Dual& x, Dual y) { return x = x + y; }
inline Dual sqrt(Dual x) {
  const double s = std::sqrt(x.a);
  return {s, x.b / (2.0 * s)};
}
inline double value(double x) { return x; }
inline double value(Dual x) { return x.a; }
using std::sqrt;

template <typename T>
inline T dot3(const T* x, const T* y) {
  return x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
}
template <typename T>
inline void cross3(const T* x, const T* y, T* out) {
  out[0] = x[1] * y[2] - x[2] * y[1];
  out[1] = x[2] * y[0] - x[0] * y[2];
  out[2] = x[0] * y[1] - x[1] * y[0];
}

/// Material constants of the kernel.
struct Constants {
  double membrane;  ///< t
  double bending;   ///< t³/12
  double lambda;    ///< λ̄ = Eν/(1−ν²)
  double twoMu;     ///< 2μ = E/(1+ν)
};

Constants constantsOf(const ShellMaterial& m) {
  const double t = m.thickness, E = m.youngsModulus, nu = m.poissonRatio;
  return {t, t * t * t / 12.0, E * nu / (1.0 - nu * nu), E / (1.0 + nu)};
}

/// S = λ̄ A^{αβ} tr(A⁻¹E) + 2μ (A⁻¹ E A⁻¹)^{αβ} for a symmetric E = (E11, E12, E22).
template <typename T>
inline void stress(const double* Ac, const Constants& k, const T* E, T* S) {
  const T tr = Ac[0] * E[0] + 2.0 * (Ac[1] * E[1]) + Ac[2] * E[2];
  const T P11 = Ac[0] * E[0] + Ac[1] * E[1], P12 = Ac[0] * E[1] + Ac[1] * E[2];
  const T P21 = Ac[1] * E[0] + Ac[2] * E[1], P22 = Ac[1] * E[1] + Ac[2] * E[2];
  const T X11 = P11 * Ac[0] + P12 * Ac[1], X12 = P11 * Ac[1] + P12 * Ac[2], X22 = P21 * Ac[1] + P22 * Ac[2];
  S[0] = k.lambda * Ac[0] * tr + k.twoMu * X11;
  S[1] = k.lambda * Ac[1] * tr + k.twoMu * X12;
  S[2] = k.lambda * Ac[2] * tr + k.twoMu * X22;
}

/// The kernel: energy density (membrane, bending, each times wJ) and its gradient g with
/// respect to y = (S_u, S_v, S_uu, S_uv, S_vv) at one Gauss point.
template <typename T>
inline void density(const T* y, const ShellEnergy::RestPoint& r, const Constants& k, bool bending, T* g, T& em,
                    T& eb) {
  const T* a1 = y;
  const T* a2 = y + 3;
  // E = (a - A)/2 from the displacement of the tangents d = a - A_vec: no cancellation when
  // the strain is small
  const T d1[3] = {a1[0] - r.T[0], a1[1] - r.T[1], a1[2] - r.T[2]};
  const T d2[3] = {a2[0] - r.T[3], a2[1] - r.T[4], a2[2] - r.T[5]};
  const T E[3] = {r.T[0] * d1[0] + r.T[1] * d1[1] + r.T[2] * d1[2] + 0.5 * dot3(d1, d1),
                  0.5 * ((r.T[0] * d2[0] + r.T[1] * d2[1] + r.T[2] * d2[2]) +
                         (r.T[3] * d1[0] + r.T[4] * d1[1] + r.T[5] * d1[2]) + dot3(d1, d2)),
                  r.T[3] * d2[0] + r.T[4] * d2[1] + r.T[5] * d2[2] + 0.5 * dot3(d2, d2)};
  T S[3];
  stress(r.Ac, k, E, S);
  const T n11 = (k.membrane * r.wJ) * S[0], n12 = (k.membrane * r.wJ) * S[1], n22 = (k.membrane * r.wJ) * S[2];
  em = 0.5 * (n11 * E[0] + 2.0 * (n12 * E[1]) + n22 * E[2]);
  for (int c = 0; c < 3; ++c) {
    g[c] = n11 * a1[c] + n12 * a2[c];
    g[3 + c] = n12 * a1[c] + n22 * a2[c];
    g[6 + c] = g[9 + c] = g[12 + c] = T(0.0);
  }
  eb = T(0.0);
  if (!bending) return;
  T a3[3];
  cross3(a1, a2, a3);
  const T j = sqrt(dot3(a3, a3));
  if (value(j) == 0.0) return;  // a collapsed current surface has no normal: no bending there
  const T nrm[3] = {a3[0] / j, a3[1] / j, a3[2] / j};
  const T* s11 = y + 6;
  const T* s12 = y + 9;
  const T* s22 = y + 12;
  const T kappa[3] = {r.B[0] - dot3(s11, nrm), r.B[1] - dot3(s12, nrm), r.B[2] - dot3(s22, nrm)};
  T M[3];
  stress(r.Ac, k, kappa, M);
  const T m11 = (k.bending * r.wJ) * M[0], m12 = (k.bending * r.wJ) * M[1], m22 = (k.bending * r.wJ) * M[2];
  eb = 0.5 * (m11 * kappa[0] + 2.0 * (m12 * kappa[1]) + m22 * kappa[2]);
  // dκ = −(dS_αβ·n + S_αβ·dn), dn = (I − n nᵀ) dã₃ / j, dã₃ = da₁ × a₂ + a₁ × da₂
  T v[3], w[3], t1[3], t2[3];
  for (int c = 0; c < 3; ++c) {
    g[6 + c] = -(m11 * nrm[c]);
    g[9 + c] = -(2.0 * (m12 * nrm[c]));
    g[12 + c] = -(m22 * nrm[c]);
    v[c] = m11 * s11[c] + 2.0 * (m12 * s12[c]) + m22 * s22[c];
  }
  const T vn = dot3(v, nrm);
  for (int c = 0; c < 3; ++c) w[c] = (v[c] - vn * nrm[c]) / j;
  cross3(a2, w, t1);
  cross3(w, a1, t2);
  for (int c = 0; c < 3; ++c) {
    g[c] = g[c] - t1[c];
    g[3 + c] = g[3 + c] - t2[c];
  }
}

constexpr int kMaxPoints = kMaxDegree + 1;
/// (u order, v order) of the five derivatives in y.
constexpr int kOrderU[5] = {1, 0, 2, 1, 0};
constexpr int kOrderV[5] = {0, 1, 0, 1, 2};

/// What one element pass needs: the tables and sizes.
struct Tables {
  int L1, L2, Q1, Q2, cols;
  const double* tu;  // [q][order][a], L1 wide
  const double* tv;
  double u(int q, int d, int a) const { return tu[(q * 3 + d) * L1 + a]; }
  double v(int q, int d, int b) const { return tv[(q * 3 + d) * L2 + b]; }
};

/// One element (e1, e2) with sum factorisation: gathers the net (loader(row, c) -> T), runs
/// the kernel at each Gauss point and adds the gradient to out(row, c, value) when `grad`.
/// Returns the element's energies.
template <typename T, typename Load, typename Store>
void elementPass(const Tables& tb, int e1, int e2, const ShellEnergy::RestPoint* rest, const Constants& k,
                 bool bending, bool grad, Load&& load, Store&& store, T& em, T& eb) {
  const int L1 = tb.L1, L2 = tb.L2, Q1 = tb.Q1, Q2 = tb.Q2;
  // T[a][q2][dv][c] = Σ_b tv[q2][dv][b] X[a][b][c]
  T Tv[kMaxPoints][kMaxPoints][3][3];
  for (int a = 0; a < L1; ++a) {
    T X[kMaxPoints][3];
    const Eigen::Index base = Eigen::Index(e1 + a) * tb.cols + e2;
    for (int b = 0; b < L2; ++b)
      for (int c = 0; c < 3; ++c) X[b][c] = load(base + b, c);
    for (int q2 = 0; q2 < Q2; ++q2)
      for (int d = 0; d < 3; ++d)
        for (int c = 0; c < 3; ++c) {
          T s = T(0.0);
          for (int b = 0; b < L2; ++b) s += tb.v(q2, d, b) * X[b][c];
          Tv[a][q2][d][c] = s;
        }
  }
  T U[kMaxPoints][kMaxPoints][3][3];
  if (grad)
    for (int a = 0; a < L1; ++a)
      for (int q2 = 0; q2 < Q2; ++q2)
        for (int d = 0; d < 3; ++d)
          for (int c = 0; c < 3; ++c) U[a][q2][d][c] = T(0.0);
  em = T(0.0);
  eb = T(0.0);
  for (int q1 = 0; q1 < Q1; ++q1)
    for (int q2 = 0; q2 < Q2; ++q2) {
      T y[15];
      for (int m = 0; m < 5; ++m)
        for (int c = 0; c < 3; ++c) {
          T s = T(0.0);
          for (int a = 0; a < L1; ++a) s += tb.u(q1, kOrderU[m], a) * Tv[a][q2][kOrderV[m]][c];
          y[3 * m + c] = s;
        }
      T g[15], pm, pb;
      density(y, rest[q1 * Q2 + q2], k, bending, g, pm, pb);
      em += pm;
      eb += pb;
      if (!grad) continue;
      for (int a = 0; a < L1; ++a)
        for (int m = 0; m < 5; ++m) {
          const double w = tb.u(q1, kOrderU[m], a);
          for (int c = 0; c < 3; ++c) U[a][q2][kOrderV[m]][c] += w * g[3 * m + c];
        }
    }
  if (!grad) return;
  for (int a = 0; a < L1; ++a) {
    const Eigen::Index base = Eigen::Index(e1 + a) * tb.cols + e2;
    for (int b = 0; b < L2; ++b)
      for (int c = 0; c < 3; ++c) {
        T s = T(0.0);
        for (int q2 = 0; q2 < Q2; ++q2)
          for (int d = 0; d < 3; ++d) s += tb.v(q2, d, b) * U[a][q2][d][c];
        store(base + b, c, s);
      }
  }
}

/// y at one Gauss point (doubles) and the coefficients c[m][k] of y_m = Σ_k c[m][k] X_k.
void pointCoefficients(const Tables& tb, int q1, int q2, double c[5][kMaxPoints * kMaxPoints]) {
  for (int m = 0; m < 5; ++m)
    for (int a = 0; a < tb.L1; ++a)
      for (int b = 0; b < tb.L2; ++b) c[m][a * tb.L2 + b] = tb.u(q1, kOrderU[m], a) * tb.v(q2, kOrderV[m], b);
}

/// [x]× y = x × y as a matrix: out (row-major 3 x 3) = scale [x]×.
inline void crossMatrix(const double* x, double scale, double* out) {
  out[0] = 0.0;
  out[1] = -scale * x[2];
  out[2] = scale * x[1];
  out[3] = scale * x[2];
  out[4] = 0.0;
  out[5] = -scale * x[0];
  out[6] = -scale * x[1];
  out[7] = scale * x[0];
  out[8] = 0.0;
}

/// The 15 x 15 Hessian of the density at y, derived by hand (docs/math.md §16, "The tangent"):
/// the material part (PSD: (dE)ᵀ W C dE and (dκ)ᵀ W C dκ, W = diag(1, 2, 1) for the Voigt
/// shear) and the geometric part (the stresses times the second variations of E and κ).
/// `project`: when material + geometric is not positive definite (a compressed membrane, a
/// bending stress against the curvature), its negative eigenvalues are set to zero (the
/// nearest PSD matrix; should the eigensolver fail, the material part plus the membrane's
/// geometric part with its stress resultant made PSD). Newton on the incremental potential
/// needs a PSD tangent for a descent direction; the residual stays exact.
/// Ke[p][q] += Σ_d c[d][p] Σ_e c[e][q] H_de (3 x 3 blocks, q >= p) for one Gauss point: the
/// element tangent's inner loops (HC: scratch, 5 L 9). H column-major 15 x 15.
BSDEFORM_MULTIVERSION
void accumulateElement(int L, const double (*c)[kMaxPoints * kMaxPoints], const double* H,
                       double* HC, double* Ke) {
  // H's 3 x 3 blocks transposed into row-major [d][e][a][b] once
  double Hb[5][5][9];
  for (int d = 0; d < 5; ++d)
    for (int e = 0; e < 5; ++e)
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) Hb[d][e][3 * a + b] = H[(3 * e + b) * 15 + 3 * d + a];
  for (int d = 0; d < 5; ++d)
    for (int q = 0; q < L; ++q) {
      double* hc = &HC[(size_t(d) * L + q) * 9];
      for (int i = 0; i < 9; ++i) hc[i] = 0.0;
      for (int e = 0; e < 5; ++e) {
        const double w = c[e][q];
        for (int i = 0; i < 9; ++i) hc[i] += w * Hb[d][e][i];
      }
    }
  for (int p = 0; p < L; ++p)
    for (int d = 0; d < 5; ++d) {
      const double w = c[d][p];
      if (w == 0.0) continue;
      const double* hcd = &HC[size_t(d) * L * 9];
      double* ke = &Ke[size_t(p) * L * 9];
      for (int i = 9 * p; i < 9 * L; ++i) ke[i] += w * hcd[i];
    }
}

void densityHessianAnalytic(const double* y, const ShellEnergy::RestPoint& r, const Constants& k, bool bending,
                            bool project, double* Hout) {
  Eigen::Matrix<double, 15, 15> Hm = Eigen::Matrix<double, 15, 15>::Zero();  // material
  Eigen::Matrix<double, 15, 15> Hg = Eigen::Matrix<double, 15, 15>::Zero();  // geometric
  const Eigen::Map<const Eigen::Vector3d> a1(y), a2(y + 3);
  double E[3];
  {
    const double d1[3] = {y[0] - r.T[0], y[1] - r.T[1], y[2] - r.T[2]};
    const double d2[3] = {y[3] - r.T[3], y[4] - r.T[4], y[5] - r.T[5]};
    E[0] = r.T[0] * d1[0] + r.T[1] * d1[1] + r.T[2] * d1[2] + 0.5 * dot3(d1, d1);
    E[1] = 0.5 * ((r.T[0] * d2[0] + r.T[1] * d2[1] + r.T[2] * d2[2]) +
                  (r.T[3] * d1[0] + r.T[4] * d1[1] + r.T[5] * d1[2]) + dot3(d1, d2));
    E[2] = r.T[3] * d2[0] + r.T[4] * d2[1] + r.T[5] * d2[2] + 0.5 * dot3(d2, d2);
  }
  // W C in Voigt form (column j: the stress of the unit strain j, rows weighted 1, 2, 1)
  Eigen::Matrix3d WC;
  for (int j = 0; j < 3; ++j) {
    const double e[3] = {j == 0 ? 1.0 : 0.0, j == 1 ? 1.0 : 0.0, j == 2 ? 1.0 : 0.0};
    double s[3];
    stress(r.Ac, k, e, s);
    WC(0, j) = s[0];
    WC(1, j) = 2.0 * s[1];
    WC(2, j) = s[2];
  }
  WC = 0.5 * (WC + WC.transpose()).eval();
  const double tm = k.membrane * r.wJ;
  double S[3];
  stress(r.Ac, k, E, S);
  const double n11 = tm * S[0], n12 = tm * S[1], n22 = tm * S[2];
  // membrane: dE_i/dy over (a1, a2)
  Eigen::Matrix<double, 6, 3> G = Eigen::Matrix<double, 6, 3>::Zero();
  G.block<3, 1>(0, 0) = a1;
  G.block<3, 1>(0, 1) = 0.5 * a2;
  G.block<3, 1>(3, 1) = 0.5 * a1;
  G.block<3, 1>(3, 2) = a2;
  Hm.topLeftCorner<6, 6>() = tm * G * WC * G.transpose();
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  Hg.block<3, 3>(0, 0) = n11 * I;
  Hg.block<3, 3>(0, 3) = n12 * I;
  Hg.block<3, 3>(3, 0) = n12 * I;
  Hg.block<3, 3>(3, 3) = n22 * I;
  // the membrane's geometric part with the stress resultant made PSD (project's fallback)
  Eigen::Matrix2d nPsd = Eigen::Matrix2d::Zero();
  if (project) {
    Eigen::Matrix2d nn;
    nn << n11, n12, n12, n22;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(nn);
    nPsd = es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).asDiagonal() * es.eigenvectors().transpose();
  }
  Eigen::Vector3d a3 = a1.cross(a2);
  const double j = a3.norm();
  if (bending && j > 0.0) {
    const Eigen::Vector3d n = a3 / j;
    const Eigen::Map<const Eigen::Vector3d> s[3] = {Eigen::Map<const Eigen::Vector3d>(y + 6),
                                                    Eigen::Map<const Eigen::Vector3d>(y + 9),
                                                    Eigen::Map<const Eigen::Vector3d>(y + 12)};
    const double kappa[3] = {r.B[0] - s[0].dot(n), r.B[1] - s[1].dot(n), r.B[2] - s[2].dot(n)};
    double M[3];
    stress(r.Ac, k, kappa, M);
    const double tb = k.bending * r.wJ;
    const double mu[3] = {tb * M[0], 2.0 * tb * M[1], tb * M[2]};  // W m
    const Eigen::Matrix3d P = I - n * n.transpose();
    // dκ_i/dy: -n at S_i, (P S_i) × a2 / j at a1, a1 × (P S_i) / j at a2
    Eigen::Matrix<double, 15, 3> K = Eigen::Matrix<double, 15, 3>::Zero();
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d Ps = P * s[i];
      K.block<3, 1>(0, i) = Ps.cross(a2) / j;
      K.block<3, 1>(3, i) = a1.cross(Ps) / j;
      K.block<3, 1>(6 + 3 * i, i) = -n;
    }
    Hm += tb * K * WC * K.transpose();
    // -2 Σ μ_i dS_i · dn, dn = J1 da1 + J2 da2, J1 = -P [a2]× / j, J2 = P [a1]× / j
    double c2[9], c1[9];
    crossMatrix(a2.data(), 1.0, c2);
    crossMatrix(a1.data(), 1.0, c1);
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> X2(c2), X1(c1);
    const Eigen::Matrix3d J1 = -P * X2 / j, J2 = P * X1 / j;
    for (int i = 0; i < 3; ++i) {
      Hg.block<3, 3>(6 + 3 * i, 0) -= mu[i] * J1;
      Hg.block<3, 3>(6 + 3 * i, 3) -= mu[i] * J2;
      Hg.block<3, 3>(0, 6 + 3 * i) -= mu[i] * J1.transpose();
      Hg.block<3, 3>(3, 6 + 3 * i) -= mu[i] * J2.transpose();
    }
    // -v · d²n with v = Σ μ_i S_i: -(dã)ᵀ Hφ dã - 2 w · (da1 × da2), Hφ = -(n wᵀ + w nᵀ +
    // (v·n)/j P)/j, w = P v / j, dã = Q (da1, da2) with Q = [-[a2]×, [a1]×]
    const Eigen::Vector3d v = mu[0] * s[0] + mu[1] * s[1] + mu[2] * s[2];
    const double vn = v.dot(n);
    const Eigen::Vector3d w = P * v / j;
    Eigen::Matrix<double, 3, 6> Q;
    Q.leftCols<3>() = -X2;
    Q.rightCols<3>() = X1;
    const Eigen::Matrix3d Hphi = (n * w.transpose() + w * n.transpose() + (vn / j) * P) / j;
    Hg.topLeftCorner<6, 6>() += Q.transpose() * Hphi * Q;
    double cw[9];
    crossMatrix(w.data(), 1.0, cw);
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> Xw(cw);
    Hg.block<3, 3>(0, 3) += Xw;
    Hg.block<3, 3>(3, 0) -= Xw;
  }
  Eigen::Map<Eigen::Matrix<double, 15, 15>> H(Hout);
  H = Hm + Hg;
  if (project) {
    // positive definite to a relative margin: keep; else the PSD fallback
    const double scale = H.diagonal().cwiseAbs().maxCoeff();
    Eigen::Matrix<double, 15, 15> test = H;
    test.diagonal().array() += 1e-10 * scale + 1e-300;
    Eigen::LLT<Eigen::Matrix<double, 15, 15>> llt(test);
    if (llt.info() != Eigen::Success) {
      // the nearest positive semidefinite matrix: negative eigenvalues to zero
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 15, 15>> es(0.5 * (H + H.transpose()));
      if (es.info() == Eigen::Success) {
        H = es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).asDiagonal() * es.eigenvectors().transpose();
      } else {  // material part and the membrane's, its stress made PSD: PSD by construction
        H = Hm;
        H.block<3, 3>(0, 0) += nPsd(0, 0) * I;
        H.block<3, 3>(0, 3) += nPsd(0, 1) * I;
        H.block<3, 3>(3, 0) += nPsd(1, 0) * I;
        H.block<3, 3>(3, 3) += nPsd(1, 1) * I;
      }
    }
  }
  H = 0.5 * (H + H.transpose()).eval();
}

}  // namespace

ShellEnergy::ShellEnergy(const SplineSpace& space, const ControlNet& rest, const ShellMaterial& material)
    : m_space(space), m_rest(rest), m_material(material) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument(what);
  };
  const ShellMaterial& m = material;
  requireParameter(std::isfinite(m.youngsModulus) && m.youngsModulus > 0.0, "youngsModulus",
                   "must be a finite number > 0 (got " + numberText(m.youngsModulus) + ")");
  requireParameter(std::isfinite(m.poissonRatio) && m.poissonRatio >= 0.0 && m.poissonRatio < 0.5, "poissonRatio",
                   "must lie in [0, 0.5) (got " + numberText(m.poissonRatio) + ")");
  requireParameter(std::isfinite(m.thickness) && m.thickness > 0.0, "thickness",
                   "must be a finite number > 0 (got " + numberText(m.thickness) + ")");
  requireParameter(std::isfinite(m.density) && m.density > 0.0, "density",
                   "must be a finite number > 0 (got " + numberText(m.density) + ")");
  require(rest.rows() == space.netSize(), "ShellEnergy: the rest net does not fit the spline space");
  m_bending = space.degreeU() >= 2 && space.degreeV() >= 2;
  m_qu = space.degreeU() + 1;
  m_qv = space.degreeV() + 1;
  auto table = [](const BSplineBasis1D& basis, int points, std::vector<double>& t) {
    const QuadratureRule& rule = gaussLegendre(points);
    const int L = basis.degree() + 1;
    t.assign(size_t(points * 3 * L), 0.0);
    for (int q = 0; q < points; ++q) {
      LocalBasis lb;
      basis.evaluateInSpan(0, rule.nodes[size_t(q)] * basis.spacing(), std::min(2, basis.degree()), lb);
      for (int d = 0; d <= std::min(2, basis.degree()); ++d)
        for (int a = 0; a < L; ++a) t[size_t((q * 3 + d) * L + a)] = lb.d[size_t(d)][size_t(a)];
    }
  };
  table(space.basisU(), m_qu, m_tu);
  table(space.basisV(), m_qv, m_tv);
  const QuadratureRule& ru = gaussLegendre(m_qu);
  const QuadratureRule& rv = gaussLegendre(m_qv);
  const int S1 = space.basisU().numSpans(), S2 = space.basisV().numSpans();
  const double h1 = space.basisU().spacing(), h2 = space.basisV().spacing();
  m_points.resize(size_t(S1) * S2 * m_qu * m_qv);
  double area = 0.0;
  for (int e1 = 0; e1 < S1; ++e1)
    for (int e2 = 0; e2 < S2; ++e2)
      for (int q1 = 0; q1 < m_qu; ++q1)
        for (int q2 = 0; q2 < m_qv; ++q2) {
          const double u = (e1 + ru.nodes[size_t(q1)]) * h1, v = (e2 + rv.nodes[size_t(q2)]) * h2;
          const SurfacePoint p = space.evaluate(rest, u, v, 2);
          const Eigen::Vector3d a3 = p.du.cross(p.dv);
          const double J = a3.norm();
          const double scale = p.du.squaredNorm() + p.dv.squaredNorm();
          if (!(J > 1e-10 * scale) || !std::isfinite(J)) {
            std::ostringstream os;
            os << "the rest surface is degenerate at (u, v) = (" << numberText(u) << ", " << numberText(v)
               << "): S_u x S_v vanishes there (a pole?), and a shell needs a regular rest surface";
            throw std::invalid_argument(os.str());
          }
          const Eigen::Vector3d n = a3 / J;
          RestPoint& r = m_points[((size_t(e1) * S2 + e2) * m_qu + q1) * m_qv + q2];
          for (int c = 0; c < 3; ++c) {
            r.T[c] = p.du[c];
            r.T[3 + c] = p.dv[c];
          }
          r.A[0] = p.du.dot(p.du);
          r.A[1] = p.du.dot(p.dv);
          r.A[2] = p.dv.dot(p.dv);
          const double det = r.A[0] * r.A[2] - r.A[1] * r.A[1];
          r.Ac[0] = r.A[2] / det;
          r.Ac[1] = -r.A[1] / det;
          r.Ac[2] = r.A[0] / det;
          r.B[0] = p.duu.dot(n);
          r.B[1] = p.duv.dot(n);
          r.B[2] = p.dvv.dot(n);
          r.wJ = ru.weights[size_t(q1)] * rv.weights[size_t(q2)] * h1 * h2 * J;
          area += r.wJ;
        }
  m_restArea = area;
}

double ShellEnergy::restAreaElement(double u, double v) const {
  const SurfacePoint p = m_space.evaluate(m_rest, u, v, 1);
  return p.du.cross(p.dv).norm();
}

// Rows of the net are split into blocks of knot spans in u; blocks of one parity touch disjoint
// net rows (a block spans at least n1 + 1 spans), so each parity runs its blocks in parallel and
// every net row receives its sums in the same order for any thread count.
template <typename Fn>
void ShellEnergy::forEachBlock(Fn&& fn) const {
  const int S1 = m_space.basisU().numSpans();
  const int size = std::max(m_space.degreeU() + 1, 4);
  const int blocks = (S1 + size - 1) / size;
  for (int parity = 0; parity < 2; ++parity) {
    const int parts = (blocks - parity + 1) / 2;
    if (parts <= 0) continue;
    runParts(parts, [&](int p) {
      const int b = 2 * p + parity;
      fn(b, b * size, std::min(S1, (b + 1) * size));
    });
  }
}

ShellEnergies ShellEnergy::energy(const ControlNet& net) const {
  const int S1 = m_space.basisU().numSpans(), S2 = m_space.basisV().numSpans();
  const Tables tb{m_space.degreeU() + 1, m_space.degreeV() + 1, m_qu, m_qv, m_space.netCols(), m_tu.data(), m_tv.data()};
  const Constants k = constantsOf(m_material);
  const int size = std::max(m_space.degreeU() + 1, 4);
  std::vector<ShellEnergies> partial(size_t((S1 + size - 1) / size));
  const double* X = net.data();
  forEachBlock([&](int b, int s0, int s1) {
    ShellEnergies sum;
    for (int e1 = s0; e1 < s1; ++e1)
      for (int e2 = 0; e2 < S2; ++e2) {
        double em, eb;
        elementPass<double>(
            tb, e1, e2, &m_points[(size_t(e1) * S2 + e2) * m_qu * m_qv], k, m_bending, false,
            [X](Eigen::Index r, int c) { return X[3 * r + c]; }, [](Eigen::Index, int, double) {}, em, eb);
        sum.membrane += em;
        sum.bending += eb;
      }
    partial[size_t(b)] = sum;
  });
  ShellEnergies total;
  for (const ShellEnergies& p : partial) {
    total.membrane += p.membrane;
    total.bending += p.bending;
  }
  return total;
}

void ShellEnergy::gradient(const ControlNet& net, ControlNet& grad) const {
  const int S2 = m_space.basisV().numSpans();
  const Tables tb{m_space.degreeU() + 1, m_space.degreeV() + 1, m_qu, m_qv, m_space.netCols(), m_tu.data(), m_tv.data()};
  const Constants k = constantsOf(m_material);
  grad.setZero(net.rows(), 3);
  const double* X = net.data();
  double* G = grad.data();
  forEachBlock([&](int, int s0, int s1) {
    for (int e1 = s0; e1 < s1; ++e1)
      for (int e2 = 0; e2 < S2; ++e2) {
        double em, eb;
        elementPass<double>(
            tb, e1, e2, &m_points[(size_t(e1) * S2 + e2) * m_qu * m_qv], k, m_bending, true,
            [X](Eigen::Index r, int c) { return X[3 * r + c]; },
            [G](Eigen::Index r, int c, double s) { G[3 * r + c] += s; }, em, eb);
      }
  });
}

void ShellEnergy::hessianProduct(const ControlNet& net, const ControlNet& dir, ControlNet& out) const {
  const int S2 = m_space.basisV().numSpans();
  const Tables tb{m_space.degreeU() + 1, m_space.degreeV() + 1, m_qu, m_qv, m_space.netCols(), m_tu.data(), m_tv.data()};
  const Constants k = constantsOf(m_material);
  out.setZero(net.rows(), 3);
  const double* X = net.data();
  const double* D = dir.data();
  double* O = out.data();
  forEachBlock([&](int, int s0, int s1) {
    for (int e1 = s0; e1 < s1; ++e1)
      for (int e2 = 0; e2 < S2; ++e2) {
        Dual em, eb;
        elementPass<Dual>(
            tb, e1, e2, &m_points[(size_t(e1) * S2 + e2) * m_qu * m_qv], k, m_bending, true,
            [X, D](Eigen::Index r, int c) { return Dual(X[3 * r + c], D[3 * r + c]); },
            [O](Eigen::Index r, int c, Dual s) { O[3 * r + c] += s.b; }, em, eb);
      }
  });
}

void ShellEnergy::elementHessians(const ControlNet& net, HessianMode mode, bool serial,
                                  const std::function<void(int, int, const double*)>& sink) const {
  const int S1 = m_space.basisU().numSpans(), S2 = m_space.basisV().numSpans();
  const int L1 = m_space.degreeU() + 1, L2 = m_space.degreeV() + 1, L = L1 * L2, cols = m_space.netCols();
  const Tables tb{L1, L2, m_qu, m_qv, cols, m_tu.data(), m_tv.data()};
  const Constants k = constantsOf(m_material);
  const bool project = mode == HessianMode::Projected;
  auto elements = [&](int s0, int s1) {
    // K_pq = Σ_d c[d][p] (Σ_e c[e][q] H_de) in 3 x 3 blocks, the upper blocks (q >= p) only,
    // mirrored at the end
    std::vector<double> Ke(size_t(L) * L * 9), HC(size_t(5) * L * 9);
    double c[5][kMaxPoints * kMaxPoints];
    alignas(32) double H[225];
    for (int e1 = s0; e1 < s1; ++e1)
      for (int e2 = 0; e2 < S2; ++e2) {
        std::fill(Ke.begin(), Ke.end(), 0.0);
        const RestPoint* rest = &m_points[(size_t(e1) * S2 + e2) * m_qu * m_qv];
        double X[kMaxPoints * kMaxPoints][3];
        for (int p = 0; p < L; ++p) {
          const Eigen::Index r = Eigen::Index(e1 + p / L2) * cols + e2 + p % L2;
          for (int cc = 0; cc < 3; ++cc) X[p][cc] = net(r, cc);
        }
        for (int q1 = 0; q1 < m_qu; ++q1)
          for (int q2 = 0; q2 < m_qv; ++q2) {
            pointCoefficients(tb, q1, q2, c);
            double y[15] = {};
            for (int p = 0; p < L; ++p)
              for (int m = 0; m < 5; ++m)
                for (int cc = 0; cc < 3; ++cc) y[3 * m + cc] += c[m][p] * X[p][cc];
            densityHessianAnalytic(y, rest[q1 * m_qv + q2], k, m_bending, project, H);
            accumulateElement(L, c, H, HC.data(), Ke.data());
          }
        for (int p = 0; p < L; ++p)
          for (int q = 0; q < p; ++q)
            for (int a = 0; a < 3; ++a)
              for (int b = 0; b < 3; ++b) Ke[(size_t(p) * L + q) * 9 + 3 * a + b] = Ke[(size_t(q) * L + p) * 9 + 3 * b + a];
        sink(e1, e2, Ke.data());
      }
  };
  if (serial)
    elements(0, S1);
  else
    forEachBlock([&](int, int s0, int s1) { elements(s0, s1); });
}

void ShellEnergy::hessian(const ControlNet& net, bool project, std::vector<Eigen::Triplet<double>>& out) const {
  const int S1 = m_space.basisU().numSpans(), S2 = m_space.basisV().numSpans();
  const int L2 = m_space.degreeV() + 1, L = (m_space.degreeU() + 1) * L2, cols = m_space.netCols();
  out.clear();
  out.reserve(size_t(S1) * S2 * size_t(9 * L * L));
  elementHessians(net, project ? HessianMode::Projected : HessianMode::Exact, true,
                  [&](int e1, int e2, const double* Ke) {
                    for (int p = 0; p < L; ++p) {
                      const Eigen::Index rp = Eigen::Index(e1 + p / L2) * cols + e2 + p % L2;
                      for (int q = 0; q < L; ++q) {
                        const Eigen::Index rq = Eigen::Index(e1 + q / L2) * cols + e2 + q % L2;
                        const double* ke = &Ke[(size_t(p) * L + q) * 9];
                        for (int a = 0; a < 3; ++a)
                          for (int b = 0; b < 3; ++b) out.emplace_back(int(3 * rp + a), int(3 * rq + b), ke[3 * a + b]);
                      }
                    }
                  });
}

Eigen::VectorXd ShellEnergy::lumpedMass() const {
  const int S1 = m_space.basisU().numSpans(), S2 = m_space.basisV().numSpans();
  const int L1 = m_space.degreeU() + 1, L2 = m_space.degreeV() + 1, cols = m_space.netCols();
  const Tables tb{L1, L2, m_qu, m_qv, cols, m_tu.data(), m_tv.data()};
  const double rhoT = m_material.density * m_material.thickness;
  Eigen::VectorXd mass = Eigen::VectorXd::Zero(m_space.netSize());
  for (int e1 = 0; e1 < S1; ++e1)
    for (int e2 = 0; e2 < S2; ++e2)
      for (int q1 = 0; q1 < m_qu; ++q1)
        for (int q2 = 0; q2 < m_qv; ++q2) {
          const double wJ = m_points[((size_t(e1) * S2 + e2) * m_qu + q1) * m_qv + q2].wJ;
          for (int a = 0; a < L1; ++a)
            for (int b = 0; b < L2; ++b)
              mass[Eigen::Index(e1 + a) * cols + e2 + b] += rhoT * wJ * tb.u(q1, 0, a) * tb.v(q2, 0, b);
        }
  return mass;
}

double ShellEnergy::eigenvalueBound(const ControlNet& net, const Eigen::VectorXd& mass) const {
  const int S2 = m_space.basisV().numSpans();
  const int L1 = m_space.degreeU() + 1, L2 = m_space.degreeV() + 1, L = L1 * L2, cols = m_space.netCols();
  const Tables tb{L1, L2, m_qu, m_qv, cols, m_tu.data(), m_tv.data()};
  const Constants k = constantsOf(m_material);
  Eigen::VectorXd rows = Eigen::VectorXd::Zero(m_space.netSize());
  forEachBlock([&](int, int s0, int s1) {
    double c[5][kMaxPoints * kMaxPoints];
    for (int e1 = s0; e1 < s1; ++e1)
      for (int e2 = 0; e2 < S2; ++e2) {
        const RestPoint* rest = &m_points[(size_t(e1) * S2 + e2) * m_qu * m_qv];
        for (int q1 = 0; q1 < m_qu; ++q1)
          for (int q2 = 0; q2 < m_qv; ++q2) {
            pointCoefficients(tb, q1, q2, c);
            double y[15] = {};
            for (int p = 0; p < L; ++p) {
              const Eigen::Index r = Eigen::Index(e1 + p / L2) * cols + e2 + p % L2;
              for (int m = 0; m < 5; ++m)
                for (int cc = 0; cc < 3; ++cc) y[3 * m + cc] += c[m][p] * net(r, cc);
            }
            Eigen::Matrix<double, 15, 15> H;
            densityHessianAnalytic(y, rest[q1 * m_qv + q2], k, m_bending, false, H.data());
            double s[5] = {};
            for (int m = 0; m < 5; ++m)
              for (int p = 0; p < L; ++p) s[m] += std::abs(c[m][p]);
            double rd[5] = {};
            for (int d = 0; d < 5; ++d)
              for (int e = 0; e < 5; ++e) {
                const double block = H.block<3, 3>(3 * d, 3 * e).cwiseAbs().rowwise().sum().maxCoeff();
                rd[d] += s[e] * block;
              }
            for (int p = 0; p < L; ++p) {
              double sum = 0.0;
              for (int d = 0; d < 5; ++d) sum += std::abs(c[d][p]) * rd[d];
              rows[Eigen::Index(e1 + p / L2) * cols + e2 + p % L2] += sum;
            }
          }
      }
  });
  double bound = 0.0;
  for (Eigen::Index p = 0; p < rows.size(); ++p)
    if (mass[p] > 0.0) bound = std::max(bound, rows[p] / mass[p]);
  return bound;
}

}  // namespace bsdeform
