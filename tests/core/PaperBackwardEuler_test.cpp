// SPDX-License-Identifier: MIT
// BACKWARD_EULER with the paper's energy (TimeStepper.h, BackwardEulerStepper; docs/math.md
// §16): the same incremental potential and Newton as SHELL's, over the paper's quadratic energy
// and its mass (MassMatrix.h). A step without state forces is the linear backward Euler step,
// checked against a dense solve written here; the paper's constant tangent folded through
// derived and periodic layers equals its Hessian product; the energy of a free swing never
// rises; it converges at first order; the barrier contact works on it (issue 35, item 6): a
// sheet of the paper's model dropped onto a thin plate rests on it and never crosses.
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <memory>
#include <random>

#include "../support/ObstacleMeshes.h"
#include "../support/TangentCheck.h"
#include "bsdeform/contact/BarrierContact.h"
#include "bsdeform/contact/BroadPhase.h"
#include "bsdeform/contact/CollisionProxy.h"
#include "bsdeform/dynamics/MassMatrix.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/dynamics/TangentMatrix.h"
#include "bsdeform/forces/ForceLaws.h"

using namespace bsdeform;
using bsdeform::test::box;
using bsdeform::test::worldOf;

namespace {
ModelParameters paperSheet(Integrator integrator, double dt) {
  ModelParameters p;
  p.numU = p.numV = 6;
  p.boundaries = Boundaries{Boundary::Clamped, Boundary::Free, Boundary::Free, Boundary::Free};
  p.weights = Weights{};
  p.weights.w10 = p.weights.w01 = 20.0;
  p.weights.w20 = p.weights.w02 = 0.5;
  p.weights.w11 = 0.5;
  p.mass = 0.01;
  p.damping = 0.0;
  p.integrator = integrator;
  p.timeStep = dt;
  p.newtonVelocityTolerance = 1e-12;
  p.newtonTolerance = 1e-13;
  return p;
}

/// The held rows of `net` (the clamped side's layers, pins) back at rest, derived layers and
/// copies completed.
void holdAtRest(const Simulation& sim, ControlNet& net) {
  const SplineSpace& s = sim.space();
  for (int i = 0; i < s.netRows(); ++i)
    for (int j = 0; j < s.netCols(); ++j) {
      const Eigen::Index r = Eigen::Index(i) * s.netCols() + j;
      if (!s.isMoving(i, j)) net.row(r) = sim.rest().row(r);
    }
  for (Eigen::Index r : sim.pinnedRows()) net.row(r) = sim.rest().row(r);
  s.completeNet(net, &sim.rest());
}

ControlNet lifted(const Simulation& sim, double amount) {
  ControlNet net = sim.rest();
  for (Eigen::Index r = 0; r < net.rows(); ++r) {
    const double u = sim.rest()(r, 0), v = sim.rest()(r, 1);
    net(r, 2) += amount * u * u * (1.0 + 0.3 * v);
  }
  holdAtRest(sim, net);
  return net;
}

double mechanicalEnergy(const Simulation& sim) { return sim.kineticEnergy() + sim.strainEnergy().total; }
}  // namespace

TEST_CASE("BACKWARD_EULER, paper's energy: a step is the linear backward Euler step of M, C and A_II",
          "[core][paper]") {
  for (double damping : {0.0, 0.7}) {
    for (bool pinned : {false, true}) {
      CAPTURE(damping, pinned);
      ModelParameters p = paperSheet(Integrator::BackwardEuler, 0.01);
      p.damping = damping;
      if (pinned) p.pins.push_back(Eigen::Vector2d(1.0, 1.0));
      Simulation sim(p);
      const Eigen::Vector3d g(0.0, 0.3, -9.81);
      sim.addForce(std::make_shared<GravityForce>(p.mass, g));
      const ControlNet start = lifted(sim, 0.05);
      ControlNet before = start;
      before.col(1).array() -= 0.002;  // moving in +y
      holdAtRest(sim, before);
      sim.setState(start, before, 0.0, 0);
      ControlNet load = ControlNet::Zero(sim.space().numMoving(), 3);  // gravity: constant
      GravityForce(p.mass, g).addLoad(LoadContext{sim.space(), start, start, p.timeStep, 0.0}, load);
      REQUIRE(sim.step() == Status::Ok);
      // (m/h^2 + c/h) x + A_II x = m (2P - P-)/h^2 + (c/h) P + L + A_II x_rest, rows of pinned
      // points held
      const SplineSpace& s = sim.space();
      const Eigen::MatrixXd A = Eigen::MatrixXd(sim.stencil().movingMatrix());
      const Eigen::Index n = s.numMoving();
      const double h = p.timeStep, m = p.mass, c = p.damping;
      const ControlNet P = s.gatherMoving(start), Pm = s.gatherMoving(before), xr = s.gatherMoving(sim.rest());
      Eigen::MatrixXd K = A;
      K.diagonal().array() += m / (h * h) + c / h;
      Eigen::MatrixXd rhs = m / (h * h) * (2.0 * P - Pm) + (c / h) * P + load + A * xr;
      for (Eigen::Index f = 0; f < n; ++f) {
        const Eigen::Index r = s.movingToNet(f);
        const bool isPinned =
            std::find(sim.pinnedRows().begin(), sim.pinnedRows().end(), r) != sim.pinnedRows().end();
        if (!isPinned) continue;
        rhs -= K.col(f) * P.row(f);
        K.row(f).setZero();
        K.col(f).setZero();
        K(f, f) = 1.0;
        rhs.row(f) = P.row(f);
      }
      const Eigen::MatrixXd expected = K.ldlt().solve(rhs);
      const ControlNet got = s.gatherMoving(sim.current());
      const double err = (got - expected).cwiseAbs().maxCoeff();
      CAPTURE(err, sim.lastNewtonIterations());
      CHECK(err <= 1e-9 * (expected - P).cwiseAbs().maxCoeff());
      CHECK((expected - P).cwiseAbs().maxCoeff() > 1e-4);  // it moved
    }
  }
}

