// SPDX-License-Identifier: MIT
// Probes and support reactions (dynamics/Probe.h, dynamics/Reactions.h; docs/math.md "Probes
// and reactions"): the full-net gradient and loads fold onto the model's own, the reactions of
// an equilibrium balance the applied loads for every kind of support and both energies, and
// symmetric or statically determinate cases carry the loads the statics say.
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>

#include "bsdeform/dynamics/Probe.h"
#include "bsdeform/dynamics/Reactions.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/forces/ForceLaws.h"
#include "bsdeform/spline/RestShape.h"

using namespace bsdeform;

namespace {

ModelParameters shellParams(int nu, int nv, Boundaries b) {
  ModelParameters p;
  p.degreeU = p.degreeV = 3;
  p.numU = nu;
  p.numV = nv;
  p.boundaries = b;
  p.energy = EnergyModel::Shell;
  p.material.youngsModulus = 1.0e5;
  p.material.poissonRatio = 0.3;
  p.material.thickness = 0.01;
  p.material.density = 100.0;
  return p;
}

Boundaries sides(Boundary uMin, Boundary uMax, Boundary vMin, Boundary vMax) { return Boundaries{uMin, uMax, vMin, vMax}; }

// T^T g: a full-net vector folded onto the unknowns (periodic copies onto what they repeat,
// derived points onto their sources with their weights, held points dropped)
ControlNet fold(const SplineSpace& s, const ControlNet& g) {
  ControlNet out = ControlNet::Zero(s.numMoving(), 3);
  const LayerRange &mu = s.movingU(), &mv = s.movingV();
  for (int i = 0; i < s.netRows(); ++i)
    for (int j = 0; j < s.netCols(); ++j)
      for (const LayerWeight& wu : s.foldU(i))
        for (const LayerWeight& wv : s.foldV(j))
          out.row(Eigen::Index(wu.layer - mu.first) * mv.count + (wv.layer - mv.first)) +=
              wu.weight * wv.weight * g.row(Eigen::Index(i) * s.netCols() + j);
  return out;
}

const Eigen::Vector3d& side(const SupportReactions& r, const std::string& name) {
  for (const SupportReactions::Side& s : r.sides)
    if (s.name == name) return s.force;
  FAIL("no reaction of side " << name);
  static const Eigen::Vector3d none = Eigen::Vector3d::Zero();
  return none;
}

// Every increment of `result` balances: applied + reactions = -(what the points outside the
// bands and pins sum to) to rounding, that sum is the model's own residual there, within the
// Cauchy–Schwarz bound sqrt(unknowns) |residual|, and below `tolerance` |applied|.
void checkBalance(Simulation& sim, const StaticResult& result, double tolerance) {
  const SplineSpace& s = sim.space();
  for (const StaticResult::Increment& inc : result.increments) {
    const SupportReactions r = supportReactions(sim, inc.net, inc.loadFactor);
    CAPTURE(inc.loadFactor, inc.residual, r.applied.transpose(), r.imbalance().transpose(), r.elsewhere.transpose());
    REQUIRE(r.applied.norm() > 0.0);
    double size = r.applied.norm();
    for (const SupportReactions::Side& side : r.sides) size += side.force.norm();
    for (const Eigen::Vector3d& pin : r.pins) size += pin.norm();
    CHECK((r.imbalance() + r.elsewhere).norm() <= 1e-10 * size);
    // the model's residual dW/dx - L on the unknowns (pinned ones left out)
    sim.setState(inc.net, 0.0, 0);
    ControlNet R;
    sim.energy().gradient(inc.net, R);
    R -= inc.loadFactor * sim.loadVector();
    for (Eigen::Index f = 0; f < R.rows(); ++f)
      if (sim.heldCoordinate(f, 0)) R.row(f).setZero();
    CHECK(r.elsewhere.norm() <= std::sqrt(double(R.rows())) * R.norm() + 1e-12 * size);
    CHECK(r.imbalance().norm() <= tolerance * r.applied.norm());
  }
}

}  // namespace

