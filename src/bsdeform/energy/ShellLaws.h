// SPDX-License-Identifier: MIT
#pragma once
/// @file ShellLaws.h
/// The shell's material laws (docs/math.md §16 and §16.1), the policies the kinematics kernel
/// (ShellKinematics.h) is instantiated with. A law sees one Gauss point of the mid-surface: the
/// rest point r (A_αβ, A^{αβ}, B_αβ, the weight wJ) and the strains there, the membrane strain
/// E = ½(a − A) and the bending strain κ = B − b (each (11, 12, 22)), and returns
///   resultants(): the energy (membrane and bending part, times wJ) and the stress resultants
///                 n^{αβ} = ∂w/∂E_αβ and m^{αβ} = ∂w/∂κ_αβ as symmetric tensors (times wJ);
///   material():   n and m again, and D = ∂²w/∂(E, κ)² (6 x 6, Voigt, shear counted twice,
///                 times wJ): the material part of the 15 x 15 density Hessian is
///                 [dE/dy dκ/dy] D [dE/dy dκ/dy]ᵀ, formed by the kinematics kernel from the
///                 Jacobians' few non-zero blocks. kCoupled: whether D couples E and κ (else its
///                 off-diagonal 3 x 3 blocks are zero and the kernel skips them).
/// κ = nullptr: no bending strain (degree 1, or a collapsed current normal), membrane only.
/// Private to the core (not installed).

#include <Eigen/Core>
#include <cmath>
#include <limits>

#include "bsdeform/energy/Shell.h"
#include "bsdeform/energy/ShellDual.h"
#include "bsdeform/spline/GaussLegendre.h"

namespace bsdeform::shell {

using RestPoint = ShellEnergy::RestPoint;
using Matrix15 = Eigen::Matrix<double, 15, 15>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;

/// Plane-stress St. Venant–Kirchhoff: w = wJ (½ t E:C:E + ½ t³/12 κ:C:κ),
/// C^{αβγδ} = λ̄ A^{αβ}A^{γδ} + μ(A^{αγ}A^{βδ} + A^{αδ}A^{βγ}), λ̄ = Eν/(1−ν²).
struct SaintVenantKirchhoff {
  double membrane;  ///< t
  double bending;   ///< t³/12
  double lambda;    ///< λ̄ = Eν/(1−ν²)
  double twoMu;     ///< 2μ = E/(1+ν)

  explicit SaintVenantKirchhoff(const ShellMaterial& m)
      : membrane(m.thickness),
        bending(m.thickness * m.thickness * m.thickness / 12.0),
        lambda(m.youngsModulus * m.poissonRatio / (1.0 - m.poissonRatio * m.poissonRatio)),
        twoMu(m.youngsModulus / (1.0 + m.poissonRatio)) {}

  /// S = λ̄ A^{αβ} tr(A⁻¹E) + 2μ (A⁻¹ E A⁻¹)^{αβ} for a symmetric E = (E11, E12, E22).
  template <typename T>
  void stress(const double* Ac, const T* E, T* S) const {
    const T tr = Ac[0] * E[0] + 2.0 * (Ac[1] * E[1]) + Ac[2] * E[2];
    const T P11 = Ac[0] * E[0] + Ac[1] * E[1], P12 = Ac[0] * E[1] + Ac[1] * E[2];
    const T P21 = Ac[1] * E[0] + Ac[2] * E[1], P22 = Ac[1] * E[1] + Ac[2] * E[2];
    const T X11 = P11 * Ac[0] + P12 * Ac[1], X12 = P11 * Ac[1] + P12 * Ac[2], X22 = P21 * Ac[1] + P22 * Ac[2];
    S[0] = lambda * Ac[0] * tr + twoMu * X11;
    S[1] = lambda * Ac[1] * tr + twoMu * X12;
    S[2] = lambda * Ac[2] * tr + twoMu * X22;
  }

  template <typename T>
  void resultants(const RestPoint& r, const T* E, const T* kappa, T* n, T* m, T& em, T& eb) const {
    T S[3];
    stress(r.Ac, E, S);
    for (int i = 0; i < 3; ++i) n[i] = (membrane * r.wJ) * S[i];
    em = 0.5 * (n[0] * E[0] + 2.0 * (n[1] * E[1]) + n[2] * E[2]);
    eb = T(0.0);
    if (!kappa) return;
    T M[3];
    stress(r.Ac, kappa, M);
    for (int i = 0; i < 3; ++i) m[i] = (bending * r.wJ) * M[i];
    eb = 0.5 * (m[0] * kappa[0] + 2.0 * (m[1] * kappa[1]) + m[2] * kappa[2]);
  }

