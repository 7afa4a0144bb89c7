// SPDX-License-Identifier: MIT
// Free and periodic sides, pins and the start rule: the operator against brute-force quadrature
// for every combination of side conditions, and analytic properties of the dynamics.
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <random>

#include "bsdeform/spline/GaussLegendre.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/energy/StiffnessStencil.h"

using namespace bsdeform;

namespace {
constexpr double kPi = 3.14159265358979323846;

// The five side pairs of one direction.
const std::pair<Boundary, Boundary> kSidePairs[] = {{Boundary::Clamped, Boundary::Clamped},
                                                    {Boundary::Clamped, Boundary::Free},
                                                    {Boundary::Free, Boundary::Clamped},
                                                    {Boundary::Free, Boundary::Free},
                                                    {Boundary::Periodic, Boundary::Periodic}};

// y_m = dE/dP_m, E = a(S, S)/2 over [0,1]^2, by brute force: Gauss quadrature on every knot
// cell, each B-spline from the cardinal definition, S summed over every control point of the
// full net (periodic copies included); the derivative with respect to a moving point is the
// sum of a(B_k, S) over the B-splines k it stands for.
ControlNet bruteForceGradient(const SplineSpace& s, const Weights& w, const ControlNet& net) {
  const int n1 = s.degreeU(), n2 = s.degreeV(), R = s.netRows(), C = s.netCols();
  const double h1 = s.basisU().spacing(), h2 = s.basisV().spacing();
  const QuadratureRule& g1 = gaussLegendre(n1 + 2);
  const QuadratureRule& g2 = gaussLegendre(n2 + 2);
  ControlNet y = ControlNet::Zero(s.numMoving(), 3);
  std::vector<double> du[3], dv[3];
  for (int c1 = 0; c1 < s.basisU().numSpans(); ++c1)
    for (int c2 = 0; c2 < s.basisV().numSpans(); ++c2)
      for (size_t q1 = 0; q1 < g1.nodes.size(); ++q1)
        for (size_t q2 = 0; q2 < g2.nodes.size(); ++q2) {
          const double u = (c1 + g1.nodes[q1]) * h1, v = (c2 + g2.nodes[q2]) * h2;
          const double wq = g1.weights[q1] * g2.weights[q2] * h1 * h2;
          for (int p = 0; p < 3; ++p) {
            du[p].assign(R, 0.0);
            dv[p].assign(C, 0.0);
            for (int i = 0; i < R; ++i) du[p][i] = cardinalBSplineDerivative(n1, p, u / h1 - (i - n1)) * std::pow(h1, -p);
            for (int j = 0; j < C; ++j) dv[p][j] = cardinalBSplineDerivative(n2, p, v / h2 - (j - n2)) * std::pow(h2, -p);
          }
          // derivatives of S: D[(p, q)] = sum_j P_j D^p b_j1 D^q b_j2
          auto dS = [&](int p, int q) {
            Eigen::RowVector3d d = Eigen::RowVector3d::Zero();
            for (int i = 0; i < R; ++i)
              for (int j = 0; j < C; ++j) d += du[p][i] * dv[q][j] * net.row(Eigen::Index(i) * C + j);
            return d;
          };
          const Eigen::RowVector3d S10 = dS(1, 0), S01 = dS(0, 1), S11 = dS(1, 1), S20 = dS(2, 0), S02 = dS(0, 2);
          // chain rule: net layer (i, j) moves with the moving layers it folds onto (itself, the
          // point a periodic copy repeats, the sources of a derived point with their weights)
          for (int i = 0; i < R; ++i)
            for (int j = 0; j < C; ++j) {
              const Eigen::RowVector3d g = wq * (w.w10 * du[1][i] * dv[0][j] * S10 + w.w01 * du[0][i] * dv[1][j] * S01 +
                                                 2 * w.w11 * du[1][i] * dv[1][j] * S11 + w.w20 * du[2][i] * dv[0][j] * S20 +
                                                 w.w02 * du[0][i] * dv[2][j] * S02);
              for (const LayerWeight& fu : s.foldU(i))
                for (const LayerWeight& fv : s.foldV(j))
                  y.row(Eigen::Index(fu.layer - s.movingU().first) * s.movingV().count + (fv.layer - s.movingV().first)) +=
                      fu.weight * fv.weight * g;
            }
        }
  return y;
}

// A rest net that closes in every periodic direction: a u-periodic direction goes round the
// z axis, a v-periodic one round a circle in the (r, z) plane (a torus when both are).
ControlNet closedRest(const SplineSpace& s, double R = 1.0, double r = 0.35) {
  ControlNet net(s.netSize(), 3);
  const int Mu = s.numU() + s.degreeU(), Mv = s.numV() + s.degreeV();
  for (int k1 = -s.degreeU(); k1 < Mu; ++k1)
    for (int k2 = -s.degreeV(); k2 < Mv; ++k2) {
      const double a = 2 * kPi * k1 / Mu, b = 2 * kPi * k2 / Mv;
      const double gu = s.grevilleU(k1), gv = s.grevilleV(k2);
      Eigen::Vector3d p;
      if (s.periodicU() && s.periodicV())
        p << (R + r * std::cos(b)) * std::cos(a), (R + r * std::cos(b)) * std::sin(a), r * std::sin(b);
      else if (s.periodicU())
        p << R * std::cos(a), R * std::sin(a), gv;
      else if (s.periodicV())
        p << gu, R * std::cos(b), R * std::sin(b);
      else
        p << gu, gv, 0.0;
      net.row(s.netIndex(k1, k2)) = p.transpose();
    }
  return net;
}

double maxDiff(const ControlNet& a, const ControlNet& b) { return (a - b).cwiseAbs().maxCoeff(); }

// The stencil of space `s` with random weights on a random net (held points too: their coupling
// is part of the operator; derived layers made to follow their sources) against the brute-force
// gradient, and the assembled moving block: equal to the stencil on the net built from the
// unknowns alone, symmetric, its diagonal the one computed without assembly.
void checkOperator(const SplineSpace& s, std::mt19937& rng, double blockTolerance) {
  std::uniform_real_distribution<double> W(0.05, 2.0), X(-1.0, 1.0);
  const Weights w{W(rng), W(rng), W(rng), W(rng), W(rng)};
  const StiffnessStencil st(s, w);
  ControlNet net(s.netSize(), 3);
  for (Eigen::Index i = 0; i < net.rows(); ++i) net.row(i) << X(rng), X(rng), X(rng);
  s.completeNet(net, nullptr);
  ControlNet fast;
  st.applyMoving(net, fast);
  const ControlNet ref = bruteForceGradient(s, w, net);
  CHECK(maxDiff(fast, ref) <= 1e-10 * (1.0 + ref.cwiseAbs().maxCoeff()));
  ControlNet movingOnly = ControlNet::Zero(s.netSize(), 3);
  s.scatterMoving(s.gatherMoving(net), movingOnly);
  s.completeNet(movingOnly, nullptr);
  st.applyMoving(movingOnly, fast);
  const Eigen::SparseMatrix<double> A = st.movingMatrix();
  const double scale = 1.0 + Eigen::MatrixXd(A).cwiseAbs().maxCoeff();
  CHECK(maxDiff(fast, A * s.gatherMoving(net)) <= blockTolerance * (1.0 + fast.cwiseAbs().maxCoeff()));
  CHECK(Eigen::MatrixXd(A - Eigen::SparseMatrix<double>(A.transpose())).cwiseAbs().maxCoeff() <= blockTolerance * scale);
  CHECK((st.movingDiagonal() - Eigen::VectorXd(Eigen::MatrixXd(A).diagonal())).cwiseAbs().maxCoeff() <=
        blockTolerance * scale);
}
}  // namespace