TEST_CASE("BACKWARD_EULER, paper's energy: its constant tangent, folded through derived and periodic layers, is "
          "the Hessian product",
          "[core][paper]") {
  using B = Boundary;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> X(-1.0, 1.0);
  for (const Boundaries& b : {Boundaries{B::Free, B::Free, B::Free, B::Free},
                              Boundaries{B::Periodic, B::Periodic, B::SimplySupported, B::BuiltIn},
                              Boundaries{B::SimplySupported, B::Clamped, B::Periodic, B::Periodic}}) {
    const SplineSpace s(3, 3, 5, 6, b);
    const StiffnessStencil stencil(s, Weights{1.0, 2.0, 0.5, 0.25, 0.3});
    const ControlNet rest = s.grevillePlane();
    const PaperEnergy energy(s, stencil, rest, true, false, 1.0);
    std::vector<int> start;
    std::vector<std::pair<Eigen::Index, double>> fold;
    s.foldMap(start, fold);
    TangentMatrix K(s, start, fold);
    K.addScalarMatrix(stencil.movingMatrix(), 1.0);
    ControlNet d(s.numMoving(), 3);
    for (Eigen::Index i = 0; i < d.size(); ++i) d.data()[i] = X(rng);
    ControlNet Hd;
    energy.hessianProduct(rest, d, Hd);
    CHECK(test::tangentProductError(K, d, Hd) <= 1e-11 * Hd.cwiseAbs().maxCoeff());
    CHECK(Hd.cwiseAbs().maxCoeff() > 0.0);
  }
}

TEST_CASE("MassMatrix: T^T W T next to derived layers is applied and solved consistently, pinned rows left out",
          "[core][paper]") {
  const SplineSpace s(3, 3, 5, 6,
                      Boundaries{Boundary::SimplySupported, Boundary::Free, Boundary::BuiltIn, Boundary::Free});
  Eigen::VectorXd W(s.netSize());
  for (Eigen::Index p = 0; p < W.size(); ++p) W[p] = 1.0 + 0.01 * double(p % 7);
  std::vector<char> pinned(size_t(s.numMoving()), 0);
  pinned[3] = 1;
  const auto M = MassMatrix::folded(s, W, pinned);
  REQUIRE(!M->isDiagonal());
  // kinetic energy: ½ Σ_p W_p |(T v)_p|² over the net
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> X(-1.0, 1.0);
  ControlNet v(s.numMoving(), 3);
  for (Eigen::Index i = 0; i < v.size(); ++i) v.data()[i] = X(rng);
  ControlNet net = ControlNet::Zero(s.netSize(), 3);
  s.scatterMoving(v, net);
  s.completeNet(net, nullptr);
  double direct = 0.0;
  for (Eigen::Index p = 0; p < net.rows(); ++p) direct += 0.5 * W[p] * net.row(p).squaredNorm();
  CHECK(M->kineticEnergy(v) == Approx(direct).epsilon(1e-12));
  // solve: M_ff^-1 on the free rows, zero on the pinned one
  ControlNet a = v;
  M->solve(a);
  CHECK(a.row(3).norm() == 0.0);
  ControlNet back = a;
  back = M->apply(a);
  for (Eigen::Index f = 0; f < v.rows(); ++f)
    if (f != 3) CHECK((back.row(f) - v.row(f)).norm() <= 1e-10);
}

