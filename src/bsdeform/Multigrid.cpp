// SPDX-License-Identifier: MIT
#include "bsdeform/Multigrid.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>

#include "bsdeform/HugePages.h"
#include "bsdeform/Multiversion.h"

namespace bsdeform {

/// A square banded matrix: entries (i, i + d) for |d| <= bandwidth; in a periodic matrix column
/// i + d wraps modulo the size.
class BandMatrix {
 public:
  BandMatrix() = default;
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

// x += y
BSDEFORM_MULTIVERSION
void addTo(const ControlNet& y, ControlNet& x) {
  const double* __restrict py = y.data();
  double* __restrict px = x.data();
  for (Eigen::Index m = 0; m < x.size(); ++m) px[m] += py[m];
}

// y = b - y over n entries.
BSDEFORM_MULTIVERSION
void subtractFrom(const double* __restrict b, double* __restrict y, long n) {
  for (long m = 0; m < n; ++m) y[m] = b[m] - y[m];
}

// The smoothers work on [lambda / ratio, lambda] of diag^-1 K: the B-spline coarse spaces take
// the rest. Measured (docs/benchmarks.md): with degrees 2 to 7 the ratio 3 needs 4-6 iterations
// where 8 needs 7-8 (bicubic: 2 and 4 are no better, 12 and more worse; lumped mass about as
// many or up to a fifth more); with degree 1 it needs more, so bilinear levels keep 8.
constexpr double kSmoothingRatio = 3.0, kSmoothingRatioLinear = 8.0;

// Most entries in one row of a level's 1-D matrix.
constexpr int kMaxTaps = 64;

// out = sum_k coef[k] rows[k] (or out += that) over len entries: one pass that keeps the sum in
// registers.
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

/// c * U[u] (x) V[v]
struct Term {
  double c;
  int u, v;
};

/// Row buffers of the transfers.
struct TransferScratch {
  std::vector<double> row, pad, filtered;
};

/// 1-D transfer between a fine and a coarse index set: coarse function j is the sum of
/// w * fine function f over children[j]; parents[f] lists the same pairs by fine index.
/// The same as a filter: coarse function i sits at fine position stride i + first and its
/// children are the fine functions at that position + k with weight taps[k], dropped outside
/// [0, fineSize) or, when periodic, wrapped.
struct Transfer1D {
  std::vector<std::vector<std::pair<int, double>>> children, parents;
  std::vector<double> taps;
  int stride = 1, first = 0, fineSize = 0;
  bool periodic = false;
  int coarseSize() const { return int(children.size()); }
};

Transfer1D identityTransfer(int n) {
  Transfer1D t;
  t.children.resize(size_t(n));
  t.parents.resize(size_t(n));
  for (int i = 0; i < n; ++i) t.children[size_t(i)] = t.parents[size_t(i)] = {{i, 1.0}};
  t.taps = {1.0};
  t.fineSize = n;
  return t;
}

/// Dyadic knot insertion for uniform B-splines of degree n on the fine index set of `dir`.
/// Returns false (and leaves `t` alone) when the direction is too small to coarsen.
bool subdivisionTransfer(const MultigridDirection& dir, int degree, Transfer1D& t) {
  const int nf = dir.size();
  std::vector<double> w(size_t(degree + 2));
  w[0] = std::ldexp(1.0, -degree);
  for (int k = 1; k <= degree + 1; ++k) w[size_t(k)] = w[size_t(k - 1)] * double(degree + 2 - k) / double(k);
  int jmin, jmax;
  if (dir.periodic) {
    jmin = 0;
    jmax = (nf + 1) / 2 - 1;
    if (jmax + 1 <= 2 * degree + 2) return false;
  } else {
    jmin = dir.clampedMin ? 0 : -((degree + 1) / 2);
    jmax = dir.clampedMax ? (nf - 1 - (degree + 1)) / 2 : (nf - 1) / 2;
    if (jmax - jmin + 1 < degree + 2 || jmax - jmin + 1 >= nf) return false;
  }
  t.children.assign(size_t(jmax - jmin + 1), {});
  t.parents.assign(size_t(nf), {});
  t.taps = w;
  t.stride = 2;
  t.first = 2 * jmin;
  t.fineSize = nf;
  t.periodic = dir.periodic;
  for (int j = jmin; j <= jmax; ++j)
    for (int k = 0; k <= degree + 1; ++k) {
      int f = 2 * j + k;
      if (dir.periodic) f %= nf;
      if (f < 0 || f >= nf) continue;
      t.children[size_t(j - jmin)].emplace_back(f, w[size_t(k)]);
      t.parents[size_t(f)].emplace_back(j - jmin, w[size_t(k)]);
    }
  return true;
}

/// P^T B P for the transfer P.
BandMatrix galerkin(const BandMatrix& B, const Transfer1D& t) {
  const int nc = t.coarseSize();
  auto offset = [&](int i, int j) {
    int d = j - i;
    if (B.periodic()) {
      d = ((d % nc) + nc) % nc;
      if (d > nc / 2) d -= nc;
    }
    return d;
  };
  auto forEach = [&](auto&& fn) {
    for (int i = 0; i < nc; ++i)
      for (const auto& [f, wf] : t.children[size_t(i)])
        for (int d = -B.bandwidth(); d <= B.bandwidth(); ++d) {
          const int g = B.column(f, d);
          const double v = B.at(f, d);
          if (g < 0 || v == 0.0) continue;
          for (const auto& [j, wg] : t.parents[size_t(g)]) fn(i, j, wf * v * wg);
        }
  };
  int bw = 0;
  forEach([&](int i, int j, double) { bw = std::max(bw, std::abs(offset(i, j))); });
  BandMatrix C(nc, bw, B.periodic());
  forEach([&](int i, int j, double v) { C.at(i, offset(i, j)) += v; });
  return C;
}

/// The 1-D Gram matrix G^p of the moving layers of one direction (StiffnessStencil.h); with
/// derived layers (SIMPLY_SUPPORTED, BUILT_IN) T^T G T: a derived neighbour's entry folds onto
/// its source layers (SplineSpace::foldU), which lie within the band.
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

}  // namespace

struct MultigridPreconditioner::Level {
  MultigridDirection u, v;
  int degreeU = 0, degreeV = 0;
  std::vector<Term> terms;
  int mu = 0, mv = 0;
  Eigen::VectorXd invDiag;  ///< per point
  double lambda = 1.0;      ///< upper estimate of lambda_max(diag^-1 K~)
  bool coarsest = false;
  Transfer1D toCoarseU, toCoarseV;
  Eigen::LLT<Eigen::MatrixXd> llt;  ///< coarsest level only
  /// right-hand side, solution, residual; y: the smoothing added into x (and power-iteration
  /// scratch); s: the smoother's product
  ControlNet r, x, res, y, s;
  TransferScratch transferScratch;
  /// The operator as sum_j A_j (x) V_j: A_j = sum of c U over the terms with v = j (`vIndex`).
  struct Factor {
    BandMatrix A;
    int vIndex;
  };
  std::vector<Factor> factors;
  /// w_j = (A_j (x) I) x for one row, padded by V_j's bandwidth on both sides (zeros, or the
  /// wrapped halo)
  std::vector<std::vector<double>> wRows;