TEST_CASE("Boundary: the operator equals a brute-force quadrature assembly for every side combination, degrees 1..5",
          "[core]") {
  std::mt19937 rng(3);
  int cases = 0;
  for (int n = 1; n <= 5; ++n)
    for (const auto& su : kSidePairs)
      for (const auto& sv : kSidePairs) {
        const int n2 = 1 + (n + cases) % 5;  // mixed degrees too
        const int N1 = 2 + cases % 3, N2 = 1 + (cases / 3) % 4;
        const SplineSpace s(n, n2, N1, N2, Boundaries{su.first, su.second, sv.first, sv.second});
        INFO("degrees " << n << "," << n2 << " N " << N1 << "," << N2 << " sides " << boundaryName(su.first) << "/"
                        << boundaryName(su.second) << " x " << boundaryName(sv.first) << "/" << boundaryName(sv.second));
        checkOperator(s, rng, 1e-12);
        ++cases;
      }
  CHECK(cases == 125);
}

TEST_CASE("Boundary: SIMPLY_SUPPORTED and BUILT_IN operators equal brute-force quadrature over the constrained space",
          "[core]") {
  // the gradient with respect to the unknowns of a(S, S)/2, S from the whole net: T^T of the
  // full gradient (the brute force folds each net layer's derivative onto the moving layers)
  const std::pair<Boundary, Boundary> edges[] = {{Boundary::SimplySupported, Boundary::SimplySupported},
                                                 {Boundary::BuiltIn, Boundary::BuiltIn},
                                                 {Boundary::SimplySupported, Boundary::Free},
                                                 {Boundary::BuiltIn, Boundary::Clamped},
                                                 {Boundary::Free, Boundary::BuiltIn},
                                                 {Boundary::BuiltIn, Boundary::SimplySupported}};
  std::mt19937 rng(5);
  int cases = 0;
  for (int n = 1; n <= 5; ++n)
    for (const auto& su : edges)
      for (int k = 0; k < 3; ++k) {
        // v sides: another new pair, an old pair, or the transpose case (new kinds in v only)
        const std::pair<Boundary, Boundary> sv =
            k == 0 ? edges[size_t(cases + 1) % 6] : k == 1 ? kSidePairs[size_t(cases) % 5] : su;
        const std::pair<Boundary, Boundary> uu = k == 2 ? kSidePairs[size_t(cases) % 5] : su;
        const int n2 = 1 + (n + cases) % 5;
        const int N1 = 3 + cases % 3, N2 = 3 + (cases / 3) % 3;
        const SplineSpace s(n, n2, N1, N2, Boundaries{uu.first, uu.second, sv.first, sv.second});
        INFO("degrees " << n << "," << n2 << " N " << N1 << "," << N2 << " sides " << boundaryName(uu.first) << "/"
                        << boundaryName(uu.second) << " x " << boundaryName(sv.first) << "/" << boundaryName(sv.second));
        checkOperator(s, rng, 1e-11);
        ++cases;
      }
}

