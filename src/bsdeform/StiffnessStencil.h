// SPDX-License-Identifier: MIT
#pragma once
/// @file StiffnessStencil.h
/// The stiffness operator A of eq. 7 as an exact shift-invariant stencil.
///
/// With h = 1/(N+n) every free B-spline has its support inside [0,1]^2, so
/// \f$a(B_k, B_j)\f$ for a free k depends only on d = j - k (fixed j included: that is A_IB).
/// Each weight term factorises into 1-D integrals
/// \f$G^p(d) = \int D^p b_{k,h} D^p b_{k+d,h} = h^{1-2p} g_p(d)\f$:
/// \f[ S(d) = \omega_{10} G_u^1 G_v^0 + \omega_{01} G_u^0 G_v^1 + 2\omega_{11} G_u^1 G_v^1
///          + \omega_{20} G_u^2 G_v^0 + \omega_{02} G_u^0 G_v^2. \f]

#include <Eigen/Sparse>
#include <vector>

#include "bsdeform/SplineSpace.h"

namespace bsdeform {

/// The five weights of the energy (paper §3). All must be finite and >= 0.
struct Weights {
  double w10 = 0.1;   ///< \f$\omega_{10}\f$: stretching along u
  double w01 = 0.1;   ///< \f$\omega_{01}\f$: stretching along v
  double w11 = 0.01;  ///< \f$\omega_{11}\f$: twist (enters eq. 7 as 2 w11)
  double w20 = 0.01;  ///< \f$\omega_{20}\f$: bending along u
  double w02 = 0.01;  ///< \f$\omega_{02}\f$: bending along v
};

/// \f$g_p(d) = \int_{\mathbb{R}} D^p b^n(x)\, D^p b^n(x-d)\, dx\f$ for d = 0..n (even in d),
/// exact (Gauss–Legendre with n+1 points per unit span). Zero for p > n.
std::vector<double> cardinalGram(int degree, int order);

class StiffnessStencil {
 public:
  /// @throws std::invalid_argument for a negative or non-finite weight (names it)
  StiffnessStencil(const SplineSpace& space, const Weights& weights);

  int radiusU() const { return m_ru; }
  int radiusV() const { return m_rv; }
  /// \f$a(B_k, B_{k+d})\f$, zero for |d1| > n1 or |d2| > n2.
  double coefficient(int d1, int d2) const;

  /// out = (A P)_free for a full net P: for every free point k, sum_d S(d) P(k+d).
  /// `out` is resized to numFree x 3 (free order). Includes A_IB P_B when P holds fixed points.
  void applyFree(const ControlNet& net, ControlNet& out) const;

  /// The free–free block A_II (numFree x numFree, scalar, shared by x, y, z).
  Eigen::SparseMatrix<double> interiorMatrix() const;

  /// Upper bound of \f$\lambda_{max}(A_{II})\f$ from the stencil's symbol (the Fourier
  /// transform of S; A_II is a finite section of the Toeplitz operator, so its spectrum lies
  /// below the symbol's maximum), sampled on a grid and corrected with Bernstein's inequality.
  double eigenvalueBound() const;
  /// Gershgorin bound sum_d |S(d)| (looser, for comparison).
  double gershgorinBound() const;

  /// One fused explicit central-difference update of every free point (design.md §2), in
  /// increment form: P_new = P + alpha (L - (A P)_free) + gamma (P - P_old), written over
  /// `previous`. Uses the same arithmetic as applyFree(), so L = applyFree(P) leaves a resting
  /// P exactly unchanged.
  /// Fixed points of `previous` are left as they are (the caller keeps them equal to P's).
  /// @param[in] load numFree x 3 effective load, free order
  /// @return false if any new coordinate is not finite or exceeds `limit` in magnitude
  bool centralDifferenceUpdate(const ControlNet& current, ControlNet& previous, const ControlNet& load,
                               double alpha, double gamma, double limit) const;

 private:
  template <typename RowFunction>
  void forEachFreeRow(const ControlNet& net, RowFunction&& fn) const;

  const SplineSpace* m_space;
  int m_ru, m_rv;
  /// Folded unique coefficients: m_half[a * (rv+1) + b] = S(±a, ±b), a = 0..ru, b = 0..rv.
  std::vector<double> m_half;
};

}  // namespace bsdeform
