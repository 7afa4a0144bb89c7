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

#include "bsdeform/ImplicitSystem.h"
#include "bsdeform/Multigrid.h"
#include "bsdeform/RestShape.h"
#include "bsdeform/Simulation.h"

using namespace bsdeform;

namespace {

struct Case {
  std::string name;
  Boundaries sides;
  bool lumped;
  std::vector<Eigen::Vector2d> pins;
};

const Boundary C = Boundary::Clamped, F = Boundary::Free, P = Boundary::Periodic;

std::vector<Case> cases() {
  return {{"clamped", {C, C, C, C}, false, {}},
          {"curtain (three free sides), lumped", {F, F, F, C}, true, {}},
          {"all free, lumped", {F, F, F, F}, true, {}},
          {"tube (u periodic)", {P, P, C, C}, false, {}},
          {"torus, lumped", {P, P, P, P}, true, {}},
          {"free with pins", {F, F, C, F}, false, {{0.3, 0.6}, {0.9, 0.1}, {0.0, 0.5}}}};
}

// K as the dense matrix the system stands for: D + A_II/4 with pinned rows and columns reduced
// to D.
Eigen::MatrixXd denseK(const StiffnessStencil& st, const Eigen::VectorXd& D, const std::vector<Eigen::Index>& pinned) {
  Eigen::MatrixXd K = 0.25 * Eigen::MatrixXd(st.movingMatrix());
  for (Eigen::Index f : pinned) {
    K.row(f).setZero();
    K.col(f).setZero();
  }
  K.diagonal() += D;
  return K;
}

std::vector<Eigen::Index> pinnedMoving(const SplineSpace& s, const std::vector<Eigen::Vector2d>& pins) {
  std::vector<Eigen::Index> out;
  for (const Eigen::Vector2d& pin : pins) {
    const int su = s.basisU().span(pin.x()), sv = s.basisV().span(pin.y());
    for (int k1 = su - s.degreeU(); k1 <= su; ++k1)
      for (int k2 = sv - s.degreeV(); k2 <= sv; ++k2) {
        const Eigen::Index m = s.movingIndex(k1, k2);
        if (m >= 0 && std::find(out.begin(), out.end(), m) == out.end()) out.push_back(m);
      }
  }
  return out;
}

// A mass term like the simulation's: nodal (constant) or lumped (rho times the row sums, smaller
// at a free edge), over dt^2, plus damping.
Eigen::VectorXd massTerm(const SplineSpace& s, const StiffnessStencil& st, bool lumped, double dt) {
  Eigen::VectorXd D(s.numMoving());
  for (Eigen::Index f = 0; f < s.numMoving(); ++f) {
    const Eigen::Index r = s.movingToNet(f);
    const int i = int(r / s.netCols()), j = int(r % s.netCols());
    const double m = lumped ? st.gramU().rowSum(st.gramU().rowType(i)) * st.gramV().rowSum(st.gramV().rowType(j)) : 1.0;
    D[f] = m / (dt * dt) + 0.3 * m / (2 * dt);
  }
  return D;
}

double relativeError(const ControlNet& x, const Eigen::MatrixXd& ref) { return (x - ref).norm() / ref.norm(); }

}  // namespace

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

TEST_CASE("Multigrid: the Kronecker operator is K, and the V-cycle is symmetric positive definite, every boundary kind",
          "[core]") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> X(-1.0, 1.0);
  auto random = [&](Eigen::Index n) {
    ControlNet v(n, 3);
    for (Eigen::Index i = 0; i < v.size(); ++i) v.data()[i] = X(rng);
    return v;
  };
  // even sizes halve exactly; odd ones give a periodic direction its overlapping last coarse
  // function and a free or clamped one an uneven end
  for (const auto& [nu, nv] : {std::pair{56, 48}, std::pair{57, 49}})
  for (const Case& c : cases()) {
    const SplineSpace s(3, 2, nu, nv, c.sides);
    const StiffnessStencil st(s, Weights{0.5, 0.3, 0.05, 0.02, 0.04});
    const Eigen::VectorXd D = massTerm(s, st, c.lumped, c.lumped ? 0.01 : 0.1);
    INFO(c.name << ", " << nu << " x " << nv << ", " << s.numMoving() << " moving points");
    MultigridPreconditioner mg(s, st, st.weights(), D);
    CHECK(mg.levels() >= 3);
    for (int l = 1; l < mg.levels(); ++l) CHECK(mg.levelPoints(l) < mg.levelPoints(l - 1));

    // K~ (no pins: the separable mass fit is exact for nodal and for lumped mass of one density)
    const Eigen::MatrixXd K = denseK(st, D, {});
    const ControlNet x = random(s.numMoving()), y = random(s.numMoving());
    ControlNet Kx;
    mg.applyOperator(x, Kx);
    const Eigen::MatrixXd ref = K * Eigen::MatrixXd(x);
    CHECK((Kx - ref).norm() <= 1e-13 * ref.norm());

    // B = one V-cycle: x.By = y.Bx, x.Bx > 0, and B K is close to the identity on a smooth and a
    // rough vector (a useless preconditioner, e.g. a wrong coarse operator, fails this)
    ControlNet Bx, By;
    mg.apply(x, Bx);
    mg.apply(y, By);
    const double xBy = (x.array() * By.array()).sum(), yBx = (y.array() * Bx.array()).sum();
    CHECK(std::abs(xBy - yBx) <= 1e-12 * x.norm() * By.norm());
    CHECK((x.array() * Bx.array()).sum() > 0.0);
    ControlNet smooth(s.numMoving(), 3);
    for (Eigen::Index f = 0; f < s.numMoving(); ++f)
      smooth.row(f) << std::sin(0.05 * double(f)), 1.0, std::cos(0.01 * double(f));
    for (const ControlNet& v : {x, smooth}) {
      ControlNet Kv, BKv;
      mg.applyOperator(v, Kv);
      mg.apply(Kv, BKv);
      CHECK((BKv - v).norm() <= 0.6 * v.norm());
    }
  }
}

