// SPDX-License-Identifier: MIT
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "bsdeform/spline/BSpline.h"
#include "bsdeform/spline/GaussLegendre.h"

using namespace bsdeform;

namespace {
// m-th derivative obtained by differentiating the recurrence (eq. 1) with the product rule,
// independent of Theorem 2.1:
// D^m[x/n b(x)] = x/n D^m b(x) + m/n D^{m-1} b(x), and likewise for the second term.
double recurrenceDerivative(int n, int m, double x) {
  if (n == 0) return m == 0 ? ((x >= 0 && x < 1) ? 1.0 : 0.0) : 0.0;
  double r = x / n * recurrenceDerivative(n - 1, m, x) + (n + 1 - x) / n * recurrenceDerivative(n - 1, m, x - 1);
  if (m > 0)
    r += double(m) / n * (recurrenceDerivative(n - 1, m - 1, x) - recurrenceDerivative(n - 1, m - 1, x - 1));
  return r;
}
}  // namespace

TEST_CASE("BSpline: cardinal b^n is symmetric, non-negative, supported on [0,n+1], integrates to 1", "[core]") {
  for (int n = 1; n <= kMaxDegree; ++n) {
    const QuadratureRule& g = gaussLegendre(n + 1);
    double integral = 0.0;
    for (int s = 0; s <= n; ++s)
      for (size_t q = 0; q < g.nodes.size(); ++q) integral += g.weights[q] * cardinalBSpline(n, s + g.nodes[q]);
    CHECK(integral == Approx(1.0).epsilon(1e-14));
    for (double x = -1.0; x <= n + 2.0; x += 0.137) {
      const double b = cardinalBSpline(n, x);
      CHECK(b >= 0.0);
      if (x <= 0.0 || x >= n + 1) CHECK(b == 0.0);
      CHECK(b == Approx(cardinalBSpline(n, n + 1 - x)).margin(1e-15));
    }
  }
}

TEST_CASE("BSpline: partition of unity and non-negativity of the basis on [0,1]", "[core]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (int n = 1; n <= kMaxDegree; ++n)
    for (int N : {1, 2, 5, 17}) {
      BSplineBasis1D basis(n, N);
      for (int t = 0; t < 200; ++t) {
        const double u = (t == 0) ? 0.0 : (t == 1) ? 1.0 : U(rng);
        LocalBasis lb;
        basis.evaluate(u, n, lb);
        double sum = 0.0;
        for (int i = 0; i < lb.count; ++i) {
          CHECK(lb.d[0][i] >= -1e-15);
          sum += lb.d[0][i];
        }
        CHECK(sum == Approx(1.0).epsilon(1e-13));
        CHECK(lb.first >= -n);
        CHECK(lb.first + n <= N + n - 1);
        // derivatives of a partition of unity vanish
        for (int m = 1; m <= n; ++m) {
          double dsum = 0.0, scale = 0.0;
          for (int i = 0; i < lb.count; ++i) dsum += lb.d[m][i], scale += std::abs(lb.d[m][i]);
          CHECK(std::abs(dsum) <= 1e-11 * scale);
        }
      }
    }
}

TEST_CASE("BSpline: local values equal the scaled cardinal B-spline b^n(u/h - k)", "[core]") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (int n = 1; n <= kMaxDegree; ++n) {
    BSplineBasis1D basis(n, 6);
    const double h = basis.spacing();
    for (int t = 0; t < 50; ++t) {
      const double u = U(rng);
      LocalBasis lb;
      basis.evaluate(u, 0, lb);
      for (int k = -n; k < 6 + n; ++k) {
        const int i = k - lb.first;
        const double local = (i >= 0 && i <= n) ? lb.d[0][i] : 0.0;
        CHECK(local == Approx(cardinalBSpline(n, u / h - k)).margin(1e-13));
      }
    }
  }
}

TEST_CASE("BSpline: derivatives (Theorem 2.1) match finite differences and the differentiated recurrence", "[core]") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(0.02, 0.98);
  for (int n = 1; n <= kMaxDegree; ++n) {
    const int N = 4;
    BSplineBasis1D basis(n, N);
    const double h = basis.spacing();
    for (int t = 0; t < 40; ++t) {
      double u = U(rng);
      // stay away from knots so that finite differences see one polynomial piece
      const double x = u / h;
      if (std::abs(x - std::round(x)) < 1e-3) continue;
      LocalBasis lb, lp, lm;
      const double eps = 1e-6;
      basis.evaluate(u, n, lb);
      basis.evaluateInSpan(basis.span(u), u + eps, n, lp);
      basis.evaluateInSpan(basis.span(u), u - eps, n, lm);
      for (int m = 0; m <= n; ++m)
        for (int i = 0; i <= n; ++i) {
          const int k = lb.first + i;
          // against the recurrence differentiated directly (chain rule gives h^-m)
          const double ref = recurrenceDerivative(n, m, x - k) * std::pow(1.0 / h, m);
          CHECK(lb.d[m][i] == Approx(ref).epsilon(1e-10).margin(1e-9 * std::pow(1.0 / h, m)));
          CHECK(cardinalBSplineDerivative(n, m, x - k) == Approx(recurrenceDerivative(n, m, x - k)).margin(1e-12));
          if (m >= 1) {
            const double fd = (lp.d[m - 1][i] - lm.d[m - 1][i]) / (2 * eps);
            CHECK(lb.d[m][i] == Approx(fd).epsilon(1e-5).margin(1e-5 * std::pow(1.0 / h, m)));
          }
        }
      // orders above the degree are zero
      LocalBasis hi;
      basis.evaluate(u, kMaxDegree, hi);
      for (int m = n + 1; m <= kMaxDegree; ++m)
        for (int i = 0; i <= n; ++i) CHECK(hi.d[m][i] == 0.0);
    }
  }
}

TEST_CASE("BSpline: free functions and their first n-1 derivatives vanish exactly on the boundary", "[core]") {
  for (int n = 1; n <= kMaxDegree; ++n)
    for (int N : {1, 3, 8}) {
      BSplineBasis1D basis(n, N);
      for (double u : {0.0, 1.0}) {
        LocalBasis lb;
        basis.evaluate(u, n, lb);
        for (int i = 0; i <= n; ++i) {
          const int k = lb.first + i;
          if (k < 0 || k >= N) continue;
          for (int m = 0; m < n; ++m) CHECK(lb.d[m][i] == 0.0);
        }
      }
    }
}

TEST_CASE("GaussLegendre: q points integrate x^p exactly for p <= 2q-1", "[core]") {
  for (int q = 1; q <= 12; ++q) {
    const QuadratureRule& r = gaussLegendre(q);
    for (int p = 0; p <= 2 * q - 1; ++p) {
      double s = 0.0;
      for (int i = 0; i < q; ++i) s += r.weights[i] * std::pow(r.nodes[i], p);
      CHECK(s == Approx(1.0 / (p + 1)).epsilon(1e-14));
    }
  }
  CHECK_THROWS_WITH(gaussLegendre(0), Catch::Contains("got 0"));
}
