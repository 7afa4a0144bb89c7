// SPDX-License-Identifier: MIT
// The Kirchhoff–Love shell energy (Shell.h, docs/math.md §16): its force is the gradient of its
// energy, its Hessian product the derivative of its force, its assembled Hessian the same
// operator, it vanishes under rigid motions of any rest shape, and its stability bound bounds.
#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "bsdeform/energy/Shell.h"

using namespace bsdeform;

namespace {
constexpr double kPi = 3.14159265358979323846;

// A doubly curved rest net: a piece of a torus-like surface over the Greville plane.
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

ShellMaterial material() {
  ShellMaterial m;
  m.youngsModulus = 2.0e3;
  m.poissonRatio = 0.3;
  m.thickness = 0.05;
  m.density = 7.0;
  return m;
}

Eigen::Matrix3d rotation(double a, double b, double c) {
  return (Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(b, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(c, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}
}  // namespace

TEST_CASE("shell force is the gradient of its energy, degrees 1 to 5", "[shell]") {
  std::mt19937 rng(7);
  for (int nu : {1, 2, 3, 4, 5})
    for (int nv : {2, 3, 5}) {
      CAPTURE(nu, nv);
      const SplineSpace s(nu, nv, 4, 3, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
      const ControlNet rest = curvedRest(s);
      const ShellEnergy shell(s, rest, material());
      CHECK(shell.hasBending() == (nu >= 2 && nv >= 2));
      const ControlNet x = rest + randomNet(rest.rows(), rng, 0.05);
      ControlNet g;
      shell.gradient(x, g);
      const ControlNet dir = randomNet(rest.rows(), rng, 1.0);
      // central differences of the energy along dir, Richardson-extrapolated
      auto W = [&](double eps) { return shell.energy(x + eps * dir).total(); };
      const double e = 1e-4;
      const double d1 = (W(e) - W(-e)) / (2 * e), d2 = (W(2 * e) - W(-2 * e)) / (4 * e);
      const double fd = (4 * d1 - d2) / 3;
      const double exact = (g.array() * dir.array()).sum();
      CHECK(std::abs(fd - exact) <= 1e-7 * (std::abs(exact) + g.norm() * dir.norm() * 1e-3));
      CHECK(std::abs(exact) > 1e-3 * g.norm() * dir.norm() * 1e-3);  // a meaningful direction
    }
}

TEST_CASE("shell Hessian product is the derivative of the force and equals the assembled Hessian", "[shell]") {
  std::mt19937 rng(11);
  for (int n : {2, 3, 4, 5}) {
    CAPTURE(n);
    const SplineSpace s(n, n, 3, 4, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
    const ControlNet rest = curvedRest(s);
    const ShellEnergy shell(s, rest, material());
    const ControlNet x = rest + randomNet(rest.rows(), rng, 0.1);
    const ControlNet dir = randomNet(rest.rows(), rng, 1.0);
    ControlNet hv, gp, gm, gp2, gm2;
    shell.hessianProduct(x, dir, hv);
    const double e = 1e-5;
    shell.gradient(x + e * dir, gp);
    shell.gradient(x - e * dir, gm);
    shell.gradient(x + 2 * e * dir, gp2);
    shell.gradient(x - 2 * e * dir, gm2);
    const ControlNet fd = (4.0 * (gp - gm) / (2 * e) - (gp2 - gm2) / (4 * e)) / 3.0;
    CHECK((fd - hv).norm() <= 1e-7 * hv.norm());
    CHECK(hv.norm() > 0.0);

    std::vector<Eigen::Triplet<double>> t;
    shell.hessian(x, false, t);
    Eigen::SparseMatrix<double> H(3 * rest.rows(), 3 * rest.rows());
    H.setFromTriplets(t.begin(), t.end());
    const Eigen::VectorXd hvAssembled = H * Eigen::Map<const Eigen::VectorXd>(dir.data(), dir.size());
    CHECK((hvAssembled - Eigen::Map<const Eigen::VectorXd>(hv.data(), hv.size())).norm() <= 1e-11 * hv.norm());
    const Eigen::MatrixXd Hd(H);
    CHECK((Hd - Hd.transpose()).norm() <= 1e-12 * Hd.norm());

    // projected: positive semidefinite, and equal to the true Hessian at rest (which is)
    shell.hessian(x, true, t);
    Eigen::SparseMatrix<double> P(3 * rest.rows(), 3 * rest.rows());
    P.setFromTriplets(t.begin(), t.end());
    const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Eigen::MatrixXd(P)).eigenvalues();
    CHECK(ev.minCoeff() >= -1e-10 * ev.maxCoeff());
  }
}

TEST_CASE("shell energy and force vanish under rigid motions of open, periodic and closed rest shapes", "[shell]") {
  const Eigen::Matrix3d R = rotation(0.7, -1.1, 2.3);
  const Eigen::RowVector3d shift(3.0, -2.0, 5.5);
  SECTION("open") {
    const SplineSpace s(3, 3, 5, 4, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
    const ControlNet rest = curvedRest(s);
    const ShellEnergy shell(s, rest, material());
    const ControlNet moved = (rest * R.transpose()).rowwise() + shift;
    ControlNet g;
    shell.gradient(moved, g);
    // the scale: the force of a 1 % stretch
    ControlNet gs;
    shell.gradient(1.01 * rest, gs);
    CHECK(g.norm() <= 1e-12 * gs.norm());
    CHECK(shell.energy(moved).total() <= 1e-20 * shell.energy(1.01 * rest).total() + 1e-30);
    CHECK(shell.energy(1.01 * rest).total() > 0.0);
  }
  SECTION("periodic: a cylinder") {
    const SplineSpace s(3, 3, 6, 4,
                        Boundaries{Boundary::Periodic, Boundary::Periodic, Boundary::Free, Boundary::Free});
    ControlNet rest = s.grevillePlane();
    for (Eigen::Index r = 0; r < rest.rows(); ++r) {
      const double a = 2 * kPi * rest(r, 0), z = rest(r, 1);
      rest.row(r) << std::cos(a), std::sin(a), z;
    }
    const ShellEnergy shell(s, rest, material());
    ControlNet g, gs;
    shell.gradient((rest * R.transpose()).rowwise() + shift, g);
    shell.gradient(1.01 * rest, gs);
    CHECK(g.norm() <= 1e-12 * gs.norm());
    CHECK(shell.restArea() == Approx(surfaceArea(s, rest)).epsilon(1e-6));  // another quadrature of the same area
  }
  SECTION("closed: a torus") {
    const SplineSpace s(3, 3, 8, 6,
                        Boundaries{Boundary::Periodic, Boundary::Periodic, Boundary::Periodic, Boundary::Periodic});
    ControlNet rest = s.grevillePlane();
    for (Eigen::Index r = 0; r < rest.rows(); ++r) {
      const double a = 2 * kPi * rest(r, 0), b = 2 * kPi * rest(r, 1);
      rest.row(r) << (2 + 0.6 * std::cos(b)) * std::cos(a), (2 + 0.6 * std::cos(b)) * std::sin(a), 0.6 * std::sin(b);
    }
    const ShellEnergy shell(s, rest, material());
    ControlNet g, gs;
    shell.gradient((rest * R.transpose()).rowwise() + shift, g);
    shell.gradient(1.01 * rest, gs);
    CHECK(g.norm() <= 1e-12 * gs.norm());
    CHECK(shell.energy((rest * R.transpose()).rowwise() + shift).total() <=
          1e-20 * shell.energy(1.01 * rest).total());
  }
}

TEST_CASE("shell energy of a uniform stretch and a cylindrical bend are the closed forms", "[shell]") {
  // A flat unit square stretched by (1 + s) in x: E11 = ((1+s)^2 - 1)/2, others 0, so
  // W = t/2 E/(1 - nu^2) E11^2 (the plane-stress modulus) exactly.
  const ShellMaterial m = material();
  const SplineSpace s(3, 3, 4, 4, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
  const ControlNet rest = s.grevillePlane();
  const ShellEnergy shell(s, rest, m);
  ControlNet stretched = rest;
  stretched.col(0) *= 1.2;
  const double E11 = 0.5 * (1.2 * 1.2 - 1.0);
  const ShellEnergies e = shell.energy(stretched);
  CHECK(e.membrane == Approx(0.5 * m.thickness * m.youngsModulus / (1 - m.poissonRatio * m.poissonRatio) * E11 * E11)
                          .epsilon(1e-12));
  CHECK(e.bending == Approx(0.0).margin(1e-20));
  // Rolled onto a cylinder of radius R without stretching: kappa11 = 1/R (per unit length), so
  // W = 1/2 t^3/12 E/(1 - nu^2) / R^2 over the unit area, to the net's approximation of the arc.
  const double R = 2.0;
  const SplineSpace f(5, 3, 24, 4, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
  const ControlNet flat = f.grevillePlane();
  const ShellEnergy plate(f, flat, m);
  // interpolate the arc x = R sin(u/R), z = R (1 - cos(u/R)) by its Greville-point values
  // corrected with one quasi-interpolation sweep: the energy error is then dominated by the
  // tiny membrane strain the approximation leaves.
  ControlNet rolled = flat;
  for (Eigen::Index r = 0; r < rolled.rows(); ++r) {
    const double u = flat(r, 0);
    rolled(r, 0) = R * std::sin(u / R);
    rolled(r, 2) = R * (1 - std::cos(u / R));
  }
  const ShellEnergies b = plate.energy(rolled);
  const double D = m.youngsModulus * std::pow(m.thickness, 3) / (12 * (1 - m.poissonRatio * m.poissonRatio));
  CHECK(b.bending == Approx(0.5 * D / (R * R)).epsilon(2e-2));
}

TEST_CASE("shell lumped mass is rho t times the rest area", "[shell]") {
  const SplineSpace s(3, 2, 5, 6, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
  const ControlNet rest = curvedRest(s);
  const ShellMaterial m = material();
  const ShellEnergy shell(s, rest, m);
  const Eigen::VectorXd mass = shell.lumpedMass();
  CHECK(mass.minCoeff() > 0.0);
  CHECK(mass.sum() == Approx(m.density * m.thickness * shell.restArea()).epsilon(1e-12));
}

TEST_CASE("shell stability bound bounds the generalised eigenvalues", "[shell]") {
  std::mt19937 rng(3);
  for (int n : {2, 3, 4}) {
    CAPTURE(n);
    const SplineSpace s(n, n, 4, 3, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
    const ControlNet rest = curvedRest(s);
    const ShellEnergy shell(s, rest, material());
    const Eigen::VectorXd mass = shell.lumpedMass();
    for (double amplitude : {0.0, 0.1}) {
      const ControlNet x = rest + randomNet(rest.rows(), rng, amplitude);
      std::vector<Eigen::Triplet<double>> t;
      shell.hessian(x, false, t);
      Eigen::SparseMatrix<double> H(3 * rest.rows(), 3 * rest.rows());
      H.setFromTriplets(t.begin(), t.end());
      Eigen::VectorXd w(3 * rest.rows());
      for (Eigen::Index p = 0; p < rest.rows(); ++p) w.segment<3>(3 * p).setConstant(1.0 / std::sqrt(mass[p]));
      const Eigen::MatrixXd S = w.asDiagonal() * Eigen::MatrixXd(H) * w.asDiagonal();
      const double lmax = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(S).eigenvalues().maxCoeff();
      const double bound = shell.eigenvalueBound(x, mass);
      CHECK(bound >= lmax);
      CHECK(bound <= 20.0 * lmax);  // and not uselessly loose
    }
  }
}

TEST_CASE("shell refuses a bad material and a degenerate rest surface", "[shell]") {
  const SplineSpace s(3, 3, 3, 3, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
  ShellMaterial m = material();
  m.poissonRatio = 0.5;
  CHECK_THROWS_WITH(ShellEnergy(s, s.grevillePlane(), m), Catch::Contains("poissonRatio"));
  m = material();
  m.thickness = -1;
  CHECK_THROWS_WITH(ShellEnergy(s, s.grevillePlane(), m), Catch::Contains("thickness"));
  ControlNet line = s.grevillePlane();
  line.col(1).setZero();  // every point on the x axis: S_v = 0
  CHECK_THROWS_WITH(ShellEnergy(s, line, material()), Catch::Contains("degenerate"));
}

TEST_CASE("shell element Hessians say whether the projection changed any Gauss point's", "[shell]") {
  // A flat sheet stretched equally in both directions is stable: its density Hessians are
  // positive definite and the projected mode changes none (a tangent then projects the loads
  // instead, Simulation::tangent). Compressed, the membrane's geometric stiffness is negative
  // out of the plane and the projection clamps them; the exact mode never projects.
  const SplineSpace s(3, 3, 5, 5, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
  const ControlNet rest = s.grevillePlane();
  const ShellEnergy shell(s, rest, material());
  long elements = 0;
  auto count = [&elements](int, int, const double*) { ++elements; };
  ControlNet stretched = rest, compressed = rest;
  stretched.leftCols(2) *= 1.1;
  compressed.leftCols(2) *= 0.9;
  CHECK_FALSE(shell.elementHessians(stretched, HessianMode::Projected, true, count));
  const long perCall = elements;
  REQUIRE(perCall == long(s.basisU().numSpans()) * s.basisV().numSpans());
  CHECK(shell.elementHessians(compressed, HessianMode::Projected, true, count));
  CHECK(shell.elementHessians(compressed, HessianMode::Definite, false, count));  // on the kernel threads
  CHECK_FALSE(shell.elementHessians(compressed, HessianMode::Exact, false, count));
  CHECK(elements == 4 * perCall);
}
