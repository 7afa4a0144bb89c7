// SPDX-License-Identifier: MIT
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "bsdeform/spline/GaussLegendre.h"
#include "bsdeform/energy/StiffnessStencil.h"

using namespace bsdeform;

namespace {
// a(B_k, B_j) of eq. 7 by brute-force 2-D Gauss quadrature over every knot cell of [0,1]^2,
// evaluating each B-spline from the cardinal definition (no stencil, no LocalBasis).
double bruteForceEntry(const SplineSpace& s, const Weights& w, int k1, int k2, int j1, int j2) {
  const int n1 = s.degreeU(), n2 = s.degreeV();
  const double h1 = s.basisU().spacing(), h2 = s.basisV().spacing();
  const QuadratureRule& g1 = gaussLegendre(n1 + 2);
  const QuadratureRule& g2 = gaussLegendre(n2 + 2);
  auto D1 = [&](int k, int p, double u) { return cardinalBSplineDerivative(n1, p, u / h1 - k) * std::pow(h1, -p); };
  auto D2 = [&](int k, int p, double v) { return cardinalBSplineDerivative(n2, p, v / h2 - k) * std::pow(h2, -p); };
  double sum = 0.0;
  for (int c1 = 0; c1 < s.basisU().numSpans(); ++c1)
    for (int c2 = 0; c2 < s.basisV().numSpans(); ++c2)
      for (size_t q1 = 0; q1 < g1.nodes.size(); ++q1)
        for (size_t q2 = 0; q2 < g2.nodes.size(); ++q2) {
          const double u = (c1 + g1.nodes[q1]) * h1, v = (c2 + g2.nodes[q2]) * h2;
          const double wq = g1.weights[q1] * g2.weights[q2] * h1 * h2;
          const double integrand =
              w.w10 * D1(k1, 1, u) * D2(k2, 0, v) * D1(j1, 1, u) * D2(j2, 0, v) +
              w.w01 * D1(k1, 0, u) * D2(k2, 1, v) * D1(j1, 0, u) * D2(j2, 1, v) +
              2 * w.w11 * D1(k1, 1, u) * D2(k2, 1, v) * D1(j1, 1, u) * D2(j2, 1, v) +
              w.w20 * D1(k1, 2, u) * D2(k2, 0, v) * D1(j1, 2, u) * D2(j2, 0, v) +
              w.w02 * D1(k1, 0, u) * D2(k2, 2, v) * D1(j1, 0, u) * D2(j2, 2, v);
          sum += wq * integrand;
        }
  return sum;
}
}  // namespace

TEST_CASE("StiffnessStencil: 1-D Gram integrals equal the autocorrelation b^{2n+1}", "[core]") {
  // int D^p b^n(x) D^p b^n(x-d) dx = (-1)^p D^{2p} b^{2n+1}(n+1+d): an independent closed form.
  for (int n = 1; n <= kMaxDegree; ++n)
    for (int p = 0; p <= 2; ++p) {
      const std::vector<double> g = cardinalGram(n, p);
      for (int d = 0; d <= n; ++d) {
        const double ref = p > n ? 0.0 : (p % 2 ? -1.0 : 1.0) * cardinalBSplineDerivative(2 * n + 1, 2 * p, n + 1.0 + d);
        CHECK(g[d] == Approx(ref).margin(1e-13));
      }
    }
  // classic values: cubic mass 151/315, linear stiffness (2, -1)
  CHECK(cardinalGram(3, 0)[0] == Approx(151.0 / 315.0).epsilon(1e-14));
  CHECK(cardinalGram(1, 1)[0] == Approx(2.0));
  CHECK(cardinalGram(1, 1)[1] == Approx(-1.0));
}

