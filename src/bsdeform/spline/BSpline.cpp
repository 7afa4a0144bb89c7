// SPDX-License-Identifier: MIT
#include "bsdeform/spline/BSpline.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace bsdeform {

double cardinalBSpline(int degree, double x) {
  if (degree < 0) return 0.0;
  if (degree == 0) return (x >= 0.0 && x < 1.0) ? 1.0 : 0.0;
  if (x <= 0.0 || x >= degree + 1) return 0.0;
  const double n = degree;
  return x / n * cardinalBSpline(degree - 1, x) + (n + 1.0 - x) / n * cardinalBSpline(degree - 1, x - 1.0);
}

namespace {
double binomial(int m, int i) {
  double r = 1.0;
  for (int t = 1; t <= i; ++t) r = r * (m - i + t) / t;
  return r;
}
}  // namespace

double cardinalBSplineDerivative(int degree, int order, double x) {
  if (order > degree) return 0.0;
  double sum = 0.0;
  for (int i = 0; i <= order; ++i) {
    const double sign = (i % 2 == 0) ? 1.0 : -1.0;
    sum += sign * binomial(order, i) * cardinalBSpline(degree - order, x - i);
  }
  return sum;
}

BSplineBasis1D::BSplineBasis1D(int degree, int numFree) : m_degree(degree), m_numFree(numFree) {
  if (degree < 1 || degree > kMaxDegree)
    throw std::invalid_argument("B-spline degree must be between 1 and " + std::to_string(kMaxDegree) +
                                ", got " + std::to_string(degree));
  if (numFree < 1)
    throw std::invalid_argument("number of free control points must be at least 1, got " +
                                std::to_string(numFree));
}

int BSplineBasis1D::span(double u) const {
  const int spans = numSpans();
  // u * spans is exact at u = 0 and u = 1 (spans is an integer), so the boundary maps exactly.
  double x = u * spans;
  int s = static_cast<int>(std::floor(x));
  if (s < 0) s = 0;
  if (s >= spans) s = spans - 1;
  return s;
}

void BSplineBasis1D::evaluate(double u, int maxOrder, LocalBasis& out) const {
  evaluateInSpan(span(u), u, maxOrder, out);
}

void BSplineBasis1D::evaluateInSpan(int s, double u, int maxOrder, LocalBasis& out) const {
  const int n = m_degree;
  const int spans = numSpans();
  // Local coordinate in the span; the functions non-zero there are k = s-n .. s, and function
  // k = s - j is b^n evaluated at tau + j.
  const double tau = u * spans - s;
  // table[p][j] = b^p(tau + j), j = 0..p, built by the recurrence (eq. 1) level by level.
  double table[kMaxDegree + 1][kMaxDegree + 2] = {};
  table[0][0] = 1.0;
  for (int p = 1; p <= n; ++p) {
    for (int j = 0; j <= p; ++j) {
      const double t = tau + j;
      const double left = (j <= p - 1) ? table[p - 1][j] : 0.0;       // b^{p-1}(t)
      const double right = (j >= 1) ? table[p - 1][j - 1] : 0.0;      // b^{p-1}(t-1)
      table[p][j] = (t * left + (p + 1 - t) * right) / p;
    }
  }
  out.first = s - n;
  out.count = n + 1;
  if (maxOrder < 0) maxOrder = 0;
  if (maxOrder > kMaxDegree) maxOrder = kMaxDegree;
  double hinv = static_cast<double>(spans);
  // Index in `out` is i = 0..n for function first + i = s - n + i, i.e. j = n - i.
  for (int m = 0; m <= maxOrder; ++m) {
    const double scale = std::pow(hinv, m);
    for (int i = 0; i <= n; ++i) {
      if (m > n) {
        out.d[m][i] = 0.0;
        continue;
      }
      const int j = n - i;
      // Theorem 2.1: D^m b_{k,h}^n = h^{-m} sum_r (-1)^r C(m,r) b^{n-m}(x/h - k - r).
      double sum = 0.0;
      double c = 1.0;  // binomial(m, r) with sign
      for (int r = 0; r <= m; ++r) {
        const int jj = j - r;
        if (jj >= 0 && jj <= n - m) sum += c * table[n - m][jj];
        c = -c * (m - r) / (r + 1);
      }
      out.d[m][i] = scale * sum;
    }
  }
}

}  // namespace bsdeform
