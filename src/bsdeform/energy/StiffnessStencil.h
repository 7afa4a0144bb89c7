// SPDX-License-Identifier: MIT
#pragma once
/// @file StiffnessStencil.h
/// The stiffness operator A of eq. 7 for every boundary condition, exact and O(N1 N2).
///
/// A is a sum of Kronecker products of 1-D Gram matrices over [0,1]:
/// \f[ A = \omega_{10} G_u^1 \otimes G_v^0 + \omega_{01} G_u^0 \otimes G_v^1
///        + 2\omega_{11} G_u^1 \otimes G_v^1 + \omega_{20} G_u^2 \otimes G_v^0
///        + \omega_{02} G_u^0 \otimes G_v^2, \qquad
///   G^p_{kj} = \int_0^1 D^p b_{k,h}\, D^p b_{j,h}\, du. \f]
/// With h = 1/(N+n) a row k whose B-spline lies inside [0,1] (k = 0..N-1) is the whole-line
/// value \f$h^{1-2p} g_p(j-k)\f$ (Toeplitz); only the 2n rows of the outer layers are
/// truncated integrals (GramRows1D). A periodic direction folds k onto k mod (N+n) (circulant).
/// So the interior is one shift-invariant 2-D stencil S(d) (the fast kernel), and the rows of
/// the outer layers of a FREE side form a band of O(n (N1 + N2)) points with exact rows.
/// Clamped layers are not unknowns; applying A to the full net includes their coupling
/// (A_IB P_B).

#include <Eigen/Sparse>
#include <functional>
#include <utility>
#include <vector>

#include "bsdeform/spline/SplineSpace.h"

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

/// The exact rows of the 1-D Gram matrices \f$G^p\f$ (p = 0, 1, 2) of one direction over [0,1].
/// Row types: 0 for the Toeplitz rows (k = 0..N-1, and every row of a periodic direction);
/// 1..n for the layers k = -n..-1 and n+1..2n for k = N..N+n-1 (truncated integrals).
///
/// A side with derived layers (SIMPLY_SUPPORTED, BUILT_IN; SplineSpace::EdgeLayers) changes the
/// unknowns: the full layer vector is y = T x + const, T the identity on moving layers and Z on
/// derived ones. The row of a source layer s is then the row of \f$T^T G\f$,
/// \f$G(s, \cdot) + \sum_e Z_{es} G(e, \cdot)\f$, still within d = -n..n, applied to the whole
/// net with its derived layers up to date: that is the gradient of the energy with respect to
/// x. rowSum() stays the layer's own integral: the mass of the unknowns is \f$T^T W T\f$ for
/// the layers' masses W (Simulation, EdgeMass), not a diagonal.
class GramRows1D {
 public:
  GramRows1D(const BSplineBasis1D& basis, Boundary lo, Boundary hi);
  int degree() const { return m_n; }
  /// Row type of net layer i (0-based, k = i - n).
  int rowType(int layer) const;
  /// \f$G^p(k, k+d)\f$ for a row of type `type`, d = -n..n; zero where k+d is not a B-spline
  /// of the index set. Scaled by \f$h^{1-2p}\f$.
  double entry(int p, int type, int d) const { return m_rows[p][size_t(type) * (2 * m_n + 1) + (d + m_n)]; }
  /// \f$\int_0^1 b_{k,h}\f$ for a row of type `type` (h for type 0): the lumped mass factor.
  double rowSum(int type) const { return m_rowSum[size_t(type)]; }
  /// \f$\lambda_{max}(T^T T)\f$: |T x|^2 <= this |x|^2 (1 without derived layers).
  double transformBound() const { return m_transformBound; }

 private:
  int m_n;
  int m_numInner;
  bool m_periodic;
  std::vector<double> m_rows[3];
  std::vector<double> m_rowSum;
  double m_transformBound = 1.0;
};

/// Moving points from which StiffnessStencil::centralDifferenceUpdate() and applyMoving() split
/// their interior rows over kernelThreads() (bsdeform/base/Parallel.h); below, waking a thread costs
/// more than it saves (the crossover is measured for the explicit step in docs/benchmarks.md).
/// The result is the same bits either way. Benchmarks and tests may change it (0: always split).
long explicitParallelMinPoints();
void setExplicitParallelMinPoints(long points);

