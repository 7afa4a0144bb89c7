// SPDX-License-Identifier: MIT
#include "bsdeform/dynamics/TangentMatrix.h"

#include <algorithm>
#include <cassert>

namespace bsdeform {

TangentMatrix::TangentMatrix(const SplineSpace& space, std::vector<int> foldStart,
                             std::vector<std::pair<Eigen::Index, double>> foldEntries)
    : m_space(space), m_foldStart(std::move(foldStart)), m_foldEntries(std::move(foldEntries)) {
  const Eigen::Index n = space.numMoving();
  const int S1 = space.basisU().numSpans(), S2 = space.basisV().numSpans();
  const int L1 = space.degreeU() + 1, L2 = space.degreeV() + 1, cols = space.netCols();
  std::vector<std::vector<Eigen::Index>> below(static_cast<size_t>(n));
  std::vector<Eigen::Index> unknowns;
  for (int e1 = 0; e1 < S1; ++e1)
    for (int e2 = 0; e2 < S2; ++e2) {
      unknowns.clear();
      for (int a = 0; a < L1; ++a)
        for (int b = 0; b < L2; ++b) {
          const Eigen::Index p = Eigen::Index(e1 + a) * cols + e2 + b;
          for (int k = m_foldStart[size_t(p)]; k < m_foldStart[size_t(p) + 1]; ++k)
            unknowns.push_back(m_foldEntries[size_t(k)].first);
        }
      std::sort(unknowns.begin(), unknowns.end());
      unknowns.erase(std::unique(unknowns.begin(), unknowns.end()), unknowns.end());
      for (size_t i = 0; i < unknowns.size(); ++i)
        for (size_t j = 0; j < i; ++j) below[size_t(unknowns[j])].push_back(unknowns[i]);
    }
  m_rowStart.assign(size_t(n) + 1, 0);
  for (Eigen::Index g = 0; g < n; ++g) {
    std::vector<Eigen::Index>& r = below[size_t(g)];
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
    m_rowStart[size_t(g) + 1] = m_rowStart[size_t(g)] + Eigen::Index(r.size());
    m_rows.insert(m_rows.end(), r.begin(), r.end());
  }
  m_rowExtra.assign(m_rows.size(), 0);
  m_baseStart = m_rowStart;
  m_baseRows = m_rows;
  buildMatrix();
}

void TangentMatrix::buildMatrix() {
  const Eigen::Index n = Eigen::Index(m_rowStart.size()) - 1;
  // column 3 g + b: rows 3 g + b .. 3 g + 2 (the diagonal block's lower part), then 3 rows per
  // row unknown f > g
  const Eigen::Index size = 3 * n;
  m_matrix.resize(size, size);
  std::vector<Eigen::Index> outer(size_t(size) + 1, 0);
  for (Eigen::Index g = 0; g < n; ++g)
    for (int b = 0; b < 3; ++b)
      outer[size_t(3 * g + b) + 1] = outer[size_t(3 * g + b)] + (3 - b) + 3 * (m_rowStart[size_t(g) + 1] - m_rowStart[size_t(g)]);
  const Eigen::Index nnz = outer.back();
  m_matrix.resizeNonZeros(nnz);
  int* outerPtr = m_matrix.outerIndexPtr();
  int* inner = m_matrix.innerIndexPtr();
  for (Eigen::Index c = 0; c <= size; ++c) outerPtr[c] = int(outer[size_t(c)]);
  for (Eigen::Index g = 0; g < n; ++g)
    for (int b = 0; b < 3; ++b) {
      Eigen::Index at = outer[size_t(3 * g + b)];
      for (int a = b; a < 3; ++a) inner[at++] = int(3 * g + a);
      for (Eigen::Index k = m_rowStart[size_t(g)]; k < m_rowStart[size_t(g) + 1]; ++k)
        for (int a = 0; a < 3; ++a) inner[at++] = int(3 * m_rows[size_t(k)] + a);
    }
  setZero();
}

void TangentMatrix::setZero() {
  std::fill(m_matrix.valuePtr(), m_matrix.valuePtr() + m_matrix.nonZeros(), 0.0);
  m_touched.clear();
  m_aside.clear();
}

bool TangentMatrix::settlePattern() {
  // the blocks beyond the elements' this assembly needs, and those the pattern has
  std::vector<std::pair<Eigen::Index, Eigen::Index>> needed = m_touched, have;
  for (const Aside& a : m_aside) needed.emplace_back(a.g, a.f);
  std::sort(needed.begin(), needed.end());
  needed.erase(std::unique(needed.begin(), needed.end()), needed.end());
  const Eigen::Index n = Eigen::Index(m_rowStart.size()) - 1;
  for (Eigen::Index g = 0; g < n; ++g)
    for (Eigen::Index k = m_rowStart[size_t(g)]; k < m_rowStart[size_t(g) + 1]; ++k)
      if (m_rowExtra[size_t(k)]) have.emplace_back(g, m_rows[size_t(k)]);
  if (needed == have) return false;
  // the new pattern: per column the elements' rows and the needed ones, merged
  const Eigen::SparseMatrix<double> old = m_matrix;
  const std::vector<Aside> aside = std::move(m_aside);
  m_rowStart.assign(size_t(n) + 1, 0);
  m_rows.clear();
  m_rowExtra.clear();
  size_t next = 0;
  for (Eigen::Index g = 0; g < n; ++g) {
    Eigen::Index k = m_baseStart[size_t(g)];
    const Eigen::Index kEnd = m_baseStart[size_t(g) + 1];
    while (k < kEnd || (next < needed.size() && needed[next].first == g)) {
      const bool takeExtra = next < needed.size() && needed[next].first == g &&
                             (k == kEnd || needed[next].second < m_baseRows[size_t(k)]);
      m_rows.push_back(takeExtra ? needed[next++].second : m_baseRows[size_t(k++)]);
      m_rowExtra.push_back(takeExtra ? 1 : 0);
    }
    m_rowStart[size_t(g) + 1] = Eigen::Index(m_rows.size());
  }
  buildMatrix();
  // this assembly's values where the two patterns share an entry (an extra no longer needed
  // was not touched: zero), then the blocks kept aside, in the order they came
  const Eigen::Index size = 3 * n;
  for (Eigen::Index c = 0; c < size; ++c) {
    Eigen::SparseMatrix<double>::InnerIterator to(m_matrix, c);
    for (Eigen::SparseMatrix<double>::InnerIterator from(old, c); from; ++from) {
      while (to && to.row() < from.row()) ++to;
      if (to && to.row() == from.row()) to.valueRef() = from.value();
    }
  }
  for (const Aside& a : aside) addUnknownBlock(a.f, a.g, a.B, a.scale, a.transposed);
  m_touched = std::move(needed);  // every extra block this assembly met (a second call keeps them)
  m_heldMask.clear();  // the held entries' positions moved
  m_heldPositions.clear();
  m_heldDiagonal.clear();
  return true;
}

Eigen::Index TangentMatrix::position(Eigen::Index f, int a, Eigen::Index g, int b) const {
  const Eigen::Index column = m_matrix.outerIndexPtr()[3 * g + b];
  if (f == g) return column + (a - b);
  const auto first = m_rows.begin() + m_rowStart[size_t(g)], last = m_rows.begin() + m_rowStart[size_t(g) + 1];
  const auto it = std::lower_bound(first, last, f);
  if (it == last || *it != f) return -1;
  return column + (3 - b) + 3 * (it - first) + a;
}

// B row-major 3 x 3 (row a of f, column b of g), or its transpose
void TangentMatrix::addUnknownBlock(Eigen::Index f, Eigen::Index g, const double* B, double scale, bool transposed) {
  double* values = m_matrix.valuePtr();
  if (f == g) {
    for (int b = 0; b < 3; ++b) {
      double* col = values + m_matrix.outerIndexPtr()[3 * g + b];
      for (int a = b; a < 3; ++a) col[a - b] += scale * (transposed ? B[3 * b + a] : B[3 * a + b]);
    }
    return;
  }
  const Eigen::Index column = m_matrix.outerIndexPtr()[3 * g];
  const auto first = m_rows.begin() + m_rowStart[size_t(g)], last = m_rows.begin() + m_rowStart[size_t(g) + 1];
  const auto it = std::lower_bound(first, last, f);
  if (it == last || *it != f) {  // beyond the pattern: kept aside until settlePattern()
    Aside a{f, g, {}, scale, transposed};
    std::copy(B, B + 9, a.B);
    m_aside.push_back(a);
    return;
  }
  if (m_rowExtra[size_t(it - m_rows.begin())]) m_touched.emplace_back(g, f);
  const Eigen::Index at = column + 3 + 3 * (it - first);
  // the rows of f in the three columns of g: at, then at + (column length) ...
  const int* outer = m_matrix.outerIndexPtr();
  const Eigen::Index offset = at - outer[3 * g];  // 3 + 3 k
  for (int b = 0; b < 3; ++b) {
    double* col = values + outer[3 * g + b] + offset - b;
    for (int a = 0; a < 3; ++a) col[a] += scale * (transposed ? B[3 * b + a] : B[3 * a + b]);
  }
}

void TangentMatrix::addElement(int e1, int e2, const double* Ke, double scale) {
  const int L1 = m_space.degreeU() + 1, L2 = m_space.degreeV() + 1, L = L1 * L2, cols = m_space.netCols();
  Eigen::Index pts[64];
  assert(L <= 64);
  for (int p = 0; p < L; ++p) pts[p] = Eigen::Index(e1 + p / L2) * cols + e2 + p % L2;
  for (int p = 0; p < L; ++p) {
    const int p0 = m_foldStart[size_t(pts[p])], p1 = m_foldStart[size_t(pts[p]) + 1];
    if (p0 == p1) continue;
    for (int q = 0; q < L; ++q) {
      const int q0 = m_foldStart[size_t(pts[q])], q1 = m_foldStart[size_t(pts[q]) + 1];
      const double* block = Ke + (size_t(p) * L + q) * 9;
      for (int i = p0; i < p1; ++i) {
        const auto& [f, wf] = m_foldEntries[size_t(i)];
        for (int j = q0; j < q1; ++j) {
          const auto& [g, wg] = m_foldEntries[size_t(j)];
          if (f < g) continue;  // the (q, p) block gives it, transposed
          addUnknownBlock(f, g, block, scale * wf * wg, false);
        }
      }
    }
  }
}

void TangentMatrix::addNetBlock(Eigen::Index p, Eigen::Index q, const Eigen::Matrix3d& B) {
  const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> Br = B;
  for (int i = m_foldStart[size_t(p)]; i < m_foldStart[size_t(p) + 1]; ++i) {
    const auto& [f, wf] = m_foldEntries[size_t(i)];
    for (int j = m_foldStart[size_t(q)]; j < m_foldStart[size_t(q) + 1]; ++j) {
      const auto& [g, wg] = m_foldEntries[size_t(j)];
      if (f < g) continue;
      addUnknownBlock(f, g, Br.data(), wf * wg, false);
    }
  }
}

void TangentMatrix::addScalarMatrix(const Eigen::SparseMatrix<double>& M, double scale) {
  double* values = m_matrix.valuePtr();
  for (int k = 0; k < M.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(M, k); it; ++it) {
      const Eigen::Index f = it.row(), g = it.col();
      if (f < g) continue;
      for (int c = 0; c < 3; ++c) {
        const Eigen::Index at = position(f, c, g, c);
        assert(at >= 0);
        if (at >= 0) values[at] += scale * it.value();
      }
    }
}

void TangentMatrix::applyHeld(const std::vector<char>& heldMask) {
  if (heldMask != m_heldMask) {
    m_heldMask = heldMask;
    m_heldPositions.clear();
    m_heldDiagonal.clear();
    const int* outer = m_matrix.outerIndexPtr();
    const int* inner = m_matrix.innerIndexPtr();
    for (Eigen::Index c = 0; c < m_matrix.cols(); ++c)
      for (int k = outer[c]; k < outer[c + 1]; ++k) {
        const int r = inner[k];
        if (heldMask[size_t(r)] || heldMask[size_t(c)]) {
          if (r == c)
            m_heldDiagonal.push_back(k);
          else
            m_heldPositions.push_back(k);
        }
      }
  }
  double* values = m_matrix.valuePtr();
  for (Eigen::Index k : m_heldPositions) values[k] = 0.0;
  for (Eigen::Index k : m_heldDiagonal) values[k] = 1.0;
}

Eigen::VectorXd TangentMatrix::multiply(const Eigen::VectorXd& x) const {
  Eigen::VectorXd y = m_matrix.selfadjointView<Eigen::Lower>() * x;
  return y;
}

}  // namespace bsdeform
