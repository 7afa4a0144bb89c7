// SPDX-License-Identifier: MIT
#pragma once
/// @file EdgeMass.h
/// The mass matrix of the unknowns next to SIMPLY_SUPPORTED and BUILT_IN sides.
///
/// A derived layer (SplineSpace::EdgeLayers) is not an unknown, but its control points move
/// (y = T x + const) and keep their own mass: the kinetic energy is \f$\tfrac12 \sum_l W_l
/// |\dot y_l|^2\f$ over every layer that moves, W the model's masses per control point (m for
/// NODAL, rho times the row sum for LUMPED), so the mass of the unknowns is \f$M = T^T W T\f$.
/// It is the Kronecker product \f$M_u \otimes M_v\f$ of 1-D matrices that are diagonal except
/// for one small dense block (the source layers) per such side. With it the physics does not
/// depend on which layers were eliminated, the total mass is that of the moving layers, and
/// \f$\lambda_{max}(M^{-1} T^T A T) \le \lambda_{max}(W^{-1} A)\f$ over the whole layer space:
/// the stability bounds of the other sides hold unchanged.

#include <Eigen/Sparse>
#include <vector>

#include "bsdeform/spline/SplineSpace.h"
#include "bsdeform/energy/StiffnessStencil.h"

namespace bsdeform {

class EdgeMass {
 public:
  /// @param lumped  W = density * rowSum_u * rowSum_v (LUMPED) or density (NODAL)
  EdgeMass(const SplineSpace& space, const GramRows1D& gu, const GramRows1D& gv, bool lumped, double density);

  /// W of net point (i, j): the mass of one control point of the model (moving or derived).
  double layerMass(int i, int j) const { return m_scale * m_wu[size_t(i)] * m_wv[size_t(j)]; }
  /// The diagonal of M at moving net point (i, j).
  double diagonal(int i, int j) const;

  /// out = M x, x and out numMoving x 3 (order of SplineSpace::movingToNet).
  void apply(const ControlNet& x, ControlNet& out) const;
  /// r = M^-1 r (numMoving x 3).
  void solve(ControlNet& r) const;
  /// The off-diagonal entries of M (moving-point numbers), times `scale`.
  std::vector<Eigen::Triplet<double>> offDiagonal(double scale) const;
  /// The explicit step's band solve (StiffnessStencil::centralDifferenceUpdate): for band
  /// point k of `band`, (scale M^-1 r)_k = sum over plan entries (index into the band,
  /// coefficient) of coefficient * r[index], as CSR rows (`start` has band.size() + 1 entries).
  /// Every point M couples a band point with is a band point (the source layers are).
  struct BandPlan {
    std::vector<int> start;
    std::vector<std::pair<int, double>> entries;
  };
  BandPlan bandPlan(const std::vector<StiffnessStencil::BandPoint>& band, double scale) const;
  /// Pinned moving points (by moving-point number): solve() and bandPlan() then give the
  /// accelerations of the others with the pinned ones at zero, \f$M_{ff}^{-1} r_f\f$ (pinned
  /// entries of the result are zero).
  void setPinned(const std::vector<Eigen::Index>& pinnedMoving);

 private:
  const SplineSpace* m_space;
  double m_scale;
  std::vector<double> m_wu, m_wv;  ///< per net layer
  /// Rows of M_u, M_v and of their inverses over the moving layers (net layers as keys).
  std::vector<std::vector<LayerWeight>> m_rowU, m_rowV, m_invU, m_invV;
  /// Source block of each net layer (-1: a layer of its own). M couples a point only within the
  /// product of its two blocks; such a group with a pinned point is solved apart.
  std::vector<int> m_blockU, m_blockV;
  struct PinnedGroup {
    std::vector<Eigen::Index> free;  ///< the group's unpinned moving points
    Eigen::MatrixXd inverse;          ///< of M restricted to them
  };
  std::vector<char> m_pinned;  ///< per moving point
  std::vector<std::pair<std::pair<long long, long long>, PinnedGroup>> m_pinnedGroups;
  std::pair<long long, long long> groupKey(int i, int j) const;
  /// Row of moving net point (i, j) of scale M^-1 (of M_ff^-1 within a group with a pin; empty
  /// for a pinned point): (moving-point number, coefficient). What solve() and bandPlan() use.
  void inverseRow(int i, int j, double scale, std::vector<std::pair<Eigen::Index, double>>& out) const;
  const PinnedGroup* pinnedGroup(int i, int j) const;
};

}  // namespace bsdeform