  static constexpr bool kCoupled = false;

  void material(const RestPoint& r, const double* E, const double* kappa, double* n, double* m, Matrix6& D) const {
    // W C in Voigt form (column j: the stress of the unit strain j, rows weighted 1, 2, 1)
    Eigen::Matrix3d WC;
    for (int j = 0; j < 3; ++j) {
      const double e[3] = {j == 0 ? 1.0 : 0.0, j == 1 ? 1.0 : 0.0, j == 2 ? 1.0 : 0.0};
      double s[3];
      stress(r.Ac, e, s);
      WC(0, j) = s[0];
      WC(1, j) = 2.0 * s[1];
      WC(2, j) = s[2];
    }
    WC = 0.5 * (WC + WC.transpose()).eval();
    const double tm = membrane * r.wJ;
    double S[3];
    stress(r.Ac, E, S);
    for (int i = 0; i < 3; ++i) n[i] = tm * S[i];
    D.setZero();
    D.topLeftCorner<3, 3>() = tm * WC;
    if (!kappa) return;
    double M[3];
    stress(r.Ac, kappa, M);
    const double tb = bending * r.wJ;
    for (int i = 0; i < 3; ++i) m[i] = tb * M[i];
    D.bottomRightCorner<3, 3>() = tb * WC;
  }
};

/// Compressible neo-Hookean, plane stress by condensing the thickness stretch, integrated
/// through the thickness (Kiendl, Hsu, Wu and Reali 2015, CMAME 291; docs/math.md §16.1). Per
/// reference volume Ψ = μ/2 (I₁ − 3 − 2 ln J) + λ/2 (ln J)², μ = E/(2(1+ν)),
/// λ = Eν/((1+ν)(1−2ν)), with I₁ = G^{αβ}g_αβ + C₃₃, J² = C₃₃ det g / det G at the distance z
/// from the mid-surface: g = a − 2z b, G = A − 2z B (the z² terms dropped), that is
/// g − G = 2(E + zκ). C₃₃ solves S³³ = 2∂Ψ/∂C₃₃ = 0. The energy per mid-surface Gauss point is
/// wJ Σ_i w_i Ψ(z_i) with Gauss–Legendre points z_i on [−t/2, t/2] (volume element dz dA).
struct NeoHookean {
  static constexpr int kThicknessPoints = 3;  ///< exact for polynomials of degree 5 in z
  double mu;         ///< μ = E/(2(1+ν))
  double lambda;     ///< λ = Eν/((1+ν)(1−2ν))
  double thickness;  ///< t
  double z[kThicknessPoints], w[kThicknessPoints];  ///< points on [−t/2, t/2], weights (sum t)
  /// Split the energy into membrane (t Ψ̂ of E alone, on the mid-surface) and bending (the
  /// rest): one more evaluation per Gauss point, wanted by energy() only.
  bool split = false;

  explicit NeoHookean(const ShellMaterial& m)
      : mu(m.youngsModulus / (2.0 * (1.0 + m.poissonRatio))),
        lambda(m.youngsModulus * m.poissonRatio / ((1.0 + m.poissonRatio) * (1.0 - 2.0 * m.poissonRatio))),
        thickness(m.thickness) {
    const QuadratureRule& rule = gaussLegendre(kThicknessPoints);
    for (int k = 0; k < kThicknessPoints; ++k) {
      z[k] = m.thickness * (rule.nodes[size_t(k)] - 0.5);
      w[k] = m.thickness * rule.weights[size_t(k)];
    }
  }

