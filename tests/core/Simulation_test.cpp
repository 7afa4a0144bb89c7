// SPDX-License-Identifier: MIT
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <memory>
#include <random>

#include "../support/ThreadSettings.h"
#include "bsdeform/base/Parallel.h"
#include "bsdeform/spline/RestShape.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/energy/StiffnessStencil.h"

using namespace bsdeform;

namespace {
ModelParameters paperParams(int N = 6) {
  ModelParameters p;  // omega = 0.1, 0.1, 0.01, 0.01, 0.01; m = 1; dt = 0.1 (paper §5)
  p.numU = p.numV = N;
  return p;
}

double maxBoundaryError(const Simulation& sim) {
  double err = 0.0;
  for (int i = 0; i <= 50; ++i) {
    const double s = i / 50.0;
    err = std::max(err, (sim.evaluate(s, 0.0).position - Eigen::Vector3d(s, 0, 0)).norm());
    err = std::max(err, (sim.evaluate(s, 1.0).position - Eigen::Vector3d(s, 1, 0)).norm());
    err = std::max(err, (sim.evaluate(0.0, s).position - Eigen::Vector3d(0, s, 0)).norm());
    err = std::max(err, (sim.evaluate(1.0, s).position - Eigen::Vector3d(1, s, 0)).norm());
  }
  return err;
}

double maxDiff(const ControlNet& a, const ControlNet& b) { return (a - b).cwiseAbs().maxCoeff(); }
}  // namespace

TEST_CASE("Simulation: the Greville plane is an equilibrium of the unloaded system", "[core]") {
  for (Integrator integ : {Integrator::Explicit, Integrator::Implicit})
    for (ElasticReference ref : {ElasticReference::Rest, ElasticReference::Absolute}) {
      ModelParameters p = paperParams(7);
      p.integrator = integ;
      p.reference = ref;
      p.damping = 0.0;
      Simulation sim(p);
      sim.advance(200);
      CHECK(sim.status() == Status::Ok);
      CHECK(maxDiff(sim.current(), sim.rest()) < 1e-13);
    }
}

TEST_CASE("Simulation: boundary curves stay exact after 1000 steps under random forces", "[core]") {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> U(0.0, 1.0), F(-50.0, 50.0);
  for (Integrator integ : {Integrator::Explicit, Integrator::Implicit}) {
    ModelParameters p = paperParams(8);
    p.integrator = integ;
    Simulation sim(p);
    for (int i = 0; i < 5; ++i)
      sim.addForce(std::make_shared<PointForce>(U(rng), U(rng), Eigen::Vector3d(F(rng), F(rng), F(rng))));
    const double a = U(rng) * 0.5, b = U(rng) * 0.5;
    sim.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(F(rng), F(rng), F(rng)), ParamRect{a, a + 0.4, b, b + 0.3}));
    sim.addForce(std::make_shared<DistributedForce>(
        [](const SurfaceSample& s) { return Eigen::Vector3d(0, 10 * std::sin(3 * s.t), 30 * std::cos(5 * s.t + s.u)); },
        kDependsOnTime));
    sim.advance(1000);
    REQUIRE(sim.status() == Status::Ok);
    CHECK(sim.deformationNorm() > 0.1);
    CHECK(maxBoundaryError(sim) <= 1e-12);
  }
}

TEST_CASE("Simulation: a long damped run converges to the directly solved static solution", "[core]") {
  for (Integrator integ : {Integrator::Explicit, Integrator::Implicit}) {
    ModelParameters p = paperParams(8);
    p.integrator = integ;
    p.damping = 2.0;
    Simulation sim(p);
    sim.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, 20)));
    sim.addForce(std::make_shared<PointForce>(0.3, 0.6, Eigen::Vector3d(1, 2, -3)));
    const ControlNet equilibrium = sim.staticSolution();
    // residual of A_II P = L - A_IB P_B, checked independently with the stencil on the full net
    ControlNet AP;
    sim.stencil().applyMoving(equilibrium, AP);
    CHECK((AP - sim.loadVector()).norm() < 1e-9 * sim.loadVector().norm());
    sim.advance(4000);
    REQUIRE(sim.status() == Status::Ok);
    INFO("integrator " << int(integ));
    CHECK(maxDiff(sim.current(), equilibrium) < 1e-8 * equilibrium.cwiseAbs().maxCoeff());
    CHECK(sim.kineticEnergy() < 1e-12);
  }
}

