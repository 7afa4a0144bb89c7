// SPDX-License-Identifier: MIT
// The force laws of ForceLaws.h: each position-dependent law's lambda_max(M^-1 K) (K from the
// finite-difference Jacobian of support/ForceFieldCheck.h) against the class's eigenvalueBound,
// direction and sign tests, parameter validation. Their Jacobians and energies are checked in
// ForceField_test.cpp, with every other force law.
//
// BSDEFORM_PRINT_FIGURES=1 prints the measured Jacobian errors and bound ratios.
#include <Eigen/Eigenvalues>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include "../support/ForceFieldCheck.h"
#include "bsdeform/forces/ForceLaws.h"
#include "bsdeform/dynamics/Simulation.h"

using namespace bsdeform;
using namespace bsdeform::test;

namespace {
void figure(const std::string& line) {
  static const bool on = std::getenv("BSDEFORM_PRINT_FIGURES") != nullptr;
  if (on) std::printf("  [figure] %s\n", line.c_str());
}
std::string fmt(const char* f, double a, double b = 0.0, double c = 0.0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, f, a, b, c);
  return buf;
}

using Matrix = Eigen::MatrixXd;
using Vector = Eigen::VectorXd;

/// A model: its space, the mass of each moving point and the MassContext the forces see.
struct Model {
  std::string name;
  std::unique_ptr<Simulation> sim;  // null: NODAL m = 1 on `space` without a simulation
  std::unique_ptr<SplineSpace> ownSpace;
  double interiorMass = 1.0;

  const SplineSpace& space() const { return sim ? sim->space() : *ownSpace; }
  double massAt(int i, int j) const { return sim ? sim->massAt(i, j) : 1.0; }
  MassContext context() const {
    return MassContext{space(), interiorMass, [this](int i, int j) { return massAt(i, j); }};
  }
  /// Diagonal of M over the 3 numMoving coordinates (order 3 m + coordinate).
  Vector massVector() const {
    const SplineSpace& s = space();
    Vector m(3 * s.numMoving());
    const int w = s.movingV().count;
    for (Eigen::Index f = 0; f < s.numMoving(); ++f)
      m.segment<3>(3 * f).setConstant(massAt(s.movingU().first + int(f / w), s.movingV().first + int(f % w)));
    return m;
  }
};

Model nodalModel(int n1, int n2, int N1, int N2, Boundaries b = Boundaries()) {
  Model m;
  m.name = "NODAL m=1";
  m.ownSpace = std::make_unique<SplineSpace>(n1, n2, N1, N2, b);
  return m;
}

/// All sides FREE, LUMPED mass of density rho (smaller masses next to the edges).
Model lumpedFreeModel(int n1, int n2, int N1, int N2, double rho) {
  ModelParameters p;
  p.degreeU = n1;
  p.degreeV = n2;
  p.numU = N1;
  p.numV = N2;
  p.boundaries = {Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free};
  p.massModel = MassModel::Lumped;
  p.mass = rho;
  Model m;
  m.name = "LUMPED all FREE";
  m.sim = std::make_unique<Simulation>(p);
  m.interiorMass = rho * m.sim->space().basisU().spacing() * m.sim->space().basisV().spacing();
  return m;
}

ControlNet loadOf(const Force& force, const SplineSpace& s, const ControlNet& cur, const ControlNet& prev,
                  double dt = 0.1) {
  ControlNet load = ControlNet::Zero(s.numMoving(), 3);
  force.addLoad(LoadContext{s, cur, prev, dt, 0.0}, load);
  return load;
}
ControlNet loadOf(const Force& force, const SplineSpace& s, const ControlNet& net) { return loadOf(force, s, net, net); }

/// dL/dP at `net` by finite differences (support/ForceFieldCheck.h).
Matrix fdJacobian(const Force& force, const SplineSpace& s, const ControlNet& net) {
  return forForce("", force, s, net).jacobian();
}