  /// Ψ and S^{αβ} = ∂Ψ/∂E_αβ at one thickness point with rest metric G and strain e (11, 12,
  /// 22); with D non-null also ∂²Ψ/∂e² (3 x 3 row-major, Voigt, shear counted twice). False
  /// where the metric collapses (det g ≤ 0): no energy has a finite value there.
  template <typename T>
  bool point(const double* G, const T* e, T* S, T& psi, double* D) const {
    const double detG = G[0] * G[2] - G[1] * G[1];
    const double Gi[3] = {G[2] / detG, -G[1] / detG, G[0] / detG};
    const T tr = Gi[0] * e[0] + 2.0 * (Gi[1] * e[1]) + Gi[2] * e[2];  // tr(G⁻¹E)
    const T detE = e[0] * e[2] - e[1] * e[1];
    const T rel = 2.0 * tr + 4.0 * (detE / detG);  // det g / det G − 1
    if (!(value(rel) > -1.0)) return false;
    const T r = log1p(rel);                        // ln(det g / det G)
    const T x = logC33(r);                         // ln C₃₃
    const T L = r + x;                             // ln J²
    const T c1 = expm1(x);                         // C₃₃ − 1
    // Ψ = μ/2 (tr(G⁻¹g) − 2 + C₃₃ − 1 − ln J²) + λ/8 (ln J²)², each difference formed without
    // cancellation for small strains
    psi = (0.5 * mu) * (2.0 * tr + c1 - L) + (0.125 * lambda) * (L * L);
    const T g0 = G[0] + 2.0 * e[0], g1 = G[1] + 2.0 * e[1], g2 = G[2] + 2.0 * e[2];
    const T detg = g0 * g2 - g1 * g1;
    const T gi[3] = {g2 / detg, -g1 / detg, g0 / detg};
    // S = μ(G⁻¹ − g⁻¹) + λ/2 ln J² g⁻¹, with G⁻¹ − g⁻¹ = 2 G⁻¹ E g⁻¹
    const T X11 = Gi[0] * e[0] + Gi[1] * e[1], X12 = Gi[0] * e[1] + Gi[1] * e[2];
    const T X21 = Gi[1] * e[0] + Gi[2] * e[1], X22 = Gi[1] * e[1] + Gi[2] * e[2];
    const T Y11 = X11 * gi[0] + X12 * gi[1], Y12 = X11 * gi[1] + X12 * gi[2];
    const T Y21 = X21 * gi[0] + X22 * gi[1], Y22 = X21 * gi[1] + X22 * gi[2];
    const T hl = (0.5 * lambda) * L;
    S[0] = (2.0 * mu) * Y11 + hl * gi[0];
    S[1] = mu * (Y12 + Y21) + hl * gi[1];
    S[2] = (2.0 * mu) * Y22 + hl * gi[2];
    if (D) {
      // condensed tangent (C₃₃ eliminated): ℂ̂ = a (g⁻¹g⁻¹ + g⁻¹g⁻¹)ₛ + b g⁻¹ ⊗ g⁻¹,
      // a = μ − λ/2 ln J², b = 2λμC₃₃ / (2μC₃₃ + λ)
      const double c = 1.0 + value(c1);
      const double a = mu - 0.5 * lambda * value(L), b = 2.0 * lambda * mu * c / (2.0 * mu * c + lambda);
      const double p = value(gi[0]), q = value(gi[1]), s = value(gi[2]);
      const double C[3][3] = {{(2 * a + b) * p * p, (2 * a + b) * p * q, 2 * a * q * q + b * p * s},
                              {(2 * a + b) * p * q, a * (p * s + q * q) + b * q * q, (2 * a + b) * q * s},
                              {2 * a * q * q + b * p * s, (2 * a + b) * q * s, (2 * a + b) * s * s}};
      const double W[3] = {1.0, 2.0, 1.0};
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) D[3 * i + j] = W[i] * W[j] * C[i][j];
    }
    return true;
  }

  /// ln C₃₃ from S³³ = 0: h(x) = μ(eˣ − 1) + λ/2 (r + x) = 0, increasing and convex in x, so
  /// Newton from the linearised root converges monotonically after its first step.
  double logC33(double r) const {
    double x = -lambda * r / (2.0 * mu + lambda);
    for (int it = 0; it < 60; ++it) {
      const double dx = (mu * std::expm1(x) + 0.5 * lambda * (r + x)) / (mu * std::exp(x) + 0.5 * lambda);
      x -= dx;
      if (!(std::abs(dx) > 1e-15 * (1.0 + std::abs(x)))) break;
    }
    return x;
  }
  /// For dual numbers: the root of the value part, and its derivative from one Newton step in
  /// dual arithmetic from there (h = 0 at the root: dx = −∂h/∂r dr / h'(x)).
  Dual logC33(Dual r) const {
    const double x = logC33(r.a);
    return {x, -(0.5 * lambda) * r.b / (mu * std::exp(x) + 0.5 * lambda)};
  }