TEST_CASE("Simulation: explicit and implicit agree at small time steps, second order", "[core]") {
  auto run = [](Integrator integ, double dt) {
    ModelParameters p = paperParams(6);
    p.integrator = integ;
    p.timeStep = dt;
    p.damping = 0.3;
    Simulation sim(p);
    sim.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 5, 20), ParamRect{0.2, 0.7, 0.3, 0.8}));
    sim.advance(std::lround(2.0 / dt));
    return sim.current();
  };
  const ControlNet e1 = run(Integrator::Explicit, 0.004), i1 = run(Integrator::Implicit, 0.004);
  const ControlNet e2 = run(Integrator::Explicit, 0.002), i2 = run(Integrator::Implicit, 0.002);
  const double d1 = maxDiff(e1, i1), d2 = maxDiff(e2, i2);
  const double scale = (e2 - run(Integrator::Explicit, 1e-9 + 0.002)).norm() + e2.cwiseAbs().maxCoeff();
  INFO("difference at dt 0.004: " << d1 << ", at 0.002: " << d2);
  CHECK(d2 < 1e-3 * scale);
  CHECK(d1 / d2 == Approx(4.0).epsilon(0.15));  // both schemes are second order
}

TEST_CASE("Simulation: a time step ten times above the limit is sub-stepped and stays stable", "[core]") {
  ModelParameters p = paperParams(24);
  Simulation probe(p);
  p.timeStep = 10.0 * probe.stabilityLimit();
  p.damping = 0.0;
  Simulation sim(p);
  CHECK(sim.subSteps() >= 10);
  CHECK(sim.subStepSize() <= p.stabilitySafety * sim.stabilityLimit() * (1 + 1e-12));
  CHECK(sim.subSteps() * sim.subStepSize() == Approx(p.timeStep));
  sim.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, 20)));
  const double staticMax = (sim.staticSolution() - sim.rest()).cwiseAbs().maxCoeff();
  sim.advance(300);
  REQUIRE(sim.status() == Status::Ok);
  // undamped response to a suddenly applied load peaks at twice the static deflection
  CHECK((sim.current() - sim.rest()).cwiseAbs().maxCoeff() <= 2.05 * staticMax);

  // the same step without sub-stepping blows up: detected, reported, last finite state kept
  p.autoSubstep = false;
  Simulation raw(p);
  raw.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, 20)));
  const Status st = raw.advance(300);
  CHECK(st == Status::Diverged);
  CHECK(raw.statusMessage().find("diverged") != std::string::npos);
  CHECK(raw.current().allFinite());
  const long stoppedAt = raw.stepCount();
  CHECK(raw.step() == Status::Diverged);
  CHECK(raw.stepCount() == stoppedAt);
  raw.reset();
  CHECK(raw.status() == Status::Ok);
  CHECK(raw.time() == 0.0);
}

TEST_CASE("Simulation: the reported stability limit is a safe lower bound of the true one", "[core]") {
  for (MassModel mm : {MassModel::Nodal, MassModel::Lumped}) {
    ModelParameters p = paperParams(10);
    p.massModel = mm;
    p.mass = (mm == MassModel::Nodal) ? 1.0 : 50.0;
    Simulation sim(p);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Eigen::MatrixXd(sim.stencil().movingMatrix()), Eigen::EigenvaluesOnly);
    const double m = (mm == MassModel::Nodal) ? p.mass : p.mass * sim.space().basisU().spacing() * sim.space().basisV().spacing();
    const double trueLimit = 2.0 / std::sqrt(eig.eigenvalues().maxCoeff() / m);
    CHECK(sim.stabilityLimit() <= trueLimit);
    CHECK(sim.stabilityLimit() >= 0.9 * trueLimit);
    // just above the true limit the raw scheme diverges, just below it does not
    for (double factor : {0.98, 1.05}) {
      ModelParameters q = p;
      q.autoSubstep = false;
      q.damping = 0.0;
      q.timeStep = factor * trueLimit;
      Simulation s(q);
      s.addForce(std::make_shared<PointForce>(0.43, 0.52, Eigen::Vector3d(0, 0, 1)));
      s.advance(3000);
      CHECK((s.status() == Status::Ok) == (factor < 1.0));
    }
  }
}

