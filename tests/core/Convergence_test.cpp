// SPDX-License-Identifier: MIT
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>

#include "bsdeform/spline/GaussLegendre.h"
#include "bsdeform/spline/RestShape.h"
#include "bsdeform/dynamics/Simulation.h"

using namespace bsdeform;

namespace {
// Manufactured solution for the membrane problem -(z_uu + z_vv) = f, z = 0 on the boundary:
// z = g(u) g(v), g = (u(1-u))^n, whose derivatives up to order n-1 vanish on the boundary, as
// those of every function of the discrete space do.
struct Manufactured {
  int n;
  double g(double x) const { return std::pow(x * (1 - x), n); }
  double g2(double x) const {
    const double w = x * (1 - x), w1 = 1 - 2 * x;
    return n * (n - 1) * std::pow(w, n - 2) * w1 * w1 - 2.0 * n * std::pow(w, n - 1);
  }
  double z(double u, double v) const { return g(u) * g(v); }
  double f(double u, double v) const { return -(g2(u) * g(v) + g(u) * g2(v)); }
};

// The L2 norm over [0,1]^2 of e(u, v), Gauss-Legendre with n+3 points per knot cell.
template <typename Error>
double l2Norm(int n, int spans, Error&& e) {
  const QuadratureRule& q = gaussLegendre(n + 3);
  double err2 = 0.0;
  for (int a = 0; a < spans; ++a)
    for (int b = 0; b < spans; ++b)
      for (size_t i = 0; i < q.nodes.size(); ++i)
        for (size_t j = 0; j < q.nodes.size(); ++j) {
          const double x = e((a + q.nodes[i]) / spans, (b + q.nodes[j]) / spans);
          err2 += q.weights[i] * q.weights[j] * x * x / (double(spans) * spans);
        }
  return std::sqrt(err2);
}

double l2Error(int n, int N) {
  ModelParameters p;
  p.degreeU = p.degreeV = n;
  p.numU = p.numV = N;
  p.weights = Weights{1.0, 1.0, 0.0, 0.0, 0.0};
  Simulation sim(p);
  const Manufactured m{n};
  sim.addForce(std::make_shared<DistributedForce>(
      [m](const SurfaceSample& s) { return Eigen::Vector3d(0, 0, m.f(s.u, s.v)); }, kConstant, ParamRect{}, 3));
  const ControlNet net = sim.staticSolution();
  return l2Norm(n, N + n, [&](double u, double v) { return sim.space().evaluate(net, u, v, 0).position.z() - m.z(u, v); });
}
}  // namespace

TEST_CASE("Convergence: manufactured membrane problem converges in L2 at order n+1", "[core][slow]") {
  for (int n : {2, 3}) {
    const double e1 = l2Error(n, 16), e2 = l2Error(n, 32), e3 = l2Error(n, 64);
    // measured order against h = 1/(N+n)
    const double o12 = std::log(e1 / e2) / std::log((32.0 + n) / (16.0 + n));
    const double o23 = std::log(e2 / e3) / std::log((64.0 + n) / (32.0 + n));
    INFO("degree " << n << ": L2 errors " << e1 << ", " << e2 << ", " << e3 << "; orders " << o12 << ", " << o23);
    CHECK(e3 < e2);
    CHECK(o23 == Approx(n + 1).margin(0.3));
  }
}

namespace {
// The same membrane problem on a tube: u PERIODIC, v clamped. The displacement along z from
// the rest net (a cylinder: the rest is an equilibrium, reference REST) is the manufactured
// d = s(u) g(v), s = sin 2 pi u + cos(4 pi u) / 2 periodic, g = (v(1-v))^n.
double l2ErrorPeriodic(int n, int N) {
  constexpr double pi = 3.14159265358979323846;
  ModelParameters p;
  p.degreeU = p.degreeV = n;
  p.numU = p.numV = N;
  p.weights = Weights{1.0, 1.0, 0.0, 0.0, 0.0};
  p.boundaries = shapeBoundaries(ShapeKind::Cylinder, Boundaries());
  const SplineSpace space(n, n, N, N, p.boundaries);
  Simulation sim(p, shapeRestNet(ShapeKind::Cylinder, ShapeSize(), space));
  const Manufactured m{n};
  auto s = [=](double u) { return std::sin(2 * pi * u) + 0.5 * std::cos(4 * pi * u); };
  auto s2 = [=](double u) { return -4 * pi * pi * std::sin(2 * pi * u) - 8 * pi * pi * std::cos(4 * pi * u); };
  sim.addForce(std::make_shared<DistributedForce>(
      [=](const SurfaceSample& q) { return Eigen::Vector3d(0, 0, -(s2(q.u) * m.g(q.v) + s(q.u) * m.g2(q.v))); },
      kConstant, ParamRect{}, 3));
  const ControlNet net = sim.staticSolution();
  const SplineSpace& sp = sim.space();
  return l2Norm(n, N + n, [&](double u, double v) {
    const double d = sp.evaluate(net, u, v, 0).position.z() - sp.evaluate(sim.rest(), u, v, 0).position.z();
    return d - s(u) * m.g(v);
  });
}
}  // namespace

TEST_CASE("Convergence: with one periodic direction the membrane problem still converges at order n+1",
          "[core][slow]") {
  for (int n : {2, 3}) {
    const double e1 = l2ErrorPeriodic(n, 16), e2 = l2ErrorPeriodic(n, 32), e3 = l2ErrorPeriodic(n, 64);
    const double o23 = std::log(e2 / e3) / std::log((64.0 + n) / (32.0 + n));
    INFO("degree " << n << ": L2 errors " << e1 << ", " << e2 << ", " << e3 << "; order " << o23);
    CHECK(e3 < e2);
    CHECK(o23 == Approx(n + 1).margin(0.3));
  }
}
