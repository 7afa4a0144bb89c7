// SPDX-License-Identifier: MIT
// IPC's lagged smooth friction (Friction.h, docs/math.md §18.3): the smoothing functions against
// their closed forms and differences, the frozen frames against brute-force closest points, and the
// pair potential's gradient and Hessian against differences in both regimes (slip below and above ε).
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "bsdeform/contact/Friction.h"

using namespace bsdeform;

namespace {
template <typename F>
double central(F&& f, double x, double h) {
  return (4 * (f(x + h) - f(x - h)) / (2 * h) - (f(x + 2 * h) - f(x - 2 * h)) / (4 * h)) / 3;
}
}  // namespace

TEST_CASE("Friction: f0' = f1, f1 rises from 0 to 1 over epsilon, and the 2x2 Hessian is PSD", "[core][contact]") {
  const double eps = 2e-3;
  CHECK(smoothFrictionF0(0.0, eps) == Approx(eps / 3.0));
  CHECK(smoothFrictionF0(eps, eps) == Approx(eps));
  CHECK(smoothFrictionF1(0.0, eps) == 0.0);
  CHECK(smoothFrictionF1(eps, eps) == Approx(1.0));
  CHECK(smoothFrictionF1(5 * eps, eps) == 1.0);
  for (double y : {1e-4, 7e-4, 1.9e-3, 2.5e-3, 1e-2}) {
    INFO("y " << y);
    CHECK(central([&](double x) { return smoothFrictionF0(x, eps); }, y, 1e-7) ==
          Approx(smoothFrictionF1(y, eps)).epsilon(1e-7));
    CHECK(smoothFrictionF1OverY(y, eps) * y == Approx(smoothFrictionF1(y, eps)));
    // (f1' y - f1) / y³ with f1' by differences
    const double df1 = central([&](double x) { return smoothFrictionF1(x, eps); }, y, 1e-8);
    CHECK(smoothFrictionHessianTerm(y, eps) == Approx((df1 * y - smoothFrictionF1(y, eps)) / (y * y * y)).epsilon(1e-5));
    const Eigen::Vector2d u(0.6 * y, -0.8 * y);
    const Eigen::Matrix2d H = smoothFrictionF1OverY(y, eps) * Eigen::Matrix2d::Identity() +
                              smoothFrictionHessianTerm(y, eps) * u * u.transpose();
    CHECK(Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(H).eigenvalues().minCoeff() >= -1e-9 * H.norm());
  }
}

TEST_CASE("Friction: the frozen frame joins the closest points and is normal to the line between them",
          "[core][contact]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> X(-1.0, 1.0);
  auto point = [&] { return Eigen::Vector3d(X(rng), X(rng), X(rng)); };
  for (int trial = 0; trial < 400; ++trial) {
    const Eigen::Vector3d p = point(), t0 = point(), t1 = point(), t2 = point();
    FrictionPair f;
    pointTriangleFrame(p, t0, t1, t2, f);
    CHECK(f.coefficient[0] == 1.0);
    const double b0 = -f.coefficient[1], b1 = -f.coefficient[2], b2 = -f.coefficient[3];
    CHECK(b0 + b1 + b2 == Approx(1.0));
    CHECK(std::min({b0, b1, b2}) >= -1e-12);
    const Eigen::Vector3d c = b0 * t0 + b1 * t1 + b2 * t2;
    // brute force: no point of the triangle on a fine barycentric grid is closer
    double best = 1e300;
    for (int i = 0; i <= 60; ++i)
      for (int j = 0; i + j <= 60; ++j) best = std::min(best, (p - (t0 + i / 60.0 * (t1 - t0) + j / 60.0 * (t2 - t0))).norm());
    CHECK((p - c).norm() <= best + 1e-12);
    CHECK((p - c).norm() >= best - 0.05);
    CHECK((f.basis.transpose() * f.basis - Eigen::Matrix2d::Identity()).norm() < 1e-12);
    CHECK((f.basis.transpose() * (p - c)).norm() < 1e-10 * (p - c).norm());

    const Eigen::Vector3d a0 = point(), a1 = point(), q0 = point(), q1 = point();
    FrictionPair e;
    edgeEdgeFrame(a0, a1, q0, q1, e);
    const double alpha = e.coefficient[1], beta = -e.coefficient[3];
    CHECK(e.coefficient[0] + e.coefficient[1] == Approx(1.0));
    CHECK(e.coefficient[2] + e.coefficient[3] == Approx(-1.0));
    const Eigen::Vector3d ca = a0 + alpha * (a1 - a0), cb = q0 + beta * (q1 - q0);
    double edgeBest = 1e300;
    for (int i = 0; i <= 200; ++i)
      for (int j = 0; j <= 200; ++j) edgeBest = std::min(edgeBest, ((a0 + i / 200.0 * (a1 - a0)) - (q0 + j / 200.0 * (q1 - q0))).norm());
    CHECK((ca - cb).norm() <= edgeBest + 1e-12);
    CHECK((e.basis.transpose() * (ca - cb)).norm() < 1e-10 * (ca - cb).norm());
  }
}

TEST_CASE("Friction: the pair potential's gradient and Hessian against differences, sticking and sliding",
          "[core][contact]") {
  FrictionPair f;
  pointTriangleFrame(Eigen::Vector3d(0.2, 0.3, 0.01), Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
                     Eigen::Vector3d(0, 1, 0), f);
  f.normalForce = 3.0;
  const double mu = 0.4, eps = 1e-3;
  for (double size : {2e-4, 8e-4, 5e-3}) {  // slips below, near and above eps
    const Eigen::Vector3d r = size * Eigen::Vector3d(0.6, -0.8, 0.3);
    Eigen::Vector3d g;
    Eigen::Matrix3d H;
    const double D = frictionPotential(f, r, mu, eps, &g, &H);
    INFO("slip " << size);
    CHECK(D > 0.0);
    for (int k = 0; k < 3; ++k) {
      auto along = [&](double t) {
        Eigen::Vector3d q = r;
        q[k] += t;
        return q;
      };
      CHECK(central([&](double t) { return frictionPotential(f, along(t), mu, eps, nullptr, nullptr); }, 0.0, 1e-8) ==
            Approx(g[k]).margin(1e-9));
      for (int l = 0; l < 3; ++l)
        CHECK(central([&](double t) {
                Eigen::Vector3d gg;
                frictionPotential(f, along(t), mu, eps, &gg, nullptr);
                return gg[l];
              }, 0.0, 1e-8) == Approx(H(l, k)).margin(1e-5 * H.norm()));
    }
    CHECK(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(H).eigenvalues().minCoeff() >= -1e-9 * H.norm());
    // the normal component of the slip does nothing; sliding, the force is mu lambda
    CHECK(g.dot(Eigen::Vector3d::UnitZ()) == Approx(0.0).margin(1e-12));
    if (size > eps) CHECK(g.norm() == Approx(mu * f.normalForce));
  }
}