TEST_CASE("Boundary: 1-D edge rows are truncated integrals and row sums add up to the integral of 1", "[core]") {
  for (int n = 1; n <= 7; ++n)
    for (int N : {1, 2, 9}) {
      const BSplineBasis1D basis(n, N);
      const GramRows1D g(basis, Boundary::Clamped, Boundary::Free);
      // partition of unity: the row sums over all N + 2n functions integrate 1 over [0,1]
      double total = 0.0;
      for (int layer = 0; layer < N + 2 * n; ++layer) total += g.rowSum(g.rowType(layer));
      CHECK(total == Approx(1.0).epsilon(1e-13));
      // mass rows: sum_j G^0(k, j) = int_0^1 b_k (partition of unity again)
      for (int layer = 0; layer < N + 2 * n; ++layer) {
        double row = 0.0;
        for (int d = -n; d <= n; ++d) row += g.entry(0, g.rowType(layer), d);
        CHECK(row == Approx(g.rowSum(g.rowType(layer))).epsilon(1e-12));
      }
      // the outermost function is only its last polynomial piece on [0, h]: int = h/(n+1)!
      double fact = 1.0;
      for (int i = 2; i <= n + 1; ++i) fact *= i;
      if (N >= n) CHECK(g.rowSum(g.rowType(0)) == Approx(basis.spacing() / fact).epsilon(1e-12));
    }
}

