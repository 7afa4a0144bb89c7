// SPDX-License-Identifier: MIT
#include "bsdeform/StiffnessStencil.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "bsdeform/GaussLegendre.h"

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

namespace {
void checkWeight(double w, const char* name) {
  if (!std::isfinite(w) || w < 0.0)
    throw std::invalid_argument(std::string("weight ") + name + " must be finite and >= 0, got " + std::to_string(w));
}
}  // namespace

StiffnessStencil::StiffnessStencil(const SplineSpace& space, const Weights& w)
    : m_space(&space), m_ru(space.degreeU()), m_rv(space.degreeV()) {
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
}

double StiffnessStencil::coefficient(int d1, int d2) const {
  d1 = std::abs(d1);
  d2 = std::abs(d2);
  if (d1 > m_ru || d2 > m_rv) return 0.0;
  return m_half[size_t(d1) * (m_rv + 1) + d2];
}

Eigen::SparseMatrix<double> StiffnessStencil::interiorMatrix() const {
  const SplineSpace& s = *m_space;
  const int N1 = s.numFreeU(), N2 = s.numFreeV();
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(size_t(s.numFree()) * (2 * m_ru + 1) * (2 * m_rv + 1));
  for (int a = 0; a < N1; ++a)
    for (int b = 0; b < N2; ++b)
      for (int d1 = -m_ru; d1 <= m_ru; ++d1)
        for (int d2 = -m_rv; d2 <= m_rv; ++d2) {
          const int a2 = a + d1, b2 = b + d2;
          if (a2 < 0 || a2 >= N1 || b2 < 0 || b2 >= N2) continue;
          t.emplace_back(a * N2 + b, a2 * N2 + b2, coefficient(d1, d2));
        }
  Eigen::SparseMatrix<double> A(s.numFree(), s.numFree());
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

double StiffnessStencil::gershgorinBound() const {
  double sum = 0.0;
  for (int d1 = -m_ru; d1 <= m_ru; ++d1)
    for (int d2 = -m_rv; d2 <= m_rv; ++d2) sum += std::abs(coefficient(d1, d2));
  return sum;
}

double StiffnessStencil::eigenvalueBound() const {
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
  return std::min(gridMax / (1.0 - slack), gershgorinBound());
}

namespace {

// Row kernels, written with GCC/Clang vector extensions so that they vectorise for certain:
// four doubles per vector (AVX2 in the avx2 clone, two SSE2 registers in the default one).
// The core is compiled with -ffp-contract=off, so every clone and every chunk width rounds
// identically and the explicit step reproduces applyFree() bit for bit.
typedef double v4 __attribute__((vector_size(32), aligned(8), may_alias));
typedef long long v4i __attribute__((vector_size(32)));

// Helpers are forced inline so that each CPU-specific clone compiles them for its own ISA.
#define BSDEFORM_INLINE inline __attribute__((always_inline))
BSDEFORM_INLINE v4 load4(const double* p) { return *reinterpret_cast<const v4*>(p); }
BSDEFORM_INLINE void store4(double* p, v4 x) { *reinterpret_cast<v4*>(p) = x; }
BSDEFORM_INLINE v4 splat(double x) { return v4{x, x, x, x}; }

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

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define BSDEFORM_MULTIVERSION __attribute__((target_clones("avx2", "default")))
#else
#define BSDEFORM_MULTIVERSION
#endif

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
void StiffnessStencil::forEachFreeRow(const ControlNet& net, RowFunction&& fn) const {
  const SplineSpace& s = *m_space;
  const long rowLen = 3L * s.netCols();
  // Folded row sums q_a = P(i+a) + P(i-a): halves the work of the symmetric stencil.
  thread_local std::vector<double> qbuf;
  qbuf.resize(size_t(m_ru) * rowLen);
  const double* q[kMaxDegree + 1];
  const double* P = net.data();
  for (int a = 0; a < s.numFreeU(); ++a) {
    const long i = a + m_ru;  // net row
    q[0] = P + i * rowLen;
    for (int r = 1; r <= m_ru; ++r) {
      double* dst = qbuf.data() + (r - 1) * rowLen;
      addRows(P + (i + r) * rowLen, P + (i - r) * rowLen, dst, rowLen);
      q[r] = dst;
    }
    fn(a, i * rowLen, q);
  }
}

void StiffnessStencil::applyFree(const ControlNet& net, ControlNet& out) const {
  const SplineSpace& s = *m_space;
  out.resize(s.numFree(), 3);
  const int N2 = s.numFreeV();
  const long mBegin = 3L * m_rv, mEnd = 3L * (m_rv + N2);
  forEachFreeRow(net, [&](int a, long, const double* const* q) {
    applyRow(q, m_half.data(), m_ru, m_rv, mBegin, mEnd, out.data() + 3L * a * N2);
  });
}

bool StiffnessStencil::centralDifferenceUpdate(const ControlNet& current, ControlNet& previous, const ControlNet& load,
                                               double alpha, double gamma, double limit) const {
  const int N2 = m_space->numFreeV();
  const long mBegin = 3L * m_rv, mEnd = 3L * (m_rv + N2);
  bool ok = true;
  forEachFreeRow(current, [&](int a, long rowStart, const double* const* q) {
    ok &= updateRow(q, m_half.data(), m_ru, m_rv, mBegin, mEnd, current.data() + rowStart, previous.data() + rowStart,
                    load.data() + 3L * a * N2, alpha, gamma, limit);
  });
  return ok;
}

}  // namespace bsdeform