TEST_CASE("Simulation: runs are deterministic, resumable and resettable", "[core]") {
  auto make = [] {
    auto sim = std::make_unique<Simulation>(paperParams(9));
    sim->addForce(std::make_shared<DistributedForce>(
        [](const SurfaceSample& s) { return Eigen::Vector3d(0, 0, 30 * std::sin(2 * s.t) - 5 * s.velocity.z()); },
        kDependsOnTime | kDependsOnVelocity));
    return sim;
  };
  auto a = make(), b = make();
  a->advance(50);
  b->advance(50);
  REQUIRE(a->current().size() == b->current().size());
  CHECK(std::memcmp(a->current().data(), b->current().data(), sizeof(double) * a->current().size()) == 0);
  // resume from a copy of the state
  auto c = make();
  c->setState(a->current(), a->previous(), a->time(), a->stepCount());
  a->advance(50);
  c->advance(50);
  CHECK(std::memcmp(a->current().data(), c->current().data(), sizeof(double) * a->current().size()) == 0);
  CHECK(c->time() == a->time());
  CHECK(c->stepCount() == 100);
  a->reset();
  CHECK(a->current() == a->rest());
  CHECK(a->time() == 0.0);
  CHECK(a->stepCount() == 0);
  CHECK(a->deformationNorm() == 0.0);
}

TEST_CASE("Simulation: time- and position-dependent forces are re-evaluated every step", "[core]") {
  ModelParameters p = paperParams(8);
  p.damping = 3.0;
  Simulation sim(p);
  // switched on at t = 0.5: nothing moves before
  sim.addForce(std::make_shared<DistributedForce>(
      [](const SurfaceSample& s) { return Eigen::Vector3d(0, 0, s.t >= 0.5 ? 10.0 : 0.0); }, kDependsOnTime));
  sim.advance(5);
  CHECK(sim.deformationNorm() == 0.0);
  sim.advance(2);
  CHECK(sim.deformationNorm() > 0.0);
  // a spring to an anchor above the centre: the equilibrium balances spring and elasticity
  const Eigen::Vector3d anchor(0.5, 0.5, 1.0);
  const double k = 5.0;
  sim.clearForces();
  sim.reset();
  const double limitBefore = sim.stabilityLimit();
  sim.addForce(std::make_shared<PointForce>(
      0.5, 0.5, [anchor, k](const SurfaceSample& s) { return Eigen::Vector3d(k * (anchor - s.position)); },
      kDependsOnPosition, k));
  CHECK(sim.stabilityLimit() < limitBefore);
  sim.advance(3000);
  REQUIRE(sim.status() == Status::Ok);
  const double z = sim.evaluate(0.5, 0.5).position.z();
  CHECK(z > 0.05);
  CHECK(z < 1.0);
  ControlNet AP;
  sim.stencil().applyMoving(sim.current(), AP);
  CHECK((AP - sim.loadVector()).norm() < 1e-8);
}

TEST_CASE("Simulation: energy is conserved without damping and load", "[core]") {
  for (Integrator integ : {Integrator::Explicit, Integrator::Implicit}) {
    ModelParameters p = paperParams(8);
    p.damping = 0.0;
    p.integrator = integ;
    Simulation probe(p);
    p.timeStep = 0.05 * probe.stabilityLimit();
    Simulation sim(p);
    ControlNet bumped = sim.rest();
    for (Eigen::Index f = 0; f < sim.space().numMoving(); ++f) {
      const Eigen::Index r = sim.space().movingToNet(f);
      bumped(r, 2) = std::sin(3.14159 * bumped(r, 0)) * std::sin(3.14159 * bumped(r, 1)) * 0.2;
    }
    sim.setState(bumped, bumped, 0.0, 0);
    const double e0 = sim.strainEnergy().total;
    REQUIRE(e0 > 0.0);
    double lo = 1e300, hi = 0.0;
    for (int i = 0; i < 2000; ++i) {
      sim.step();
      const double e = sim.strainEnergy().total + sim.kineticEnergy();
      lo = std::min(lo, e);
      hi = std::max(hi, e);
    }
    INFO("integrator " << int(integ) << " energy range " << lo << " .. " << hi << " initial " << e0);
    CHECK(lo > 0.9 * e0);
    CHECK(hi < 1.1 * e0);
  }
}

TEST_CASE("Simulation: strain energy terms add up and match 1/2 D^T A D", "[core]") {
  ModelParameters p = paperParams(6);
  Simulation sim(p);
  sim.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(3, 4, 20)));
  sim.advance(30);
  const StrainEnergy e = sim.strainEnergy();
  CHECK(e.total == Approx(e.w10 + e.w01 + e.w11 + e.w20 + e.w02));
  const ControlNet D = sim.space().gatherMoving(sim.current() - sim.rest());
  const double ref = 0.5 * D.cwiseProduct(ControlNet(sim.stencil().movingMatrix() * D)).sum();
  CHECK(e.total == Approx(ref).epsilon(1e-12));
  CHECK(e.w10 > 0.0);
  CHECK(e.w02 > 0.0);
}

