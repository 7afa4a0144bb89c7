// SPDX-License-Identifier: MIT
#pragma once
/// @file MultigridOperator.h
/// One multigrid level's operator (Multigrid.h): \f$\tilde K = \sum_t c_t\, U_t \otimes V_t\f$,
/// a sum of Kronecker products of banded 1-D matrices, applied with 1-D passes in O(points).
/// Private to the core (Multigrid.cpp, MultigridTransfer.cpp and the tests): not installed.

#include <Eigen/Core>
#include <vector>

#include "bsdeform/spline/SplineSpace.h"
#include "bsdeform/energy/StiffnessStencil.h"

namespace bsdeform::multigrid {

/// A square banded matrix: entries (i, i + d) for |d| <= bandwidth; in a periodic matrix column
/// i + d wraps modulo the size.
class BandMatrix {
 public:
  BandMatrix() = default;
  /// @throws std::invalid_argument for a periodic matrix of at most 2 bandwidth rows
  BandMatrix(int size, int bandwidth, bool periodic);
  int size() const { return m_size; }
  int bandwidth() const { return m_bw; }
  bool periodic() const { return m_periodic; }
  double& at(int i, int d) { return m_v[size_t(i) * size_t(2 * m_bw + 1) + size_t(d + m_bw)]; }
  double at(int i, int d) const { return m_v[size_t(i) * size_t(2 * m_bw + 1) + size_t(d + m_bw)]; }
  /// Column of offset d in row i, or -1 outside a non-periodic matrix.
  int column(int i, int d) const;
  /// Finds the rows [toeplitzBegin, toeplitzEnd) around the middle that are one row shifted
  /// (same entries, no column wrapped or missing); call after the entries are set.
  void findToeplitzRows();
  int toeplitzBegin() const { return m_toeplitzBegin; }
  int toeplitzEnd() const { return m_toeplitzEnd; }

 private:
  int m_size = 0;
  int m_bw = 0;
  bool m_periodic = false;
  int m_toeplitzBegin = 0, m_toeplitzEnd = 0;
  std::vector<double> m_v;
};

/// One direction of one level: the 1-D matrices of the Kronecker terms and how the level's
/// points coarsen.
struct MultigridDirection {
  std::vector<BandMatrix> matrices;  ///< the distinct 1-D factors of this direction
  /// Kinds of the two ends: a clamped end keeps only coarse B-splines whose children all exist,
  /// a free end every coarse B-spline that has a child.
  bool clampedMin = true, clampedMax = true, periodic = false;
  int size() const { return matrices.empty() ? 0 : matrices.front().size(); }
};

/// c * U[u] (x) V[v]
struct Term {
  double c;
  int u, v;
};

/// Most entries in one row of a level's 1-D matrix.
constexpr int kMaxTaps = 64;

/// out = sum_k coef[k] rows[k] (or out += that) over len entries: one pass that keeps the sum in
/// registers (BSDEFORM_MULTIVERSION: AVX2 where the CPU has it, rounding alike).
void combineRows(const double* const* rows, const double* coef, int count, long len, double* out, bool accumulate);

/// The 1-D Gram matrix G^p of the moving layers of one direction (StiffnessStencil.h); with
/// derived layers (SIMPLY_SUPPORTED, BUILT_IN) T^T G T: a derived neighbour's entry folds onto
/// its source layers (SplineSpace::foldU), which lie within the band.
BandMatrix gramMatrix(const GramRows1D& g, const LayerRange& moving, int netLayers, bool periodic, int p,
                      const std::vector<LayerWeight>& (SplineSpace::*fold)(int) const, const SplineSpace& space);

/// The diagonal matrix of d, periodic like its direction.
BandMatrix diagonalMatrix(const Eigen::VectorXd& d, bool periodic);

/// \f$\tilde K = \sum_t c_t\, U_t \otimes V_t\f$ on mu x mv points (3 coordinates each, v
/// fastest), applied as \f$\sum_j (I \otimes V_j)(A_j \otimes I)\f$ with \f$A_j\f$ the sum of the
/// \f$c_t U_t\f$ that share \f$V_j\f$: one pass of combineRows per row and factor.
class KroneckerOperator {
 public:
  MultigridDirection u, v;
  std::vector<Term> terms;
  int mu = 0, mv = 0;

  Eigen::Index points() const { return Eigen::Index(mu) * mv; }
  /// Builds the factors and work rows, and finds the Toeplitz rows of the v matrices; call once
  /// the directions and terms are set.
  /// @throws std::runtime_error when a factor's band is wider than kMaxTaps
  void prepare();
  /// diag = the diagonal of K~, absSum[k] = sum_t |c_t| |U_t row a|_1 |V_t row b|_1 (>= the
  /// absolute row sum of K~ at point k = a mv + b: the Gershgorin bound's numerator).
  void diagonalAndRowSums(Eigen::VectorXd& diag, Eigen::VectorXd& absSum) const;
  /// out = K~ x, or out = rhs - K~ x when rhs is given (out sized by the caller).
  void apply(const ControlNet& x, const ControlNet* rhs, ControlNet& out);
  /// K~ as a dense points x points matrix (one coordinate), for the coarsest level's solve.
  Eigen::MatrixXd dense() const;

 private:
  /// The operator as sum_j A_j (x) V_j: A_j = sum of c U over the terms with v = j (`vIndex`).
  struct Factor {
    BandMatrix A;
    int vIndex;
  };
  std::vector<Factor> m_factors;
  /// w_j = (A_j (x) I) x for one row, padded by V_j's bandwidth on both sides (zeros, or the
  /// wrapped halo)
  std::vector<std::vector<double>> m_wRows;
};

}  // namespace bsdeform::multigrid
