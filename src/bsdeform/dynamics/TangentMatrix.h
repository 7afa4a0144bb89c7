// SPDX-License-Identifier: MIT
#pragma once
/// @file TangentMatrix.h
/// The Newton tangent over the unknowns' coordinates (index 3 f + c, f a moving control point in
/// the order of SplineSpace::movingToNet), assembled in place into a sparsity pattern fixed once
/// per model: every pair of unknowns that share an element (after the fold T of the net onto
/// the unknowns: periodic copies, derived layers) has a 3 x 3 block, lower triangle only (what
/// CHOLMOD reads with Eigen::Lower). No triplets, no sort: an element's matrix is added through
/// a binary search per block, and the matrix's symbolic factorisation can be kept while the
/// pattern stays. Blocks between points that share no element (self-contact couples two parts
/// of a surface) are added to the pattern as they come: settlePattern() after an assembly makes
/// the pattern the elements' plus exactly the other blocks that assembly touched, so the pattern
/// depends on that assembly alone, not on the ones before it (a resumed run factorises the same
/// matrices).

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <utility>
#include <vector>

#include "bsdeform/spline/SplineSpace.h"

namespace bsdeform {

class TangentMatrix {
 public:
  /// @param foldStart, foldEntries  T: net point p is Σ weight × unknown over the entries
  ///        [foldStart[p], foldStart[p+1]) (ShellModelEnergy::foldStart(); held points have none)
  TangentMatrix(const SplineSpace& space, std::vector<int> foldStart,
                std::vector<std::pair<Eigen::Index, double>> foldEntries);

  /// Every value to zero (the pattern stays).
  void setZero();
  /// Adds scale Tᵀ Ke T for the element matrix Ke of element (e1, e2) (ShellEnergy::
  /// elementHessians() layout: all blocks [p][q], symmetric). Safe from several threads at once
  /// for elements whose net points fold onto disjoint unknowns.
  void addElement(int e1, int e2, const double* Ke, double scale);
  /// Adds the 3 x 3 block B coupling net point p (rows) to net point q (columns), folded through
  /// T. A symmetric contribution is added as its (p, q) and its (q, p) blocks (for p != q); only
  /// the lower triangle is kept. Points of no common element (self-contact) are kept aside until
  /// settlePattern(). Not from several threads at once.
  void addNetBlock(Eigen::Index p, Eigen::Index q, const Eigen::Matrix3d& B);
  /// After an assembly: the pattern becomes the elements' plus the other blocks this assembly
  /// touched (those kept aside added, in the order they came: the same sums as had the pattern
  /// held them from the start); true if it changed (a new symbolic factorisation is due).
  bool settlePattern();
  /// Adds scale (M ⊗ I3) for a symmetric matrix M over the unknowns (the mass T^T W T), whose
  /// pattern lies in the elements'.
  void addScalarMatrix(const Eigen::SparseMatrix<double>& M, double scale);
  /// Held coordinates (mask per coordinate 3 f + c, non-zero held): their rows and columns
  /// cleared and 1 on the diagonal, so a solve leaves them unchanged.
  void applyHeld(const std::vector<char>& heldMask);

  /// The lower triangle (compressed column storage), 3 numMoving square.
  const Eigen::SparseMatrix<double>& matrix() const { return m_matrix; }
  /// y = K x with the full symmetric K (for tests and energy checks).
  Eigen::VectorXd multiply(const Eigen::VectorXd& x) const;

 private:
  /// Position in the value array of entry (row 3 f + a, column 3 g + b), f >= g (a >= b when
  /// f == g); -1 if not in the pattern.
  Eigen::Index position(Eigen::Index f, int a, Eigen::Index g, int b) const;
  void addUnknownBlock(Eigen::Index f, Eigen::Index g, const double* B, double scale, bool transposed);

  const SplineSpace& m_space;
  std::vector<int> m_foldStart;
  std::vector<std::pair<Eigen::Index, double>> m_foldEntries;
  /// For column unknown g: the row unknowns f > g with a block, ascending, in
  /// m_rows[m_rowStart[g] .. m_rowStart[g+1]).
  std::vector<Eigen::Index> m_rowStart, m_rows;
  /// Per entry of m_rows: 1 for a block beyond the elements' (a self-contact coupling).
  std::vector<char> m_rowExtra;
  /// The elements' blocks: for column unknown g the rows in m_baseRows[m_baseStart[g] ..).
  std::vector<Eigen::Index> m_baseStart, m_baseRows;
  /// This assembly's blocks beyond the elements': (g, f), f > g, touched in the pattern, and
  /// those kept aside (not in it yet) with their values, in the order they came.
  std::vector<std::pair<Eigen::Index, Eigen::Index>> m_touched;
  struct Aside {
    Eigen::Index f, g;
    double B[9];
    double scale;
    bool transposed;
  };
  std::vector<Aside> m_aside;
  /// The pattern from m_rowStart and m_rows (values zero).
  void buildMatrix();
  Eigen::SparseMatrix<double> m_matrix;
  std::vector<Eigen::Index> m_heldPositions;  ///< values cleared by applyHeld (built at first use)
  std::vector<Eigen::Index> m_heldDiagonal;
  std::vector<char> m_heldMask;
};

}  // namespace bsdeform