/// lambda_max(M^-1 K) for a symmetric K (K symmetrised first).
double lambdaMaxSymmetric(const Matrix& K, const Vector& mass) {
  const Vector d = mass.cwiseSqrt().cwiseInverse();
  Matrix A = d.asDiagonal() * K * d.asDiagonal();
  A = 0.5 * (A + A.transpose()).eval();
  return Eigen::SelfAdjointEigenSolver<Matrix>(A, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
}

/// Spectral radius of M^-1 K (K not symmetric).
double spectralRadius(const Matrix& K, const Vector& mass) {
  const Matrix A = mass.cwiseInverse().asDiagonal() * K;
  return Eigen::EigenSolver<Matrix>(A, false).eigenvalues().cwiseAbs().maxCoeff();
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Spring

TEST_CASE("ForceLaws: spring: its bound is lambda_max(M^-1 K) exactly", "[core]") {
  std::vector<Model> models;
  models.push_back(nodalModel(3, 2, 4, 3));
  models.push_back(lumpedFreeModel(2, 3, 3, 3, 2.5));
  models.push_back(nodalModel(3, 3, 5, 4, {Boundary::Periodic, Boundary::Periodic, Boundary::Clamped, Boundary::Clamped}));
  models.back().name = "NODAL periodic in u";
  const double k = 37.0;
  for (const Model& model : models) {
    const SplineSpace& s = model.space();
    const ControlNet net = deformedNet(s, 0.3);
    for (const Eigen::Vector2d& uv : {Eigen::Vector2d(0.37, 0.61), Eigen::Vector2d(0.02, 0.5), Eigen::Vector2d(1.0, 0.3),
                                 Eigen::Vector2d(1.0, 0.0)}) {
      INFO(model.name << " at (" << uv.x() << ", " << uv.y() << ")");
      const SpringForce spring(uv.x(), uv.y(), Eigen::Vector3d(0.4, 0.7, 1.2), k);
      const Matrix J = fdJacobian(spring, s, net);  // -k beta beta^T (ForceField_test)
      const double lambda = lambdaMaxSymmetric(-J, model.massVector());
      const double bound = spring.eigenvalueBound(model.context());
      // exact, up to the finite-difference error (absolute: beta may be all but 0 near an edge)
      const double tol = 1e-8 * k / model.massVector().minCoeff();
      CHECK(lambda <= bound + tol);
      CHECK(lambda >= bound - tol);
      figure(model.name + fmt(" spring at (%.2f, %.2f): lambda %.6e", uv.x(), uv.y(), lambda) + fmt(", bound %.6e", bound));
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Plane contact

TEST_CASE("ForceLaws: plane contact, fully penetrating (K = k G (x) n n^T): bound and lambda_max", "[core]") {
  std::vector<Model> models;
  models.push_back(nodalModel(3, 2, 4, 3));
  models.push_back(lumpedFreeModel(2, 3, 3, 3, 2.5));
  const double k = 50.0;
  for (const Model& model : models) {
    INFO(model.name);
    const SplineSpace& s = model.space();
    const ControlNet net = deformedNet(s, 0.3);
    const PlaneContactForce plane(Eigen::Vector3d(0.5, 0.5, 3.0), Eigen::Vector3d(0.3, -0.2, 1.0), k);
    const Matrix J = fdJacobian(plane, s, net);
    const double lambda = lambdaMaxSymmetric(-J, model.massVector());
    const double bound = plane.eigenvalueBound(model.context());
    CHECK(lambda <= bound * (1.0 + 1e-9));
    CHECK(lambda > 0.3 * bound);  // Gershgorin is not far off for the Gram matrix
    figure(model.name + fmt(" plane, full contact: lambda/bound %.3f", lambda / bound));
  }
}

TEST_CASE("ForceLaws: plane contact, partly penetrating: bound", "[core]") {
  std::vector<Model> models;
  models.push_back(nodalModel(3, 2, 4, 3));
  models.push_back(lumpedFreeModel(2, 3, 3, 3, 2.5));
  const double k = 50.0;
  for (const Model& model : models) {
    INFO(model.name);
    const SplineSpace& s = model.space();
    const ControlNet net = deformedNet(s, 0.3);
    const Eigen::Vector3d c(0.0, 0.0, 0.12), n = Eigen::Vector3d(0.1, 0.05, 1.0).normalized();
    const PlaneContactForce plane(c, n, k);
    const Matrix J = fdJacobian(plane, s, net);
    const double lambda = lambdaMaxSymmetric(-J, model.massVector());
    const double bound = plane.eigenvalueBound(model.context());
    CHECK(lambda > 0.0);
    CHECK(lambda <= bound * (1.0 + 1e-9));
    figure(model.name + fmt(" plane, partial contact: lambda/bound %.3f", lambda / bound));
  }
}

TEST_CASE("ForceLaws: plane contact pushes out along the normal only where the surface penetrates", "[core]") {
  const SplineSpace s(3, 3, 5, 5);
  const ControlNet flat0 = s.grevillePlane();  // z = 0
  const double k = 20.0;
  // above the plane z = -0.1: nothing
  CHECK(loadOf(PlaneContactForce(Eigen::Vector3d(0, 0, -0.1), Eigen::Vector3d(0, 0, 2), k), s, flat0).isZero(0.0));
  // below the plane z = 0.1 (normal +z): every point is pushed up, by k * depth * r_m
  const ControlNet L = loadOf(PlaneContactForce(Eigen::Vector3d(3, -1, 0.1), Eigen::Vector3d(0, 0, 2), k), s, flat0);
  const double h2 = s.basisU().spacing() * s.basisV().spacing();
  for (Eigen::Index m = 0; m < L.rows(); ++m) CHECK((L.row(m) - Eigen::RowVector3d(0, 0, k * 0.1 * h2)).norm() < 1e-13);
  // the normal's orientation picks the free side: flipped, the same surface is outside
  CHECK(loadOf(PlaneContactForce(Eigen::Vector3d(0, 0, 0.1), Eigen::Vector3d(0, 0, -1), k), s, flat0).isZero(0.0));
}

// ---------------------------------------------------------------------------------------------
// Sphere contact

TEST_CASE("ForceLaws: sphere contact: bound", "[core]") {
  std::vector<Model> models;
  models.push_back(nodalModel(3, 2, 4, 3));
  models.push_back(lumpedFreeModel(2, 3, 3, 3, 2.5));
  const double k = 80.0;
  for (const Model& model : models) {
    INFO(model.name);
    const SplineSpace& s = model.space();
    const ControlNet net = deformedNet(s, 0.3);
    const Eigen::Vector3d c(0.45, 0.55, -0.4);
    const double r = 0.75;
    const SphereContactForce sphere(c, r, k);
    const Matrix K = -fdJacobian(sphere, s, net);  // symmetric (ForceField_test)
    const double lambda = lambdaMaxSymmetric(K, model.massVector());
    const double bound = sphere.eigenvalueBound(model.context());
    CHECK(lambda > 0.0);
    CHECK(lambda <= bound * (1.0 + 1e-9));
    figure(model.name + fmt(" sphere: lambda/bound %.3f", lambda / bound));
  }
}

TEST_CASE("ForceLaws: sphere contact pushes out of the sphere only inside it", "[core]") {
  const SplineSpace s(3, 3, 5, 5);
  const ControlNet plane = s.grevillePlane();  // z = 0
  const double k = 20.0;
  // a sphere below the sheet, not reaching it: nothing
  CHECK(loadOf(SphereContactForce(Eigen::Vector3d(0.5, 0.5, -0.5), 0.45, k), s, plane).isZero(0.0));
  // a sphere below the sheet, reaching through it: pushes the sheet up, and away from the centre
  const Eigen::Vector3d c(0.5, 0.5, -0.2);
  const ControlNet L = loadOf(SphereContactForce(c, 0.4, k), s, plane);
  CHECK(L.col(2).minCoeff() >= 0.0);
  CHECK(L.col(2).sum() > 0.0);
  for (Eigen::Index m = 0; m < L.rows(); ++m) {
    const Eigen::Vector3d p = plane.row(s.movingToNet(m)).transpose();
    CHECK(L.row(m).dot((p - c).transpose()) >= 0.0);
  }
  // a sphere above: pushes down
  CHECK(loadOf(SphereContactForce(Eigen::Vector3d(0.5, 0.5, 0.2), 0.4, k), s, plane).col(2).sum() < 0.0);
}

// ---------------------------------------------------------------------------------------------
// Pressure

TEST_CASE("ForceLaws: pressure: the spectral-radius bound of the follower load", "[core]") {
  std::vector<Model> models;
  models.push_back(nodalModel(3, 2, 4, 3));
  models.push_back(lumpedFreeModel(2, 3, 3, 3, 2.5));
  const double p = 6.0;
  for (const Model& model : models) {
    for (double amp : {0.0, 0.3, 0.8}) {
      INFO(model.name << " bump " << amp);
      const SplineSpace& s = model.space();
      const ControlNet net = deformedNet(s, amp);
      const std::vector<QPoint> rule = classRule(s);
      // sigma = min(|S_u|, |S_v|) sin(theta) over the points the load is evaluated at
      double sigma = INFINITY;
      for (const QPoint& q : rule) {
        const SurfacePoint sp = s.evaluate(net, q.u, q.v, 1);
        sigma = std::min(sigma, sp.du.cross(sp.dv).norm() / std::max(sp.du.norm(), sp.dv.norm()));
      }
      const PressureForce pressure(p, sigma);
      const Matrix J = fdJacobian(pressure, s, net);
      const double rho = spectralRadius(-J, model.massVector());
      const double bound = pressure.eigenvalueBound(model.context());
      CHECK(rho <= bound * (1.0 + 1e-9));
      // the norm the bound is built on, measured
      const Matrix A = model.massVector().cwiseInverse().asDiagonal() * J;
      double blockNorm = 0.0;
      for (Eigen::Index m = 0; m < s.numMoving(); ++m) {
        double row = 0.0;
        for (Eigen::Index n = 0; n < s.numMoving(); ++n) row += A.block<3, 3>(3 * m, 3 * n).operatorNorm();
        blockNorm = std::max(blockNorm, row);
      }
      CHECK(blockNorm <= bound * (1.0 + 1e-9));
      if (amp == 0.0) {
        // nearly flat (only the small in-plane distortion): the eigenvalues are close to 0
        CHECK(rho < 1e-3 * bound);
      }
      figure(model.name + fmt(" pressure, bump %.1f: sigma %.3f", amp, sigma) +
             fmt(", rho/bound %.2e, block-norm/bound %.3f", rho / bound, blockNorm / bound));
    }
  }
}

TEST_CASE("ForceLaws: pressure acts along the unit normal", "[core]") {
  const SplineSpace s(3, 2, 5, 4);
  const ControlNet plane = s.grevillePlane();  // S_u x S_v = +z
  const double h2 = s.basisU().spacing() * s.basisV().spacing();
  const ControlNet L = loadOf(PressureForce(3.0), s, plane);
  for (Eigen::Index m = 0; m < L.rows(); ++m) CHECK((L.row(m) - Eigen::RowVector3d(0, 0, 3.0 * h2)).norm() < 1e-13);
  // a stretched sheet gets the same load (unit normal, per unit parameter area)
  ControlNet big = plane * 4.0;
  CHECK((loadOf(PressureForce(3.0), s, big) - L).norm() < 1e-12);
  // negative pressure pulls the other way
  CHECK((loadOf(PressureForce(-3.0), s, plane) + L).norm() < 1e-13);
}

// ---------------------------------------------------------------------------------------------
// Drag and gravity

TEST_CASE("ForceLaws: drag opposes the velocity and has no stiffness", "[core]") {
  Model model = lumpedFreeModel(3, 3, 4, 4, 1.0);
  const SplineSpace& s = model.space();
  const ControlNet cur = deformedNet(s, 0.2);
  const Eigen::RowVector3d v(0.3, -0.2, 1.5);
  const double dt = 0.05, c = 4.0;
  ControlNet prev = cur;
  prev.rowwise() -= dt * v;  // a rigid motion at velocity v
  const DragForce drag(c);
  const ControlNet L = loadOf(drag, s, cur, prev, dt);
  // all sides free: the B-splines sum to 1 on [0,1]^2, so the total is -c v exactly
  CHECK((L.colwise().sum() + c * v).norm() < 1e-12);
  for (Eigen::Index m = 0; m < L.rows(); ++m) CHECK(L.row(m).dot(v) < 0.0);
  // at rest: nothing, wherever the surface is
  CHECK(loadOf(drag, s, cur, cur, dt).isZero(0.0));
  CHECK(drag.dependence() == kDependsOnVelocity);
  CHECK(drag.eigenvalueBound(model.context()) == 0.0);
  const double h2 = s.basisU().spacing() * s.basisV().spacing();
  CHECK(drag.dampingRateBound(model.context()) == Approx(c * h2 / model.interiorMass));
}

TEST_CASE("ForceLaws: gravity gives every moving point the acceleration g with lumped mass", "[core]") {
  for (bool free : {false, true}) {
    ModelParameters p;
    p.degreeU = 3;
    p.degreeV = 2;
    p.numU = 5;
    p.numV = 4;
    if (free) p.boundaries = {Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free};
    p.massModel = MassModel::Lumped;
    p.mass = 0.7;
    Simulation sim(p);
    const Eigen::Vector3d g(0.5, 0.0, -9.81);
    sim.addForce(std::make_shared<GravityForce>(p.mass, g));
    const ControlNet L = sim.loadVector();
    const SplineSpace& s = sim.space();
    const int w = s.movingV().count;
    INFO((free ? "all FREE" : "CLAMPED"));
    for (Eigen::Index m = 0; m < L.rows(); ++m) {
      const double mass = sim.massAt(s.movingU().first + int(m / w), s.movingV().first + int(m % w));
      CHECK((L.row(m).transpose() / mass - g).norm() < 1e-12);
    }
    CHECK(sim.eigenvalueBound() == sim.elasticEigenvalueBound());  // constant: no stiffness
  }
}

TEST_CASE("ForceLaws: gravity without a density takes the model's mass per area from the load context", "[core]") {
  const Eigen::Vector3d g(0.5, 0.0, -9.81);
  for (int model = 0; model < 3; ++model) {
    ModelParameters p;
    p.numU = 6;
    p.numV = 5;
    p.massModel = model == 1 ? MassModel::Lumped : MassModel::Nodal;
    p.mass = model == 1 ? 0.7 : 0.02;
    if (model == 2) {
      p.energy = EnergyModel::Shell;
      p.material.density = 472.6;
      p.material.thickness = 0.318e-3;
    }
    INFO("model " << model);
    Simulation fromModel(p), given(p);
    fromModel.addForce(std::make_shared<GravityForce>(g));
    given.addForce(std::make_shared<GravityForce>(given.massPerArea(), g));
    const ControlNet a = fromModel.loadVector(), b = given.loadVector();
    CHECK(b.cwiseAbs().maxCoeff() > 0.0);
    CHECK((a - b).cwiseAbs().maxCoeff() <= 1e-13 * b.cwiseAbs().maxCoeff());  // rho (g w) against (rho g) w
    // and straight from a context that says so
    const ControlNet& net = fromModel.current();
    LoadContext ctx{fromModel.space(), net, net, p.timeStep, 0.0};
    ctx.massPerArea = 2.5;
    ControlNet la = ControlNet::Zero(net.rows(), 3), lb = ControlNet::Zero(net.rows(), 3);
    GravityForce(g).addLoad(ctx, la);
    GravityForce(2.5, g).addLoad(ctx, lb);
    CHECK((la - lb).cwiseAbs().maxCoeff() <= 1e-13 * lb.cwiseAbs().maxCoeff());
    CHECK(GravityForce(g).modelDensity());
    CHECK(!GravityForce(2.5, g).modelDensity());
  }
}

// ---------------------------------------------------------------------------------------------
// Validation

TEST_CASE("ForceLaws: bad parameters are rejected naming the parameter and the value", "[core]") {
  const Eigen::Vector3d z(0, 0, 1), bad(0, NAN, 1);
  CHECK_THROWS_WITH(SpringForce(1.5, 0.5, z, 1.0), Catch::Contains("spring point u") && Catch::Contains("1.5"));
  CHECK_THROWS_WITH(SpringForce(0.5, -0.25, z, 1.0), Catch::Contains("spring point v") && Catch::Contains("-0.25"));
  CHECK_THROWS_WITH(SpringForce(0.5, 0.5, bad, 1.0), Catch::Contains("spring anchor") && Catch::Contains("nan"));
  CHECK_THROWS_WITH(SpringForce(0.5, 0.5, z, -2.0), Catch::Contains("spring stiffness") && Catch::Contains("-2"));
  CHECK_THROWS_WITH(DragForce(-0.5), Catch::Contains("drag coefficient") && Catch::Contains("-0.5"));
  CHECK_THROWS_WITH(DragForce(INFINITY), Catch::Contains("drag coefficient") && Catch::Contains("inf"));
  CHECK_THROWS_WITH(PressureForce(NAN), Catch::Contains("pressure") && Catch::Contains("nan"));
  CHECK_THROWS_WITH(PressureForce(1.0, 0.0), Catch::Contains("minStretch") && Catch::Contains("0"));
  CHECK_THROWS_WITH(PlaneContactForce(z, Eigen::Vector3d::Zero(), 1.0),
                    Catch::Contains("plane contact normal") && Catch::Contains("(0, 0, 0)"));
  CHECK_THROWS_WITH(PlaneContactForce(bad, z, 1.0), Catch::Contains("plane contact point"));
  CHECK_THROWS_WITH(PlaneContactForce(z, z, -1.0), Catch::Contains("plane contact stiffness") && Catch::Contains("-1"));
  CHECK_THROWS_WITH(SphereContactForce(z, -0.1, 1.0), Catch::Contains("sphere contact radius") && Catch::Contains("-0.1"));
  CHECK_THROWS_WITH(SphereContactForce(bad, 0.1, 1.0), Catch::Contains("sphere contact center"));
  CHECK_THROWS_WITH(SphereContactForce(z, 0.1, NAN), Catch::Contains("sphere contact stiffness"));
  CHECK_THROWS_WITH(GravityForce(-1.0, z), Catch::Contains("gravity mass density") && Catch::Contains("-1"));
  CHECK_THROWS_WITH(GravityForce(1.0, bad), Catch::Contains("gravity acceleration"));
  // accessors keep what was given (the normal normalised)
  const PlaneContactForce plane(z, Eigen::Vector3d(0, 3, 4), 2.0);
  CHECK((plane.normal() - Eigen::Vector3d(0, 0.6, 0.8)).norm() < 1e-15);
  const SpringForce spring(0.97, 0.5, z, 3.0);
  CHECK(spring.u() == 0.97);
  CHECK(spring.stiffness() == 3.0);
}
