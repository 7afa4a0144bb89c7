// SPDX-License-Identifier: MIT
#include "bsdeform/dynamics/MultigridOperator.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "bsdeform/base/Multiversion.h"

namespace bsdeform::multigrid {

BandMatrix::BandMatrix(int size, int bandwidth, bool periodic)
    : m_size(size), m_bw(bandwidth), m_periodic(periodic), m_v(size_t(size) * size_t(2 * bandwidth + 1), 0.0) {
  if (periodic && size <= 2 * bandwidth)
    throw std::invalid_argument("multigrid: a periodic direction needs more than " + std::to_string(2 * bandwidth) +
                                " moving layers, got " + std::to_string(size));
}

void BandMatrix::findToeplitzRows() {
  // the longest run of rows equal to the middle row, all of whose columns exist unwrapped
  const int mid = m_size / 2;
  auto same = [&](int i) {
    if (i - m_bw < 0 || i + m_bw >= m_size) return false;
    for (int d = -m_bw; d <= m_bw; ++d)
      if (at(i, d) != at(mid, d)) return false;
    return true;
  };
  if (!same(mid)) {
    m_toeplitzBegin = m_toeplitzEnd = 0;
    return;
  }
  m_toeplitzBegin = m_toeplitzEnd = mid;
  while (same(m_toeplitzBegin - 1)) --m_toeplitzBegin;
  while (same(m_toeplitzEnd)) ++m_toeplitzEnd;
}

int BandMatrix::column(int i, int d) const {
  const int j = i + d;
  if (m_periodic) return ((j % m_size) + m_size) % m_size;
  return j >= 0 && j < m_size ? j : -1;
}

namespace {

// y = b - y over n entries.
BSDEFORM_MULTIVERSION
void subtractFrom(const double* __restrict b, double* __restrict y, long n) {
  for (long m = 0; m < n; ++m) y[m] = b[m] - y[m];
}

}  // namespace

BSDEFORM_MULTIVERSION
void combineRows(const double* const* rows, const double* coef, int count, long len, double* out, bool accumulate) {
  using namespace simd;
  long m = 0;
  for (; m + 8 <= len; m += 8) {
    v4 lo = accumulate ? load4(out + m) : splat(0.0);
    v4 hi = accumulate ? load4(out + m + 4) : splat(0.0);
    for (int k = 0; k < count; ++k) {
      const v4 c = splat(coef[k]);
      lo += c * load4(rows[k] + m);
      hi += c * load4(rows[k] + m + 4);
    }
    store4(out + m, lo);
    store4(out + m + 4, hi);
  }
  for (; m < len; ++m) {
    double acc = accumulate ? out[m] : 0.0;
    for (int k = 0; k < count; ++k) acc += coef[k] * rows[k][m];
    out[m] = acc;
  }
}

BandMatrix gramMatrix(const GramRows1D& g, const LayerRange& moving, int netLayers, bool periodic, int p,
                      const std::vector<LayerWeight>& (SplineSpace::*fold)(int) const, const SplineSpace& space) {
  const int n = g.degree();
  BandMatrix B(moving.count, n, periodic);
  for (int a = 0; a < moving.count; ++a) {
    const int i = moving.first + a;
    const int type = g.rowType(i);
    for (int d = -n; d <= n; ++d) {
      if (periodic) {
        B.at(a, d) = g.entry(p, type, d);
        continue;
      }
      const int l = i + d;
      if (l < 0 || l >= netLayers) continue;
      for (const LayerWeight& w : (space.*fold)(l)) B.at(a, w.layer - i) += w.weight * g.entry(p, type, d);
    }
  }
  return B;
}

BandMatrix diagonalMatrix(const Eigen::VectorXd& d, bool periodic) {
  BandMatrix B(int(d.size()), 0, periodic);
  for (int i = 0; i < int(d.size()); ++i) B.at(i, 0) = d[i];
  return B;
}

void KroneckerOperator::prepare() {
  m_factors.clear();
  for (size_t j = 0; j < v.matrices.size(); ++j) {
    int bw = -1;
    for (const Term& term : terms)
      if (size_t(term.v) == j) bw = std::max(bw, u.matrices[size_t(term.u)].bandwidth());
    if (bw < 0) continue;
    if (2 * std::max(bw, v.matrices[j].bandwidth()) + 1 > kMaxTaps)
      throw std::runtime_error("multigrid: a level's band is wider than " + std::to_string(kMaxTaps));
    BandMatrix A(mu, bw, u.periodic);
    for (const Term& term : terms) {
      if (size_t(term.v) != j) continue;
      const BandMatrix& U = u.matrices[size_t(term.u)];
      for (int a = 0; a < mu; ++a)
        for (int d = -U.bandwidth(); d <= U.bandwidth(); ++d) A.at(a, d) += term.c * U.at(a, d);
    }
    m_factors.push_back({std::move(A), int(j)});
  }
  m_wRows.assign(m_factors.size(), {});
  for (size_t k = 0; k < m_factors.size(); ++k)
    m_wRows[k].assign(size_t(3 * (mv + 2 * v.matrices[size_t(m_factors[k].vIndex)].bandwidth())), 0.0);
  for (BandMatrix& V : v.matrices) V.findToeplitzRows();
}

void KroneckerOperator::diagonalAndRowSums(Eigen::VectorXd& diag, Eigen::VectorXd& absSum) const {
  diag = Eigen::VectorXd::Zero(points());
  absSum = Eigen::VectorXd::Zero(points());
  for (const Term& term : terms) {
    const BandMatrix& U = u.matrices[size_t(term.u)];
    const BandMatrix& V = v.matrices[size_t(term.v)];
    for (int a = 0; a < mu; ++a) {
      double ru = 0.0;
      for (int d = -U.bandwidth(); d <= U.bandwidth(); ++d) ru += std::abs(U.at(a, d));
      for (int b = 0; b < mv; ++b) {
        double rv = 0.0;
        for (int d = -V.bandwidth(); d <= V.bandwidth(); ++d) rv += std::abs(V.at(b, d));
        const Eigen::Index k = Eigen::Index(a) * mv + b;
        diag[k] += term.c * U.at(a, 0) * V.at(b, 0);
        absSum[k] += std::abs(term.c) * ru * rv;
      }
    }
  }
}

void KroneckerOperator::apply(const ControlNet& xNet, const ControlNet* rhsNet, ControlNet& outNet) {
  const double* x = xNet.data();
  double* out = outNet.data();
  const long rowLen = 3L * mv;
  const double* rows[kMaxTaps];
  double coef[kMaxTaps];
  for (int a = 0; a < mu; ++a) {
    // w_k = (A_k (x) I) x, row a
    for (size_t k = 0; k < m_factors.size(); ++k) {
      const BandMatrix& A = m_factors[k].A;
      const int bw = v.matrices[size_t(m_factors[k].vIndex)].bandwidth();
      double* w = m_wRows[k].data() + 3L * bw;
      int count = 0;
      for (int d = -A.bandwidth(); d <= A.bandwidth(); ++d) {
        const int col = A.column(a, d);
        const double c = A.at(a, d);
        if (col < 0 || c == 0.0) continue;
        rows[count] = x + long(col) * rowLen;
        coef[count++] = c;
      }
      combineRows(rows, coef, count, rowLen, w, false);
      if (v.periodic && bw > 0) {  // wrapped halo
        std::copy(w + rowLen - 3L * bw, w + rowLen, w - 3L * bw);
        std::copy(w, w + 3L * bw, w + rowLen);
      }
    }
    // out row = sum_k (I (x) V_k) w_k: Toeplitz rows in one pass per k, the others entry by entry
    double* o = out + long(a) * rowLen;
    std::fill(o, o + rowLen, 0.0);
    for (size_t k = 0; k < m_factors.size(); ++k) {
      const BandMatrix& V = v.matrices[size_t(m_factors[k].vIndex)];
      const int bw = V.bandwidth();
      const double* w = m_wRows[k].data() + 3L * bw;
      const int t0 = V.toeplitzBegin(), t1 = V.toeplitzEnd();
      if (t1 > t0) {
        int count = 0;
        for (int d = -bw; d <= bw; ++d) {
          rows[count] = w + 3L * (t0 + d);
          coef[count++] = V.at(t0, d);
        }
        combineRows(rows, coef, count, 3L * (t1 - t0), o + 3L * t0, true);
      }
      for (int b = 0; b < mv; ++b) {
        if (b == t0 && t1 > t0) b = t1;
        if (b >= mv) break;
        for (int d = -bw; d <= bw; ++d) {
          const double c = V.at(b, d);
          const double* wb = w + 3L * (b + d);  // the padding holds zeros or the wrapped halo
          o[3 * b] += c * wb[0];
          o[3 * b + 1] += c * wb[1];
          o[3 * b + 2] += c * wb[2];
        }
      }
    }
    if (rhsNet) subtractFrom(rhsNet->data() + long(a) * rowLen, o, rowLen);
  }
}

Eigen::MatrixXd KroneckerOperator::dense() const {
  const Eigen::Index n = points();
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n);
  for (const Term& term : terms) {
    const BandMatrix& U = u.matrices[size_t(term.u)];
    const BandMatrix& V = v.matrices[size_t(term.v)];
    for (int a = 0; a < mu; ++a)
      for (int du2 = -U.bandwidth(); du2 <= U.bandwidth(); ++du2) {
        const int a2 = U.column(a, du2);
        if (a2 < 0) continue;
        for (int b = 0; b < mv; ++b)
          for (int dv2 = -V.bandwidth(); dv2 <= V.bandwidth(); ++dv2) {
            const int b2 = V.column(b, dv2);
            if (b2 < 0) continue;
            K(Eigen::Index(a) * mv + b, Eigen::Index(a2) * mv + b2) += term.c * U.at(a, du2) * V.at(b, dv2);
          }
      }
  }
  return K;
}

}  // namespace bsdeform::multigrid
