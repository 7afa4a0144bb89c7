// SPDX-License-Identifier: MIT
#include "bsdeform/dynamics/MassMatrix.h"

#include <Eigen/SparseCholesky>
#include <stdexcept>

namespace bsdeform {

struct MassMatrix::Factor {
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
  std::vector<Eigen::Index> freeOf;  ///< unknown -> row of the reduced matrix, -1 if pinned
  Eigen::Index size = 0;
};

MassMatrix::MassMatrix(Eigen::VectorXd diagonal, std::vector<char> pinned)
    : m_diagonal(std::move(diagonal)), m_pinned(std::move(pinned)) {
  const Eigen::Index n = m_diagonal.size();
  if (Eigen::Index(m_pinned.size()) != n) throw std::invalid_argument("MassMatrix: one pinned flag per unknown");
  for (Eigen::Index f = 0; f < n; ++f)
    if (!(m_diagonal[f] > 0.0)) throw std::runtime_error("MassMatrix: a mass that is not positive");
  m_matrix.resize(n, n);
  m_matrix.reserve(Eigen::VectorXi::Constant(n, 1));
  for (Eigen::Index f = 0; f < n; ++f) m_matrix.insert(f, f) = m_diagonal[f];
  m_matrix.makeCompressed();
}

MassMatrix::MassMatrix(Eigen::SparseMatrix<double> matrix, std::vector<char> pinned)
    : m_matrix(std::move(matrix)), m_pinned(std::move(pinned)) {
  if (m_matrix.rows() != m_matrix.cols() || Eigen::Index(m_pinned.size()) != m_matrix.rows())
    throw std::invalid_argument("MassMatrix: a square matrix and one pinned flag per unknown");
  m_matrix.makeCompressed();
  m_diagonal = m_matrix.diagonal();
  for (int k = 0; k < m_matrix.outerSize() && m_diagonalOnly; ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(m_matrix, k); it; ++it)
      if (it.row() != it.col() && it.value() != 0.0) {
        m_diagonalOnly = false;
        break;
      }
  if (!m_diagonalOnly) factorise();
}

MassMatrix::~MassMatrix() = default;

std::unique_ptr<MassMatrix> MassMatrix::folded(const SplineSpace& space, const Eigen::VectorXd& netMass,
                                               std::vector<char> pinned) {
  std::vector<int> start;
  std::vector<std::pair<Eigen::Index, double>> fold;
  space.foldMap(start, fold);
  const Eigen::Index n = space.numMoving();
  std::vector<Eigen::Triplet<double>> t;
  for (Eigen::Index p = 0; p < space.netSize(); ++p)
    for (int a = start[size_t(p)]; a < start[size_t(p) + 1]; ++a)
      for (int b = start[size_t(p)]; b < start[size_t(p) + 1]; ++b)
        t.emplace_back(int(fold[size_t(a)].first), int(fold[size_t(b)].first),
                       netMass[p] * fold[size_t(a)].second * fold[size_t(b)].second);
  Eigen::SparseMatrix<double> M(n, n);
  M.setFromTriplets(t.begin(), t.end());
  return std::make_unique<MassMatrix>(std::move(M), std::move(pinned));
}

void MassMatrix::factorise() {
  auto factor = std::make_unique<Factor>();
  const Eigen::Index n = size();
  factor->freeOf.assign(size_t(n), -1);
  for (Eigen::Index f = 0; f < n; ++f)
    if (!m_pinned[size_t(f)]) factor->freeOf[size_t(f)] = factor->size++;
  std::vector<Eigen::Triplet<double>> reduced;
  for (int k = 0; k < m_matrix.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(m_matrix, k); it; ++it) {
      const Eigen::Index r = factor->freeOf[size_t(it.row())], c = factor->freeOf[size_t(it.col())];
      if (r >= 0 && c >= 0) reduced.emplace_back(int(r), int(c), it.value());
    }
  Eigen::SparseMatrix<double> Mf(factor->size, factor->size);
  Mf.setFromTriplets(reduced.begin(), reduced.end());
  factor->ldlt.compute(Mf);
  if (factor->ldlt.info() != Eigen::Success) throw std::runtime_error("the mass matrix T^T W T is singular");
  m_factor = std::move(factor);
}

ControlNet MassMatrix::apply(const ControlNet& a) const {
  if (m_diagonalOnly) return m_diagonal.asDiagonal() * a;
  return m_matrix * a;
}

void MassMatrix::solve(ControlNet& a) const {
  if (m_diagonalOnly) {
    for (Eigen::Index f = 0; f < a.rows(); ++f)
      if (m_pinned[size_t(f)])
        a.row(f).setZero();
      else
        a.row(f) /= m_diagonal[f];
    return;
  }
  const Factor& s = *m_factor;
  Eigen::MatrixXd r(s.size, 3);
  for (Eigen::Index f = 0; f < a.rows(); ++f)
    if (s.freeOf[size_t(f)] >= 0) r.row(s.freeOf[size_t(f)]) = a.row(f);
  const Eigen::MatrixXd x = s.ldlt.solve(r);
  for (Eigen::Index f = 0; f < a.rows(); ++f)
    if (s.freeOf[size_t(f)] >= 0)
      a.row(f) = x.row(s.freeOf[size_t(f)]);
    else
      a.row(f).setZero();
}

double MassMatrix::kineticEnergy(const ControlNet& v) const { return 0.5 * (v.array() * apply(v).array()).sum(); }

}  // namespace bsdeform