  template <typename T>
  void resultants(const RestPoint& r, const T* E, const T* kappa, T* n, T* m, T& em, T& eb) const {
    T S[3], psi;
    for (int i = 0; i < 3; ++i) n[i] = m[i] = T(0.0);
    em = eb = T(0.0);
    if (!kappa) {  // membrane only: E is the same through the thickness
      if (!point(r.A, E, S, psi, nullptr)) return collapsed(n, m, em, eb);
      for (int i = 0; i < 3; ++i) n[i] = (thickness * r.wJ) * S[i];
      em = (thickness * r.wJ) * psi;
      return;
    }
    T total = T(0.0);
    for (int k = 0; k < kThicknessPoints; ++k) {
      const double G[3] = {r.A[0] - 2.0 * z[k] * r.B[0], r.A[1] - 2.0 * z[k] * r.B[1], r.A[2] - 2.0 * z[k] * r.B[2]};
      const T e[3] = {E[0] + z[k] * kappa[0], E[1] + z[k] * kappa[1], E[2] + z[k] * kappa[2]};
      if (!point(G, e, S, psi, nullptr)) return collapsed(n, m, em, eb);
      for (int i = 0; i < 3; ++i) {
        n[i] += (w[k] * r.wJ) * S[i];
        m[i] += (w[k] * z[k] * r.wJ) * S[i];
      }
      total += (w[k] * r.wJ) * psi;
    }
    if (split) {
      if (!point(r.A, E, S, psi, nullptr)) return collapsed(n, m, em, eb);
      em = (thickness * r.wJ) * psi;
      eb = total - em;
    } else {
      em = total;
    }
  }

  static constexpr bool kCoupled = true;

  void material(const RestPoint& r, const double* E, const double* kappa, double* n, double* m, Matrix6& D) const {
    double S[3], psi, Dz[9];
    D.setZero();
    for (int i = 0; i < 3; ++i) n[i] = m[i] = 0.0;
    if (!kappa) {
      if (!point(r.A, E, S, psi, Dz)) return;  // no finite energy: no stiffness either
      const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> Dm(Dz);
      for (int i = 0; i < 3; ++i) n[i] = (thickness * r.wJ) * S[i];
      D.topLeftCorner<3, 3>() = (thickness * r.wJ) * Dm;
      return;
    }
    for (int k = 0; k < kThicknessPoints; ++k) {
      const double Gk[3] = {r.A[0] - 2.0 * z[k] * r.B[0], r.A[1] - 2.0 * z[k] * r.B[1], r.A[2] - 2.0 * z[k] * r.B[2]};
      const double e[3] = {E[0] + z[k] * kappa[0], E[1] + z[k] * kappa[1], E[2] + z[k] * kappa[2]};
      if (!point(Gk, e, S, psi, Dz)) {
        for (int i = 0; i < 3; ++i) n[i] = m[i] = 0.0;
        D.setZero();
        return;
      }
      const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> Dm(Dz);
      const double wk = w[k] * r.wJ;
      for (int i = 0; i < 3; ++i) {
        n[i] += wk * S[i];
        m[i] += wk * z[k] * S[i];
      }
      D.topLeftCorner<3, 3>() += wk * Dm;
      D.topRightCorner<3, 3>() += (wk * z[k]) * Dm;
      D.bottomRightCorner<3, 3>() += (wk * z[k] * z[k]) * Dm;
    }
    D.bottomLeftCorner<3, 3>() = D.topRightCorner<3, 3>().transpose();
  }

 private:
  /// Where the metric collapses the energy is +∞ (assigned: no floating-point exception) and
  /// no stress is returned; a line search refuses such a state.
  template <typename T>
  static void collapsed(T* n, T* m, T& em, T& eb) {
    for (int i = 0; i < 3; ++i) n[i] = m[i] = T(0.0);
    em = T(std::numeric_limits<double>::infinity());
    eb = T(0.0);
  }
};

}  // namespace bsdeform::shell