TEST_CASE("Reactions: the full-net gradient and loads fold onto the model's own", "[core]") {
  // every side kind, a periodic direction and pins, both energies, a state away from rest
  struct Case {
    const char* name;
    ModelParameters p;
    bool cylinder;
  };
  std::vector<Case> cases;
  {
    ModelParameters p = shellParams(6, 5, sides(Boundary::SimplySupported, Boundary::BuiltIn, Boundary::Clamped, Boundary::Free));
    p.pins = {Eigen::Vector2d(0.5, 0.9)};
    cases.push_back({"SHELL, SIMPLY_SUPPORTED, BUILT_IN, CLAMPED, FREE and a pin", p, false});
  }
  cases.push_back({"SHELL cylinder, u PERIODIC", shellParams(8, 4, sides(Boundary::Periodic, Boundary::Periodic, Boundary::BuiltIn, Boundary::Free)), true});
  {
    ModelParameters p;
    p.numU = 6;
    p.numV = 5;
    p.boundaries = sides(Boundary::SimplySupported, Boundary::BuiltIn, Boundary::Clamped, Boundary::Free);
    p.pins = {Eigen::Vector2d(0.5, 0.9)};
    cases.push_back({"PAPER, every side kind and a pin", p, false});
    p.reference = ElasticReference::Absolute;
    p.pins.clear();
    cases.push_back({"PAPER, Absolute reference", p, false});
  }
  {
    ModelParameters p;
    p.numU = 8;
    p.numV = 4;
    p.boundaries = sides(Boundary::Periodic, Boundary::Periodic, Boundary::Clamped, Boundary::SimplySupported);
    cases.push_back({"PAPER cylinder, u PERIODIC", p, true});
  }
  for (Case& c : cases) {
    INFO(c.name);
    const SplineSpace s(c.p.degreeU, c.p.degreeV, c.p.numU, c.p.numV, c.p.boundaries);
    const ControlNet rest = c.cylinder ? shapeRestNet(ShapeKind::Cylinder, ShapeSize(), s) : s.grevillePlane();
    Simulation sim(c.p, rest);
    sim.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0.3, -0.2, -1.0), ParamRect{0.1, 0.8, 0.0, 0.6}));
    sim.addForce(std::make_shared<PointForce>(0.7, 0.35, Eigen::Vector3d(0.5, 1.0, 2.0)));
    sim.addForce(std::make_shared<SpringForce>(0.3, 0.6, Eigen::Vector3d(0.2, 0.4, 0.3), 2.0));
    // a state away from rest: the unknowns moved smoothly, the net completed
    ControlNet x = s.gatherMoving(rest);
    for (Eigen::Index f = 0; f < x.rows(); ++f) {
      const Eigen::Index r = s.movingToNet(f);
      x.row(f) += 0.05 * Eigen::RowVector3d(std::sin(3.0 * r), std::cos(2.0 * r), std::sin(0.7 * r + 1.0));
    }
    ControlNet net = rest;
    s.scatterMoving(x, net);
    s.completeNet(net, &rest);
    sim.setState(net, 0.0, 0, HeldPoints::Reset);
    net = sim.current();  // pinned points back at rest

    ControlNet g;
    sim.energy().gradient(net, g);
    const ControlNet folded = fold(s, fullNetEnergyGradient(sim, net));
    for (Eigen::Index f = 0; f < g.rows(); ++f) {
      if (!sim.heldCoordinate(f, 0)) {  // pinned rows: the model's gradient is not asked there
        CAPTURE(f);
        CHECK((folded.row(f) - g.row(f)).norm() <= 1e-10 * (1.0 + g.norm()));
      }
    }
    const ControlNet L = sim.loadVector();
    CHECK((fold(s, fullNetLoad(sim, net)) - L).norm() <= 1e-12 * (1.0 + L.norm()));
    // the energy is invariant under translation: its full-net gradient sums to zero
    CHECK(fullNetEnergyGradient(sim, net).colwise().sum().norm() <= 1e-10 * (1.0 + g.norm()));
    // and the point load's share of the applied sum is the load itself (partition of unity)
    const SupportReactions r = supportReactions(sim, net);
    CHECK((r.applied - fullNetLoad(sim, net).colwise().sum().transpose()).norm() <= 1e-12);
  }
}

TEST_CASE("Reactions: a SHELL plate CLAMPED on four sides: each side carries a quarter of the vertical load", "[core]") {
  ModelParameters p = shellParams(8, 8, Boundaries());
  Simulation sim(p);
  const double q = 2.0, P = 0.5;
  sim.addForce(std::make_shared<GravityForce>(p.material.density * p.material.thickness, Eigen::Vector3d(0, 0, -q)));
  sim.addForce(std::make_shared<PointForce>(0.5, 0.5, Eigen::Vector3d(0, 0, -P)));
  const StaticResult result = sim.solveStatic(p.newtonTolerance, 40, LinearSolver::Automatic, 2);
  REQUIRE(result.increments.size() == 2);
  checkBalance(sim, result, 1e-6);
  const SupportReactions r = supportReactions(sim, result.net);
  // the applied load: gravity's m g over the unit square and the point load
  CHECK(r.applied.z() == Approx(-(p.material.density * p.material.thickness * q + P)).epsilon(1e-12));
  CHECK(std::abs(r.applied.x()) + std::abs(r.applied.y()) <= 1e-14);
  REQUIRE(r.sides.size() == 4);
  for (const char* name : {"umin", "umax", "vmin", "vmax"}) {
    INFO(name);
    CHECK(side(r, name).z() == Approx(-r.applied.z() / 4).epsilon(1e-7));
  }
  // the membrane pulls each side inwards, opposite sides alike
  CHECK(side(r, "umin").x() == Approx(-side(r, "umax").x()).epsilon(1e-6));
  CHECK(side(r, "vmin").y() == Approx(-side(r, "vmax").y()).epsilon(1e-6));
  CHECK(side(r, "umin").x() < 0.0);  // the support at u = 0 pulls towards -x (sign: force ON the surface)
  // away from equilibrium (the rest net under the load) the same sum shows the imbalance: the
  // check can fail
  const SupportReactions atRest = supportReactions(sim, sim.rest());
  CHECK(atRest.imbalance().norm() > 0.5 * atRest.applied.norm());
}

