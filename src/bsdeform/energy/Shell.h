// SPDX-License-Identifier: MIT
#pragma once
/// @file Shell.h
/// The isogeometric Kirchhoff–Love thin shell (Kiendl et al. 2009) on the model's spline space:
/// the geometrically exact energy the `SHELL` model uses instead of the paper's eq. 7
/// (docs/math.md §16). Per Gauss point of the parameter square, with a_α = S_,α,
/// n = a₁×a₂/|a₁×a₂|, the metric a_αβ = a_α·a_β and the curvature b_αβ = S_,αβ·n of the current
/// surface and A_αβ, B_αβ, J₀ = |A₁×A₂| of the rest surface:
///   membrane strain E = ½(a − A), bending strain κ = B − b,
///   C^{αβγδ} = λ̄ A^{αβ}A^{γδ} + μ (A^{αγ}A^{βδ} + A^{αδ}A^{βγ}),  λ̄ = Eν/(1−ν²), μ = E/(2(1+ν)),
///   W = ∫ (½ t E:C:E + ½ t³/12 κ:C:κ) J₀ du dv   (St. Venant–Kirchhoff, plane stress),
/// or, with ShellMaterialLaw::NeoHookean, W = ∫∫ Ψ(E + zκ) dz J₀ du dv with a compressible
/// neo-Hookean Ψ condensed to plane stress (docs/math.md §16.1).
/// The rest surface is stress-free whatever its shape. Degree 1 in either direction has no
/// second derivatives: the membrane part only.
///
/// Three parts: the kinematics kernel (ShellKinematics.h: the five surface derivatives
/// y = (S_u, S_v, S_uu, S_uv, S_vv) at a Gauss point → E, κ and their derivatives), the material
/// law (ShellLaws.h: E, κ → energy, stress resultants and their tangent) and the element loops
/// here. The kernel is written once for doubles and for dual numbers: the Hessian–vector product
/// is the exact directional derivative of the gradient. The 15 x 15 Hessian of the density, for
/// the assembled tangent, is derived by hand for both laws (docs/math.md §16, "The tangent", and
/// §16.1) and checked against the dual numbers in the tests.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <algorithm>
#include <functional>
#include <vector>

#include "bsdeform/spline/SplineSpace.h"

namespace bsdeform {

/// The shell's strain energy per reference volume (docs/math.md §16 and §16.1).
enum class ShellMaterialLaw {
  SaintVenantKirchhoff,  ///< S = C:E, plane stress, membrane t and bending t³/12 (the default)
  NeoHookean,  ///< compressible neo-Hookean, plane stress by condensing the thickness stretch,
               ///< integrated through the thickness (Kiendl et al. 2015); SVK's for small strains
};

/// A homogeneous, isotropic elastic sheet (SI units in the nodes: Pa, m, kg/m³).
struct ShellMaterial {
  double youngsModulus = 1.0e6;  ///< E > 0
  double poissonRatio = 0.3;     ///< ν in [0, 0.5)
  double thickness = 1.0e-3;     ///< t > 0
  double density = 1000.0;       ///< ρ > 0 (mass per volume; ρ t per rest area)
  ShellMaterialLaw law = ShellMaterialLaw::SaintVenantKirchhoff;  ///< the strain energy
};

/// The two parts of the shell's strain energy.
struct ShellEnergies {
  double membrane = 0.0;
  double bending = 0.0;
  double total() const { return membrane + bending; }
};

/// Which element Hessian ShellEnergy::elementHessians() gives.
/// (A tangent's assembly passes it on to the loads' Jacobians: see Projected and Definite.)
enum class HessianMode {
  Exact,      ///< the exact second derivative of the energy (indefinite under compression)
  Projected,  ///< at each Gauss point where the exact density Hessian is not positive definite,
              ///< its nearest PSD matrix (negative eigenvalues set to zero): PSD everywhere. In
              ///< a tangent the loads' Jacobians stay exact, unless the projection changed no
              ///< Gauss point (the matrix would be the exact one): then as Definite
  Definite,   ///< the energy's as Projected; in a tangent, the loads' Jacobians projected too where
              ///< a load can make its own PSD (JacobianSink::wantsDefinite: barrier contact's pairs)
};

class ShellEnergy {
 public:
  /// Precomputes the rest surface at every Gauss point ((n+1) per knot span and direction).
  /// @throws std::invalid_argument naming the parameter for a bad material, and naming (u, v)
  ///         where the rest surface is degenerate (S_u x S_v = 0: a pole of a sphere or cone)
  ShellEnergy(const SplineSpace& space, const ControlNet& rest, const ShellMaterial& material);

