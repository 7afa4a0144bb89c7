// SPDX-License-Identifier: MIT
// The force laws of ForceLaws.h: SOFA-style finite-difference checks of each position-dependent
// law's load Jacobian (against its formula, and its lambda_max(M^-1 K) against the class's
// eigenvalueBound), direction and sign tests, parameter validation.
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

#include "bsdeform/ForceLaws.h"
#include "bsdeform/GaussLegendre.h"
#include "bsdeform/Simulation.h"

using namespace bsdeform;

namespace {
constexpr double kPi = 3.14159265358979323846;

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

/// The Greville plane (or, periodic, the Greville abscissae of the moving points) with a bump
/// of height `amp` and a small in-plane distortion: a "small deformed net".
ControlNet deformedNet(const SplineSpace& s, double amp) {
  ControlNet net = ControlNet::Zero(s.netSize(), 3);
  for (int k1 = -s.degreeU(); k1 < s.numU() + s.degreeU(); ++k1)
    for (int k2 = -s.degreeV(); k2 < s.numV() + s.degreeV(); ++k2)
      net.row(s.netIndex(k1, k2)) << s.grevilleU(k1), s.grevilleV(k2), 0.0;
  ControlNet P = s.gatherMoving(net);
  for (Eigen::Index f = 0; f < P.rows(); ++f) {
    const double x = P(f, 0), y = P(f, 1);
    P(f, 2) += amp * std::sin(kPi * x) * std::sin(kPi * y) + 0.05 * amp * std::cos(3.0 * x + 2.0 * y);
    P(f, 0) += 0.03 * std::sin(2.0 * y + 0.3);
    P(f, 1) += 0.02 * std::cos(3.0 * x);
  }
  s.scatterMoving(P, net);
  return net;
}

ControlNet loadOf(const Force& force, const SplineSpace& s, const ControlNet& cur, const ControlNet& prev,
                  double dt = 0.1) {
  ControlNet load = ControlNet::Zero(s.numMoving(), 3);
  force.addLoad(LoadContext{s, cur, prev, dt, 0.0}, load);
  return load;
}
ControlNet loadOf(const Force& force, const SplineSpace& s, const ControlNet& net) { return loadOf(force, s, net, net); }

Vector flat(const ControlNet& L) { return Eigen::Map<const Vector>(L.data(), L.size()); }

/// J(3m+i, 3n+j) = dL_{m,i} / dP_{n,j} by central differences (periodic copies follow).
Matrix fdJacobian(const Force& force, const SplineSpace& s, const ControlNet& net, double eps) {
  const Eigen::Index n = 3 * s.numMoving();
  Matrix J(n, n);
  const ControlNet P = s.gatherMoving(net);
  for (Eigen::Index c = 0; c < n; ++c) {
    ControlNet plus = net, minus = net, Pp = P, Pm = P;
    Pp(c / 3, c % 3) += eps;
    Pm(c / 3, c % 3) -= eps;
    s.scatterMoving(Pp, plus);
    s.scatterMoving(Pm, minus);
    J.col(c) = (flat(loadOf(force, s, plus)) - flat(loadOf(force, s, minus))) / (2.0 * eps);
  }
  return J;
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

/// B-splines of the moving points at (u, v) and their u, v derivatives (periodic copies summed).
struct MovingBasis {
  Vector b, bu, bv;
};
MovingBasis movingBasis(const SplineSpace& s, double u, double v) {
  LocalBasis lu, lv;
  s.basisU().evaluate(u, 1, lu);
  s.basisV().evaluate(v, 1, lv);
  MovingBasis out{Vector::Zero(s.numMoving()), Vector::Zero(s.numMoving()), Vector::Zero(s.numMoving())};
  const int w = s.movingV().count;
  for (int a = 0; a < lu.count; ++a) {
    const int i = s.movingLayerU(lu.first + a + s.degreeU());
    if (i < 0) continue;
    for (int b = 0; b < lv.count; ++b) {
      const int j = s.movingLayerV(lv.first + b + s.degreeV());
      if (j < 0) continue;
      const Eigen::Index m = Eigen::Index(i - s.movingU().first) * w + (j - s.movingV().first);
      out.b[m] += lu.d[0][a] * lv.d[0][b];
      out.bu[m] += lu.d[1][a] * lv.d[0][b];
      out.bv[m] += lu.d[0][a] * lv.d[1][b];
    }
  }
  return out;
}

/// Tensor Gauss rule with `points` nodes per knot span and direction, on [0,1]^2.
struct QPoint {
  double u, v, w;
};
std::vector<QPoint> tensorRule(const SplineSpace& s, int pointsU, int pointsV) {
  const QuadratureRule &ru = gaussLegendre(pointsU), &rv = gaussLegendre(pointsV);
  const int su = s.basisU().numSpans(), sv = s.basisV().numSpans();
  std::vector<QPoint> out;
  for (int a = 0; a < su; ++a)
    for (size_t p = 0; p < ru.nodes.size(); ++p)
      for (int b = 0; b < sv; ++b)
        for (size_t q = 0; q < rv.nodes.size(); ++q)
          out.push_back({(a + ru.nodes[p]) / su, (b + rv.nodes[q]) / sv, ru.weights[p] / su * rv.weights[q] / sv});
  return out;
}
/// The rule DistributedForce uses for the contact and pressure laws (n + 1 + 2 points).
std::vector<QPoint> classRule(const SplineSpace& s) { return tensorRule(s, s.degreeU() + 3, s.degreeV() + 3); }

/// Jacobian of a density law by the same quadrature: J_mn = sum_q w_q B_m (df/dP_n), where
/// dfdP(q, basis, n) is the 3x3 derivative of the density at point q w.r.t. moving point n.
Matrix quadratureJacobian(const SplineSpace& s, const std::vector<QPoint>& rule,
                          const std::function<Eigen::Matrix3d(const QPoint&, const MovingBasis&, Eigen::Index)>& dfdP) {
  const Eigen::Index N = s.numMoving();
  Matrix J = Matrix::Zero(3 * N, 3 * N);
  for (const QPoint& q : rule) {
    const MovingBasis mb = movingBasis(s, q.u, q.v);
    for (Eigen::Index n = 0; n < N; ++n) {
      if (mb.b[n] == 0.0 && mb.bu[n] == 0.0 && mb.bv[n] == 0.0) continue;
      const Eigen::Matrix3d D = dfdP(q, mb, n);
      for (Eigen::Index m = 0; m < N; ++m)
        if (mb.b[m] != 0.0) J.block<3, 3>(3 * m, 3 * n) += q.w * mb.b[m] * D;
    }
  }
  return J;
}

Eigen::Matrix3d cross(const Eigen::Vector3d& a) {
  Eigen::Matrix3d X;
  X << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return X;
}

double maxAbs(const Matrix& A) { return A.cwiseAbs().maxCoeff(); }

}  // namespace

// ---------------------------------------------------------------------------------------------
// Spring

TEST_CASE("ForceLaws: spring Jacobian is -k beta beta^T and its bound is exact", "[core]") {
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
      const Matrix J = fdJacobian(spring, s, net, 1e-6);
      // beta from a unit point force (whose load is exact, Force_test)
      const Vector beta = loadOf(PointForce(uv.x(), uv.y(), Eigen::Vector3d(1, 0, 0)), s, net).col(0);
      Matrix expected = Matrix::Zero(J.rows(), J.cols());
      for (Eigen::Index m = 0; m < beta.size(); ++m)
        for (Eigen::Index n = 0; n < beta.size(); ++n)
          expected.block<3, 3>(3 * m, 3 * n) = -k * beta[m] * beta[n] * Eigen::Matrix3d::Identity();
      const double err = maxAbs(J - expected) / k;
      CHECK(err < 1e-8);
      const double lambda = lambdaMaxSymmetric(-J, model.massVector());
      const double bound = spring.eigenvalueBound(model.context());
      // exact, up to the finite-difference error (absolute: beta may be all but 0 near an edge)
      const double tol = 1e-8 * k / model.massVector().minCoeff();
      CHECK(lambda <= bound + tol);
      CHECK(lambda >= bound - tol);
      figure(model.name + fmt(" spring at (%.2f, %.2f): FD error %.1e", uv.x(), uv.y(), err) +
             fmt(", lambda %.6e, bound %.6e", lambda, bound));
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Plane contact

TEST_CASE("ForceLaws: plane contact, fully penetrating, has Jacobian -k G (x) n n^T", "[core]") {
  std::vector<Model> models;
  models.push_back(nodalModel(3, 2, 4, 3));
  models.push_back(lumpedFreeModel(2, 3, 3, 3, 2.5));
  const double k = 50.0;
  const Eigen::Vector3d normal = Eigen::Vector3d(0.3, -0.2, 1.0).normalized();
  for (const Model& model : models) {
    INFO(model.name);
    const SplineSpace& s = model.space();
    const ControlNet net = deformedNet(s, 0.3);
    const PlaneContactForce plane(Eigen::Vector3d(0.5, 0.5, 3.0), Eigen::Vector3d(0.3, -0.2, 1.0), k);
    const Matrix J = fdJacobian(plane, s, net, 1e-6);
    // The Gram matrix of the moving B-splines, exact with n + 1 points per span.
    const Matrix expected = quadratureJacobian(s, tensorRule(s, s.degreeU() + 1, s.degreeV() + 1),
                                               [&](const QPoint&, const MovingBasis& mb, Eigen::Index n) {
                                                 return Eigen::Matrix3d(-k * mb.b[n] * normal * normal.transpose());
                                               });
    const double err = maxAbs(J - expected) / maxAbs(expected);
    CHECK(err < 1e-7);
    const double lambda = lambdaMaxSymmetric(-J, model.massVector());
    const double bound = plane.eigenvalueBound(model.context());
    CHECK(lambda <= bound * (1.0 + 1e-9));
    CHECK(lambda > 0.3 * bound);  // Gershgorin is not far off for the Gram matrix
    figure(model.name + fmt(" plane, full contact: FD relative error %.1e, lambda/bound %.3f", err, lambda / bound));
  }
}

TEST_CASE("ForceLaws: plane contact, partly penetrating: FD Jacobian and bound", "[core]") {
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
    const Matrix J = fdJacobian(plane, s, net, 1e-7);
    const Matrix expected =
        quadratureJacobian(s, classRule(s), [&](const QPoint& q, const MovingBasis& mb, Eigen::Index m) {
          const double depth = -(s.evaluate(net, q.u, q.v, 0).position - c).dot(n);
          return Eigen::Matrix3d(depth > 0.0 ? Eigen::Matrix3d(-k * mb.b[m] * n * n.transpose()) : Eigen::Matrix3d::Zero());
        });
    const double err = maxAbs(J - expected) / maxAbs(expected);
    CHECK(err < 1e-6);
    const double lambda = lambdaMaxSymmetric(-J, model.massVector());
    const double bound = plane.eigenvalueBound(model.context());
    CHECK(lambda > 0.0);
    CHECK(lambda <= bound * (1.0 + 1e-9));
    figure(model.name + fmt(" plane, partial contact: FD relative error %.1e, lambda/bound %.3f", err, lambda / bound));
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

TEST_CASE("ForceLaws: sphere contact: FD Jacobian and bound", "[core]") {
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
    const Matrix J = fdJacobian(sphere, s, net, 1e-7);
    const Matrix expected =
        quadratureJacobian(s, classRule(s), [&](const QPoint& q, const MovingBasis& mb, Eigen::Index m) {
          const Eigen::Vector3d d = s.evaluate(net, q.u, q.v, 0).position - c;
          const double len = d.norm();
          if (len >= r) return Eigen::Matrix3d(Eigen::Matrix3d::Zero());
          const Eigen::Vector3d e = d / len;
          // df/dS = -k e e^T + k (r/|d| - 1)(I - e e^T)
          const Eigen::Matrix3d P = e * e.transpose();
          return Eigen::Matrix3d(mb.b[m] * (-k * P + k * (r / len - 1.0) * (Eigen::Matrix3d::Identity() - P)));
        });
    const double err = maxAbs(J - expected) / maxAbs(expected);
    CHECK(err < 1e-6);
    const Matrix K = -J;
    CHECK(maxAbs(K - K.transpose()) < 1e-6 * maxAbs(K));  // a potential force: symmetric
    const double lambda = lambdaMaxSymmetric(K, model.massVector());
    const double bound = sphere.eigenvalueBound(model.context());
    CHECK(lambda > 0.0);
    CHECK(lambda <= bound * (1.0 + 1e-9));
    figure(model.name + fmt(" sphere: FD relative error %.1e, lambda/bound %.3f", err, lambda / bound));
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

TEST_CASE("ForceLaws: pressure: FD Jacobian of the follower load and its spectral-radius bound", "[core]") {
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
      const Matrix J = fdJacobian(pressure, s, net, 1e-7);
      const Matrix expected =
          quadratureJacobian(s, rule, [&](const QPoint& q, const MovingBasis& mb, Eigen::Index m) {
            const SurfacePoint sp = s.evaluate(net, q.u, q.v, 1);
            const Eigen::Vector3d N = sp.du.cross(sp.dv);
            const Eigen::Vector3d n = N.normalized();
            // d n / d P_m = (I - n n^T) (B_m,u [.] x S_v + B_m,v S_u x [.]) / |N|
            const Eigen::Matrix3d dN = -mb.bu[m] * cross(sp.dv) + mb.bv[m] * cross(sp.du);
            return Eigen::Matrix3d(p * (Eigen::Matrix3d::Identity() - n * n.transpose()) * dN / N.norm());
          });
      const double err = maxAbs(J - expected) / maxAbs(expected);
      CHECK(err < 1e-6);
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
      figure(model.name + fmt(" pressure, bump %.1f: FD relative error %.1e, sigma %.3f", amp, err, sigma) +
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
