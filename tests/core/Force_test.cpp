// SPDX-License-Identifier: MIT
#include <catch2/catch.hpp>
#include <cmath>

#include "bsdeform/forces/Force.h"

using namespace bsdeform;

namespace {
// int_{-inf}^{x} b^n = sum_{i>=0} b^{n+1}(x - i): the exact antiderivative of a cardinal B-spline.
double cardinalIntegral(int n, double x) {
  if (x >= n + 1) return 1.0;
  double s = 0.0;
  for (int i = 0; i <= n + 1; ++i) s += cardinalBSpline(n + 1, x - i);
  return s;
}
double basisIntegral(const BSplineBasis1D& b, int k, double lo, double hi) {
  const double h = b.spacing();
  return h * (cardinalIntegral(b.degree(), hi / h - k) - cardinalIntegral(b.degree(), lo / h - k));
}

ControlNet loadOf(const Force& f, const SplineSpace& s, double t = 0.0) {
  const ControlNet net = s.grevillePlane();
  ControlNet load = ControlNet::Zero(s.numMoving(), 3);
  f.addLoad(LoadContext{s, net, net, 0.1, t}, load);
  return load;
}
}  // namespace

TEST_CASE("Force: a point force gives L_k = F B_k(u0, v0) exactly", "[core]") {
  const SplineSpace s(3, 2, 6, 5);
  const Eigen::Vector3d F(1.5, -2.0, 3.0);
  const double u0 = 0.37, v0 = 0.61;
  const ControlNet L = loadOf(PointForce(u0, v0, F), s);
  const double h1 = s.basisU().spacing(), h2 = s.basisV().spacing();
  for (int a = 0; a < 6; ++a)
    for (int b = 0; b < 5; ++b) {
      const double B = cardinalBSpline(3, u0 / h1 - a) * cardinalBSpline(2, v0 / h2 - b);
      CHECK((L.row(a * 5 + b).transpose() - F * B).norm() < 1e-14);
    }
}

TEST_CASE("Force: a region force is integrated exactly (knot spans split at its edges)", "[core]") {
  for (int n : {1, 2, 3, 5}) {
    const SplineSpace s(n, n, 7, 7);
    const Eigen::Vector3d f(0.0, 100.0, -40.0);
    const ParamRect r{0.4, 0.6, 0.33, 0.71};  // edges inside knot spans
    const ControlNet L = loadOf(DistributedForce(f, r), s);
    for (int a = 0; a < 7; ++a)
      for (int b = 0; b < 7; ++b) {
        const double I = basisIntegral(s.basisU(), a, r.u0, r.u1) * basisIntegral(s.basisV(), b, r.v0, r.v1);
        INFO("degree " << n << " k = (" << a << "," << b << ")");
        CHECK((L.row(a * 7 + b).transpose() - f * I).norm() <= 1e-13 * f.norm());
      }
  }
}

TEST_CASE("Force: a uniform force loads every free point with f h1 h2", "[core]") {
  const SplineSpace s(3, 4, 5, 9);
  const Eigen::Vector3d f(0, 0, 7);
  const ControlNet L = loadOf(DistributedForce(f), s);
  const double w = s.basisU().spacing() * s.basisV().spacing();
  for (Eigen::Index i = 0; i < L.rows(); ++i) CHECK((L.row(i).transpose() - f * w).norm() < 1e-14);
}

TEST_CASE("Force: a smooth density converges with the number of Gauss points", "[core]") {
  const SplineSpace s(3, 3, 8, 8);
  const double pi = 3.14159265358979323846;
  auto density = [pi](const SurfaceSample& p) {
    return Eigen::Vector3d(50 * std::sin(p.v * pi), 50 * std::sin(p.u * pi), 200 * std::cos(p.u * pi) * std::sin(p.v * pi));
  };
  const ControlNet ref = loadOf(DistributedForce(density, kConstant, ParamRect{}, 12), s);
  const ControlNet low = loadOf(DistributedForce(density, kConstant, ParamRect{}, 0), s);
  const ControlNet mid = loadOf(DistributedForce(density, kConstant, ParamRect{}, 2), s);
  const double eLow = (low - ref).norm(), eMid = (mid - ref).norm();
  CHECK(eMid < eLow);
  CHECK(eMid < 1e-6 * ref.norm());
}