  Eigen::Index points() const { return Eigen::Index(mu) * mv; }

  void prepare() {
    factors.clear();
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
      factors.push_back({std::move(A), int(j)});
    }
    wRows.assign(factors.size(), {});
    for (size_t k = 0; k < factors.size(); ++k)
      wRows[k].assign(size_t(3 * (mv + 2 * v.matrices[size_t(factors[k].vIndex)].bandwidth())), 0.0);
    for (BandMatrix& V : v.matrices) V.findToeplitzRows();
    // diagonal and Gershgorin bound of diag^-1 K~
    Eigen::VectorXd diag = Eigen::VectorXd::Zero(points()), absSum = Eigen::VectorXd::Zero(points());
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
    if (!(diag.minCoeff() > 0.0)) throw std::runtime_error("multigrid: a level's operator has a diagonal entry <= 0");
    invDiag = diag.cwiseInverse();
    const double gershgorin = absSum.cwiseProduct(invDiag).maxCoeff();
    for (ControlNet* m : {&x, &res, &y}) allocateNet(*m, points());
    // the finest level's estimate waits for useExactOperator() (its operator may change); the
    // coarsest level is solved, not smoothed
    lambda = finest || coarsest ? gershgorin : std::min(gershgorin, estimateLambda());
  }
  bool finest = false;