TEST_CASE("BACKWARD_EULER, paper's energy: the energy of a free swing never rises, and falls with damping",
          "[core][paper]") {
  for (double damping : {0.0, 0.05}) {
    CAPTURE(damping);
    ModelParameters p = paperSheet(Integrator::BackwardEuler, 0.02);
    p.damping = damping;
    Simulation sim(p);
    const ControlNet start = lifted(sim, 0.1);
    sim.setState(start, start, 0.0, 0);
    double last = mechanicalEnergy(sim);
    const double e0 = last;
    REQUIRE(e0 > 0.0);
    for (int k = 0; k < 80; ++k) {
      REQUIRE(sim.step() == Status::Ok);
      const double e = mechanicalEnergy(sim);
      CHECK(e <= last * (1.0 + 1e-12));
      last = e;
    }
    CHECK(last < 0.9 * e0);  // backward Euler dissipates, damping or not
  }
}

// [slow]: many small steps, long under the sanitizers (the Release suite runs it)
TEST_CASE("BACKWARD_EULER, paper's energy: first order in the time step, toward the same motion as IMPLICIT",
          "[core][paper][slow]") {
  auto finalState = [](Integrator integrator, double dt) {
    Simulation sim(paperSheet(integrator, dt));
    const ControlNet start = lifted(sim, 0.1);
    sim.setState(start, start, 0.0, 0);
    sim.advance(long(0.2 / dt + 0.5));
    REQUIRE(sim.status() == Status::Ok);
    return ControlNet(sim.current());
  };
  const ControlNet a = finalState(Integrator::BackwardEuler, 4e-3), b = finalState(Integrator::BackwardEuler, 2e-3),
                   c = finalState(Integrator::BackwardEuler, 1e-3);
  const double ratio = (a - b).norm() / (b - c).norm();
  CAPTURE(ratio);
  CHECK(ratio > 1.7);
  CHECK(ratio < 2.4);
  // and the limit is Newmark's (second order: its own error at 1e-4 is far below these)
  const ControlNet reference = finalState(Integrator::Implicit, 1e-4);
  const double errB = (b - reference).norm(), errC = (c - reference).norm();
  CAPTURE(errB, errC);
  CHECK(errC < 0.6 * errB);
  CHECK(errC < 0.05 * (c - lifted(Simulation(paperSheet(Integrator::Implicit, 1e-4)), 0.1)).norm());
}

TEST_CASE("BACKWARD_EULER, paper's energy: barrier contact holds a falling sheet on a thin plate, nothing crossing",
          "[core][paper][contact]") {
  ModelParameters p = paperSheet(Integrator::BackwardEuler, 0.02);
  p.boundaries = Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free};
  p.massModel = MassModel::Lumped;
  p.mass = 0.15;  // kg per unit parameter area
  p.damping = 0.02;
  p.newtonVelocityTolerance = 1e-6;
  p.newtonTolerance = 1e-9;
  Simulation sim(p);
  sim.addForce(std::make_shared<GravityForce>(p.mass, Eigen::Vector3d(0, 0, -9.81)));
  const double top = -0.05;
  const TriangleMesh plate = box(Eigen::Vector3d(-0.5, -0.5, top - 0.002), Eigen::Vector3d(1.5, 1.5, top));
  BarrierContactParameters bp;
  bp.offset = 0.005;
  bp.dhat = 0.002;
  bp.mass = sim.massPerArea();
  bp.samplesPerSpan = 4;
  auto contact = std::make_shared<BarrierContactForce>(worldOf(plate), bp);
  sim.addForce(contact);
  ControlNet previous = sim.rest();
  previous.col(2).array() += 0.06;  // 3 m/s down
  sim.setState(sim.rest(), previous, 0.0, 0);
  double lowest = 1e300;
  const ContactMesh obstacle = staticContactMesh(plate);
  const CollisionProxy proxy(sim.space(), bp.samplesPerSpan);
  for (int step = 0; step < 25; ++step) {
    const Status status = sim.step();
    INFO("step " << step << ": " << sim.statusMessage());
    REQUIRE(status == Status::Ok);
    // every proxy vertex above the plate's top by the offset (the plate is wider than the sheet)
    Eigen::MatrixX3d vertices;
    proxy.positions(sim.current(), vertices);
    const double gap = vertices.col(2).minCoeff() - top;
    CHECK(gap >= bp.offset * (1.0 - 1e-9));
    lowest = std::min(lowest, gap);
    for (int i = 0; i <= 10; ++i)
      for (int j = 0; j <= 10; ++j)
        CHECK(sim.evaluate(i / 10.0, j / 10.0).position.z() - top >= bp.offset - contact->lastDeviationBound());
  }
  CHECK(lowest < bp.offset + bp.dhat);  // it landed
  CHECK(sim.kineticEnergy() < 1e-4);    // and rests there
}

TEST_CASE("BACKWARD_EULER, paper's energy: a side moved by a map is refused, naming SHELL", "[core][paper]") {
  Simulation sim(paperSheet(Integrator::BackwardEuler, 0.01));
  Eigen::Matrix3d turn = Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()).toRotationMatrix();
  sim.setSideMotion(0, turn, Eigen::Vector3d::Zero());
  CHECK(sim.step() == Status::Refused);
  CHECK_THAT(sim.statusMessage(), Catch::Contains("SHELL"));
}