class StiffnessStencil {
 public:
  /// @throws std::invalid_argument for a negative or non-finite weight (names it)
  StiffnessStencil(const SplineSpace& space, const Weights& weights);

  const Weights& weights() const { return m_weights; }
  int radiusU() const { return m_ru; }
  int radiusV() const { return m_rv; }
  /// Interior stencil \f$a(B_k, B_{k+d})\f$ for a B-spline k inside [0,1]^2 (whole-line
  /// integrals), zero for |d1| > n1 or |d2| > n2.
  double coefficient(int d1, int d2) const;
  /// The symbol bound of the whole-line stencil alone (no derived-layer factor).
  double symbolBound() const;
  const GramRows1D& gramU() const { return m_gu; }
  const GramRows1D& gramV() const { return m_gv; }
  /// Whether some moving row is not an interior-stencil row (a FREE side exists).
  bool hasBand() const { return !m_band.empty(); }

  /// out = (A P) on the moving points for a full net P (periodic copies in sync): for every
  /// moving point m, the derivative of a(S, S)/2 with respect to P_m. Includes A_IB P_B when P
  /// holds the held points. `out` is resized to numMoving x 3 (order of movingToNet). Splits its
  /// rows over kernelThreads() like centralDifferenceUpdate(), with the same bits.
  void applyMoving(const ControlNet& net, ControlNet& out) const;

  /// The moving–moving block A_II (numMoving x numMoving, scalar, shared by x, y, z).
  Eigen::SparseMatrix<double> movingMatrix() const;
  /// The diagonal of movingMatrix() (numMoving), without assembling it: what Jacobi scaling of
  /// the implicit system needs.
  Eigen::VectorXd movingDiagonal() const;

  /// Upper bound of \f$\lambda_{max}(A_{II})\f$ from the interior stencil's symbol (the
  /// Fourier transform of S), sampled on a grid and corrected with Bernstein's inequality.
  /// Valid for every boundary condition: a truncated integral is at most the whole-line one, so
  /// \f$x^T A_{II} x \le x^T T x\f$ for the Toeplitz section T, and a circulant's spectrum is
  /// its symbol sampled. With derived layers (GramRows1D) the unknowns x give the layers
  /// y = T x, and the bound is multiplied by transformBound() of each direction.
  double eigenvalueBound() const;
  /// Gershgorin bound sum_d |S(d)| (looser, for comparison). Like eigenvalueBound() it
  /// includes the factor transformBound() of each direction with derived layers.
  double gershgorinBound() const;

  /// Upper bound of \f$\lambda_{max}(R^{-1} A_{II})\f$ with R the lumped (row-sum) mass of
  /// unit density, element by element: \f$A = \sum_e A_e\f$, \f$R = \sum_e R_e\f$ with
  /// \f$R_e = \mathrm{diag}(\int_e B_k)\f$, so \f$x^TAx \le \max_e \lambda(A_e, R_e)\, x^TRx\f$.
  /// Every knot cell has the same element matrices, so this is one small eigenproblem, valid
  /// for every boundary condition (needed when a FREE side makes R smaller at the edges). With
  /// derived layers it bounds \f$\lambda_{max}((T^T R T)^{-1} T^T A T)\f$ alike (the Rayleigh
  /// quotient of y = T x).
  double elementEigenvalueBound() const;

  /// One fused explicit central-difference update of every free point (design.md §2), in
  /// increment form: P_new = P + alpha (L - (A P)_free) + gamma (P - P_old), written over
  /// `previous`. Uses the same arithmetic as applyMoving(), so L = applyMoving(P) leaves a resting
  /// P exactly unchanged.
  /// Fixed points of `previous` are left as they are (the caller keeps them equal to P's).
  /// @param[in] load numFree x 3 effective load, free order
  /// @return false if any new coordinate is not finite or exceeds `limit` in magnitude
  /// @param[in] alphaScale if not null, alpha is multiplied by alphaScale(i, j) on the band
  ///            points (lumped mass smaller at a free edge); interior points use alpha as is
  /// Periodic copies of `previous` are not refreshed (the caller does, after holding pins).
  /// @param[in] bandSolve if not null (sides with derived layers: a mass matrix that is not
  ///            diagonal there), it replaces alphaScale: bandSolve(k0, k1, r, out) gets the
  ///            residuals L - A P of band points k0..k1-1 (order of bandPoints()) in r[0..] and
  ///            writes m M^-1 of them to out[0..], m the mass that alpha is for. It is called
  ///            for the band points of one interior row (possibly on several threads at once),
  ///            then for those of the rows before and after the interior ones: M must couple a
  ///            band point only with band points of the same call.
  using BandSolve = std::function<void(size_t, size_t, const Eigen::RowVector3d*, Eigen::RowVector3d*)>;
  bool centralDifferenceUpdate(const ControlNet& current, ControlNet& previous, const ControlNet& load,
                               double alpha, double gamma, double limit,
                               const std::function<double(int, int)>& alphaScale = nullptr,
                               const BandSolve& bandSolve = nullptr) const;

