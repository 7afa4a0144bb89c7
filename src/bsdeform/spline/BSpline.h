// SPDX-License-Identifier: MIT
#pragma once
/// @file BSpline.h
/// Uniform B-splines (González-Hidalgo, Mir, Nicolau, §2): the cardinal B-spline b^n by the
/// recurrence (eq. 1), its derivatives (Theorem 2.1, eq. 3) and the 1-D basis on [0,1] used by the
/// finite-element model (§4.2, with the corrected spacing h = 1/(N+n), see docs/math.md).

#include <array>

namespace bsdeform {

/// Highest supported degree.
constexpr int kMaxDegree = 7;

/// Cardinal uniform B-spline \f$b^n(x)\f$ (eq. 1), support [0, n+1), b^0 = 1 on [0,1).
/// @param[in] degree n >= 0
double cardinalBSpline(int degree, double x);

/// m-th derivative of \f$b^n\f$ (eq. 3 with h = 1):
/// \f$ D^m b^n(x) = \sum_{i=0}^m (-1)^i \binom{m}{i} b^{n-m}(x-i) \f$, zero when m > n.
double cardinalBSplineDerivative(int degree, int order, double x);

/// Values and derivatives of the n+1 basis functions that are non-zero on one knot span.
/// `d[m][j]` is the m-th derivative of function `first + j` (j = 0..n).
struct LocalBasis {
  int first = 0;  ///< paper index k of the first non-zero function
  int count = 0;  ///< n + 1
  std::array<std::array<double, kMaxDegree + 1>, kMaxDegree + 1> d{};
};

/// The 1-D basis of the model: degree n, N free functions, h = 1/(N+n), functions
/// \f$b_{k,h}^n(u) = b^n(u/h - k)\f$ for the paper's index set k = -n .. N+n-1; the free ones are
/// k = 0 .. N-1 (their support lies inside [0,1]).
class BSplineBasis1D {
 public:
  /// @throws std::invalid_argument for degree outside 1..7 or numFree < 1
  BSplineBasis1D(int degree, int numFree);

  int degree() const { return m_degree; }
  int numFree() const { return m_numFree; }
  /// N + 2n: every function relevant on [0,1]
  int numTotal() const { return m_numFree + 2 * m_degree; }
  /// N + n knot spans of width h cover [0,1]
  int numSpans() const { return m_numFree + m_degree; }
  double spacing() const { return 1.0 / numSpans(); }

  /// Knot span index of u (spans are [s h, (s+1) h); u = 1 belongs to the last span).
  int span(double u) const;

  /// Non-zero functions at u and their derivatives up to `maxOrder` (<= degree; higher ones
  /// are zero and reported as such). Local support: O(n^2) work, independent of N.
  void evaluate(double u, int maxOrder, LocalBasis& out) const;

  /// Same, for a point known to lie in span `s` (avoids the floor for quadrature loops).
  void evaluateInSpan(int s, double u, int maxOrder, LocalBasis& out) const;

 private:
  int m_degree;
  int m_numFree;
};

}  // namespace bsdeform