TEST_CASE("Force: callables see position, velocity, normal and time as requested", "[core]") {
  const SplineSpace s(3, 3, 4, 4);
  ControlNet cur = s.grevillePlane(), prev = s.grevillePlane();
  for (Eigen::Index f = 0; f < s.numMoving(); ++f) {
    cur(s.movingToNet(f), 2) += 0.5;
    prev(s.movingToNet(f), 2) += 0.3;
  }
  const LoadContext ctx{s, cur, prev, 0.1, 2.5};
  const SurfaceSample smp = sampleSurface(ctx, 0.5, 0.5, kDependsOnPosition | kDependsOnVelocity | kDependsOnNormal);
  const SurfacePoint ref = s.evaluate(cur, 0.5, 0.5, 1);
  CHECK((smp.position - ref.position).norm() < 1e-14);
  CHECK((smp.normal - ref.normal()).norm() < 1e-14);
  CHECK(smp.velocity.z() == Approx((ref.position.z() - s.evaluate(prev, 0.5, 0.5).position.z()) / 0.1));
  CHECK(smp.t == 2.5);
}

TEST_CASE("Force: bad force parameters are rejected with their value", "[core]") {
  CHECK_THROWS_WITH(PointForce(1.5, 0.5, Eigen::Vector3d(0, 0, 1)), Catch::Contains("u") && Catch::Contains("1.5"));
  CHECK_THROWS_WITH(PointForce(0.5, 0.5, Eigen::Vector3d(0, NAN, 1)), Catch::Contains("finite"));
  CHECK_THROWS_WITH(DistributedForce(Eigen::Vector3d(0, 0, 1), ParamRect{0.6, 0.4, 0, 1}), Catch::Contains("u0 <= u1"));
  CHECK_THROWS_WITH(DistributedForce(Eigen::Vector3d(0, 0, 1), ParamRect{0, 1, -0.1, 1}), Catch::Contains("v0"));
}

TEST_CASE("Force: a constant density's separable load equals the general quadrature load", "[core]") {
  using B = Boundary;
  const Boundaries clamped, free{B::Free, B::Free, B::Free, B::Clamped}, periodic{B::Periodic, B::Periodic, B::Free, B::Clamped};
  const ParamRect rects[] = {{0.0, 1.0, 0.0, 1.0},     {0.3, 0.7, 0.3, 0.7},  {0.4, 0.6, 0.33, 0.71},
                             {0.0, 0.05, 0.9, 1.0},    {0.25, 0.25, 0.1, 0.9}, {0.5, 0.5000001, 0.0, 1.0},
                             {0.1, 0.9, 0.2, 0.2 + 1e-9}};
  int compared = 0;
  for (const Boundaries& bc : {clamped, free, periodic})
    for (int n1 : {1, 2, 3, 5})
      for (int n2 : {1, 3, 4}) {
        const SplineSpace s(n1, n2, 9 + n1, 7 + n2, bc);
        for (const ParamRect& r : rects) {
          const Eigen::Vector3d f(1.5, -40.0, 200.0);
          const DistributedForce force(f, r);
          if (force.isLine()) {  // a line load: see the next test
            ++compared;
            continue;
          }
          const ControlNet net = s.grevillePlane();
          const LoadContext ctx{s, net, net, 0.1, 0.0};
          ControlNet separable = ControlNet::Zero(s.numMoving(), 3), general = separable;
          force.addLoad(ctx, separable);
          force.addLoadByQuadrature(ctx, general);
          INFO("degrees (" << n1 << ", " << n2 << "), rect [" << r.u0 << ", " << r.u1 << "] x [" << r.v0 << ", "
                           << r.v1 << "], boundaries " << boundaryName(bc.uMin) << "/" << boundaryName(bc.vMin));
          const double scale = general.cwiseAbs().maxCoeff();
          CHECK((separable - general).cwiseAbs().maxCoeff() <= 1e-14 * scale);
          if (r.u1 > r.u0 && r.v1 > r.v0) CHECK(scale > 0.0);
          else CHECK(scale == 0.0);
          // it adds to the load it is given
          ControlNet onTop = ControlNet::Constant(s.numMoving(), 3, 0.25);
          force.addLoad(ctx, onTop);
          CHECK((onTop.array() - 0.25 - separable.array()).abs().maxCoeff() <= 1e-15 * (0.25 + scale));
          ++compared;
        }
      }
  CHECK(compared == 3 * 4 * 3 * 7);
}

