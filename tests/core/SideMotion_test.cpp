// SPDX-License-Identifier: MIT
// A CLAMPED side moved by a prescribed map under BACKWARD_EULER (Simulation::setSideMotion): the
// held layers are where the map puts them, a strip twisted by turning one end has its middle
// turned by half the angle (the symmetry of the problem), two ends moved together carry the
// sheet rigidly, a resumed run is bit-identical, a move that would cross an obstacle is refused
// before anything crossed, and the refusals name what to change.
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>

#include "../support/ObstacleMeshes.h"
#include "bsdeform/contact/BarrierContact.h"
#include "bsdeform/dynamics/Simulation.h"

using namespace bsdeform;
using bsdeform::test::box;
using bsdeform::test::worldOf;

namespace {
constexpr double kWidth = 0.25;  // the strip: x in [0, 1] along u, y in [0, kWidth] along v

ModelParameters strip(Boundaries b = Boundaries{Boundary::Clamped, Boundary::Clamped, Boundary::Free, Boundary::Free}) {
  ModelParameters p;
  p.numU = 10;
  p.numV = 3;
  p.boundaries = b;
  p.energy = EnergyModel::Shell;
  p.material = ShellMaterial{1.0e6, 0.3, 0.01, 1000.0};
  p.damping = 10.0;  // near critical for the twist (5 rad/s): settles within a second
  p.integrator = Integrator::BackwardEuler;
  p.timeStep = 0.01;
  p.newtonVelocityTolerance = 1e-7;
  return p;
}

ControlNet stripRest(const ModelParameters& p) {
  const SplineSpace s(p.degreeU, p.degreeV, p.numU, p.numV, p.boundaries);
  ControlNet net = s.grevillePlane();
  net.col(1) *= kWidth;
  return net;
}

/// The turn by `angle` about the strip's centre line (the x axis through y = kWidth / 2).
void turn(double angle, Eigen::Matrix3d& linear, Eigen::Vector3d& offset) {
  linear = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Vector3d c(0.0, 0.5 * kWidth, 0.0);
  offset = c - linear * c;
}

/// The angle of the cross-section u about the x axis (from S(u, 0) to S(u, 1)).
double sectionAngle(const Simulation& sim, double u) {
  const Eigen::Vector3d d = sim.evaluate(u, 1.0).position - sim.evaluate(u, 0.0).position;
  return std::atan2(d.z(), d.y());
}
}  // namespace

TEST_CASE("A moved side: a strip twisted by turning one end turns its middle by half the angle",
          "[shell][motion][slow]") {
  const ModelParameters p = strip();
  Simulation sim(p, stripRest(p));
  const double angle = 0.6;
  Eigen::Matrix3d linear;
  Eigen::Vector3d offset;
  for (int step = 1; step <= 150; ++step) {
    turn(angle * std::min(1.0, step / 20.0), linear, offset);  // turned in 0.2 s, then held
    sim.setSideMotion(1, linear, offset);
    REQUIRE(sim.step() == Status::Ok);
  }
  INFO(sim.statusMessage());
  // the held layers are exactly where the map puts the rest's (three layers of the cubic net)
  const SplineSpace& s = sim.space();
  double held = 0.0;
  for (int i = s.netRows() - 3; i < s.netRows(); ++i)
    for (int j = 0; j < s.netCols(); ++j) {
      const Eigen::Index r = Eigen::Index(i) * s.netCols() + j;
      held = std::max(held, (sim.current().row(r).transpose() - (linear * sim.rest().row(r).transpose() + offset)).norm());
    }
  CHECK(held == 0.0);
  // the ends: one at rest, one turned; the middle by half (the problem maps onto itself turned
  // by half the angle and flipped end for end), and the quarters in between
  CHECK(std::abs(sectionAngle(sim, 0.0)) < 1e-12);
  CHECK(sectionAngle(sim, 1.0) == Approx(angle).epsilon(1e-9));
  CHECK(sectionAngle(sim, 0.5) == Approx(0.5 * angle).epsilon(2e-3));
  const double quarter = sectionAngle(sim, 0.25), threeQuarters = sectionAngle(sim, 0.75);
  CHECK(quarter > 0.05 * angle);
  CHECK(quarter < 0.5 * angle);
  CHECK(quarter + threeQuarters == Approx(angle).epsilon(2e-3));
  // the strip has an energy of twisting; freed again, it untwists back to rest
  CHECK(sim.strainEnergy().total > 0.0);
  sim.clearSideMotion(1);
  for (int step = 0; step < 150; ++step) REQUIRE(sim.step() == Status::Ok);
  CHECK(std::abs(sectionAngle(sim, 0.5)) < 1e-3 * angle);
}

