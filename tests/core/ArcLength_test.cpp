// SPDX-License-Identifier: MIT
// Arc-length continuation (dynamics/ArcLength) on a structure whose equilibrium path is known in
// closed form and has both a limit point (the load passes a maximum: snap-through) and a
// snap-back (the loaded point's displacement turns back), which load control cannot pass.
#include <Eigen/SparseCore>
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>

#include "bsdeform/dynamics/ArcLength.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/forces/Force.h"

using namespace bsdeform;

namespace {

// Von Mises' two-bar truss: bars of axial stiffness k from (±a, 0) to an apex at height h - w
// (w downwards), the load λ pulling down a point joined to the apex by a spring ks (its
// displacement v). W = k (L - L0)² + ½ ks (v - w)², L = sqrt(a² + (h - w)²). Equilibrium:
// λ = ks (v - w) = 2k (L0 - L)(h - w)/L, so along the path, parametrised by w,
// λ(w) = 2k (L0 - L(w))(h - w)/L(w) and v(w) = w + λ(w)/ks.
struct Truss {
  double a = 1.0, h = 0.5, k = 1.0, ks = 0.1;
  double L(double w) const { return std::sqrt(a * a + (h - w) * (h - w)); }
  double L0() const { return L(0.0); }
  double lambdaOf(double w) const { return 2.0 * k * (L0() - L(w)) * (h - w) / L(w); }
  double vOf(double w) const { return w + lambdaOf(w) / ks; }
  ArcLengthProblem problem() const {
    ArcLengthProblem p;
    p.evaluate = [this](const Eigen::VectorXd& x, Eigen::VectorXd& g, Eigen::VectorXd& F) {
      const double w = x[0], v = x[1], l = L(w), dl = -(h - w) / l;
      g.resize(2);
      g[0] = 2.0 * k * (l - L0()) * dl + ks * (w - v);
      g[1] = ks * (v - w);
      F = Eigen::Vector2d(0.0, 1.0);
    };
    p.tangent = [this](const Eigen::VectorXd& x) {
      const double w = x[0], l = L(w), dl = -(h - w) / l, ddl = a * a / (l * l * l);
      Eigen::SparseMatrix<double> K(2, 2);
      K.insert(0, 0) = 2.0 * k * (dl * dl + (l - L0()) * ddl) + ks;
      K.insert(1, 0) = -ks;
      K.insert(1, 1) = ks;
      return K;
    };
    p.lowerOnly = true;
    return p;
  }
};

}  // namespace

TEST_CASE("Arc length traces a two-bar truss through its limit point and snap-back onto the closed form",
          "[arclength]") {
  const Truss t;
  ArcLengthOptions o;
  o.maxSteps = 2000;
  o.maxLoad = 0.06;  // above the limit load (about 0.043): reached only after the snap-through
  o.arcLength = 0.02;
  o.tolerance = 1e-12;
  const std::vector<ArcLengthPoint> path = arcLengthPath(Eigen::Vector2d::Zero(), t.problem(), o);
  REQUIRE(path.size() > 10);
  double lambdaMax = 0.0, lambdaMin = 0.0;
  bool loadFell = false, displacementTurned = false;
  for (size_t i = 0; i < path.size(); ++i) {
    const double w = path[i].x[0], v = path[i].x[1], l = path[i].loadFactor;
    CAPTURE(i, w, v, l);
    CHECK(l == Approx(t.lambdaOf(w)).margin(1e-9));
    CHECK(v == Approx(t.vOf(w)).margin(1e-8));
    if (w < t.h) lambdaMax = std::max(lambdaMax, l);  // before the snap
    lambdaMin = std::min(lambdaMin, l);
    if (i > 0) {
      loadFell |= l < path[i - 1].loadFactor;
      displacementTurned |= v < path[i - 1].x[1];
      CHECK(w > path[i - 1].x[0]);  // the apex goes on down: the path never turns back on itself
    }
  }
  CHECK(loadFell);
  CHECK(displacementTurned);
  CHECK(lambdaMin < -0.03);                 // the unstable branch, under a pull upwards
  CHECK(path.back().x[0] > 2.0 * t.h);      // snapped through, beyond the mirror image
  CHECK(path.back().loadFactor > o.maxLoad);
  // the limit load: the closed form's maximum over w, found by the path to within its step
  double closedMax = 0.0;
  for (double w = 0.0; w < t.h; w += 1e-5) closedMax = std::max(closedMax, t.lambdaOf(w));
  CHECK(lambdaMax == Approx(closedMax).epsilon(0.02));
}

TEST_CASE("Arc length refuses what it cannot do, naming it", "[arclength]") {
  const Truss t;
  ArcLengthOptions o;
  o.maxLoad = 0.0;
  CHECK_THROWS_WITH(arcLengthPath(Eigen::Vector2d::Zero(), t.problem(), o), Catch::Contains("load factor must be > 0"));
  // a structure nothing holds: the tangent is singular
  ArcLengthProblem loose = t.problem();
  loose.tangent = [](const Eigen::VectorXd&) {
    Eigen::SparseMatrix<double> K(2, 2);
    K.insert(0, 0) = 0.0;
    K.insert(1, 1) = 0.0;
    return K;
  };
  o.maxLoad = 1.0;
  CHECK_THROWS_WITH(arcLengthPath(Eigen::Vector2d::Zero(), loose, o), Catch::Contains("cannot be factorised"));
}