  const ShellMaterial& material() const { return m_material; }
  /// Whether the bending part is present (both degrees >= 2).
  bool hasBending() const { return m_bending; }
  /// Area of the rest surface, ∫ J₀ du dv.
  double restArea() const { return m_restArea; }

  /// Membrane and bending energy of the full net `net` (periodic copies in sync).
  ShellEnergies energy(const ControlNet& net) const;
  /// grad = dW/dP for every point of the full net (netSize x 3), held points included; with
  /// `energy`, also W (the total of energy(), summed in blocks of knot spans in a fixed order:
  /// the same for every thread count, equal to energy().total() up to rounding).
  void gradient(const ControlNet& net, ControlNet& grad, double* energy = nullptr) const;
  /// out = H(net) dir (netSize x 3): the exact directional derivative of gradient().
  void hessianProduct(const ControlNet& net, const ControlNet& dir, ControlNet& out) const;
  /// Triplets of the Hessian of W at `net` over the full net's coordinates (index 3 row + c).
  /// `project`: each Gauss point's 15 x 15 Hessian of the density is projected onto the
  /// positive semidefinite matrices first, so the sum is positive semidefinite (what a Newton
  /// step on an indefinite tangent uses). Duplicates are summed by setFromTriplets.
  void hessian(const ControlNet& net, bool project, std::vector<Eigen::Triplet<double>>& out) const;
  /// The element Hessians of W at `net`: sink(e1, e2, Ke) for every element (knot span e1 in u,
  /// e2 in v), Ke the ((n1+1)(n2+1) x 3)^2 matrix row-major in 3 x 3 blocks [p][q][a][b], local
  /// point p = a * (n2 + 1) + b at net point (e1 + a, e2 + b). The density Hessian is derived
  /// by hand (docs/math.md §16, "The tangent"; §16.1 for the neo-Hookean law's material part),
  /// not by dual numbers. Unless `serial`, sink is
  /// called from several threads at once, for elements of u-blocks that touch disjoint net rows
  /// (each net row's contributions come in the same order for any thread count). Returns
  /// whether the projection changed any Gauss point's Hessian (false for HessianMode::Exact).
  bool elementHessians(const ControlNet& net, HessianMode mode, bool serial,
                       const std::function<void(int, int, const double*)>& sink) const;
  /// Lumped mass of every net point: ρ t ∫ B_k J₀ du dv (the row sums of the consistent mass).
  Eigen::VectorXd lumpedMass() const;
  /// A rigorous upper bound of λ_max(W⁻¹ H(net)) for the diagonal `mass` (net points, each
  /// > 0): the largest row sum of |W⁻¹ H| (Gershgorin), each Gauss point's 3 x 3 blocks bounded
  /// by their row sums. Valid at this state; the explicit scheme re-evaluates it every step.
  double eigenvalueBound(const ControlNet& net, const Eigen::VectorXd& mass) const;
  /// Rest area element J₀ = |S_u x S_v| of the rest surface at (u, v).
  double restAreaElement(double u, double v) const;

  /// Gauss points per knot span and direction.
  int pointsU() const { return m_qu; }
  int pointsV() const { return m_qv; }

  /// Rest data at one Gauss point.
  struct RestPoint {
    double Ac[3];  ///< A^{11}, A^{12}, A^{22} (inverse metric)
    double A[3];   ///< A_11, A_12, A_22
    double T[6];   ///< A_1, A_2 (rest tangents: E = A_a·d_b-symmetrised + d·d/2 with d = a - A,
                   ///< exact for small displacements where a·a - A cancels)
    double B[3];   ///< B_11, B_12, B_22
    double wJ;     ///< quadrature weight x J₀ (h1 h2 included)
  };

 private:
  /// Knot spans in u per block of forEachBlock(), and the number of blocks.
  int blockSize() const { return std::max(m_space.degreeU() + 1, 4); }
  int numBlocks() const { return (m_space.basisU().numSpans() + blockSize() - 1) / blockSize(); }
  template <typename Fn>
  void forEachBlock(Fn&& fn) const;

  const SplineSpace& m_space;
  ControlNet m_rest;
  ShellMaterial m_material;
  bool m_bending = true;
  int m_qu = 0, m_qv = 0;
  /// 1-D tables: value, first and second derivative of the n+1 functions of a span at each
  /// Gauss point (the same in every span of a uniform basis), [q][order][a].
  std::vector<double> m_tu, m_tv;
  std::vector<RestPoint> m_points;  ///< element (e1 * spansV + e2), then q1 * qv + q2
  double m_restArea = 0.0;
};

}  // namespace bsdeform
