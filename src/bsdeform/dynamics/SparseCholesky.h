// SPDX-License-Identifier: MIT
#pragma once
/// @file SparseCholesky.h
/// The Newton tangent's Cholesky factorisation: CHOLMOD's supernodal LLᵀ with its symbolic
/// analysis kept while the pattern stays, fed the permuted matrix it factorises directly.
///
/// cholmod_factorize, given the lower triangle of K (what TangentMatrix assembles), makes
/// tril(P K Pᵀ) for its numeric factorisation with two permuted transposes, each of them a
/// counting pass, a scatter and two allocations of the whole matrix, at every factorisation
/// (5 % of a 32² Newton iteration). The pattern is the same from one factorisation to the next,
/// so here those transposes run once, at the analysis, on the entries' own indices: what they
/// make is a gather list, and every factorisation after that is one gather of K's values into
/// the kept tril(P K Pᵀ) and cholmod_super_numeric on it. The matrix CHOLMOD factorises, its
/// ordering, supernodes and solve are those of cholmod_factorize and cholmod_solve (Eigen's
/// CholmodSupernodalLLT before): the same bits.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <vector>

namespace bsdeform {

/// The Newton tangent's supernodal Cholesky factorisation (CHOLMOD), its symbolic analysis kept
/// while the pattern stays; the matrix CHOLMOD factorises made by one gather (see the file's note).
class SparseCholesky {
 public:
  /// CHOLMOD's fill-reducing orderings (the analysis's choice, or one forced: benchmarks).
  enum class Ordering { Default, Metis, NestedDissection };

  explicit SparseCholesky(Ordering ordering = Ordering::Default);
  ~SparseCholesky();
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;

  /// Factorises the symmetric matrix whose lower triangle K holds (compressed columns, rows
  /// ascending, no duplicates, as TangentMatrix and Eigen's triangularView make it; entries
  /// above the diagonal, if K has them, are not read). The
  /// symbolic analysis is made again only when K's pattern is not the last one's. False if K is
  /// not positive definite (then solve() must not be called until a factorisation succeeds).
  /// K must be compressed (std::invalid_argument otherwise).
  bool factor(const Eigen::SparseMatrix<double>& K);
  /// Whether the last factor() succeeded.
  bool isFactored() const { return m_isFactored; }
  /// K⁻¹ B for the last successful factorisation; one column per right-hand side (a vector is
  /// one column).
  Eigen::MatrixXd solve(const Eigen::Ref<const Eigen::MatrixXd>& B);

  /// How many symbolic analyses factor() has made.
  int analyses() const { return m_analyses; }
  /// CHOLMOD's counts from the last analysis: the factor's non-zeros (its simplicial count,
  /// without the supernodes' explicit zeros) and the flops of one numeric factorisation; -1
  /// before the first analysis.
  double factorNonZeros() const;
  double factorFlops() const;

 private:
  void analyse(const Eigen::SparseMatrix<double>& K);

  struct Cholmod;
  std::unique_ptr<Cholmod> m_c;
  /// The pattern of the last analysis (empty: none yet).
  std::vector<int> m_outer, m_inner;
  /// tril(P K Pᵀ)'s value j is K's value m_gather[j].
  std::vector<int> m_gather;
  int m_analyses = 0;
  bool m_isFactored = false;
};

}  // namespace bsdeform