namespace {
// The hinged cylindrical roof of Sze, Liu and Lo 2004 (problem 3.8; Sabir and Lock 1972): R =
// 2540, length 508 along the axis (x), half-angle 0.1 rad, straight edges (v = 0, 1) hinged
// (SIMPLY_SUPPORTED), curved edges (u = 0, 1) free, E = 3102.75, nu = 0.3, a point load at the
// centre. The net's points on the cylinder at their Greville abscissae (a bicubic net of
// `spans` knot spans each way).
Simulation hingedRoof(int spans, double thickness) {
  ModelParameters p;
  p.degreeU = p.degreeV = 3;
  p.numU = p.numV = spans - 3;
  p.boundaries = Boundaries{Boundary::Free, Boundary::Free, Boundary::SimplySupported, Boundary::SimplySupported};
  p.energy = EnergyModel::Shell;
  p.material = ShellMaterial{3102.75, 0.3, thickness, 1.0};
  const SplineSpace s(3, 3, p.numU, p.numV, p.boundaries);
  ControlNet rest(s.netSize(), 3);
  const double R = 2540.0, theta = 0.1;
  for (int i = 0; i < s.netRows(); ++i)
    for (int j = 0; j < s.netCols(); ++j) {
      const double u = s.grevilleU(i - 3), v = s.grevilleV(j - 3), phi = theta * (2.0 * v - 1.0);
      rest.row(Eigen::Index(i) * s.netCols() + j) << 508.0 * (u - 0.5), R * std::sin(phi), R * std::cos(phi);
    }
  return Simulation(p, rest);
}
}  // namespace

TEST_CASE("Arc length on a SHELL: the hinged roof's path agrees with load control before its limit point, "
          "snaps through, and the thinner roof snaps back",
          "[arclength][shell]") {
  auto trace = [](double P, Simulation& roof) {
    roof.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, -P), ParamRect{0.5, 0.5, 0.5, 0.5}));
    ArcLengthOptions o;
    o.maxSteps = 200;
    o.maxLoad = 1.0;
    o.tolerance = 1e-9;
    o.arcLength = 3.0;
    return roof.solveStaticArcLength(o);
  };
  auto deflection = [](const Simulation& roof, const ControlNet& net) {
    return roof.evaluate(0.5, 0.5).position.z() - roof.space().evaluate(net, 0.5, 0.5, 0).position.z();
  };
  SECTION("t = 12.7: a limit point, then the load rises again on the far branch") {
    Simulation roof = hingedRoof(10, 12.7);
    const StaticResult path = trace(3000.0, roof);
    double peak = 0.0, peakDeflection = 0.0;
    bool fell = false, roseAgain = false;
    for (size_t i = 0; i < path.increments.size(); ++i) {
      const auto& inc = path.increments[i];
      CHECK(inc.residual <= 1e-9);
      if (i > 0 && inc.loadFactor < path.increments[i - 1].loadFactor) fell = true;
      if (fell && i > 0 && inc.loadFactor > path.increments[i - 1].loadFactor) roseAgain = true;
      if (!fell) {
        peak = inc.loadFactor;
        peakDeflection = deflection(roof, inc.net);
      }
    }
    CHECK(fell);
    CHECK(roseAgain);
    CHECK(deflection(roof, path.net) > 2.0 * 12.69);  // beyond the rise R (1 - cos 0.1): inverted
    CAPTURE(peak * 3000.0, peakDeflection);
    // before the limit point the path is load control's: the same equilibrium at the same load
    const StaticResult::Increment& early = path.increments[2];
    REQUIRE(early.loadFactor < peak);
    Simulation controlled = hingedRoof(10, 12.7);
    controlled.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, -3000.0 * early.loadFactor),
                                                           ParamRect{0.5, 0.5, 0.5, 0.5}));
    const StaticResult direct = controlled.solveStatic(1e-11, 100, LinearSolver::Automatic, 2);
    CHECK(deflection(roof, early.net) == Approx(deflection(controlled, direct.net)).epsilon(1e-6));
  }
  SECTION("t = 6.35: the centre's deflection turns back (snap-back) and the load changes sign") {
    Simulation roof = hingedRoof(10, 6.35);
    const StaticResult path = trace(1000.0, roof);
    bool turnedBack = false;
    double lowest = 0.0;
    for (size_t i = 1; i < path.increments.size(); ++i) {
      turnedBack |= deflection(roof, path.increments[i].net) < deflection(roof, path.increments[i - 1].net);
      lowest = std::min(lowest, path.increments[i].loadFactor);
    }
    CHECK(turnedBack);
    CHECK(lowest < 0.0);
    CHECK(path.increments.back().loadFactor > 1.0);  // through it all, up to the full load
  }
}

TEST_CASE("Arc length refuses the paper's energy and a surface nothing holds, naming why", "[arclength][shell]") {
  ModelParameters p;
  p.numU = p.numV = 4;
  Simulation paper(p);
  CHECK_THROWS_WITH(paper.solveStaticArcLength(ArcLengthOptions()), Catch::Contains("only the SHELL energy"));
  p.energy = EnergyModel::Shell;
  p.boundaries = Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free};
  Simulation loose(p);
  CHECK_THROWS_WITH(loose.solveStaticArcLength(ArcLengthOptions()), Catch::Contains("nothing holds the surface"));
}