  /// 1.15 times a power-iteration estimate of lambda_max(diag^-1 K) (a lower estimate): the
  /// smoother still reduces every mode up to 4/3 of its upper end.
  double estimateLambda() {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> X(-1.0, 1.0);
    for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] = X(rng);
    double estimate = 0.0;
    for (int it = 0; it < 20; ++it) {
      apply(x, nullptr, y);
      y = invDiag.asDiagonal() * y;
      estimate = std::sqrt(y.squaredNorm() / x.squaredNorm());
      x = y / y.norm();
    }
    return 1.15 * estimate;
  }

  /// The finest level's own operator K (pins and all), when given: used instead of K~.
  MultigridPreconditioner::Operator exact;
  MultigridPreconditioner::SmoothingStep exactStep;

  /// out = K x (K~ x), or out = rhs - K x when rhs is given.
  void apply(const ControlNet& xNet, const ControlNet* rhsNet, ControlNet& outNet) {
    if (exact) {
      exact(xNet, rhsNet, outNet);
      return;
    }
    const double* x = xNet.data();
    double* out = outNet.data();
    const long rowLen = 3L * mv;
    const double* rows[kMaxTaps];
    double coef[kMaxTaps];
    for (int a = 0; a < mu; ++a) {
      // w_k = (A_k (x) I) x, row a
      for (size_t k = 0; k < factors.size(); ++k) {
        const BandMatrix& A = factors[k].A;
        const int bw = v.matrices[size_t(factors[k].vIndex)].bandwidth();
        double* w = wRows[k].data() + 3L * bw;
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
      for (size_t k = 0; k < factors.size(); ++k) {
        const BandMatrix& V = v.matrices[size_t(factors[k].vIndex)];
        const int bw = V.bandwidth();
        const double* w = wRows[k].data() + 3L * bw;
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

  /// out = p(diag^-1 K) diag^-1 b from zero (out += that when `accumulate`): the Chebyshev
  /// polynomial of smoothingDegree (1 or 2) on [lambda / ratio, lambda], which amplifies no mode
  /// of (0, (1 + 1 / ratio) lambda); degree 2 takes one product with K (`s` is its scratch).
  void smooth(const ControlNet& b, ControlNet& out, bool accumulate = false) {
    const double ratio = std::min(degreeU, degreeV) >= 2 ? kSmoothingRatio : kSmoothingRatioLinear;
    const double hi = lambda, lo = lambda / ratio;
    const double theta = 0.5 * (hi + lo), delta = 0.5 * (hi - lo);
    const double sigma = theta / delta, rho0 = 1.0 / sigma, rho1 = 1.0 / (2.0 * sigma - rho0);
    if (smoothingDegree >= 2 && exactStep) {
      exactStep(b, 1.0 / theta, 1.0 + rho1 * rho0, 2.0 * rho1 / delta, invDiag, accumulate, out);
      return;
    }
    ControlNet& target = accumulate ? y : out;
    target = invDiag.asDiagonal() * b / theta;
    if (smoothingDegree >= 2) {
      allocateNet(s, points());
      apply(target, &b, s);
      target = (1.0 + rho1 * rho0) * target + (2.0 * rho1 / delta) * (invDiag.asDiagonal() * s);
    }
    if (accumulate) addTo(y, out);
  }
  int smoothingDegree = 2;  ///< 1: damped Jacobi (no product with K)
};

namespace {

/// s = P^T f for one row in the direction of `t` (3 values per point): the row, padded by
/// K - 1 points each side (zeros; when periodic the right side holds the row's first points
/// again, and the left side is never sampled), filtered by the taps at every position, then
/// sampled at the coarse functions' positions.
void restrictRow(const double* f, const Transfer1D& t, std::vector<double>& pad, std::vector<double>& filtered,
                 double* s) {
  const int K = int(t.taps.size()), nf = t.fineSize;
  assert(K >= 1 && K <= kMaxTaps);
  const long halo = 3L * (K - 1);
  pad.assign(size_t(3L * nf + 2 * halo), 0.0);
  std::copy(f, f + 3L * nf, pad.begin() + halo);
  if (t.periodic) std::copy(f, f + halo, pad.begin() + halo + 3L * nf);  // positions nf .. nf + K - 2
  filtered.resize(size_t(3L * nf + halo));
  const double* rows[kMaxTaps];
  for (int k = 0; k < K; ++k) rows[k] = pad.data() + 3L * k;
  // filtered(q) = sum_k taps[k] f(q - (K - 1) + k)
  combineRows(rows, t.taps.data(), K, long(filtered.size()), filtered.data(), false);
  for (int i = 0; i < t.coarseSize(); ++i) {
    const double* q = filtered.data() + 3L * (t.stride * i + t.first + K - 1);
    s[3 * i] = q[0];
    s[3 * i + 1] = q[1];
    s[3 * i + 2] = q[2];
  }
}

/// f += P s for one row in the direction of `t`: the coarse values placed at their positions
/// (zeros between, K - 1 points of halo before, wrapped when periodic), filtered by the taps.
void prolongRow(const double* s, const Transfer1D& t, std::vector<double>& placed, double* f) {
  const int K = int(t.taps.size()), nf = t.fineSize;
  assert(K >= 1 && K <= kMaxTaps);
  const long halo = 3L * (K - 1);
  placed.assign(size_t(3L * nf + halo), 0.0);
  for (int i = 0; i < t.coarseSize(); ++i) {
    double* q = placed.data() + halo + 3L * (t.stride * i + t.first);
    q[0] = s[3 * i];
    q[1] = s[3 * i + 1];
    q[2] = s[3 * i + 2];
  }
  if (t.periodic) std::copy(placed.end() - halo, placed.end(), placed.begin());  // positions -(K - 1) .. -1
  const double* rows[kMaxTaps];
  for (int k = 0; k < K; ++k) rows[k] = placed.data() + halo - 3L * k;
  // f(b) += sum_k taps[k] placed(b - k)
  combineRows(rows, t.taps.data(), K, 3L * nf, f, true);
}

/// out (coarse) = (Pu (x) Pv)^T in (fine), one fine row at a time: the row restricted in v is
/// added to each of its coarse parent rows, so no restricted copy of the whole level is
/// written and read back.
void restrictTo(const ControlNet& in, const Transfer1D& tu, const Transfer1D& tv, TransferScratch& scratch,
                ControlNet& out) {
  const int muFine = int(tu.parents.size()), nvc = tv.coarseSize(), nuc = tu.coarseSize();
  const long len = 3L * nvc;
  scratch.row.resize(size_t(len));
  allocateNet(out, Eigen::Index(nuc) * nvc);
  out.setZero();
  double* s = scratch.row.data();
  for (int a = 0; a < muFine; ++a) {
    restrictRow(in.data() + 3L * a * tv.fineSize, tv, scratch.pad, scratch.filtered, s);
    for (const auto& [i, w] : tu.parents[size_t(a)]) {
      double* o = out.data() + long(i) * len;
      for (long m = 0; m < len; ++m) o[m] += w * s[m];
    }
  }
}

/// out (fine) += (Pu (x) Pv) in (coarse), one fine row at a time.
void prolongAdd(const ControlNet& in, const Transfer1D& tu, const Transfer1D& tv, TransferScratch& scratch,
                ControlNet& out) {
  const int muFine = int(tu.parents.size()), nvc = tv.coarseSize();
  const long len = 3L * nvc;
  scratch.row.resize(size_t(len));
  double* s = scratch.row.data();
  for (int a = 0; a < muFine; ++a) {
    std::fill(s, s + len, 0.0);
    for (const auto& [i, w] : tu.parents[size_t(a)]) {
      const double* c = in.data() + long(i) * len;
      for (long m = 0; m < len; ++m) s[m] += w * c[m];
    }
    prolongRow(s, tv, scratch.pad, out.data() + 3L * a * tv.fineSize);
  }
}

constexpr Eigen::Index kCoarsestPoints = 400;

}  // namespace

MultigridPreconditioner::MultigridPreconditioner(const SplineSpace& space, const StiffnessStencil& stencil,
                                                 const Weights& weights, const Eigen::VectorXd& massTerm) {
  auto fine = std::make_unique<Level>();
  Level& L = *fine;
  L.mu = space.movingU().count;
  L.mv = space.movingV().count;
  L.degreeU = space.degreeU();
  L.degreeV = space.degreeV();
  if (massTerm.size() != L.points()) throw std::invalid_argument("multigrid: the mass term needs one entry per moving point");
  const Boundaries& sides = space.boundaries();
  L.u.periodic = space.periodicU();
  L.v.periodic = space.periodicV();
  // SIMPLY_SUPPORTED and BUILT_IN sides keep some outer layers moving: their coarse functions
  // are cut at the edge like a FREE side's (the transfer only has to be a good one)
  auto allHeld = [](Boundary side, int n) { return side != Boundary::Periodic && edgeLayers(side, n).held >= n; };
  L.u.clampedMin = allHeld(sides.uMin, L.degreeU);
  L.u.clampedMax = allHeld(sides.uMax, L.degreeU);
  L.v.clampedMin = allHeld(sides.vMin, L.degreeV);
  L.v.clampedMax = allHeld(sides.vMax, L.degreeV);

  // separable fit of the mass term: D_ab ~ du(a) dv(b) / mean(D)
  const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> D(massTerm.data(), L.mu, L.mv);
  const Eigen::VectorXd du = D.rowwise().mean(), dv = D.colwise().mean().transpose();
  // periodic like the direction, so that its Galerkin products wrap instead of widening
  L.u.matrices.push_back(diagonalMatrix(du, L.u.periodic));
  L.v.matrices.push_back(diagonalMatrix(dv, L.v.periodic));
  L.terms.push_back({1.0 / D.mean(), 0, 0});
  // the five energy terms, c G_u^p (x) G_v^q / 4; index p + 1 in each direction's list
  for (int p = 0; p <= 2; ++p) {
    L.u.matrices.push_back(gramMatrix(stencil.gramU(), space.movingU(), space.netRows(), L.u.periodic, p,
                                      &SplineSpace::foldU, space));
    L.v.matrices.push_back(gramMatrix(stencil.gramV(), space.movingV(), space.netCols(), L.v.periodic, p,
                                      &SplineSpace::foldV, space));
  }
  const struct {
    double w;
    int p, q;
  } energy[] = {{weights.w10, 1, 0}, {weights.w01, 0, 1}, {2.0 * weights.w11, 1, 1}, {weights.w20, 2, 0}, {weights.w02, 0, 2}};
  for (const auto& e : energy)
    if (e.w > 0.0 && e.p <= L.degreeU && e.q <= L.degreeV) L.terms.push_back({0.25 * e.w, e.p + 1, e.q + 1});
  m_levels.push_back(std::move(fine));

  // coarser levels: Galerkin products, until small or neither direction coarsens
  for (;;) {
    Level& f = *m_levels.back();
    const bool cu = subdivisionTransfer(f.u, f.degreeU, f.toCoarseU);
    const bool cv = subdivisionTransfer(f.v, f.degreeV, f.toCoarseV);
    if (f.points() <= kCoarsestPoints || (!cu && !cv)) {
      f.coarsest = true;
      break;
    }
    if (!cu) f.toCoarseU = identityTransfer(f.mu);
    if (!cv) f.toCoarseV = identityTransfer(f.mv);
    auto c = std::make_unique<Level>();
    c->u = f.u;
    c->v = f.v;
    c->degreeU = f.degreeU;
    c->degreeV = f.degreeV;
    c->terms = f.terms;
    for (BandMatrix& B : c->u.matrices) B = galerkin(B, f.toCoarseU);
    for (BandMatrix& B : c->v.matrices) B = galerkin(B, f.toCoarseV);
    c->mu = f.toCoarseU.coarseSize();
    c->mv = f.toCoarseV.coarseSize();
    m_levels.push_back(std::move(c));
  }
  // degree 2 on the finest level, 1 (damped Jacobi) below: measured fastest (docs/benchmarks.md)
  for (size_t l = 1; l < m_levels.size(); ++l) m_levels[l]->smoothingDegree = 1;
  m_levels.front()->finest = true;
  for (auto& level : m_levels) level->prepare();

  // the coarsest level: K~ assembled densely and factorised
  Level& c = *m_levels.back();
  const Eigen::Index n = c.points();
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n);
  for (const Term& term : c.terms) {
    const BandMatrix& U = c.u.matrices[size_t(term.u)];
    const BandMatrix& V = c.v.matrices[size_t(term.v)];
    for (int a = 0; a < c.mu; ++a)
      for (int du2 = -U.bandwidth(); du2 <= U.bandwidth(); ++du2) {
        const int a2 = U.column(a, du2);
        if (a2 < 0) continue;
        for (int b = 0; b < c.mv; ++b)
          for (int dv2 = -V.bandwidth(); dv2 <= V.bandwidth(); ++dv2) {
            const int b2 = V.column(b, dv2);
            if (b2 < 0) continue;
            K(Eigen::Index(a) * c.mv + b, Eigen::Index(a2) * c.mv + b2) += term.c * U.at(a, du2) * V.at(b, dv2);
          }
      }
  }
  c.llt.compute(K);
  if (c.llt.info() != Eigen::Success) throw std::runtime_error("multigrid: the coarsest level is not positive definite");
}

MultigridPreconditioner::~MultigridPreconditioner() = default;

int MultigridPreconditioner::levels() const { return int(m_levels.size()); }

Eigen::Index MultigridPreconditioner::levelPoints(int level) const { return m_levels[size_t(level)]->points(); }

void MultigridPreconditioner::useExactOperator(Operator op, SmoothingStep step, const Eigen::VectorXd& diagonal,
                                               double lambdaBound) {
  Level& L = *m_levels.front();
  if (L.coarsest) return;  // a one-level hierarchy solves K~ directly
  L.exact = std::move(op);
  L.exactStep = std::move(step);
  L.invDiag = diagonal.cwiseInverse();
  L.lambda = std::min(lambdaBound, L.estimateLambda());
}

void MultigridPreconditioner::applyOperator(const ControlNet& x, ControlNet& y) {
  Level& L = *m_levels.front();
  allocateNet(y, L.points());
  L.apply(x, nullptr, y);
}

void MultigridPreconditioner::cycle(int level, const ControlNet& r, ControlNet& x) {
  Level& L = *m_levels[size_t(level)];
  if (L.coarsest) {
    x = L.llt.solve(r);
    return;
  }
  Level& C = *m_levels[size_t(level) + 1];
  allocateNet(x, L.points());
  L.smooth(r, x);
  L.apply(x, &r, L.res);
  restrictTo(L.res, L.toCoarseU, L.toCoarseV, L.transferScratch, C.r);
  cycle(level + 1, C.r, C.x);
  prolongAdd(C.x, L.toCoarseU, L.toCoarseV, L.transferScratch, x);
  L.apply(x, &r, L.res);
  L.smooth(L.res, x, true);
}

void MultigridPreconditioner::apply(const ControlNet& r, ControlNet& z) { cycle(0, r, z); }

}  // namespace bsdeform
