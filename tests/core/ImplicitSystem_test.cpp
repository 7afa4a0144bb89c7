// SPDX-License-Identifier: MIT
// The implicit scheme's linear system K = D + A_act/4 (ImplicitSystem): CHOLMOD and conjugate
// gradients against a dense solve for every boundary kind, pins and lumped mass; the CG
// tolerance bounds the error (and looser tolerances give larger errors); whole implicit runs
// with CG agree with runs with CHOLMOD.
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <random>
#include <string>

#include "ImplicitCases.h"
#include "bsdeform/dynamics/ImplicitSystem.h"
#include "bsdeform/spline/RestShape.h"
#include "bsdeform/dynamics/Simulation.h"

using namespace bsdeform;
using namespace bsdeform::test;

TEST_CASE("ImplicitSystem: CHOLMOD and CG solve K x = b like a dense solve, every boundary kind, pins, lumped mass",
          "[core]") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> X(-1.0, 1.0);
  for (const Case& c : cases()) {
    const SplineSpace s(3, 2, 9, 7, c.sides);
    const StiffnessStencil st(s, Weights{0.5, 0.3, 0.05, 0.02, 0.04});
    const double dt = c.lumped ? 0.01 : 0.1;
    const Eigen::VectorXd D = massTerm(s, st, c.lumped, dt);
    const std::vector<Eigen::Index> pinned = pinnedMoving(s, c.pins);
    const Eigen::MatrixXd K = denseK(st, D, pinned);
    ControlNet b(s.numMoving(), 3);
    for (Eigen::Index i = 0; i < b.size(); ++i) b.data()[i] = X(rng);
    const Eigen::MatrixXd ref = K.llt().solve(Eigen::MatrixXd(b));
    INFO(c.name << ", " << s.numMoving() << " moving points, " << pinned.size() << " pinned");

    ImplicitSystem direct(s, st, D, pinned, LinearSolver::Direct, 1e-10, 1000);
    REQUIRE(direct.method() == LinearSolver::Direct);
    ControlNet x;
    REQUIRE(direct.solve(b, x));
    CHECK(relativeError(x, ref) <= 1e-12);

    // the matrix-free product is this K
    ControlNet y;
    ImplicitSystem cg(s, st, D, pinned, LinearSolver::ConjugateGradient, 1e-12, 1000);
    REQUIRE(cg.method() == LinearSolver::ConjugateGradient);
    cg.apply(b, y);
    CHECK((y - K * Eigen::MatrixXd(b)).norm() <= 1e-13 * (K * Eigen::MatrixXd(b)).norm());
    // K's condition number is below the bound used to choose the solver
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(K);
    const double kappa = eig.eigenvalues().maxCoeff() / eig.eigenvalues().minCoeff();
    CHECK(kappa <= cg.conditionBound());

    x = ControlNet::Zero(s.numMoving(), 3);
    REQUIRE(cg.solve(b, x));
    CHECK(cg.lastIterations() > 0);
    CHECK(cg.lastResidual() <= 1e-12);
    for (int col = 0; col < 3; ++col)  // |e| / |x| <= kappa |r| / |b| in every coordinate
      CHECK((x.col(col) - ref.col(col)).norm() <= kappa * 1e-12 * ref.col(col).norm());

    // the same with the multigrid preconditioner
    ImplicitSystem mg(s, st, D, pinned, LinearSolver::Multigrid, 1e-12, 1000);
    REQUIRE(mg.method() == LinearSolver::Multigrid);
    x = ControlNet::Zero(s.numMoving(), 3);
    REQUIRE(mg.solve(b, x));
    CHECK(mg.lastResidual() <= 1e-12);
    for (int col = 0; col < 3; ++col)
      CHECK((x.col(col) - ref.col(col)).norm() <= kappa * 1e-12 * ref.col(col).norm());
  }
}

TEST_CASE("ImplicitSystem: the CG tolerance controls the error", "[core]") {
  // lumped mass and a small dt: kappa ~ 10^3, many iterations
  const SplineSpace s(3, 3, 20, 20, Boundaries{F, C, C, F});
  const StiffnessStencil st(s, Weights{});
  const Eigen::VectorXd D = massTerm(s, st, true, 0.05);
  const Eigen::MatrixXd K = denseK(st, D, {});
  // a smooth right-hand side (a load) and a rough one
  ControlNet b(s.numMoving(), 3);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> X(-1.0, 1.0);
  for (Eigen::Index f = 0; f < s.numMoving(); ++f) b.row(f) << 1.0, std::sin(0.3 * f), X(rng);
  const Eigen::MatrixXd ref = K.llt().solve(Eigen::MatrixXd(b));
  ImplicitSystem probe(s, st, D, {}, LinearSolver::ConjugateGradient, 1e-6, 100000);
  const double kappa = probe.conditionBound();
  REQUIRE(kappa > 100.0);

  double previousError = 1.0;
  int previousIterations = 0;
  std::vector<double> errors;
  for (double tol : {1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12}) {
    ImplicitSystem cg(s, st, D, {}, LinearSolver::ConjugateGradient, tol, 100000);
    ControlNet x = ControlNet::Zero(s.numMoving(), 3);
    REQUIRE(cg.solve(b, x));
    const double err = relativeError(x, ref);
    INFO("tolerance " << tol << ": " << cg.lastIterations() << " iterations, residual " << cg.lastResidual()
                      << ", error " << err);
    CHECK(cg.lastResidual() <= tol);
    for (int col = 0; col < 3; ++col) CHECK((x.col(col) - ref.col(col)).norm() <= kappa * tol * ref.col(col).norm());
    CHECK(cg.lastIterations() > previousIterations);
    CHECK(err < previousError);
    previousError = err;
    previousIterations = cg.lastIterations();
    errors.push_back(err);
  }
  // a loose tolerance stops early: its error is far above what the tight ones reach
  CHECK(errors.front() > 1e-6);
  CHECK(errors.front() > 1e6 * errors.back());
}

