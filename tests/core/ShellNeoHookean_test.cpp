// SPDX-License-Identifier: MIT
// The neo-Hookean shell law (ShellMaterialLaw::NeoHookean, ShellLaws.h, docs/math.md §16.1):
// its force is the gradient of its energy, its hand-derived Hessian the derivative of its force
// (the dual numbers), its step bound bounds, it vanishes under rigid motions, it is the closed
// form for a uniform stretch, and it is St. Venant–Kirchhoff's energy for small strains, in
// membrane and in bending.
#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "bsdeform/energy/Shell.h"

using namespace bsdeform;

namespace {
constexpr double kPi = 3.14159265358979323846;

// The doubly curved rest net of Shell_test.cpp.
ControlNet curvedRest(const SplineSpace& s) {
  ControlNet net = s.grevillePlane();
  for (Eigen::Index r = 0; r < net.rows(); ++r) {
    const double u = net(r, 0), v = net(r, 1);
    net(r, 0) = (1.5 + 0.4 * std::cos(2.0 * v)) * std::cos(1.2 * u);
    net(r, 1) = (1.5 + 0.4 * std::cos(2.0 * v)) * std::sin(1.2 * u);
    net(r, 2) = 0.4 * std::sin(2.0 * v) + 0.1 * u * v;
  }
  return net;
}

ControlNet randomNet(Eigen::Index rows, std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> d(-scale, scale);
  ControlNet net(rows, 3);
  for (Eigen::Index i = 0; i < net.size(); ++i) net.data()[i] = d(rng);
  return net;
}

ShellMaterial neoHookean(double nu = 0.3) {
  ShellMaterial m;
  m.youngsModulus = 2.0e3;
  m.poissonRatio = nu;
  m.thickness = 0.05;
  m.density = 7.0;
  m.law = ShellMaterialLaw::NeoHookean;
  return m;
}

ShellMaterial saintVenant(double nu = 0.3) {
  ShellMaterial m = neoHookean(nu);
  m.law = ShellMaterialLaw::SaintVenantKirchhoff;
  return m;
}

Eigen::Matrix3d rotation(double a, double b, double c) {
  return (Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(b, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(c, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::SparseMatrix<double> assembled(const ShellEnergy& shell, const ControlNet& x, bool project) {
  std::vector<Eigen::Triplet<double>> t;
  shell.hessian(x, project, t);
  Eigen::SparseMatrix<double> H(3 * x.rows(), 3 * x.rows());
  H.setFromTriplets(t.begin(), t.end());
  return H;
}
}  // namespace

TEST_CASE("neo-Hookean shell: force is the gradient of its energy, degrees 1 to 5", "[shell]") {
  std::mt19937 rng(17);
  for (int nu : {1, 2, 3, 4, 5})
    for (int nv : {2, 3, 5}) {
      CAPTURE(nu, nv);
      const SplineSpace s(nu, nv, 4, 3, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
      const ControlNet rest = curvedRest(s);
      const ShellEnergy shell(s, rest, neoHookean());
      const ControlNet x = rest + randomNet(rest.rows(), rng, 0.05);
      ControlNet g;
      shell.gradient(x, g);
      const ControlNet dir = randomNet(rest.rows(), rng, 1.0);
      auto W = [&](double eps) { return shell.energy(x + eps * dir).total(); };
      const double e = 1e-4;
      const double d1 = (W(e) - W(-e)) / (2 * e), d2 = (W(2 * e) - W(-2 * e)) / (4 * e);
      const double fd = (4 * d1 - d2) / 3;
      const double exact = (g.array() * dir.array()).sum();
      CHECK(std::abs(fd - exact) <= 1e-7 * (std::abs(exact) + g.norm() * dir.norm() * 1e-3));
      CHECK(std::abs(exact) > 1e-3 * g.norm() * dir.norm() * 1e-3);
      // and it is not SVK's: these strains (up to ~10 %) tell the laws apart
      ControlNet gs;
      ShellEnergy(s, rest, saintVenant()).gradient(x, gs);
      CHECK((g - gs).norm() > 1e-3 * gs.norm());
    }
}

TEST_CASE("neo-Hookean shell: the hand-derived Hessian is the dual numbers' derivative of the force", "[shell]") {
  std::mt19937 rng(19);
  for (int n : {1, 2, 3, 4, 5}) {
    CAPTURE(n);
    const SplineSpace s(n, n, 3, 4, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
    const ControlNet rest = curvedRest(s);
    const ShellEnergy shell(s, rest, neoHookean());
    const ControlNet x = rest + randomNet(rest.rows(), rng, 0.1);
    const ControlNet dir = randomNet(rest.rows(), rng, 1.0);
    // dual numbers vs fourth-order differences of the force
    ControlNet hv, gp, gm, gp2, gm2;
    shell.hessianProduct(x, dir, hv);
    // (0.1 of the net's size is a strong deformation: near-collapsed Gauss points make the
    // differences' e^4 error large at e = 1e-5, 1e-7 at 1e-6)
    const double e = 1e-6;
    shell.gradient(x + e * dir, gp);
    shell.gradient(x - e * dir, gm);
    shell.gradient(x + 2 * e * dir, gp2);
    shell.gradient(x - 2 * e * dir, gm2);
    const ControlNet fd = (4.0 * (gp - gm) / (2 * e) - (gp2 - gm2) / (4 * e)) / 3.0;
    CHECK((fd - hv).norm() <= 1e-8 * hv.norm());
    CHECK(hv.norm() > 0.0);
    // the analytic element Hessians vs the dual numbers
    const Eigen::SparseMatrix<double> H = assembled(shell, x, false);
    const Eigen::VectorXd hvAssembled = H * Eigen::Map<const Eigen::VectorXd>(dir.data(), dir.size());
    CHECK((hvAssembled - Eigen::Map<const Eigen::VectorXd>(hv.data(), hv.size())).norm() <= 1e-10 * hv.norm());
    const Eigen::MatrixXd Hd(H);
    CHECK((Hd - Hd.transpose()).norm() <= 1e-12 * Hd.norm());
    // projected: positive semidefinite
    const Eigen::SparseMatrix<double> P = assembled(shell, x, true);
    const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Eigen::MatrixXd(P)).eigenvalues();
    CHECK(ev.minCoeff() >= -1e-10 * ev.maxCoeff());
  }
}

TEST_CASE("neo-Hookean shell: the stability bound bounds the generalised eigenvalues", "[shell]") {
  std::mt19937 rng(23);
  for (int n : {2, 3}) {
    CAPTURE(n);
    const SplineSpace s(n, n, 4, 3, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
    const ControlNet rest = curvedRest(s);
    const ShellEnergy shell(s, rest, neoHookean());
    const Eigen::VectorXd mass = shell.lumpedMass();
    for (double amplitude : {0.0, 0.1, 0.3}) {
      CAPTURE(amplitude);
      const ControlNet x = rest + randomNet(rest.rows(), rng, amplitude);
      Eigen::VectorXd w(3 * rest.rows());
      for (Eigen::Index p = 0; p < rest.rows(); ++p) w.segment<3>(3 * p).setConstant(1.0 / std::sqrt(mass[p]));
      const Eigen::MatrixXd S = w.asDiagonal() * Eigen::MatrixXd(assembled(shell, x, false)) * w.asDiagonal();
      const double lmax = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(S).eigenvalues().maxCoeff();
      const double bound = shell.eigenvalueBound(x, mass);
      CHECK(bound >= lmax);
      CHECK(bound <= 20.0 * lmax);
    }
  }
}

TEST_CASE("neo-Hookean shell: energy and force vanish under rigid motions", "[shell]") {
  const Eigen::Matrix3d R = rotation(0.7, -1.1, 2.3);
  const Eigen::RowVector3d shift(3.0, -2.0, 5.5);
  auto check = [&](const SplineSpace& s, const ControlNet& rest) {
    const ShellEnergy shell(s, rest, neoHookean());
    const ControlNet moved = (rest * R.transpose()).rowwise() + shift;
    ControlNet g, gs;
    shell.gradient(moved, g);
    shell.gradient(1.01 * rest, gs);  // the scale: the force of a 1 % stretch
    CHECK(g.norm() <= 1e-12 * gs.norm());
    CHECK(std::abs(shell.energy(moved).total()) <= 1e-20 * shell.energy(1.01 * rest).total() + 1e-30);
    CHECK(shell.energy(1.01 * rest).total() > 0.0);
  };
  SECTION("open") {
    const SplineSpace s(3, 3, 5, 4, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
    check(s, curvedRest(s));
  }
  SECTION("periodic: a cylinder") {
    const SplineSpace s(3, 3, 6, 4, Boundaries{Boundary::Periodic, Boundary::Periodic, Boundary::Free, Boundary::Free});
    ControlNet rest = s.grevillePlane();
    for (Eigen::Index r = 0; r < rest.rows(); ++r) {
      const double a = 2 * kPi * rest(r, 0), z = rest(r, 1);
      rest.row(r) << std::cos(a), std::sin(a), z;
    }
    check(s, rest);
  }
  SECTION("closed: a torus") {
    const SplineSpace s(3, 3, 8, 6,
                        Boundaries{Boundary::Periodic, Boundary::Periodic, Boundary::Periodic, Boundary::Periodic});
    ControlNet rest = s.grevillePlane();
    for (Eigen::Index r = 0; r < rest.rows(); ++r) {
      const double a = 2 * kPi * rest(r, 0), b = 2 * kPi * rest(r, 1);
      rest.row(r) << (2 + 0.6 * std::cos(b)) * std::cos(a), (2 + 0.6 * std::cos(b)) * std::sin(a), 0.6 * std::sin(b);
    }
    check(s, rest);
  }
}

TEST_CASE("neo-Hookean shell: a uniform stretch of a flat sheet is the condensed closed form", "[shell]") {
  // Stretched by l in x, held at 1 in y: g = diag(l², 1), C33 solves mu (c - 1) + lambda/2
  // ln(l² c) = 0, and W = t A [mu/2 (l² + 1 + c - 3 - ln(l² c)) + lambda/8 ln(l² c)²].
  for (double nu : {0.0, 0.3, 0.45}) {
    CAPTURE(nu);
    const ShellMaterial m = neoHookean(nu);
    const double mu = m.youngsModulus / (2 * (1 + nu)), lambda = m.youngsModulus * nu / ((1 + nu) * (1 - 2 * nu));
    const SplineSpace s(3, 3, 4, 4, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
    const ControlNet rest = s.grevillePlane();
    const ShellEnergy shell(s, rest, m);
    for (double l : {0.6, 1.2, 2.5}) {
      CAPTURE(l);
      ControlNet x = rest;
      x.col(0) *= l;
      double lo = -20.0, hi = 20.0;  // ln c, by bisection: the residual increases with it
      for (int i = 0; i < 200; ++i) {
        const double x = 0.5 * (lo + hi);
        (mu * std::expm1(x) + 0.5 * lambda * (2 * std::log(l) + x) > 0 ? hi : lo) = x;
      }
      const double c = std::exp(0.5 * (lo + hi));
      const double L = std::log(l * l * c);
      const double psi = 0.5 * mu * (l * l + 1 + c - 3 - L) + 0.125 * lambda * L * L;
      const ShellEnergies e = shell.energy(x);
      CHECK(e.total() == Approx(m.thickness * shell.restArea() * psi).epsilon(1e-12));
      CHECK(e.bending == Approx(0.0).margin(1e-14 * e.total()));
    }
  }
}

TEST_CASE("neo-Hookean shell: small strains are St. Venant–Kirchhoff's, membrane and bending", "[shell]") {
  std::mt19937 rng(29);
  const SplineSpace s(3, 3, 5, 4, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
  const ControlNet rest = s.grevillePlane();  // a flat rest: through the thickness G = A
  const ShellEnergy nh(s, rest, neoHookean()), svk(s, rest, saintVenant());
  SECTION("a random state with strains of 1e-6") {
    // in-plane and out-of-plane motion of 1e-6 of the sheet's size: membrane and bending
    const ControlNet x = rest + randomNet(rest.rows(), rng, 1e-6);
    const ShellEnergies a = nh.energy(x), b = svk.energy(x);
    CAPTURE(a.membrane, a.bending, b.membrane, b.bending);
    CHECK(b.bending > 1e-4 * b.total());  // both parts are present
    CHECK(std::abs(a.total() - b.total()) <= 1e-4 * b.total());
    ControlNet ga, gb;
    nh.gradient(x, ga);
    svk.gradient(x, gb);
    CHECK((ga - gb).norm() <= 1e-4 * gb.norm());
    // the tangent at rest is the same operator
    const Eigen::MatrixXd Ha(assembled(nh, rest, false)), Hb(assembled(svk, rest, false));
    CHECK((Ha - Hb).norm() <= 1e-12 * Hb.norm());
  }
  SECTION("pure bending: a sheet rolled onto a cylinder of radius 200 t") {
    const ShellMaterial m = neoHookean();
    const double R = 200 * m.thickness;
    const SplineSpace f(5, 3, 24, 4, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
    const ControlNet flat = f.grevillePlane();
    ControlNet rolled = flat;
    for (Eigen::Index r = 0; r < rolled.rows(); ++r) {
      const double u = flat(r, 0);
      rolled(r, 0) = R * std::sin(u / R);
      rolled(r, 2) = R * (1 - std::cos(u / R));
    }
    const ShellEnergies a = ShellEnergy(f, flat, m).energy(rolled);
    const ShellEnergies b = ShellEnergy(f, flat, saintVenant()).energy(rolled);
    const double D = m.youngsModulus * std::pow(m.thickness, 3) / (12 * (1 - m.poissonRatio * m.poissonRatio));
    CAPTURE(a.membrane, a.bending, b.membrane, b.bending);
    CHECK(a.bending == Approx(b.bending).epsilon(1e-4));  // strains t/(2R) = 2.5e-3 at the faces
    CHECK(a.bending == Approx(0.5 * D / (R * R)).epsilon(1e-3));
    CHECK(a.membrane < 1e-5 * a.bending);  // the net's arc is not quite inextensible
  }
}

TEST_CASE("shell refuses a material law it does not know", "[shell]") {
  const SplineSpace s(3, 3, 3, 3, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
  ShellMaterial m = neoHookean();
  m.law = static_cast<ShellMaterialLaw>(7);
  CHECK_THROWS_WITH(ShellEnergy(s, s.grevillePlane(), m), Catch::Contains("material") && Catch::Contains("got 7"));
}