TEST_CASE("Reactions: a SHELL strip on two SIMPLY_SUPPORTED sides, two FREE, and a BUILT_IN cantilever", "[core]") {
  {
    ModelParameters p = shellParams(10, 3, sides(Boundary::SimplySupported, Boundary::SimplySupported, Boundary::Free, Boundary::Free));
    Simulation sim(p);
    sim.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, -3e-4)));
    sim.addForce(std::make_shared<PointForce>(0.25, 0.5, Eigen::Vector3d(0, 0, -1e-4)));
    const StaticResult result = sim.solveStatic(p.newtonTolerance, 40, LinearSolver::Automatic, 3);
    // a thin plate under a small load: Newton's update is judged against the displacement
    // (microns here), so the balance reaches the solver's tolerance (it stopped at 2e-5 when
    // the update was judged against the surface's size)
    checkBalance(sim, result, 1e-8);
    const SupportReactions r = supportReactions(sim, result.net);
    REQUIRE(r.sides.size() == 2);
    CHECK(r.sides[0].name == "umin");
    CHECK(r.sides[1].name == "umax");
    // a statically determinate beam, small deflection: the lever rule (the uniform load halves,
    // the point load at u = 1/4 splits 3/4 : 1/4); the membrane's share is second order
    const double deflection = -probe(sim, result.net, 0.5, 0.5).displacement.z();
    CHECK(deflection > 0.0);
    CHECK(deflection < 0.001);
    CHECK(side(r, "umin").z() == Approx(1.5e-4 + 0.75e-4).epsilon(2e-3));
    CHECK(side(r, "umax").z() == Approx(1.5e-4 + 0.25e-4).epsilon(2e-3));
    CHECK(side(r, "umin").x() == Approx(-side(r, "umax").x()).epsilon(1e-6));
  }
  {
    // a cantilever: its BUILT_IN side carries the whole load, with the large deflection's rotation
    ModelParameters p = shellParams(12, 2, sides(Boundary::BuiltIn, Boundary::Free, Boundary::Free, Boundary::Free));
    Simulation sim(p);
    sim.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, -0.02), ParamRect{1.0, 1.0, 0.0, 1.0}));
    const StaticResult result = sim.solveStatic(p.newtonTolerance, 40, LinearSolver::Automatic, 2);
    checkBalance(sim, result, 1e-6);
    const SupportReactions r = supportReactions(sim, result.net);
    REQUIRE(r.sides.size() == 1);
    CHECK(r.sides[0].name == "umin");
    CHECK(r.applied.z() == Approx(-0.02).epsilon(1e-12));
    CHECK((r.sides[0].force + r.applied).norm() <= 1e-7 * r.applied.norm());
    CHECK(-probe(sim, result.net, 1.0, 0.5).displacement.z() > 0.01);  // it did bend
  }
}

