// SPDX-License-Identifier: MIT
#include "bsdeform/energy/StiffnessStencil.h"

#include "bsdeform/base/ParameterError.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <stdexcept>
#include <string>

#include "bsdeform/spline/GaussLegendre.h"
#include "bsdeform/base/HugePages.h"
#include "bsdeform/base/Multiversion.h"
#include "bsdeform/base/Parallel.h"

namespace bsdeform {

std::vector<double> cardinalGram(int degree, int order) {
  std::vector<double> g(degree + 1, 0.0);
  if (order > degree) return g;
  const QuadratureRule& rule = gaussLegendre(degree + 1);
  for (int d = 0; d <= degree; ++d) {
    double sum = 0.0;
    // Product support is [d, n+1): integrate span by span (polynomial of degree 2(n-p) on each).
    for (int t = d; t <= degree; ++t)
      for (size_t q = 0; q < rule.nodes.size(); ++q) {
        const double x = t + rule.nodes[q];
        sum += rule.weights[q] * cardinalBSplineDerivative(degree, order, x) *
               cardinalBSplineDerivative(degree, order, x - d);
      }
    g[d] = sum;
  }
  return g;
}

GramRows1D::GramRows1D(const BSplineBasis1D& basis, Boundary lo, Boundary hi)
    : m_n(basis.degree()), m_numInner(basis.numFree()), m_periodic(lo == Boundary::Periodic) {
  const bool periodic = m_periodic;
  const int n = m_n, N = m_numInner, M = N + n;  // M knot spans of width h cover [0,1]
  const int types = periodic ? 1 : 2 * n + 1;
  const double h = basis.spacing();
  const QuadratureRule& rule = gaussLegendre(n + 1);
  for (int p = 0; p < 3; ++p) {
    m_rows[p].assign(size_t(types) * (2 * n + 1), 0.0);
    const std::vector<double> g = cardinalGram(n, p);
    const double scale = std::pow(h, 1 - 2 * p);
    for (int d = -n; d <= n; ++d) m_rows[p][size_t(d + n)] = scale * g[size_t(std::abs(d))];
    // Truncated rows, in cardinal coordinates x = u/h on [0, M]: function k is b^n(x - k).
    for (int t = 1; t < types; ++t) {
      const int k = t <= n ? t - 1 - n : N + (t - 1 - n);
      for (int d = -n; d <= n; ++d) {
        const int j = k + d;
        if (j < -n || j > M - 1) continue;  // not a B-spline of the index set
        double sum = 0.0;
        // the product's support [max(k,j), min(k,j)+n+1) cut to [0, M)
        const int lo = std::max({k, j, 0}), hi = std::min(std::min(k, j) + n + 1, M);
        for (int span = lo; span < hi; ++span)
          for (size_t q = 0; q < rule.nodes.size(); ++q) {
            const double x = span + rule.nodes[q];
            sum += rule.weights[q] * cardinalBSplineDerivative(n, p, x - k) * cardinalBSplineDerivative(n, p, x - j);
          }
        m_rows[p][size_t(t) * (2 * n + 1) + (d + n)] = scale * sum;
      }
    }
  }
  m_rowSum.assign(size_t(types), h);
  for (int t = 1; t < types; ++t) {
    const int k = t <= n ? t - 1 - n : N + (t - 1 - n);
    double sum = 0.0;
    for (int span = std::max(k, 0); span < std::min(k + n + 1, M); ++span)
      for (size_t q = 0; q < rule.nodes.size(); ++q)
        sum += rule.weights[q] * cardinalBSpline(n, span + rule.nodes[q] - k);
    m_rowSum[size_t(t)] = h * sum;
  }
  if (periodic) return;

  // Sides with derived layers: the rows of their source layers become rows of T^T G (see the
  // header), from the truncated rows computed above.
  const std::vector<double> rows[3] = {m_rows[0], m_rows[1], m_rows[2]};
  const int layers = N + 2 * n;
  auto original = [&](int p, int e, int j) {  // G^p(e, j) for net layers e, j
    const int d = j - e;
    if (d < -n || d > n) return 0.0;
    return rows[p][size_t(rowType(e)) * (2 * n + 1) + (d + n)];
  };
  for (int side = 0; side < 2; ++side) {
    const EdgeLayers e = edgeLayers(side == 0 ? lo : hi, n);
    if (e.derived == 0) continue;
    auto net = [&](int l) { return side == 0 ? l : layers - 1 - l; };
    const Eigen::MatrixXd TtT = Eigen::MatrixXd::Identity(e.sources, e.sources) + e.Z.transpose() * e.Z;
    for (int c = 0; c < e.sources; ++c) {
      const int src = net(e.held + e.derived + c), t = rowType(src);
      for (int p = 0; p < 3; ++p)
        for (int d = -n; d <= n; ++d) {
          double v = rows[p][size_t(t) * (2 * n + 1) + (d + n)];
          for (int r = 0; r < e.derived; ++r) v += e.Z(r, c) * original(p, net(e.held + r), src + d);
          m_rows[p][size_t(t) * (2 * n + 1) + (d + n)] = v;
        }
    }
    // |T x|^2 <= lambda_max(T'T) |x|^2, with a relative margin for this tiny eigenproblem
    m_transformBound = std::max(m_transformBound, (1.0 + 1e-12) * Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(
                                                                     TtT, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff());
  }
}

int GramRows1D::rowType(int layer) const {
  if (m_periodic) return 0;
  if (layer < m_n) return 1 + layer;
  if (layer >= m_numInner + m_n) return 1 + m_n + (layer - m_numInner - m_n);
  return 0;
}

namespace {
void checkWeight(double w, const char* name) {
  requireParameter(std::isfinite(w) && w >= 0.0, name, "must be finite and >= 0, got " + std::to_string(w),
                   std::string("weight ") + name);
}
}  // namespace

StiffnessStencil::StiffnessStencil(const SplineSpace& space, const Weights& w)
    : m_space(&space),
      m_weights(w),
      m_ru(space.degreeU()),
      m_rv(space.degreeV()),
      m_gu(space.basisU(), space.boundaries().uMin, space.boundaries().uMax),
      m_gv(space.basisV(), space.boundaries().vMin, space.boundaries().vMax) {
  checkWeight(w.w10, "w10");
  checkWeight(w.w01, "w01");
  checkWeight(w.w11, "w11");
  checkWeight(w.w20, "w20");
  checkWeight(w.w02, "w02");
  const double hu = space.basisU().spacing(), hv = space.basisV().spacing();
  std::vector<double> Gu[3], Gv[3];
  for (int p = 0; p < 3; ++p) {
    Gu[p] = cardinalGram(m_ru, p);
    Gv[p] = cardinalGram(m_rv, p);
    const double su = std::pow(hu, 1 - 2 * p), sv = std::pow(hv, 1 - 2 * p);
    for (double& x : Gu[p]) x *= su;
    for (double& x : Gv[p]) x *= sv;
  }
  m_half.assign(size_t(m_ru + 1) * (m_rv + 1), 0.0);
  for (int a = 0; a <= m_ru; ++a)
    for (int b = 0; b <= m_rv; ++b)
      m_half[size_t(a) * (m_rv + 1) + b] = w.w10 * Gu[1][a] * Gv[0][b] + w.w01 * Gu[0][a] * Gv[1][b] +
                                           2.0 * w.w11 * Gu[1][a] * Gv[1][b] + w.w20 * Gu[2][a] * Gv[0][b] +
                                           w.w02 * Gu[0][a] * Gv[2][b];

  // Interior rows / columns: the moving layers of Toeplitz type (k = 0..N-1; all of a
  // periodic direction).
  // (BUILT_IN of degree 1 holds layer k = 0: intersect with the moving layers)
  auto interior = [](const LayerRange& moving, int n, int N) {
    const int first = std::max(moving.first, n), last = std::min(moving.first + moving.count, n + N);
    return LayerRange{first, std::max(0, last - first)};
  };
  m_rowsInterior = space.periodicU() ? space.movingU() : interior(space.movingU(), m_ru, space.numU());
  m_colsInterior = space.periodicV() ? space.movingV() : interior(space.movingV(), m_rv, space.numV());

  // Band: every moving point with a truncated row in u or in v, with one coefficient table per
  // pair of row types: C(d1, d2) = sum over terms w G_u^p(type_u, d1) G_v^q(type_v, d2).
  const LayerRange mu = space.movingU(), mv = space.movingV();
  const int typesV = 2 * m_rv + 1, width = (2 * m_ru + 1) * (2 * m_rv + 1);
  std::vector<int> tableOf(size_t(2 * m_ru + 1) * typesV, -1);
  std::vector<int> typeV(size_t(mv.count)), bandColumns;
  for (int j = mv.first; j < mv.first + mv.count; ++j)
    if ((typeV[size_t(j - mv.first)] = m_gv.rowType(j)) != 0) bandColumns.push_back(j);
  std::vector<int> allColumns(size_t(mv.count));
  for (int j = mv.first; j < mv.first + mv.count; ++j) allColumns[size_t(j - mv.first)] = j;
  for (int i = mu.first; i < mu.first + mu.count; ++i) {
    const int tu = m_gu.rowType(i);
    // an interior row has band points only in the band columns
    for (int j : tu == 0 ? bandColumns : allColumns) {
      const int tv = typeV[size_t(j - mv.first)];
      if (tu == 0 && tv == 0) continue;
      int& t = tableOf[size_t(tu) * typesV + tv];
      if (t < 0) {
        t = int(m_tables.size());
        std::vector<double> c(size_t(width), 0.0);
        for (int d1 = -m_ru; d1 <= m_ru; ++d1)
          for (int d2 = -m_rv; d2 <= m_rv; ++d2) {
            auto Gu = [&](int p) { return m_gu.entry(p, tu, d1); };
            auto Gv = [&](int p) { return m_gv.entry(p, tv, d2); };
            c[size_t(d1 + m_ru) * (2 * m_rv + 1) + (d2 + m_rv)] = w.w10 * Gu(1) * Gv(0) + w.w01 * Gu(0) * Gv(1) +
                                                                 2.0 * w.w11 * Gu(1) * Gv(1) + w.w20 * Gu(2) * Gv(0) +
                                                                 w.w02 * Gu(0) * Gv(2);
          }
        m_tables.push_back(std::move(c));
      }
      m_band.push_back({i, j, t, Eigen::Index(i - mu.first) * mv.count + (j - mv.first)});
    }
  }
  const int rows = space.netRows(), cols = space.netCols();
  // a table symmetric in d1 (the row of a Toeplitz u layer) is folded: c (P(d1) + P(-d1))
  m_tableEntries.resize(m_tables.size());
  for (size_t t = 0; t < m_tables.size(); ++t) {
    auto at = [&](int d1, int d2) { return m_tables[t][size_t(d1 + m_ru) * (2 * m_rv + 1) + (d2 + m_rv)]; };
    bool symmetric = true;
    for (int d1 = 1; d1 <= m_ru; ++d1)
      for (int d2 = -m_rv; d2 <= m_rv; ++d2) symmetric &= at(d1, d2) == at(-d1, d2);
    for (int d1 = symmetric ? 0 : -m_ru; d1 <= m_ru; ++d1)
      for (int d2 = -m_rv; d2 <= m_rv; ++d2) {
        const double c = at(d1, d2);
        if (c == 0.0) continue;
        const long offset = 3L * (long(d1) * cols + d2), mirror = symmetric && d1 > 0 ? 3L * (-long(d1) * cols + d2) : 0;
        m_tableEntries[t].push_back({offset, mirror, c});
      }
  }
  // first band point of each net row (m_band is in row order)
  m_bandRowStart.assign(size_t(rows) + 1, 0);
  {
    size_t k = 0;
    for (int i = 0; i <= rows; ++i) {
      while (k < m_band.size() && m_band[k].i < i) ++k;
      m_bandRowStart[size_t(i)] = k;
    }
  }
  // Band rows whose interior columns the row kernel computes (their table is Toeplitz in v
  // there: a column of type 0)
  m_bandKernelRow.assign(m_band.size(), -1);
  if (!space.periodicV() && m_colsInterior.count > 0)
    for (int i = mu.first; i < mu.first + mu.count; ++i) {
      const int tu = m_gu.rowType(i);
      if (tu == 0) continue;
      KernelRow r;
      r.i = i;
      r.band = m_bandRowStart[size_t(i)] + size_t(m_colsInterior.first - mv.first);
      const std::vector<double>& table = m_tables[size_t(m_band[r.band].table)];
      r.half.resize(size_t(2 * m_ru + 1) * (m_rv + 1));
      for (int a = 0; a <= 2 * m_ru; ++a)
        for (int b = 0; b <= m_rv; ++b) r.half[size_t(a) * (m_rv + 1) + b] = table[size_t(a) * (2 * m_rv + 1) + (b + m_rv)];
      for (int c = 0; c < m_colsInterior.count; ++c) m_bandKernelRow[r.band + size_t(c)] = int(m_kernelRows.size());
      m_kernelRows.push_back(std::move(r));
    }
  m_bandDirect.resize(m_band.size());
  for (size_t k = 0; k < m_band.size(); ++k) {
    const BandPoint& b = m_band[k];
    bool direct = true;
    for (int d1 = -m_ru; d1 <= m_ru; ++d1)
      for (int d2 = -m_rv; d2 <= m_rv; ++d2) {
        if (m_tables[size_t(b.table)][size_t(d1 + m_ru) * (2 * m_rv + 1) + (d2 + m_rv)] == 0.0) continue;
        direct &= b.i + d1 >= 0 && b.i + d1 < rows && b.j + d2 >= 0 && b.j + d2 < cols;
      }
    m_bandDirect[k] = direct;
  }
}

int StiffnessStencil::neighbourU(int l) const {
  const SplineSpace& s = *m_space;
  if (s.periodicU() && l >= s.netRows()) return l - s.movingU().count;
  return (l >= 0 && l < s.netRows()) ? l : -1;
}

int StiffnessStencil::neighbourV(int l) const {
  const SplineSpace& s = *m_space;
  if (s.periodicV() && l >= s.netCols()) return l - s.movingV().count;
  return (l >= 0 && l < s.netCols()) ? l : -1;
}

Eigen::RowVector3d StiffnessStencil::bandRow(const ControlNet& net, size_t k) const {
  const BandPoint& b = m_band[k];
  if (m_bandDirect[k]) {
    const double* p = net.data() + 3L * (long(b.i) * m_space->netCols() + b.j);
    double x = 0.0, y = 0.0, z = 0.0;
    for (const BandEntry& e : m_tableEntries[size_t(b.table)]) {
      if (e.mirror) {
        x += e.c * (p[e.offset] + p[e.mirror]);
        y += e.c * (p[e.offset + 1] + p[e.mirror + 1]);
        z += e.c * (p[e.offset + 2] + p[e.mirror + 2]);
      } else {
        x += e.c * p[e.offset];
        y += e.c * p[e.offset + 1];
        z += e.c * p[e.offset + 2];
      }
    }
    return Eigen::RowVector3d(x, y, z);
  }
  const std::vector<double>& c = m_tables[size_t(b.table)];
  Eigen::RowVector3d acc = Eigen::RowVector3d::Zero();
  const Eigen::Index cols = m_space->netCols();
  for (int d1 = -m_ru; d1 <= m_ru; ++d1) {
    const int i = neighbourU(b.i + d1);
    if (i < 0) continue;
    const double* row = c.data() + size_t(d1 + m_ru) * (2 * m_rv + 1);
    for (int d2 = -m_rv; d2 <= m_rv; ++d2) {
      const int j = neighbourV(b.j + d2);
      if (j < 0 || row[d2 + m_rv] == 0.0) continue;
      acc += row[d2 + m_rv] * net.row(Eigen::Index(i) * cols + j);
    }
  }
  return acc;
}

double StiffnessStencil::coefficient(int d1, int d2) const {
  d1 = std::abs(d1);
  d2 = std::abs(d2);
  if (d1 > m_ru || d2 > m_rv) return 0.0;
  return m_half[size_t(d1) * (m_rv + 1) + d2];
}

template <typename EntryFunction>
void StiffnessStencil::forEachMovingEntry(EntryFunction&& fn) const {
  const SplineSpace& s = *m_space;
  const LayerRange mu = s.movingU(), mv = s.movingV();
  std::vector<const double*> rowTable(size_t(s.numMoving()), nullptr);
  for (const BandPoint& b : m_band) rowTable[size_t(b.m)] = m_tables[size_t(b.table)].data();
  for (int a = 0; a < mu.count; ++a)
    for (int b = 0; b < mv.count; ++b) {
      const Eigen::Index row = Eigen::Index(a) * mv.count + b;
      const double* table = rowTable[size_t(row)];
      for (int d1 = -m_ru; d1 <= m_ru; ++d1)
        for (int d2 = -m_rv; d2 <= m_rv; ++d2) {
          // the neighbour's moving layer (periodic copies fold onto what they repeat)
          const int i = neighbourU(mu.first + a + d1), j = neighbourV(mv.first + b + d2);
          if (i < 0 || j < 0) continue;
          const double c = table ? table[size_t(d1 + m_ru) * (2 * m_rv + 1) + (d2 + m_rv)] : coefficient(d1, d2);
          // the moving layers the neighbour stands for (none if held: part of A_IB)
          for (const LayerWeight& fu : s.foldU(i))
            for (const LayerWeight& fv : s.foldV(j))
              fn(row, Eigen::Index(fu.layer - mu.first) * mv.count + (fv.layer - mv.first), c * fu.weight * fv.weight);
        }
    }
}

Eigen::SparseMatrix<double> StiffnessStencil::movingMatrix() const {
  const SplineSpace& s = *m_space;
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(size_t(s.numMoving()) * (2 * m_ru + 1) * (2 * m_rv + 1));
  forEachMovingEntry([&](Eigen::Index row, Eigen::Index col, double c) { t.emplace_back(row, col, c); });
  Eigen::SparseMatrix<double> A(s.numMoving(), s.numMoving());
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

Eigen::VectorXd StiffnessStencil::movingDiagonal() const {
  Eigen::VectorXd d = Eigen::VectorXd::Zero(m_space->numMoving());
  forEachMovingEntry([&](Eigen::Index row, Eigen::Index col, double c) {
    if (row == col) d[row] += c;
  });
  return d;
}

namespace {
double gershgorinSum(const StiffnessStencil& a) {
  double sum = 0.0;
  for (int d1 = -a.radiusU(); d1 <= a.radiusU(); ++d1)
    for (int d2 = -a.radiusV(); d2 <= a.radiusV(); ++d2) sum += std::abs(a.coefficient(d1, d2));
  return sum;
}
}  // namespace

double StiffnessStencil::gershgorinBound() const {
  return gershgorinSum(*this) * m_gu.transformBound() * m_gv.transformBound();
}

double StiffnessStencil::eigenvalueBound() const {
  // x' A_II x = y' A y <= sigma |y|^2 <= sigma lambda_max(T'T) |x|^2 for y = T x (GramRows1D)
  return symbolBound() * m_gu.transformBound() * m_gv.transformBound();
}

double StiffnessStencil::symbolBound() const {
  // Symbol(t1, t2) = sum_{a,b} S(a,b) c_a c_b cos(a t1) cos(b t2), c_0 = 1, c_{>0} = 2. It is even
  // and 2 pi periodic in each variable, so [0, pi]^2 covers it.
  const int G = 1025;
  const double pi = 3.14159265358979323846;
  const double delta = pi / (G - 1);
  std::vector<double> cosv(size_t(G) * (m_rv + 1));
  for (int g = 0; g < G; ++g)
    for (int b = 0; b <= m_rv; ++b) cosv[size_t(g) * (m_rv + 1) + b] = (b == 0 ? 1.0 : 2.0) * std::cos(b * g * delta);
  double gridMax = 0.0;
  std::vector<double> r(m_rv + 1);
  for (int g1 = 0; g1 < G; ++g1) {
    for (int b = 0; b <= m_rv; ++b) {
      double sum = 0.0;
      for (int a = 0; a <= m_ru; ++a)
        sum += m_half[size_t(a) * (m_rv + 1) + b] * (a == 0 ? 1.0 : 2.0) * std::cos(a * g1 * delta);
      r[b] = sum;
    }
    for (int g2 = 0; g2 < G; ++g2) {
      double val = 0.0;
      const double* c = &cosv[size_t(g2) * (m_rv + 1)];
      for (int b = 0; b <= m_rv; ++b) val += r[b] * c[b];
      gridMax = std::max(gridMax, val);
    }
  }
  // Every point is within delta/2 of the grid in each variable; Bernstein: |d/dt T| <= deg ||T||.
  const double slack = 0.5 * delta * (m_ru + m_rv);
  return std::min(gridMax / (1.0 - slack), gershgorinSum(*this));
}

namespace {

// Row kernels, written with the vector extensions of Multiversion.h. The core is compiled with
// -ffp-contract=off, so every clone and every chunk width rounds identically and the explicit
// step reproduces applyMoving() bit for bit.
using simd::load4;
using simd::splat;
using simd::store4;
using simd::v4;
using simd::v4i;

// Sum_{a,b} S(a,b) q_a[m +- 3b] for 8 consecutive flattened entries starting at m.
// q[a] points at the folded row sum P(i+a) + P(i-a) (q[0] = P(i)).
BSDEFORM_INLINE void stencil8(const double* const* q, const double* half, int ru, int rv, long m, v4& lo, v4& hi) {
  lo = splat(0.0);
  hi = splat(0.0);
  for (int a = 0; a <= ru; ++a) {
    const double* qa = q[a] + m;
    const double* sa = half + a * (rv + 1);
    lo += splat(sa[0]) * load4(qa);
    hi += splat(sa[0]) * load4(qa + 4);
    for (int b = 1; b <= rv; ++b) {
      const v4 sab = splat(sa[b]);
      const long off = 3L * b;
      lo += sab * (load4(qa + off) + load4(qa - off));
      hi += sab * (load4(qa + 4 + off) + load4(qa + 4 - off));
    }
  }
}

// The same sum for a single entry, in the same order (used for the row's last < 8 entries).
BSDEFORM_INLINE double stencil1(const double* const* q, const double* half, int ru, int rv, long m) {
  double acc = 0.0;
  for (int a = 0; a <= ru; ++a) {
    const double* qa = q[a] + m;
    const double* sa = half + a * (rv + 1);
    acc += sa[0] * qa[0];
    for (int b = 1; b <= rv; ++b) acc += sa[b] * (qa[3L * b] + qa[-3L * b]);
  }
  return acc;
}

// dst = up + down over one net row.
BSDEFORM_MULTIVERSION
void addRows(const double* __restrict up, const double* __restrict down, double* __restrict dst, long len) {
  for (long m = 0; m < len; ++m) dst[m] = up[m] + down[m];
}

// out[m - mBegin] = (A P)(m) for the free entries m in [mBegin, mEnd) of one net row.
BSDEFORM_MULTIVERSION
void applyRow(const double* const* q, const double* half, int ru, int rv, long mBegin, long mEnd, double* out) {
  long m = mBegin;
  for (; m + 8 <= mEnd; m += 8) {
    v4 lo, hi;
    stencil8(q, half, ru, rv, m, lo, hi);
    store4(out + (m - mBegin), lo);
    store4(out + (m - mBegin) + 4, hi);
  }
  for (; m < mEnd; ++m) out[m - mBegin] = stencil1(q, half, ru, rv, m);
}

// Increment form of the central-difference update (beta - gamma = 1):
// P_new = P + alpha (L - A P) + gamma (P - P_old), written over P_old. Returns false if a new
// value is NaN or beyond +-limit.
BSDEFORM_MULTIVERSION
bool updateRow(const double* const* q, const double* half, int ru, int rv, long mBegin, long mEnd,
               const double* prow, double* oldrow, const double* lrow, double alpha, double gamma, double limit) {
  const v4 va = splat(alpha), vg = splat(gamma), vlim = splat(limit), vnlim = splat(-limit);
  v4i inRange = {-1, -1, -1, -1};
  long m = mBegin;
  for (; m + 8 <= mEnd; m += 8) {
    v4 acc[2];
    stencil8(q, half, ru, rv, m, acc[0], acc[1]);
    for (int h = 0; h < 2; ++h) {
      const long k = m + 4 * h;
      const v4 p = load4(prow + k);
      const v4 x = p + va * (load4(lrow + (k - mBegin)) - acc[h]) + vg * (p - load4(oldrow + k));
      store4(oldrow + k, x);
      inRange &= (x <= vlim) & (x >= vnlim);  // false for NaN
    }
  }
  bool ok = inRange[0] && inRange[1] && inRange[2] && inRange[3];
  for (; m < mEnd; ++m) {
    const double acc = stencil1(q, half, ru, rv, m);
    const double p = prow[m];
    const double x = p + alpha * (lrow[m - mBegin] - acc) + gamma * (p - oldrow[m]);
    oldrow[m] = x;
    ok &= (x <= limit && x >= -limit);
  }
  return ok;
}

}  // namespace

template <typename RowFunction>
void StiffnessStencil::forEachInteriorRow(const ControlNet& net, int rowBegin, int rowEnd, RowFunction&& fn) const {
  const SplineSpace& s = *m_space;
  const long rowLen = 3L * s.netCols();
  // A periodic v direction reads n2 layers past the end of a row: they are the row's layers
  // n2 .. 2 n2 - 1 again, appended to padded copies of the rows.
  const bool padV = s.periodicV();
  const long ghost = padV ? 3L * m_rv : 0, padLen = rowLen + ghost;
  const int rows = s.netRows(), shiftU = s.movingU().count;
  auto rowPtr = [&](int l) { return net.data() + long(s.periodicU() && l >= rows ? l - shiftU : l) * rowLen; };
  // Folded row sums q_a = P(i+a) + P(i-a): halves the work of the symmetric stencil.
  thread_local std::vector<double> qbuf;
  qbuf.resize(size_t(m_ru + (padV ? 1 : 0)) * padLen);
  const double* q[kMaxDegree + 1];
  for (int i = rowBegin; i < rowEnd; ++i) {
    double* buf = qbuf.data();
    if (padV) {
      std::copy(rowPtr(i), rowPtr(i) + rowLen, buf);
      std::copy(buf + 3L * m_rv, buf + 3L * m_rv + ghost, buf + rowLen);
      q[0] = buf;
      buf += padLen;
    } else {
      q[0] = rowPtr(i);
    }
    for (int r = 1; r <= m_ru; ++r) {
      double* dst = buf + (r - 1) * padLen;
      addRows(rowPtr(i + r), rowPtr(i - r), dst, rowLen);
      if (padV) std::copy(dst + 3L * m_rv, dst + 3L * m_rv + ghost, dst + rowLen);
      q[r] = dst;
    }
    fn(i, long(i) * rowLen, q);
  }
}

void StiffnessStencil::kernelRow(const ControlNet& net, const KernelRow& r, double* out) const {
  const SplineSpace& s = *m_space;
  const long rowLen = 3L * s.netCols();
  // the layers beyond the net have zero coefficients: a row of zeros stands for them
  thread_local std::vector<double> zeros;  // never written: sized once per net width
  if (zeros.size() != size_t(rowLen)) zeros.assign(size_t(rowLen), 0.0);
  const double* q[2 * kMaxDegree + 1];
  for (int a = 0; a <= 2 * m_ru; ++a) {
    const int l = r.i + a - m_ru;
    q[a] = (l >= 0 && l < s.netRows()) ? net.data() + long(l) * rowLen : zeros.data();
  }
  const long mBegin = 3L * m_colsInterior.first, mEnd = 3L * (m_colsInterior.first + m_colsInterior.count);
  applyRow(q, r.half.data(), 2 * m_ru, m_rv, mBegin, mEnd, out);
}

void StiffnessStencil::applyMoving(const ControlNet& net, ControlNet& out) const {
  const SplineSpace& s = *m_space;
  allocateNet(out, s.numMoving());
  const LayerRange mu = s.movingU(), mv = s.movingV();
  const long mBegin = 3L * m_colsInterior.first, mEnd = 3L * (m_colsInterior.first + m_colsInterior.count);
  // rows are independent: blocks of rows may run on several threads, with the same bits
  const int parts = explicitStepParts();
  runParts(parts, [&](int part) {
    const auto [rowBegin, rowEnd] = interiorRowBlock(part, parts);
    forEachInteriorRow(net, rowBegin, rowEnd, [&](int i, long, const double* const* q) {
      double* dst = out.data() + 3L * (Eigen::Index(i - mu.first) * mv.count + (m_colsInterior.first - mv.first));
      applyRow(q, m_half.data(), m_ru, m_rv, mBegin, mEnd, dst);
    });
  });
  thread_local std::vector<double> rowOut;
  rowOut.resize(3 * size_t(m_colsInterior.count));
  for (const KernelRow& r : m_kernelRows) {
    kernelRow(net, r, rowOut.data());
    for (int c = 0; c < m_colsInterior.count; ++c)
      out.row(m_band[r.band + size_t(c)].m) = Eigen::RowVector3d(rowOut[3 * size_t(c)], rowOut[3 * size_t(c) + 1], rowOut[3 * size_t(c) + 2]);
  }
  for (size_t k = 0; k < m_band.size(); ++k)
    if (m_bandKernelRow[k] < 0) out.row(m_band[k].m) = bandRow(net, k);
}

namespace {
std::atomic<long> g_explicitParallelMinPoints{96L * 96};
}  // namespace

long explicitParallelMinPoints() { return g_explicitParallelMinPoints.load(std::memory_order_relaxed); }

void setExplicitParallelMinPoints(long points) { g_explicitParallelMinPoints.store(points, std::memory_order_relaxed); }

std::pair<int, int> StiffnessStencil::interiorRowBlock(int part, int parts) const {
  const int first = m_rowsInterior.first, count = m_rowsInterior.count;
  return {first + int(long(count) * part / parts), first + int(long(count) * (part + 1) / parts)};
}

int StiffnessStencil::explicitStepParts() const {
  const long points = long(m_rowsInterior.count) * m_colsInterior.count;
  const int threads = kernelThreads();
  if (threads < 2 || points < explicitParallelMinPoints()) return 1;
  // Four blocks per thread: on a shared machine a thread that is descheduled while it holds a
  // block delays the step by one small block, not by half of it.
  return std::max(1, std::min({4 * threads, kMaxStepParts, m_rowsInterior.count}));
}

bool StiffnessStencil::centralDifferenceUpdate(const ControlNet& current, ControlNet& previous, const ControlNet& load,
                                               double alpha, double gamma, double limit,
                                               const std::function<double(int, int)>& alphaScale,
                                               const BandSolve& bandSolve) const {
  const SplineSpace& s = *m_space;
  const LayerRange mu = s.movingU(), mv = s.movingV();
  const long mBegin = 3L * m_colsInterior.first, mEnd = 3L * (m_colsInterior.first + m_colsInterior.count);
  // Rows are independent (each writes only its own entries of `previous`), so blocks of rows
  // may run on several threads with the same bits as one thread.
  const Eigen::Index cols = s.netCols();
  // Band points [k0, k1) (consecutive in m_band, closed under the band solve's coupling). The
  // band points of an interior row are done right after the row, while its neighbourhood is in
  // cache: a separate pass over the band misses the cache on every point of a large net
  // (docs/benchmarks.md, "Why the code is as it is").
  // (A P) of the kernel rows (rows that are not interior rows, done after the parts). The
  // buffer is this thread's; updateBand, which may run on a worker, reads it through a pointer.
  thread_local std::vector<double> kernelBuffer;
  kernelBuffer.resize(m_kernelRows.size() * 3 * size_t(m_colsInterior.count));
  const double* const kernelOut = kernelBuffer.data();
  for (size_t r = 0; r < m_kernelRows.size(); ++r)
    kernelRow(current, m_kernelRows[r], kernelBuffer.data() + r * 3 * size_t(m_colsInterior.count));
  auto elastic = [&](size_t k) {
    const int r = m_bandKernelRow[k];
    if (r < 0) return bandRow(current, k);
    const double* p = kernelOut + (size_t(r) * size_t(m_colsInterior.count) + (k - m_kernelRows[size_t(r)].band)) * 3;
    return Eigen::RowVector3d(p[0], p[1], p[2]);
  };
  auto updateBand = [&](size_t k0, size_t k1) {
    bool ok = true;
    if (k0 >= k1) return ok;
    if (bandSolve) {
      thread_local std::vector<Eigen::RowVector3d> r, a;
      r.resize(k1 - k0);
      a.resize(k1 - k0);
      for (size_t k = k0; k < k1; ++k) r[k - k0] = load.row(m_band[k].m) - elastic(k);
      bandSolve(k0, k1, r.data(), a.data());
      for (size_t k = k0; k < k1; ++k) {
        const Eigen::Index row = Eigen::Index(m_band[k].i) * cols + m_band[k].j;
        const Eigen::RowVector3d p = current.row(row);
        const Eigen::RowVector3d x = p + alpha * a[k - k0] + gamma * (p - previous.row(row));
        previous.row(row) = x;
        ok &= x.cwiseAbs().maxCoeff() <= limit;  // false for NaN
      }
      return ok;
    }
    for (size_t k = k0; k < k1; ++k) {
      const BandPoint& b = m_band[k];
      const double a = alphaScale ? alpha * alphaScale(b.i, b.j) : alpha;
      const Eigen::Index r = Eigen::Index(b.i) * cols + b.j;
      const Eigen::RowVector3d p = current.row(r);
      const Eigen::RowVector3d x = p + a * (load.row(b.m) - elastic(k)) + gamma * (p - previous.row(r));
      previous.row(r) = x;
      ok &= x.cwiseAbs().maxCoeff() <= limit;  // false for NaN
    }
    return ok;
  };
  const int parts = explicitStepParts();
  bool partOk[kMaxStepParts];
  runParts(parts, [&](int part) {
    const auto [rowBegin, rowEnd] = interiorRowBlock(part, parts);
    bool ok = true;
    forEachInteriorRow(current, rowBegin, rowEnd, [&](int i, long rowStart, const double* const* q) {
      const double* lrow =
          load.data() + 3L * (Eigen::Index(i - mu.first) * mv.count + (m_colsInterior.first - mv.first));
      ok &= updateRow(q, m_half.data(), m_ru, m_rv, mBegin, mEnd, current.data() + rowStart,
                      previous.data() + rowStart, lrow, alpha, gamma, limit);
      ok &= updateBand(m_bandRowStart[size_t(i)], m_bandRowStart[size_t(i) + 1]);
    });
    partOk[part] = ok;
  });
  bool ok = std::all_of(partOk, partOk + parts, [](bool b) { return b; });
  // the rows that are not interior rows: before and after them
  const int firstRow = m_rowsInterior.count ? m_rowsInterior.first : s.netRows();
  const int lastRow = m_rowsInterior.count ? m_rowsInterior.first + m_rowsInterior.count : s.netRows();
  ok &= updateBand(0, m_bandRowStart[size_t(firstRow)]);
  ok &= updateBand(m_bandRowStart[size_t(lastRow)], m_band.size());
  return ok;
}

double StiffnessStencil::elementEigenvalueBound() const {
  // 1-D element matrices on one knot span (cardinal coordinates x in [0,1]): the n+1 functions
  // b^n(x - k), k = -n..0, their Gram integrals per derivative order and their integrals.
  struct Element1D {
    Eigen::MatrixXd G[3];
    Eigen::VectorXd mass;
  };
  auto element = [](int n, double h) {
    Element1D e;
    const QuadratureRule& rule = gaussLegendre(n + 1);
    for (int p = 0; p < 3; ++p) e.G[p] = Eigen::MatrixXd::Zero(n + 1, n + 1);
    e.mass = Eigen::VectorXd::Zero(n + 1);
    for (size_t q = 0; q < rule.nodes.size(); ++q) {
      const double x = rule.nodes[q], wq = rule.weights[q];
      for (int a = 0; a <= n; ++a) {
        e.mass[a] += wq * h * cardinalBSpline(n, x + n - a);
        for (int p = 0; p < 3; ++p)
          for (int b = 0; b <= n; ++b)
            e.G[p](a, b) += wq * std::pow(h, 1 - 2 * p) * cardinalBSplineDerivative(n, p, x + n - a) *
                            cardinalBSplineDerivative(n, p, x + n - b);
      }
    }
    return e;
  };
  const Element1D eu = element(m_ru, m_space->basisU().spacing()), ev = element(m_rv, m_space->basisV().spacing());
  const Weights& w = m_weights;
  auto kron = [](const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
    Eigen::MatrixXd k(a.rows() * b.rows(), a.cols() * b.cols());
    for (Eigen::Index i = 0; i < a.rows(); ++i)
      for (Eigen::Index j = 0; j < a.cols(); ++j) k.block(i * b.rows(), j * b.cols(), b.rows(), b.cols()) = a(i, j) * b;
    return k;
  };
  const Eigen::MatrixXd A = w.w10 * kron(eu.G[1], ev.G[0]) + w.w01 * kron(eu.G[0], ev.G[1]) +
                            2.0 * w.w11 * kron(eu.G[1], ev.G[1]) + w.w20 * kron(eu.G[2], ev.G[0]) +
                            w.w02 * kron(eu.G[0], ev.G[2]);
  Eigen::VectorXd r(A.rows());
  for (Eigen::Index a = 0; a < eu.mass.size(); ++a)
    for (Eigen::Index b = 0; b < ev.mass.size(); ++b) r[a * ev.mass.size() + b] = 1.0 / std::sqrt(eu.mass[a] * ev.mass[b]);
  const Eigen::MatrixXd scaled = r.asDiagonal() * A * r.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(scaled, Eigen::EigenvaluesOnly);
  // a small relative margin covers the rounding of this 16..64-point eigenproblem
  return eig.eigenvalues().maxCoeff() * (1.0 + 1e-10);
}

}  // namespace bsdeform