TEST_CASE("Simulation: a non-planar rest net is an equilibrium (reference Rest), not for Absolute", "[core]") {
  ModelParameters p = paperParams(6);
  SplineSpace s(p.degreeU, p.degreeV, p.numU, p.numV);
  ControlNet rest = s.grevillePlane();
  for (Eigen::Index i = 0; i < rest.rows(); ++i) rest(i, 2) = 0.3 * rest(i, 0) * rest(i, 0) - 0.2 * rest(i, 1);
  Simulation relative(p, rest);
  relative.advance(100);
  CHECK(maxDiff(relative.current(), rest) < 1e-12);
  p.reference = ElasticReference::Absolute;
  Simulation absolute(p, rest);
  absolute.advance(100);
  CHECK(maxDiff(absolute.current(), rest) > 1e-3);
}

TEST_CASE("Simulation: invalid parameters throw with the parameter and the value", "[core]") {
  auto bad = [](auto mutate) {
    ModelParameters p;
    mutate(p);
    return p;
  };
  CHECK_THROWS_WITH(Simulation(bad([](ModelParameters& p) { p.degreeU = 0; })), Catch::Contains("degreeU") && Catch::Contains("0"));
  CHECK_THROWS_WITH(Simulation(bad([](ModelParameters& p) { p.degreeV = 8; })), Catch::Contains("degreeV") && Catch::Contains("8"));
  CHECK_THROWS_WITH(Simulation(bad([](ModelParameters& p) { p.numU = 0; })), Catch::Contains("numU") && Catch::Contains("0"));
  CHECK_THROWS_WITH(Simulation(bad([](ModelParameters& p) { p.timeStep = 0.0; })), Catch::Contains("timeStep") && Catch::Contains("0"));
  CHECK_THROWS_WITH(Simulation(bad([](ModelParameters& p) { p.timeStep = -0.5; })), Catch::Contains("timeStep") && Catch::Contains("-0.5"));
  CHECK_THROWS_WITH(Simulation(bad([](ModelParameters& p) { p.timeStep = NAN; })), Catch::Contains("timeStep") && Catch::Contains("nan"));
  CHECK_THROWS_WITH(Simulation(bad([](ModelParameters& p) { p.mass = -1.0; })), Catch::Contains("mass") && Catch::Contains("-1"));
  CHECK_THROWS_WITH(Simulation(bad([](ModelParameters& p) { p.damping = -2.0; })), Catch::Contains("damping") && Catch::Contains("-2"));
  CHECK_THROWS_WITH(Simulation(bad([](ModelParameters& p) { p.weights.w20 = NAN; })), Catch::Contains("w20") && Catch::Contains("nan"));
  ModelParameters p;
  SplineSpace s(p.degreeU, p.degreeV, p.numU, p.numV);
  ControlNet rest = s.grevillePlane();
  rest(7, 1) = NAN;
  CHECK_THROWS_WITH(Simulation(p, rest), Catch::Contains("rest net point 7") && Catch::Contains("nan"));
  CHECK_THROWS_WITH(Simulation(p, ControlNet::Zero(10, 3)), Catch::Contains("rest net") && Catch::Contains("got 10"));
  Simulation sim(p);
  ControlNet moved = sim.rest();
  moved(0, 2) = 1.0;  // a fixed point
  CHECK_THROWS_WITH(sim.setState(moved, moved, 0.0, 0), Catch::Contains("clamped control point"));
}