TEST_CASE("Boundary: a free surface under a uniform force accelerates rigidly, a = F_total / M_total", "[core]") {
  for (Integrator integ : {Integrator::Explicit, Integrator::Implicit}) {
    ModelParameters p;
    p.numU = 7;
    p.numV = 5;
    p.degreeV = 2;
    p.boundaries = Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free};
    p.massModel = MassModel::Lumped;
    p.mass = 2.0;
    p.damping = 0.0;
    p.timeStep = 0.01;
    p.integrator = integ;
    Simulation sim(p);
    const Eigen::Vector3d f(0.5, -1.0, 3.0);  // force per unit area on [0,1]^2: F_total = f
    sim.addForce(std::make_shared<DistributedForce>(f));
    // M_total = rho * sum of the row sums = rho (partition of unity)
    double mTotal = 0.0;
    for (Eigen::Index m = 0; m < sim.space().numMoving(); ++m) {
      const Eigen::Index r = sim.space().movingToNet(m);
      mTotal += sim.massAt(int(r / sim.space().netCols()), int(r % sim.space().netCols()));
    }
    CHECK(mTotal == Approx(p.mass).epsilon(1e-12));
    sim.advance(150);
    REQUIRE(sim.status() == Status::Ok);
    const double t = sim.time();
    const Eigen::RowVector3d shift = (0.5 * t * t / mTotal) * f.transpose();
    ControlNet expected = sim.rest();
    expected.rowwise() += shift;
    INFO("integrator " << int(integ) << " t " << t);
    CHECK(maxDiff(sim.current(), expected) <= 1e-11);
  }
}

TEST_CASE("Boundary: a curtain (one clamped side, three free) under gravity settles to the direct static solution",
          "[core]") {
  for (Integrator integ : {Integrator::Explicit, Integrator::Implicit}) {
    ModelParameters p;
    p.numU = p.numV = 6;
    p.weights = Weights{1.0, 1.0, 0.05, 0.05, 0.05};
    p.boundaries = Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Clamped};
    p.massModel = MassModel::Lumped;
    p.damping = 4.0;
    p.timeStep = 0.02;
    p.integrator = integ;
    Simulation sim(p);
    sim.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, -2.0)));
    const ControlNet equilibrium = sim.staticSolution();
    // independent residual: the elastic force A (P - P_rest) balances the load at every moving
    // point (with free edges the plane is not an equilibrium of the absolute energy: c0 != 0)
    ControlNet elastic, restForce;
    sim.stencil().applyMoving(equilibrium, elastic);
    sim.stencil().applyMoving(sim.rest(), restForce);
    CHECK(restForce.cwiseAbs().maxCoeff() > 1e-3);
    CHECK(maxDiff(elastic - restForce, sim.loadVector()) <= 1e-9 * sim.loadVector().cwiseAbs().maxCoeff());
    sim.advance(integ == Integrator::Explicit ? 4000 : 1500);
    REQUIRE(sim.status() == Status::Ok);
    INFO("integrator " << int(integ));
    CHECK(maxDiff(sim.current(), equilibrium) <= 1e-8 * (equilibrium - sim.rest()).cwiseAbs().maxCoeff());
    // the free edge opposite the clamped one hangs lowest
    CHECK(sim.evaluate(0.5, 0.0).position.z() < sim.evaluate(0.5, 0.5).position.z());
    CHECK(sim.evaluate(0.5, 1.0).position.z() == Approx(0.0).margin(1e-14));
  }
}