TEST_CASE("Force: a REGION of zero width is a line load per unit length, or a point force", "[core]") {
  // all sides FREE: every B-spline is an unknown's, so the loads sum to the total force
  const Boundaries free{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free};
  for (int n : {1, 2, 3, 5}) {
    CAPTURE(n);
    const SplineSpace s(n, n, 6, 5, free);
    const Eigen::Vector3d f(0.5, -2.0, 3.0);
    ControlNet net = s.grevillePlane();
    const LoadContext paper{s, net, net, 0.1, 0.0};
    // along v at u = 0.3, v in [0.2, 0.9]: per unit parameter length
    ControlNet load = ControlNet::Zero(s.numMoving(), 3);
    DistributedForce(f, ParamRect{0.3, 0.3, 0.2, 0.9}).addLoad(paper, load);
    CHECK((load.colwise().sum().transpose() - 0.7 * f).norm() <= 1e-13);
    // its point of action is the middle of the segment: sum of load_z * Greville coordinates
    double mv = 0.0;
    for (Eigen::Index m = 0; m < s.numMoving(); ++m) mv += load(m, 2) * net(s.movingToNet(m), 1);
    CHECK(mv / (0.7 * f.z()) == Approx(0.55).epsilon(1e-12));
    // physical units (SHELL): per unit length of the rest surface, here stretched 3x along v
    ControlNet rest = net;
    rest.col(1) *= 3.0;
    LoadContext shell{s, rest, rest, 0.1, 0.0};
    shell.rest = &rest;
    load.setZero();
    DistributedForce(f, ParamRect{0.3, 0.3, 0.2, 0.9}).addLoad(shell, load);
    CHECK((load.colwise().sum().transpose() - 3.0 * 0.7 * f).norm() <= 1e-12);
    // along u at v = 1 (an edge)
    load.setZero();
    DistributedForce(f, ParamRect{0.0, 1.0, 1.0, 1.0}).addLoad(paper, load);
    CHECK((load.colwise().sum().transpose() - f).norm() <= 1e-13);
    // both widths zero: a point force
    load.setZero();
    ControlNet point = load;
    DistributedForce(f, ParamRect{0.4, 0.4, 0.6, 0.6}).addLoad(paper, load);
    PointForce(0.4, 0.6, f).addLoad(paper, point);
    CHECK((load - point).cwiseAbs().maxCoeff() <= 1e-15);
    // and an area density per unit rest area: the stretched rest surface carries 3x the load
    load.setZero();
    DistributedForce(f).addLoad(shell, load);
    CHECK((load.colwise().sum().transpose() - 3.0 * f).norm() <= 1e-12);
  }
}

TEST_CASE("Force: one callable load on nets of other sizes and rest shapes gives each its own load", "[core]") {
  // the Gauss points, bases and rest area elements are kept between calls (the flag's wind is
  // evaluated at every sub-step); what they were made for must be checked, not assumed
  auto density = [](const SurfaceSample& p) { return Eigen::Vector3d(1.0 + p.u, p.v * p.v, std::sin(3.0 * p.t)); };
  const DistributedForce shared(density, kDependsOnTime);
  auto loadAt = [](const Force& f, const SplineSpace& s, const ControlNet& rest, double t) {
    ControlNet load = ControlNet::Zero(s.numMoving(), 3);
    f.addLoad(LoadContext{s, rest, rest, 0.01, t, &rest}, load);
    return load;
  };
  const SplineSpace a(3, 3, 7, 6), b(2, 3, 7, 6), c(3, 3, 9, 6);
  ControlNet bent = a.grevillePlane();
  for (Eigen::Index i = 0; i < bent.rows(); ++i) bent(i, 2) = 0.3 * std::sin(3.0 * bent(i, 0)) * bent(i, 1);
  const struct {
    const SplineSpace* space;
    ControlNet rest;
  } cases[] = {{&a, a.grevillePlane()}, {&a, bent}, {&b, b.grevillePlane()}, {&c, c.grevillePlane()},
               {&a, a.grevillePlane()}};
  double t = 0.0;
  for (const auto& k : cases) {
    t += 0.1;
    const ControlNet got = loadAt(shared, *k.space, k.rest, t);
    const ControlNet fresh = loadAt(DistributedForce(density, kDependsOnTime), *k.space, k.rest, t);
    CHECK((got.array() == fresh.array()).all());
  }
  // the bent rest surface has more area: its load is larger than the flat one's
  const ControlNet flat = loadAt(shared, a, a.grevillePlane(), 0.5), curved = loadAt(shared, a, bent, 0.5);
  CHECK(curved.col(0).sum() > flat.col(0).sum() * (1.0 + 1e-3));
}