TEST_CASE("Simulation: a stiff penalty force is included in the stability limit, safely and sharply", "[core]") {
  // elastic foundation f = -k z per unit area: its load Jacobian is -k times the Gram matrix
  ModelParameters p = paperParams(10);
  const double k = 2e4;
  Simulation sim(p);
  const double limitAlone = sim.stabilityLimit();
  sim.addForce(std::make_shared<DistributedForce>(
      [k](const SurfaceSample& s) { return Eigen::Vector3d(0, 0, -k * s.position.z()); }, kDependsOnPosition, ParamRect{}, 2, k));
  const SplineSpace& s = sim.space();
  const std::vector<double> g0 = cardinalGram(3, 0);
  const int N = p.numU;
  Eigen::MatrixXd K = Eigen::MatrixXd(sim.stencil().movingMatrix());
  const double area = s.basisU().spacing() * s.basisV().spacing();
  for (int a = 0; a < N; ++a)
    for (int b = 0; b < N; ++b)
      for (int c = 0; c < N; ++c)
        for (int d = 0; d < N; ++d) {
          const int d1 = std::abs(a - c), d2 = std::abs(b - d);
          if (d1 <= 3 && d2 <= 3) K(a * N + b, c * N + d) += k * area * g0[d1] * g0[d2];
        }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(K, Eigen::EigenvaluesOnly);
  const double trueLimit = 2.0 / std::sqrt(eig.eigenvalues().maxCoeff() / p.mass);
  INFO("limit " << sim.stabilityLimit() << ", true " << trueLimit << ", without the force " << limitAlone);
  CHECK(sim.stabilityLimit() <= trueLimit);
  CHECK(sim.stabilityLimit() >= 0.5 * trueLimit);
  CHECK(sim.stabilityLimit() < 0.5 * limitAlone);
  sim.advance(200);
  CHECK(sim.status() == Status::Ok);
}

TEST_CASE("Simulation: a step needing more sub-steps than maxSubSteps is refused, in any magnitude", "[core]") {
  // timeStep 1e12, w20 1e300 and mass 1e-300 need more sub-steps than an int holds: before the
  // cap the count overflowed (undefined behaviour) and the surface silently did not move.
  for (int variant = 0; variant < 4; ++variant) {
    ModelParameters p = paperParams(6);
    if (variant == 0) p.timeStep = 1e12;
    if (variant == 1) p.weights.w20 = 1e300;
    if (variant == 2) p.mass = 1e-300;
    if (variant == 3) p.timeStep = 1e8;
    Simulation sim(p);
    sim.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, 1)));
    INFO("variant " << variant);
    CHECK(sim.subStepsNeeded() > 1e4);
    CHECK(sim.subSteps() == p.maxSubSteps);  // a valid int, never a wrapped one
    const ControlNet before = sim.current();
    CHECK(sim.refusal().find("maxSubSteps = 10000") != std::string::npos);
    CHECK(sim.step() == Status::Refused);
    CHECK(sim.statusMessage().find("sub-steps") != std::string::npos);
    CHECK(sim.current() == before);
    CHECK(sim.time() == 0.0);
    CHECK(sim.stepCount() == 0);
  }
  // the cap is a parameter: raised above what is needed, the same step runs sub-stepped
  ModelParameters p = paperParams(6);
  p.timeStep = 100.0;
  Simulation probe(p);
  const double needed = probe.subStepsNeeded();
  REQUIRE(needed > 10.0);
  REQUIRE(needed < 1000.0);
  p.maxSubSteps = int(needed) - 1;
  CHECK(Simulation(p).step() == Status::Refused);
  p.maxSubSteps = int(needed);
  Simulation ok(p);
  CHECK(ok.refusal().empty());
  CHECK(ok.step() == Status::Ok);
  CHECK(ok.subSteps() == int(needed));
  p.maxSubSteps = 0;
  CHECK_THROWS_WITH(Simulation(p), Catch::Contains("maxSubSteps must be >= 1, got 0"));
}

TEST_CASE("Simulation: a time at which the step no longer advances the clock is refused", "[core]") {
  Simulation sim(paperParams(6));
  sim.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, 1)));
  const ControlNet net = sim.current();
  // 1e17 + 0.1 == 1e17: before, the runner looped forever
  sim.setState(net, net, 1e17, 5);
  CHECK(sim.refusal().find("no longer advances the clock") != std::string::npos);
  CHECK(sim.step() == Status::Refused);
  CHECK(sim.time() == 1e17);
  CHECK(sim.stepCount() == 5);
  // 1e13 + 0.1 rounds the step by about 2e-3 * 0.1: refused too (the tolerance is 1e-4 dt)
  Simulation coarse(paperParams(6));
  coarse.setState(net, net, 1e13, 0);
  CHECK_FALSE(coarse.refusal().empty());
  // 1e9 still advances by 0.1 to within 1e-7 relative: runs
  Simulation late(paperParams(6));
  late.setState(net, net, 1e9, 0);
  CHECK(late.refusal().empty());
  CHECK(late.step() == Status::Ok);
  CHECK(late.time() > 1e9);
  // reset gives the clock back
  sim.reset();
  CHECK(sim.step() == Status::Ok);
}