TEST_CASE("StiffnessStencil: the stencil reproduces a brute-force quadrature assembly of the full matrix", "[core]") {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> W(0.05, 2.0);
  const int degrees[][2] = {{3, 3}, {2, 3}, {1, 2}, {4, 2}};
  for (auto& dg : degrees) {
    const SplineSpace s(dg[0], dg[1], 4, 5);
    const Weights w{W(rng), W(rng), W(rng), W(rng), W(rng)};
    const StiffnessStencil st(s, w);
    double maxErr = 0.0, maxVal = 0.0;
    // every free row against every column of the full net (A_II and A_IB)
    for (int k1 = 0; k1 < s.numU(); ++k1)
      for (int k2 = 0; k2 < s.numV(); ++k2)
        for (int j1 = -s.degreeU(); j1 < s.numU() + s.degreeU(); ++j1)
          for (int j2 = -s.degreeV(); j2 < s.numV() + s.degreeV(); ++j2) {
            const double ref = bruteForceEntry(s, w, k1, k2, j1, j2);
            maxErr = std::max(maxErr, std::abs(st.coefficient(j1 - k1, j2 - k2) - ref));
            maxVal = std::max(maxVal, std::abs(ref));
          }
    INFO("degree " << dg[0] << "," << dg[1]);
    CHECK(maxErr <= 1e-11 * maxVal);
  }
}

TEST_CASE("StiffnessStencil: A_II is symmetric positive definite, constants and planes are in the kernel", "[core]") {
  const SplineSpace s(3, 2, 6, 7);
  const Weights w{0.3, 0.7, 0.2, 0.05, 0.11};
  const StiffnessStencil st(s, w);
  const Eigen::MatrixXd A = Eigen::MatrixXd(st.movingMatrix());
  CHECK((A - A.transpose()).norm() == 0.0);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(A);
  CHECK(eig.eigenvalues().minCoeff() > 0.0);
  // the full operator annihilates constants and (Greville) planes: (A P)_free = 0
  ControlNet out;
  ControlNet constant = ControlNet::Constant(s.netSize(), 3, 2.5);
  st.applyMoving(constant, out);
  CHECK(out.cwiseAbs().maxCoeff() < 1e-11);
  ControlNet plane = s.grevillePlane();
  st.applyMoving(plane, out);
  CHECK(out.cwiseAbs().maxCoeff() < 1e-11);
  // applyMoving agrees with the sparse matrix on the free part
  std::mt19937 rng(1);
  std::normal_distribution<double> N01;
  ControlNet net = ControlNet::Zero(s.netSize(), 3);
  for (Eigen::Index f = 0; f < s.numMoving(); ++f)
    net.row(s.movingToNet(f)) << N01(rng), N01(rng), N01(rng);
  st.applyMoving(net, out);
  const ControlNet ref = st.movingMatrix() * s.gatherMoving(net);
  CHECK((out - ref).norm() < 1e-12 * ref.norm());
}

TEST_CASE("StiffnessStencil: the symbol bound is an upper bound of lambda_max and is sharp", "[core]") {
  for (int n : {1, 2, 3, 5}) {
    const SplineSpace s(n, n, 24, 24);
    const StiffnessStencil st(s, Weights{});
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Eigen::MatrixXd(st.movingMatrix()), Eigen::EigenvaluesOnly);
    const double lmax = eig.eigenvalues().maxCoeff();
    INFO("degree " << n << " lambda_max " << lmax << " bound " << st.eigenvalueBound());
    CHECK(st.eigenvalueBound() >= lmax);
    CHECK(st.eigenvalueBound() <= 1.10 * lmax);
    CHECK(st.gershgorinBound() >= st.eigenvalueBound() * (1 - 1e-12));
  }
}

TEST_CASE("StiffnessStencil: negative or NaN weights are rejected by name", "[core]") {
  const SplineSpace s(3, 3, 4, 4);
  CHECK_THROWS_WITH(StiffnessStencil(s, Weights{-1, 0.1, 0.01, 0.01, 0.01}), Catch::Contains("w10") && Catch::Contains("-1"));
  CHECK_THROWS_WITH(StiffnessStencil(s, Weights{0.1, 0.1, NAN, 0.01, 0.01}), Catch::Contains("w11") && Catch::Contains("nan"));
}