TEST_CASE("Multigrid: conjugate gradients with the V-cycle solve K x = b on multi-level nets with pins", "[core]") {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> X(-1.0, 1.0);
  for (const auto& [nu, nv] : {std::pair{30, 26}, std::pair{31, 27}})
  for (const Case& c : cases()) {
    const SplineSpace s(3, 3, nu, nv, c.sides);
    const StiffnessStencil st(s, Weights{});
    const Eigen::VectorXd D = massTerm(s, st, c.lumped, c.lumped ? 0.01 : 0.1);
    const std::vector<Eigen::Index> pinned = pinnedMoving(s, c.pins);
    const Eigen::MatrixXd K = denseK(st, D, pinned);
    ControlNet b(s.numMoving(), 3);
    for (Eigen::Index i = 0; i < b.size(); ++i) b.data()[i] = X(rng);
    const Eigen::MatrixXd ref = K.llt().solve(Eigen::MatrixXd(b));
    ImplicitSystem mg(s, st, D, pinned, LinearSolver::Multigrid, 1e-11, 200);
    ControlNet x = ControlNet::Zero(s.numMoving(), 3);
    REQUIRE(mg.solve(b, x));
    INFO(c.name << ", " << nu << " x " << nv << ": " << mg.lastIterations() << " iterations, " << pinned.size()
                << " pinned");
    CHECK(mg.lastIterations() <= 12);  // 5-7 when written
    CHECK(relativeError(x, ref) <= mg.conditionBound() * 1e-11);
  }
}

TEST_CASE("Multigrid: the iteration count grows far slower than Jacobi-CG's as the net grows", "[core]") {
  std::vector<int> mgIterations, cgIterations;
  for (int N : {32, 64, 128}) {
    const SplineSpace s(3, 3, N, N);
    const StiffnessStencil st(s, Weights{});
    const Eigen::VectorXd D = massTerm(s, st, false, 0.5);  // a long step: kappa grows like N^2
    ControlNet b(s.numMoving(), 3);
    std::mt19937 rng(N);
    std::uniform_real_distribution<double> X(-1.0, 1.0);
    for (Eigen::Index i = 0; i < b.size(); ++i) b.data()[i] = X(rng);
    for (LinearSolver kind : {LinearSolver::Multigrid, LinearSolver::ConjugateGradient}) {
      ImplicitSystem sys(s, st, D, {}, kind, 1e-10, 5000);
      ControlNet x = ControlNet::Zero(s.numMoving(), 3);
      REQUIRE(sys.solve(b, x));
      (kind == LinearSolver::Multigrid ? mgIterations : cgIterations).push_back(sys.lastIterations());
    }
  }
  INFO("multigrid " << mgIterations[0] << ", " << mgIterations[1] << ", " << mgIterations[2] << "; Jacobi-CG "
                    << cgIterations[0] << ", " << cgIterations[1] << ", " << cgIterations[2]);
  // Jacobi-CG follows sqrt(kappa) ~ N; the V-cycle's count grows by far less (not flat: B-spline
  // multigrid with point smoothers is known to lose some efficiency as the stiffness dominates;
  // without the coarse correction it would grow like Jacobi-CG's). The increments are compared
  // (6, 10, 14 against 24, 44, 84 when written): the ratio of counts would mostly measure the
  // first count.
  CHECK(cgIterations[2] > 3 * cgIterations[0]);
  CHECK(mgIterations[2] - mgIterations[0] < 0.2 * (cgIterations[2] - cgIterations[0]));
  CHECK(mgIterations[2] <= 15);
}