TEST_CASE("Simulation: the explicit step on 2 or 3 threads gives the same bits as on one", "[core]") {
  // Blocks of interior rows run on several threads; every point's arithmetic is the same, so
  // the trajectories must agree exactly, band (FREE sides) and wrap included.
  using B = Boundary;
  const Boundaries cases[] = {Boundaries{}, Boundaries{B::Free, B::Free, B::Free, B::Free},
                              Boundaries{B::Periodic, B::Periodic, B::Free, B::Clamped}};
  const ThreadSettingsGuard restore;
  for (const Boundaries& bc : cases) {
    ModelParameters p = paperParams(0);
    p.numU = 41;  // rows not a multiple of the thread count
    p.numV = 29;
    p.boundaries = bc;
    p.massModel = MassModel::Lumped;
    p.timeStep = 1e-3;
    auto run = [&](int t) {
      setKernelThreads(t);
      setExplicitParallelMinPoints(0);  // split at this size too
      const SplineSpace space(p.degreeU, p.degreeV, p.numU, p.numV, bc);
      Simulation sim(p, shapeRestNet(bc.uMin == B::Periodic ? ShapeKind::Cylinder : ShapeKind::Plane, ShapeSize(), space));
      sim.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0.2, -0.1, 30.0), ParamRect{0.2, 0.7, 0.1, 0.8}));
      sim.addForce(std::make_shared<PointForce>(0.61, 0.27, Eigen::Vector3d(0.0, 0.4, -1.0)));
      sim.advance(30);
      REQUIRE(sim.status() == Status::Ok);
      REQUIRE((sim.current() - sim.rest()).cwiseAbs().maxCoeff() > 1e-6);  // it moved
      return std::make_pair(sim.current(), sim.previous());
    };
    const auto one = run(1), two = run(2), three = run(3);
    INFO("boundaries " << boundaryName(bc.uMin) << "/" << boundaryName(bc.vMin));
    CHECK(std::memcmp(one.first.data(), two.first.data(), sizeof(double) * one.first.size()) == 0);
    CHECK(std::memcmp(one.second.data(), two.second.data(), sizeof(double) * one.second.size()) == 0);
    CHECK(std::memcmp(one.first.data(), three.first.data(), sizeof(double) * one.first.size()) == 0);
  }
}

TEST_CASE("Simulation: the implicit step on 2 or 3 threads gives the same bits as on one", "[core]") {
  // applyMoving() splits its rows like the explicit step; the implicit system's products (CG,
  // multigrid smoothing) go through it, so every solver's trajectory must agree exactly.
  using B = Boundary;
  const ThreadSettingsGuard restore;
  const struct {
    Boundaries bc;
    LinearSolver solver;
  } cases[] = {{Boundaries{}, LinearSolver::Multigrid},
               {Boundaries{B::Free, B::Clamped, B::Free, B::Clamped}, LinearSolver::ConjugateGradient},
               {Boundaries{B::Periodic, B::Periodic, B::Free, B::Clamped}, LinearSolver::Multigrid}};
  for (const auto& c : cases) {
    ModelParameters p = paperParams(0);
    p.numU = 41;  // rows not a multiple of the thread count
    p.numV = 37;
    p.boundaries = c.bc;
    p.integrator = Integrator::Implicit;
    p.implicitSolver = c.solver;
    p.timeStep = 0.05;
    auto run = [&](int t) {
      setKernelThreads(t);
      setExplicitParallelMinPoints(0);  // split at this size too
      const SplineSpace space(p.degreeU, p.degreeV, p.numU, p.numV, c.bc);
      Simulation sim(p, shapeRestNet(c.bc.uMin == B::Periodic ? ShapeKind::Cylinder : ShapeKind::Plane, ShapeSize(), space));
      sim.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0.2, -0.1, 30.0), ParamRect{0.2, 0.7, 0.1, 0.8}));
      sim.advance(5);
      REQUIRE(sim.status() == Status::Ok);
      REQUIRE((sim.current() - sim.rest()).cwiseAbs().maxCoeff() > 1e-6);  // it moved
      return sim.current();
    };
    const ControlNet one = run(1), two = run(2), three = run(3);
    INFO("boundaries " << boundaryName(c.bc.uMin) << "/" << boundaryName(c.bc.vMin));
    CHECK(std::memcmp(one.data(), two.data(), sizeof(double) * one.size()) == 0);
    CHECK(std::memcmp(one.data(), three.data(), sizeof(double) * one.size()) == 0);
  }
}