  /// A moving point outside the interior stencil's reach (a row of a FREE, SIMPLY_SUPPORTED or
  /// BUILT_IN side's outer layers).
  struct BandPoint {
    int i, j;        ///< net layers
    int table;       ///< index of its coefficient table
    Eigen::Index m;  ///< moving-point number
  };
  const std::vector<BandPoint>& bandPoints() const { return m_band; }

 private:

  /// fn(row, col, coefficient) for every entry of A_II, row by row (entries of periodic copies
  /// and derived layers that fold onto the same column come separately and add).
  template <typename EntryFunction>
  void forEachMovingEntry(EntryFunction&& fn) const;
  /// Blocks of interior rows of one explicit update or applyMoving(): 4 kernelThreads() above the
  /// threshold, else 1.
  int explicitStepParts() const;
  static constexpr int kMaxStepParts = 64;
  /// Interior rows [begin, end) of block `part` of `parts` (consecutive, covering them all).
  std::pair<int, int> interiorRowBlock(int part, int parts) const;
  /// fn(i, rowStart, q) for the interior rows i in [rowBegin, rowEnd); q = folded row sums.
  template <typename RowFunction>
  void forEachInteriorRow(const ControlNet& net, int rowBegin, int rowEnd, RowFunction&& fn) const;
  /// sum_d C(d) P(i+d1, j+d2) for a band point (d = -n..n, wrapped or skipped at the ends)
  Eigen::RowVector3d bandRow(const ControlNet& net, size_t k) const;
  /// Net layer of neighbour layer `l` in u / v (periodic wrap), or -1 if there is no B-spline.
  int neighbourU(int l) const;
  int neighbourV(int l) const;

  const SplineSpace* m_space;
  Weights m_weights;
  int m_ru, m_rv;
  GramRows1D m_gu, m_gv;
  /// Folded unique coefficients: m_half[a * (rv+1) + b] = S(±a, ±b), a = 0..ru, b = 0..rv.
  std::vector<double> m_half;
  /// Interior rows and columns: moving layers whose rows are Toeplitz.
  LayerRange m_rowsInterior, m_colsInterior;
  /// Band: its points and the full (2n1+1)(2n2+1) coefficient table of each row-type pair.
  std::vector<BandPoint> m_band;
  std::vector<std::vector<double>> m_tables;
  /// Each table's non-zero coefficients in (d1, d2) order with the offset of their neighbour in
  /// doubles, and per band point whether every such neighbour lies in the net without a
  /// periodic wrap: bandRow() then sums straight from the net (the same terms in the same
  /// order, so the same bits).
  struct BandEntry {
    long offset, mirror;  ///< mirror: the neighbour at -d1 with the same coefficient, or 0 (none)
    double c;
  };
  std::vector<std::vector<BandEntry>> m_tableEntries;
  std::vector<char> m_bandDirect;
  std::vector<size_t> m_bandRowStart;  ///< per net row (and one past the last): its first band point
  /// A band row (an outer layer of a FREE, SIMPLY_SUPPORTED or BUILT_IN u side) whose points in
  /// the interior columns are Toeplitz in v: they are computed by the vectorised row kernel
  /// with the 2 n1 + 1 rows around unfolded (non-periodic v only). `half` is its
  /// (2 n1 + 1) x (n2 + 1) table, `band` the band index of its first interior column.
  struct KernelRow {
    int i;
    size_t band;
    std::vector<double> half;
  };
  std::vector<KernelRow> m_kernelRows;
  std::vector<int> m_bandKernelRow;  ///< per band point: its KernelRow, or -1
  /// (A P) at the interior columns of kernel row r (3 x interior columns doubles).
  void kernelRow(const ControlNet& net, const KernelRow& r, double* out) const;
};

}  // namespace bsdeform