TEST_CASE("Boundary: a periodic surface under a load independent of u stays invariant under u-shifts", "[core]") {
  ModelParameters p;
  p.numU = 9;
  p.numV = 5;
  p.boundaries = Boundaries{Boundary::Periodic, Boundary::Periodic, Boundary::Free, Boundary::Clamped};
  p.damping = 0.2;
  p.timeStep = 0.05;
  const SplineSpace space(p.degreeU, p.degreeV, p.numU, p.numV, p.boundaries);
  Simulation sim(p, closedRest(space));
  // pressure along the normal (rotationally symmetric) and an axial load depending on v
  sim.addForce(std::make_shared<DistributedForce>(
      [](const SurfaceSample& s) { return Eigen::Vector3d(0.8 * s.normal + Eigen::Vector3d(0, 0, -0.5 * s.v)); },
      kDependsOnNormal));
  sim.advance(200);
  REQUIRE(sim.status() == Status::Ok);
  REQUIRE(sim.deformationNorm() > 0.05);
  // shifting k1 by one is a rotation by 2 pi / (N1 + n1) about z
  const int M = p.numU + p.degreeU;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(2 * kPi / M, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  double err = 0.0;
  for (int k1 = 0; k1 < M; ++k1)
    for (int k2 = -p.degreeV; k2 < p.numV + p.degreeV; ++k2) {
      const Eigen::Vector3d a = sim.current().row(space.netIndex(k1, k2)).transpose();
      const Eigen::Vector3d b = sim.current().row(space.netIndex((k1 + 1) % M, k2)).transpose();
      err = std::max(err, (R * a - b).cwiseAbs().maxCoeff());
    }
  CHECK(err <= 1e-12);
  // the seam is smooth: S and its u-derivative agree at u = 0 and u = 1
  for (double v : {0.1, 0.5, 0.9}) {
    const SurfacePoint a = sim.evaluate(0.0, v, 2), b = sim.evaluate(1.0, v, 2);
    CHECK((a.position - b.position).norm() <= 1e-13);
    CHECK((a.du - b.du).norm() <= 1e-12);
    CHECK((a.duu - b.duu).norm() <= 1e-10);
  }
}

TEST_CASE("Boundary: clamped sides and pins hold exactly after 1000 steps under random forces", "[core]") {
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> U(0.0, 1.0), F(-30.0, 30.0);
  for (Integrator integ : {Integrator::Explicit, Integrator::Implicit}) {
    ModelParameters p;
    p.numU = 8;
    p.numV = 7;
    p.boundaries = Boundaries{Boundary::Free, Boundary::Clamped, Boundary::Free, Boundary::Free};
    p.pins = {Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(0.37, 1.0), Eigen::Vector2d(0.5, 0.5), Eigen::Vector2d(1.0, 0.3)};
    p.integrator = integ;
    p.massModel = MassModel::Lumped;
    p.timeStep = 0.05;
    Simulation sim(p);
    for (int i = 0; i < 5; ++i)
      sim.addForce(std::make_shared<PointForce>(U(rng), U(rng), Eigen::Vector3d(F(rng), F(rng), F(rng))));
    sim.addForce(std::make_shared<DistributedForce>(
        [](const SurfaceSample& s) { return Eigen::Vector3d(3 * std::sin(2 * s.t), 0, 10 * std::cos(3 * s.t + s.u)); },
        kDependsOnTime));
    const ControlNet rest = sim.rest();
    sim.advance(1000);
    REQUIRE(sim.status() == Status::Ok);
    CHECK(sim.deformationNorm() > 0.05);
    for (Eigen::Index r : sim.pinnedRows()) CHECK(sim.current().row(r) == rest.row(r));
    // (n+1)^2 = 16 points for each of the first three pins (disjoint spans); the pin on the
    // clamped side u = 1 holds only the 4 of its span that are not clamped already
    CHECK(sim.pinnedRows().size() == 3 * 16 + 4);
    for (const Eigen::Vector2d& pin : p.pins)
      CHECK((sim.evaluate(pin.x(), pin.y()).position - Eigen::Vector3d(pin.x(), pin.y(), 0)).norm() <= 1e-12);
    double edge = 0.0;
    for (int i = 0; i <= 40; ++i)
      edge = std::max(edge, (sim.evaluate(1.0, i / 40.0).position - Eigen::Vector3d(1.0, i / 40.0, 0)).norm());
    CHECK(edge <= 1e-12);
  }
}

TEST_CASE("Boundary: the stability bound stays above the dense lambda_max for free, periodic, supported, built-in and pinned models",
          "[core][slow]") {
  struct Case {
    Boundaries bc;
    MassModel mass;
    int n;
  };
  const Boundaries allFree{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free};
  const Boundaries tube{Boundary::Periodic, Boundary::Periodic, Boundary::Free, Boundary::Clamped};
  const Boundaries torus{Boundary::Periodic, Boundary::Periodic, Boundary::Periodic, Boundary::Periodic};
  // SIMPLY_SUPPORTED and BUILT_IN: the mass of the unknowns is T^T W T there
  using B = Boundary;
  const Boundaries ss{B::SimplySupported, B::SimplySupported, B::SimplySupported, B::SimplySupported};
  const Boundaries bi{B::BuiltIn, B::BuiltIn, B::BuiltIn, B::BuiltIn};
  const Boundaries mixed{B::BuiltIn, B::Free, B::SimplySupported, B::Free};
  const Boundaries hingedTube{B::Periodic, B::Periodic, B::SimplySupported, B::BuiltIn};
  const Case cases[] = {{allFree, MassModel::Nodal, 3}, {allFree, MassModel::Lumped, 3}, {allFree, MassModel::Lumped, 2},
                        {allFree, MassModel::Lumped, 5}, {tube, MassModel::Lumped, 3},   {torus, MassModel::Nodal, 2},
                        {tube, MassModel::Nodal, 4},     {ss, MassModel::Nodal, 2},      {ss, MassModel::Nodal, 3},
                        {ss, MassModel::Lumped, 3},      {ss, MassModel::Nodal, 5},      {bi, MassModel::Nodal, 3},
                        {bi, MassModel::Lumped, 4},      {bi, MassModel::Nodal, 5},      {mixed, MassModel::Lumped, 3},
                        {mixed, MassModel::Nodal, 4},    {hingedTube, MassModel::Lumped, 3}};
  for (const Case& c : cases) {
    ModelParameters p;
    p.degreeU = p.degreeV = c.n;
    p.numU = p.numV = 10;
    p.boundaries = c.bc;
    p.massModel = c.mass;
    p.pins = {Eigen::Vector2d(0.2, 0.7)};
    const SplineSpace s(p.degreeU, p.degreeV, p.numU, p.numV, p.boundaries);
    Simulation sim(p, closedRest(s));
    const Eigen::MatrixXd A = Eigen::MatrixXd(sim.stencil().movingMatrix());
    // the mass of the unknowns: sum over the control points that move (moving, or derived next
    // to a SIMPLY_SUPPORTED or BUILT_IN side; not a periodic copy) of W t t^T, t the point's
    // weights on the unknowns (SplineSpace::foldU x foldV): diagonal without derived layers
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(A.rows(), A.cols());
    for (int i = 0; i < s.netRows(); ++i)
      for (int j = 0; j < s.netCols(); ++j) {
        if (!s.isMoving(i, j) && !s.isDerived(i, j)) continue;
        Eigen::VectorXd t = Eigen::VectorXd::Zero(A.rows());
        for (const LayerWeight& a : s.foldU(i))
          for (const LayerWeight& b : s.foldV(j))
            t[Eigen::Index(a.layer - s.movingU().first) * s.movingV().count + (b.layer - s.movingV().first)] += a.weight * b.weight;
        M += sim.massAt(i, j) * t * t.transpose();
      }
    const double lmax =
        Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd>(A, M, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
    const double lmaxA = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(A, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
    INFO("sides " << boundaryName(c.bc.uMin) << "/" << boundaryName(c.bc.vMin) << " degree " << c.n << " lumped "
                  << (c.mass == MassModel::Lumped) << " lambda_max " << lmax << " bound " << sim.elasticEigenvalueBound()
                  << " ratio " << sim.elasticEigenvalueBound() / lmax);
    CHECK(sim.elasticEigenvalueBound() >= lmax);
    CHECK(sim.elasticEigenvalueBound() <= 4.0 * lmax);
    CHECK(sim.stencil().eigenvalueBound() >= lmaxA);
    // and stepping at the reported sub-step is stable: no growth without load or damping
    ModelParameters q = p;
    q.damping = 0.0;
    q.timeStep = 20 * sim.stabilityLimit();
    Simulation run(q, closedRest(s));
    ControlNet kick = run.current();
    for (Eigen::Index m = 0; m < s.numMoving(); ++m) kick.row(s.movingToNet(m)) += Eigen::RowVector3d(0, 0, 1e-3 * ((m * 7919) % 13));
    s.completeNet(kick, &run.rest());
    run.setState(kick, 0.0, 0, HeldPoints::Reset);
    run.step();
    const double e0 = run.kineticEnergy() + run.strainEnergy().total;
    run.advance(300);
    CHECK(run.status() == Status::Ok);
    // undamped and unloaded: the energy stays put (it would grow exponentially if unstable)
    CHECK(run.kineticEnergy() + run.strainEnergy().total < 1.5 * e0);
  }
}

TEST_CASE("Boundary: periodic and pinned models without a closing rest net or with bad pins are refused by name",
          "[core]") {
  ModelParameters p;
  p.boundaries.uMin = p.boundaries.uMax = Boundary::Periodic;
  CHECK_THROWS_WITH(Simulation(p), Catch::Contains("PERIODIC") && Catch::Contains("rest net"));
  p.boundaries.uMax = Boundary::Free;
  CHECK_THROWS_WITH(Simulation(p), Catch::Contains("boundaryUMin") && Catch::Contains("both sides"));
  ModelParameters q;
  q.pins = {Eigen::Vector2d(0.5, 1.5)};
  CHECK_THROWS_WITH(Simulation(q), Catch::Contains("pin 0") && Catch::Contains("1.5"));
  // copies that differ: the first n layers win, and the difference is reported
  ModelParameters r;
  r.boundaries.uMin = r.boundaries.uMax = Boundary::Periodic;
  const SplineSpace s(r.degreeU, r.degreeV, r.numU, r.numV, r.boundaries);
  ControlNet rest = closedRest(s);
  rest(s.netIndex(r.numU + r.degreeU - 1, 0), 2) += 0.25;  // a last-layer copy of k = -1
  Simulation sim(r, rest);
  CHECK(sim.seamMismatch() == Approx(0.25));
  for (int k2 = -r.degreeV; k2 < r.numV + r.degreeV; ++k2)
    for (int k1 = -r.degreeU; k1 < 0; ++k1)
      CHECK(sim.rest().row(s.netIndex(k1 + r.numU + r.degreeU, k2)) == rest.row(s.netIndex(k1, k2)));
}

namespace {
// Released from rest: M P'' + C P' + A P = L, P(0) = P_rest, P'(0) = 0, with M = m I, C = c I
// (nodal), solved exactly by modes: each mode of A is a damped oscillator started at rest.
ControlNet exactRelease(const Simulation& sim, double T) {
  const SplineSpace& s = sim.space();
  const ModelParameters& p = sim.parameters();
  const Eigen::MatrixXd A = Eigen::MatrixXd(sim.stencil().movingMatrix());
  ControlNet heldOnly = sim.rest();
  for (Eigen::Index m = 0; m < s.numMoving(); ++m) heldOnly.row(s.movingToNet(m)).setZero();
  ControlNet coupling, restForce;
  sim.stencil().applyMoving(heldOnly, coupling);
  sim.stencil().applyMoving(sim.rest(), restForce);
  const Eigen::MatrixXd b = sim.loadVector() + restForce - coupling;  // A x_s = b
  const Eigen::MatrixXd xs = A.ldlt().solve(b);
  const Eigen::MatrixXd x0 = s.gatherMoving(sim.rest());
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(A / p.mass);
  const Eigen::MatrixXd q0 = eig.eigenvectors().transpose() * (x0 - xs);
  const double g = p.damping / p.mass;
  Eigen::MatrixXd q = q0;
  for (Eigen::Index i = 0; i < q.rows(); ++i) {
    const double w2 = eig.eigenvalues()[i], disc = w2 - 0.25 * g * g;
    REQUIRE(disc > 0.0);  // underdamped modes only in this set-up
    const double wd = std::sqrt(disc);
    q.row(i) *= std::exp(-0.5 * g * T) * (std::cos(wd * T) + 0.5 * g / wd * std::sin(wd * T));
  }
  ControlNet net = sim.rest();
  s.scatterMoving(xs + eig.eigenvectors() * q, net);
  return net;
}

double releaseError(Integrator integ, StartRule start, double dt) {
  ModelParameters p;
  p.numU = p.numV = 5;
  p.damping = 0.3;
  p.timeStep = dt;
  p.autoSubstep = false;
  p.integrator = integ;
  p.start = start;
  Simulation sim(p);
  sim.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 2, 10), ParamRect{0.3, 0.7, 0.2, 0.6}));
  const double T = 1.0;
  sim.advance(std::lround(T / dt));
  return maxDiff(sim.current(), exactRelease(sim, T));
}
}  // namespace

TEST_CASE("Boundary: start SECOND_ORDER converges at order 2 to the release from rest, PAPER at order 1", "[core]") {
  for (Integrator integ : {Integrator::Explicit, Integrator::Implicit}) {
    const double e1 = releaseError(integ, StartRule::SecondOrder, 0.02);
    const double e2 = releaseError(integ, StartRule::SecondOrder, 0.01);
    const double p1 = releaseError(integ, StartRule::Paper, 0.02);
    const double p2 = releaseError(integ, StartRule::Paper, 0.01);
    INFO("integrator " << int(integ) << ": second order " << e1 << " -> " << e2 << ", paper " << p1 << " -> " << p2);
    CHECK(std::log2(e1 / e2) == Approx(2.0).margin(0.25));
    CHECK(std::log2(p1 / p2) == Approx(1.0).margin(0.25));
    CHECK(e2 < 0.2 * p2);
  }
}