TEST_CASE("ImplicitSystem: Automatic factorises small or ill-conditioned systems and iterates on large ones "
          "(multigrid for the hardest)",
          "[core]") {
  auto method = [](int N, MassModel mass) {
    ModelParameters p;
    p.numU = p.numV = N;
    p.integrator = Integrator::Implicit;
    p.massModel = mass;
    Simulation sim(p);
    return sim.implicitSystem()->method();
  };
  CHECK(method(8, MassModel::Nodal) == LinearSolver::Direct);
  CHECK(method(80, MassModel::Nodal) == LinearSolver::ConjugateGradient);
  CHECK(method(80, MassModel::Lumped) == LinearSolver::Direct);  // kappa ~ 6e3: ~950 predicted iterations
  // a longer step makes the mass term smaller: kappa and the predicted Jacobi-CG iterations grow
  ModelParameters q;
  q.numU = q.numV = 80;
  q.integrator = Integrator::Implicit;
  q.timeStep = 1.0;
  Simulation slow(q);
  INFO("predicted Jacobi-CG iterations " << slow.implicitSystem()->predictedIterations());
  CHECK(slow.implicitSystem()->predictedIterations() > kAutomaticMultigridIterations);
  CHECK(slow.implicitSystem()->predictedIterations() <= kAutomaticIterationLimit);
  CHECK(slow.implicitSystem()->method() == LinearSolver::Multigrid);
  // an ill-conditioned system too large to factorise quickly: multigrid
  ModelParameters big;
  big.numU = big.numV = 304;
  big.integrator = Integrator::Implicit;
  big.massModel = MassModel::Lumped;
  Simulation large(big);
  CHECK(large.implicitSystem()->predictedIterations() > kAutomaticIterationLimit);
  CHECK(large.implicitSystem()->method() == LinearSolver::Multigrid);
  ModelParameters p;
  p.integrator = Integrator::Explicit;
  CHECK(Simulation(p).implicitSystem() == nullptr);
}

TEST_CASE("Simulation: implicit runs with CG and multigrid agree with runs with CHOLMOD for every boundary kind",
          "[core]") {
  for (const Case& c : cases()) {
    auto run = [&](LinearSolver solver) {
      ModelParameters p;
      p.numU = 10;
      p.numV = 8;
      p.degreeV = 2;
      p.boundaries = c.sides;
      p.pins = c.pins;
      p.massModel = c.lumped ? MassModel::Lumped : MassModel::Nodal;
      p.timeStep = c.lumped ? 0.01 : 0.1;
      p.integrator = Integrator::Implicit;
      p.implicitSolver = solver;
      p.solverTolerance = 1e-12;
      const SplineSpace s(p.degreeU, p.degreeV, p.numU, p.numV, c.sides);
      const bool closed = s.periodicU() || s.periodicV();
      const ShapeKind kind = s.periodicU() && s.periodicV() ? ShapeKind::Torus : ShapeKind::Cylinder;
      auto sim = closed ? std::make_unique<Simulation>(p, shapeRestNet(kind, ShapeSize(), s))
                        : std::make_unique<Simulation>(p);
      REQUIRE(sim->implicitSystem()->method() == solver);
      sim->addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0.3, -0.5, 2.0), ParamRect{0.2, 0.7, 0.1, 0.6}));
      sim->addForce(std::make_shared<PointForce>(0.8, 0.3, Eigen::Vector3d(0, 0, -1.5)));
      sim->advance(40);
      REQUIRE(sim->status() == Status::Ok);
      return ControlNet(sim->current() - sim->rest());
    };
    const ControlNet direct = run(LinearSolver::Direct), cg = run(LinearSolver::ConjugateGradient),
                     mg = run(LinearSolver::Multigrid);
    INFO(c.name << ": largest displacement " << direct.cwiseAbs().maxCoeff());
    CHECK(direct.cwiseAbs().maxCoeff() > 1e-3);  // something moved
    CHECK((cg - direct).cwiseAbs().maxCoeff() <= 1e-9 * direct.cwiseAbs().maxCoeff());
    CHECK((mg - direct).cwiseAbs().maxCoeff() <= 1e-9 * direct.cwiseAbs().maxCoeff());
  }
}

TEST_CASE("Simulation: a CG solve that does not converge fails the step and keeps the last state", "[core]") {
  ModelParameters p;
  p.numU = p.numV = 12;
  p.integrator = Integrator::Implicit;
  p.implicitSolver = LinearSolver::ConjugateGradient;
  p.solverTolerance = 1e-12;
  p.maxSolverIterations = 2;
  Simulation sim(p);
  sim.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, 5)));
  CHECK(sim.step() == Status::Diverged);
  CHECK_THAT(sim.statusMessage(), Catch::Contains("conjugate gradients stopped") && Catch::Contains("after 2 iterations"));
  CHECK((sim.current() - sim.rest()).cwiseAbs().maxCoeff() == 0.0);
  CHECK_THROWS_WITH([] {
    ModelParameters q;
    q.solverTolerance = 1.0;
    Simulation s(q);
  }(), Catch::Contains("solverTolerance"));
}