TEST_CASE("Reactions: a SHELL sheet on four pins, each carrying a quarter, and a hanging cylinder", "[core]") {
  {
    ModelParameters p = shellParams(8, 8, sides(Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free));
    p.pins = {Eigen::Vector2d(0.2, 0.2), Eigen::Vector2d(0.8, 0.2), Eigen::Vector2d(0.2, 0.8), Eigen::Vector2d(0.8, 0.8)};
    Simulation sim(p);
    sim.addForce(std::make_shared<GravityForce>(p.material.density * p.material.thickness, Eigen::Vector3d(0, 0, -9.81)));
    const StaticResult result = sim.solveStatic(p.newtonTolerance, 40);
    checkBalance(sim, result, 1e-6);
    const SupportReactions r = supportReactions(sim, result.net);
    CHECK(r.sides.empty());  // FREE sides hold nothing
    REQUIRE(r.pins.size() == 4);
    for (const Eigen::Vector3d& pin : r.pins) CHECK(pin.z() == Approx(-r.applied.z() / 4).epsilon(1e-7));
  }
  {
    // u PERIODIC (holds nothing), the lower end BUILT_IN: it carries the cylinder's weight
    ModelParameters p = shellParams(8, 4, sides(Boundary::Periodic, Boundary::Periodic, Boundary::BuiltIn, Boundary::Free));
    const SplineSpace s(3, 3, 8, 4, p.boundaries);
    Simulation sim(p, shapeRestNet(ShapeKind::Cylinder, ShapeSize(), s));
    sim.addForce(std::make_shared<GravityForce>(p.material.density * p.material.thickness, Eigen::Vector3d(0, 0, -9.81)));
    const StaticResult result = sim.solveStatic(p.newtonTolerance, 40);
    checkBalance(sim, result, 1e-6);
    const SupportReactions r = supportReactions(sim, result.net);
    REQUIRE(r.sides.size() == 1);
    CHECK(r.sides[0].name == "vmin");
    CHECK(r.sides[0].force.z() == Approx(-r.applied.z()).epsilon(1e-7));
    CHECK(r.sides[0].force.head<2>().norm() <= 1e-7 * r.applied.norm());
  }
}

TEST_CASE("Reactions: the paper's energy balances too, CLAMPED, SIMPLY_SUPPORTED and pinned", "[core]") {
  {
    ModelParameters p;  // the paper's model: bicubic, every side CLAMPED
    p.numU = p.numV = 10;
    Simulation sim(p);
    sim.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, 4.0)));
    const StaticResult result = sim.solveStatic(1e-10, 100, LinearSolver::Automatic, 2);
    checkBalance(sim, result, 1e-8);
    const SupportReactions r = supportReactions(sim, result.net);
    CHECK(r.applied.z() == Approx(4.0).epsilon(1e-12));
    for (const char* name : {"umin", "umax", "vmin", "vmax"}) CHECK(side(r, name).z() == Approx(-1.0).epsilon(1e-8));
  }
  {
    ModelParameters p;
    p.numU = 9;
    p.numV = 6;
    p.boundaries = sides(Boundary::SimplySupported, Boundary::BuiltIn, Boundary::Free, Boundary::Free);
    p.pins = {Eigen::Vector2d(0.5, 0.95)};
    Simulation sim(p);
    sim.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0.5, 0, -2.0), ParamRect{0.0, 0.7, 0.2, 1.0}));
    sim.addForce(std::make_shared<PointForce>(0.8, 0.1, Eigen::Vector3d(0, 1.0, -1.0)));
    const StaticResult result = sim.solveStatic(1e-10);
    checkBalance(sim, result, 1e-8);
    const SupportReactions r = supportReactions(sim, result.net);
    REQUIRE(r.sides.size() == 2);
    REQUIRE(r.pins.size() == 1);
    CHECK(r.pins[0].norm() > 0.01 * r.applied.norm());  // the pin takes its share
  }
}

TEST_CASE("Probe: the surface point and its displacement from rest, (u, v) outside [0,1] refused", "[core]") {
  ModelParameters p;
  p.numU = p.numV = 6;
  Simulation sim(p);
  // rest is the Greville plane S = (u, v, 0)
  ProbeSample s = probe(sim, 0.25, 0.75);
  CHECK((s.point - Eigen::Vector3d(0.25, 0.75, 0)).norm() <= 1e-14);
  CHECK(s.displacement.norm() <= 1e-14);
  ControlNet moved = sim.current();
  for (Eigen::Index f = 0; f < sim.space().numMoving(); ++f) moved(sim.space().movingToNet(f), 2) += 0.5;
  sim.setState(moved, 0.0, 0);
  s = probe(sim, 0.5, 0.5);  // the middle's B-splines are all moving points: lifted by 0.5
  CHECK(s.displacement.z() == Approx(0.5).epsilon(1e-14));
  CHECK(s.point.z() == Approx(0.5).epsilon(1e-14));
  CHECK(s.point.x() == Approx(0.5).epsilon(1e-14));
  CHECK(probe(sim, 0.0, 0.5).displacement.norm() <= 1e-14);  // the clamped edge stays
  CHECK_THROWS_WITH(probe(sim, 1.5, 0.5), Catch::Contains("u must be in [0, 1], got 1.5"));
  CHECK_THROWS_WITH(probe(sim, 0.5, -0.1), Catch::Contains("v must be in [0, 1], got -0.1"));
  CHECK_THROWS_WITH(probe(sim, std::nan(""), 0.5), Catch::Contains("u must be in [0, 1]"));
}
