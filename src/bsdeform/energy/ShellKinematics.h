// SPDX-License-Identifier: MIT
#pragma once
/// @file ShellKinematics.h
/// The shell's kinematics kernel (docs/math.md §16): at one Gauss point, y = (S_u, S_v, S_uu,
/// S_uv, S_vv) → the membrane strain E = ½(a − A), the bending strain κ = B − b and their first
/// and second derivatives in y, chained with a material law (ShellLaws.h) into the energy
/// density, its gradient and its 15 x 15 Hessian. The law sees only the strains; the assembly
/// loops (Shell.cpp) see only y and the gradient or Hessian. Private to the core.

#include <cassert>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include "bsdeform/energy/ShellDual.h"
#include "bsdeform/energy/ShellLaws.h"

namespace bsdeform::shell {

/// The energy density (membrane, bending, each times wJ) of the law and its gradient g with
/// respect to y at one Gauss point, for T = double or Dual.
template <typename T, typename Law>
inline void density(const T* y, const RestPoint& r, const Law& law, bool bending, T* g, T& em, T& eb) {
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
  const T* s11 = y + 6;
  const T* s12 = y + 9;
  const T* s22 = y + 12;
  T nrm[3], j = T(0.0), invJ = T(0.0), kappa[3];
  bool curved = false;  // a bending strain exists here
  if (bending) {
    T a3[3];
    cross3(a1, a2, a3);
    j = sqrt(dot3(a3, a3));
    if (value(j) != 0.0) {  // a collapsed current surface has no normal: no bending there
      invJ = 1.0 / j;  // one division: the kernel's longest latency (ShellForces, issue 34)
      for (int c = 0; c < 3; ++c) nrm[c] = a3[c] * invJ;
      kappa[0] = r.B[0] - dot3(s11, nrm);
      kappa[1] = r.B[1] - dot3(s12, nrm);
      kappa[2] = r.B[2] - dot3(s22, nrm);
      curved = true;
    }
  }
  T n[3], m[3];
  law.resultants(r, E, curved ? kappa : nullptr, n, m, em, eb);
  for (int c = 0; c < 3; ++c) {
    g[c] = n[0] * a1[c] + n[1] * a2[c];
    g[3 + c] = n[1] * a1[c] + n[2] * a2[c];
    g[6 + c] = g[9 + c] = g[12 + c] = T(0.0);
  }
  if (!curved) return;
  // dκ = −(dS_αβ·n + S_αβ·dn), dn = (I − n nᵀ) dã₃ / j, dã₃ = da₁ × a₂ + a₁ × da₂
  T v[3], w[3], t1[3], t2[3];
  for (int c = 0; c < 3; ++c) {
    g[6 + c] = -(m[0] * nrm[c]);
    g[9 + c] = -(2.0 * (m[1] * nrm[c]));
    g[12 + c] = -(m[2] * nrm[c]);
    v[c] = m[0] * s11[c] + 2.0 * (m[1] * s12[c]) + m[2] * s22[c];
  }
  const T vn = dot3(v, nrm);
  for (int c = 0; c < 3; ++c) w[c] = (v[c] - vn * nrm[c]) * invJ;
  cross3(a2, w, t1);
  cross3(w, a1, t2);
  for (int c = 0; c < 3; ++c) {
    g[c] = g[c] - t1[c];
    g[3 + c] = g[3 + c] - t2[c];
  }
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
/// the material part (the law's: [dE dκ] D [dE dκ]ᵀ, PSD where D is) and the geometric part
/// (the stress resultants times the second variations of E and κ).
/// Both are formed block by block (3 x 3 blocks over y's five vectors a₁, a₂, S₁₁, S₁₂, S₂₂)
/// from the Jacobians' non-zero blocks: dE/dy lives on a₁ and a₂ only, dκ_i/dS_j is −n δ_ij,
/// and the geometric part has no S–S blocks; the upper blocks are formed, the lower mirrored.
/// `project`: when material + geometric is not positive definite (a compressed membrane, a
/// bending stress against the curvature), its negative eigenvalues are set to zero (the
/// nearest PSD matrix; should the eigensolver fail, the material part plus the membrane's
/// geometric part with its stress resultant made PSD). Newton on the incremental potential
/// needs a PSD tangent for a descent direction; the residual stays exact. Hout column-major,
/// symmetric to the last bit. Returns whether the projection replaced the Hessian (never
/// without `project`).
template <typename Law>
bool densityHessian(const double* y, const RestPoint& r, const Law& law, bool bending, bool project, double* Hout) {
  using Eigen::Matrix3d;
  using Eigen::Vector3d;
  const Eigen::Map<const Vector3d> a1(y), a2(y + 3);
  double E[3];
  {
    const double d1[3] = {y[0] - r.T[0], y[1] - r.T[1], y[2] - r.T[2]};
    const double d2[3] = {y[3] - r.T[3], y[4] - r.T[4], y[5] - r.T[5]};
    E[0] = r.T[0] * d1[0] + r.T[1] * d1[1] + r.T[2] * d1[2] + 0.5 * dot3(d1, d1);
    E[1] = 0.5 * ((r.T[0] * d2[0] + r.T[1] * d2[1] + r.T[2] * d2[2]) +
                  (r.T[3] * d1[0] + r.T[4] * d1[1] + r.T[5] * d1[2]) + dot3(d1, d2));
    E[2] = r.T[3] * d2[0] + r.T[4] * d2[1] + r.T[5] * d2[2] + 0.5 * dot3(d2, d2);
  }
  // dE/da₁ and dE/da₂ (columns E₁₁, E₁₂, E₂₂)
  Matrix3d G[2];
  G[0] << a1, 0.5 * a2, Vector3d::Zero();
  G[1] << Vector3d::Zero(), 0.5 * a1, a2;
  const Vector3d a3 = a1.cross(a2);
  const double j = a3.norm();
  const bool curved = bending && j > 0.0;
  Vector3d n = Vector3d::Zero();
  Matrix3d P = Matrix3d::Identity();
  Matrix3d K[2] = {Matrix3d::Zero(), Matrix3d::Zero()};  // dκ/da₁, dκ/da₂ (columns κ₁₁, κ₁₂, κ₂₂)
  double kappa[3] = {0.0, 0.0, 0.0};
  const Eigen::Map<const Vector3d> s[3] = {Eigen::Map<const Vector3d>(y + 6), Eigen::Map<const Vector3d>(y + 9),
                                           Eigen::Map<const Vector3d>(y + 12)};
  if (curved) {
    n = a3 / j;
    for (int i = 0; i < 3; ++i) kappa[i] = r.B[i] - s[i].dot(n);
    P -= n * n.transpose();
    // dκ_i/dy: (P S_i) × a2 / j at a1, a1 × (P S_i) / j at a2, −n at S_i
    for (int i = 0; i < 3; ++i) {
      const Vector3d Ps = P * s[i];
      K[0].col(i) = Ps.cross(a2) / j;
      K[1].col(i) = a1.cross(Ps) / j;
    }
  }
  double nr[3], mr[3];
  Matrix6 D;
  law.material(r, E, curved ? kappa : nullptr, nr, mr, D);
  assert((Law::kCoupled || D.template topRightCorner<3, 3>().isZero(0.0)) && "a law that couples E and kappa says so");
  Eigen::Map<Matrix15> H(Hout);
  // The material part's upper blocks: with B_X = [dE/dX dκ/dX] (3 x 6), H_XY = B_X D B_Yᵀ; at
  // S_i, B = −n e_{3+i}ᵀ, so H(a_X, S_j) = −(B_X D)_{:,3+j} nᵀ and H(S_i, S_j) = D_{3+i,3+j} n nᵀ.
  const auto materialUpper = [&] {
    Matrix3d BD[2][2];  // [a_X][membrane, bending columns of B_X D]
    const Matrix3d Dmm = D.topLeftCorner<3, 3>(), Dbb = D.bottomRightCorner<3, 3>();
    for (int x = 0; x < 2; ++x) {
      BD[x][0].noalias() = G[x] * Dmm;
      BD[x][1].noalias() = K[x] * Dbb;
      if constexpr (Law::kCoupled) {
        const Matrix3d Dmb = D.topRightCorner<3, 3>();
        BD[x][0].noalias() += K[x] * Dmb.transpose();
        BD[x][1].noalias() += G[x] * Dmb;
      }
    }
    for (int x = 0; x < 2; ++x)
      for (int z = x; z < 2; ++z)
        H.block<3, 3>(3 * x, 3 * z).noalias() = BD[x][0] * G[z].transpose() + BD[x][1] * K[z].transpose();
    if (!curved) {
      H.block<6, 9>(0, 6).setZero();
      H.block<9, 9>(6, 6).setZero();
      return;
    }
    for (int x = 0; x < 2; ++x)
      for (int i = 0; i < 3; ++i) H.block<3, 3>(3 * x, 6 + 3 * i).noalias() = -BD[x][1].col(i) * n.transpose();
    const Matrix3d nn = n * n.transpose();
    for (int i = 0; i < 3; ++i)
      for (int k = i; k < 3; ++k) H.block<3, 3>(6 + 3 * i, 6 + 3 * k) = D(3 + i, 3 + k) * nn;
  };
  // the lower blocks from the upper
  const auto mirror = [&] {
    for (int x = 0; x < 5; ++x)
      for (int z = x + 1; z < 5; ++z) H.block<3, 3>(3 * z, 3 * x) = H.block<3, 3>(3 * x, 3 * z).transpose();
  };
  materialUpper();
  const Matrix3d I = Matrix3d::Identity();
  const double n11 = nr[0], n12 = nr[1], n22 = nr[2];
  H.block<3, 3>(0, 0) += n11 * I;
  H.block<3, 3>(0, 3) += n12 * I;
  H.block<3, 3>(3, 3) += n22 * I;
  if (curved) {
    const double mu[3] = {mr[0], 2.0 * mr[1], mr[2]};  // W m
    // -2 Σ μ_i dS_i · dn, dn = J1 da1 + J2 da2, J1 = -P [a2]× / j, J2 = P [a1]× / j
    double c2[9], c1[9];
    crossMatrix(a2.data(), 1.0, c2);
    crossMatrix(a1.data(), 1.0, c1);
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> X2(c2), X1(c1);
    const Matrix3d J1t = (-P * X2 / j).transpose(), J2t = (P * X1 / j).transpose();
    for (int i = 0; i < 3; ++i) {
      H.block<3, 3>(0, 6 + 3 * i) -= mu[i] * J1t;
      H.block<3, 3>(3, 6 + 3 * i) -= mu[i] * J2t;
    }
    // -v · d²n with v = Σ μ_i S_i: -(dã)ᵀ Hφ dã - 2 w · (da1 × da2), Hφ = -(n wᵀ + w nᵀ +
    // (v·n)/j P)/j, w = P v / j, dã = Q (da1, da2) with Q = [-[a2]×, [a1]×]
    const Vector3d v = mu[0] * s[0] + mu[1] * s[1] + mu[2] * s[2];
    const double vn = v.dot(n);
    const Vector3d w = P * v / j;
    const Matrix3d Hphi = (n * w.transpose() + w * n.transpose() + (vn / j) * P) / j;
    const Matrix3d HX2 = Hphi * X2, HX1 = Hphi * X1;
    H.block<3, 3>(0, 0).noalias() += X2.transpose() * HX2;
    H.block<3, 3>(0, 3).noalias() -= X2.transpose() * HX1;
    H.block<3, 3>(3, 3).noalias() += X1.transpose() * HX1;
    double cw[9];
    crossMatrix(w.data(), 1.0, cw);
    H.block<3, 3>(0, 3) += Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(cw);
  }
  mirror();
  bool projected = false;
  if (project) {
    // positive definite to a relative margin: keep; else the PSD fallback
    const double scale = H.diagonal().cwiseAbs().maxCoeff();
    Matrix15 test = H;
    test.diagonal().array() += 1e-10 * scale + 1e-300;
    Eigen::LLT<Matrix15> llt(test);
    if (llt.info() != Eigen::Success) {
      projected = true;
      // the nearest positive semidefinite matrix: negative eigenvalues to zero
      Eigen::SelfAdjointEigenSolver<Matrix15> es(0.5 * (H + H.transpose()));
      if (es.info() == Eigen::Success) {
        H = es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).asDiagonal() * es.eigenvectors().transpose();
      } else {  // material part and the membrane's, its stress made PSD: PSD by construction
        Eigen::Matrix2d nn;
        nn << n11, n12, n12, n22;
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es2(nn);
        const Eigen::Matrix2d nPsd =
            es2.eigenvectors() * es2.eigenvalues().cwiseMax(0.0).asDiagonal() * es2.eigenvectors().transpose();
        materialUpper();
        H.block<3, 3>(0, 0) += nPsd(0, 0) * I;
        H.block<3, 3>(0, 3) += nPsd(0, 1) * I;
        H.block<3, 3>(3, 3) += nPsd(1, 1) * I;
        mirror();
      }
    }
  }
  // symmetric to the last bit: each pair of entries to its mean, once (0.5 (a + b), as
  // 0.5 (H + Hᵀ) makes it): all of them after the eigen-decomposition, else only the diagonal
  // blocks' (the others are mirrored)
  const auto mean = [&H](int i, int k) {
    const double v = 0.5 * (H(i, k) + H(k, i));
    H(i, k) = v;
    H(k, i) = v;
  };
  if (projected) {
    for (int c = 0; c < 15; ++c)
      for (int r = c + 1; r < 15; ++r) mean(r, c);
  } else {
    for (int b = 0; b < 15; b += 3) {
      mean(b + 1, b);
      mean(b + 2, b);
      mean(b + 2, b + 1);
    }
  }
  return projected;
}

}  // namespace bsdeform::shell