TEST_CASE("A moved side: both ends moved by one map carry the strip rigidly, and a resumed run is bit-identical",
          "[shell][motion][slow]") {
  ModelParameters p = strip();
  p.material.youngsModulus = 1e8;  // bending at 20 rad/s: damped out within the run
  const ControlNet rest = stripRest(p);
  const Eigen::Vector3d lift(0.02, -0.01, 0.05);
  auto motion = [&](Simulation& sim, int step) {
    const Eigen::Vector3d offset = std::min(1.0, step / 10.0) * lift;
    sim.setSideMotion(0, Eigen::Matrix3d::Identity(), offset);
    sim.setSideMotion(1, Eigen::Matrix3d::Identity(), offset);
  };
  Simulation sim(p, rest);
  ControlNet savedCurrent, savedPrevious;
  double savedTime = 0.0;
  long savedSteps = 0;
  for (int step = 1; step <= 300; ++step) {
    motion(sim, step);
    REQUIRE(sim.step() == Status::Ok);
    if (step == 6) {  // mid-move: the held layers between rest and the map's
      savedCurrent = sim.current();
      savedPrevious = sim.previous();
      savedTime = sim.time();
      savedSteps = sim.stepCount();
    }
  }
  const ControlNet moved = rest.rowwise() + lift.transpose();
  CHECK((sim.current() - moved).cwiseAbs().maxCoeff() < 1e-6);
  CHECK(sim.strainEnergy().total < 1e-12);
  // resumed from the saved state (its held layers off rest: taken as they are)
  Simulation resumed(p, rest);
  motion(resumed, 7);
  resumed.setState(savedCurrent, savedPrevious, savedTime, savedSteps);
  for (int step = 7; step <= 300; ++step) {
    motion(resumed, step);
    REQUIRE(resumed.step() == Status::Ok);
  }
  CHECK(resumed.current() == sim.current());
  // a side not moved keeps its check: a state whose clamped layers are off rest is refused
  Simulation still(p, rest);
  CHECK_THROWS_WITH(still.setState(savedCurrent, savedPrevious, savedTime, savedSteps),
                    Catch::Contains("clamped control point"));
}

TEST_CASE("A moved side is refused where it cannot be taken, naming what to change", "[shell][motion]") {
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const Eigen::Vector3d up(0, 0, 0.01);
  {  // only a CLAMPED side holds layers that can be moved
    const ModelParameters p = strip(Boundaries{Boundary::Clamped, Boundary::SimplySupported, Boundary::Free, Boundary::Free});
    Simulation sim(p, stripRest(p));
    CHECK_THROWS_WITH(sim.setSideMotion(1, I, up), Catch::Contains("side u = 1 is SIMPLY_SUPPORTED") &&
                                                       Catch::Contains("only a CLAMPED side"));
    CHECK_THROWS_WITH(sim.setSideMotion(0, I, Eigen::Vector3d(0, 0, NAN)), Catch::Contains("not finite"));
  }
  {  // a clamped neighbour that stays would tear at the corners
    const ModelParameters p = strip(Boundaries{Boundary::Clamped, Boundary::Clamped, Boundary::Clamped, Boundary::Free});
    Simulation sim(p, stripRest(p));
    sim.setSideMotion(1, I, up);
    CHECK(sim.step() == Status::Refused);
    CHECK_THAT(sim.statusMessage(), Catch::Contains("motionUMax") && Catch::Contains("motionVMin") &&
                                        Catch::Contains("make that side FREE"));
    CHECK(sim.current() == sim.rest());
  }
  {  // another integrator
    ModelParameters p = strip();
    p.integrator = Integrator::Explicit;
    Simulation sim(p, stripRest(p));
    sim.setSideMotion(1, I, up);
    CHECK(sim.step() == Status::Refused);
    CHECK_THAT(sim.statusMessage(), Catch::Contains("BACKWARD_EULER"));
  }
  {  // the static solve holds every side at rest: refused rather than ignoring the move
    const ModelParameters p = strip();
    Simulation sim(p, stripRest(p));
    sim.setSideMotion(1, I, up);
    CHECK_THROWS_WITH(sim.solveStatic(), Catch::Contains("moved side"));
  }
}

TEST_CASE("A moved side that would carry the strip through an obstacle in one step is refused before it crosses",
          "[shell][motion][contact]") {
  ModelParameters p = strip();
  p.damping = 0.0;
  const ControlNet rest = stripRest(p);
  // a 2 mm plate 3 cm above the end u = 1 (x from 0.9 on), the strip's far end under it
  const TriangleMesh plate = box(Eigen::Vector3d(0.9, -0.5, 0.03), Eigen::Vector3d(1.5, 0.75, 0.032));
  BarrierContactParameters bp;
  bp.offset = 0.004;
  bp.dhat = 0.002;
  bp.mass = 2.0;
  Simulation sim(p, rest);
  sim.addForce(std::make_shared<BarrierContactForce>(worldOf(plate), bp));
  // lifted 1 cm per step: below the plate, fine
  for (int step = 1; step <= 2; ++step) {
    sim.setSideMotion(1, Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 0.01 * step));
    INFO(sim.statusMessage());
    REQUIRE(sim.step() == Status::Ok);
  }
  const ControlNet before = sim.current();
  // then 8 cm at once: through the plate, which CCD sees in every piece the step is cut into
  sim.setSideMotion(1, Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 0.1));
  CHECK(sim.step() != Status::Ok);
  CHECK_THAT(sim.statusMessage(), Catch::Contains("a moved side's layers would cross"));
  // the last valid state is kept: nothing crossed
  CHECK(sim.current() == before);
  CHECK(sim.current().col(2).maxCoeff() < 0.03);
}
