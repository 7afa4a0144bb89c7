// SPDX-License-Identifier: MIT
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>

#include "bsdeform/spline/RestShape.h"
#include "bsdeform/dynamics/Simulation.h"

using namespace bsdeform;

namespace {
const ShapeKind kClosed[] = {ShapeKind::Cylinder, ShapeKind::Cone, ShapeKind::Sphere, ShapeKind::Ellipsoid,
                             ShapeKind::Torus};

struct Built {
  ModelParameters params;
  SplineSpace space;
  ControlNet rest;
};

Built build(ShapeKind kind, int N, int n = 3, const ShapeSize& size = ShapeSize()) {
  ModelParameters p;
  p.degreeU = p.degreeV = n;
  p.numU = p.numV = N;
  p.boundaries = shapeBoundaries(kind, Boundaries());
  SplineSpace s(n, n, N, N, p.boundaries);
  ControlNet rest = shapeRestNet(kind, size, s);
  return {p, s, rest};
}
}  // namespace

TEST_CASE("RestShape: every shape approximates the exact one and the error falls with the net size", "[core]") {
  for (ShapeKind kind : kClosed) {
    const Built a = build(kind, 8), b = build(kind, 16), c = build(kind, 32);
    const double ea = shapeGeometricError(kind, ShapeSize(), a.space, a.rest);
    const double eb = shapeGeometricError(kind, ShapeSize(), b.space, b.rest);
    const double ec = shapeGeometricError(kind, ShapeSize(), c.space, c.rest);
    INFO(shapeName(kind) << ": errors at N = 8, 16, 32: " << ea << ", " << eb << ", " << ec);
    CHECK(eb < ea);
    CHECK(ec < 0.5 * eb);
    CHECK(eb < 0.02);  // at the scenes' size, 16 x 16, default sizes (about 1 unit across)
  }
}

TEST_CASE("RestShape: poles and apex are met exactly, seams close, boundaries are imposed", "[core]") {
  const ShapeSize size;
  for (ShapeKind kind : {ShapeKind::Sphere, ShapeKind::Ellipsoid}) {
    const Built b = build(kind, 10);
    const double c = kind == ShapeKind::Sphere ? size.radius : size.radii.z();
    // every control point of the n pole layers is the pole (held rows collapsed), so S meets
    // it up to the rounding of the partition of unity
    for (int k1 = -3; k1 < 13; ++k1)
      for (int l = 1; l <= 3; ++l) {
        CHECK(b.rest.row(b.space.netIndex(k1, -l)) == Eigen::RowVector3d(0, 0, -c));
        CHECK(b.rest.row(b.space.netIndex(k1, 10 + 3 - l)) == Eigen::RowVector3d(0, 0, c));
      }
    for (double u : {0.0, 0.13, 0.5, 0.77, 1.0}) {
      CHECK((b.space.evaluate(b.rest, u, 0.0, 0).position - Eigen::Vector3d(0, 0, -c)).norm() <= 1e-15);
      CHECK((b.space.evaluate(b.rest, u, 1.0, 0).position - Eigen::Vector3d(0, 0, c)).norm() <= 1e-15);
    }
    CHECK(b.params.boundaries.vMin == Boundary::Clamped);
    CHECK(b.params.boundaries.vMax == Boundary::Clamped);
  }
  const Built cone = build(ShapeKind::Cone, 10);
  for (double u : {0.0, 0.4, 1.0})
    CHECK((cone.space.evaluate(cone.rest, u, 1.0, 0).position - Eigen::Vector3d(0, 0, 0.5 * size.height)).norm() <=
          1e-15);
  for (ShapeKind kind : kClosed) {
    const Built b = build(kind, 9);
    CHECK(b.params.boundaries.uMin == Boundary::Periodic);
    for (double v : {0.2, 0.5, 0.8}) {
      const SurfacePoint p0 = b.space.evaluate(b.rest, 0.0, v, 2), p1 = b.space.evaluate(b.rest, 1.0, v, 2);
      CHECK((p0.position - p1.position).norm() < 1e-14);
      CHECK((p0.du - p1.du).norm() < 1e-12);
    }
  }
  CHECK_THROWS_WITH(shapeRestNet(ShapeKind::Sphere, ShapeSize{-1.0}, build(ShapeKind::Sphere, 5).space),
                    Catch::Contains("radius") && Catch::Contains("-1"));
}

TEST_CASE("RestShape: every generated shape is an equilibrium of the unloaded model (reference REST)", "[core]") {
  for (ShapeKind kind : kClosed)
    for (Integrator integ : {Integrator::Explicit, Integrator::Implicit}) {
      Built b = build(kind, 8);
      b.params.integrator = integ;
      b.params.massModel = MassModel::Lumped;
      Simulation sim(b.params, b.rest);
      sim.advance(100);
      REQUIRE(sim.status() == Status::Ok);
      INFO(shapeName(kind));
      CHECK((sim.current() - sim.rest()).cwiseAbs().maxCoeff() < 1e-13);
    }
}

TEST_CASE("RestShape: a sphere under uniform pressure inflates and keeps its symmetries", "[core][slow]") {
  Built b = build(ShapeKind::Sphere, 12);
  b.params.massModel = MassModel::Lumped;
  b.params.damping = 4.0;
  b.params.weights = Weights{0.5, 0.5, 0.01, 0.01, 0.01};
  b.params.timeStep = 0.05;
  Simulation sim(b.params, b.rest);
  sim.addForce(std::make_shared<DistributedForce>([](const SurfaceSample& s) { return Eigen::Vector3d(0.3 * s.normal); },
                                                  kDependsOnNormal));
  sim.advance(400);
  REQUIRE(sim.status() == Status::Ok);
  double rMin = 1e9, rMax = 0, asym = 0, outward = 1e9;
  for (int i = 0; i <= 24; ++i)
    for (int j = 1; j < 24; ++j) {
      const double u = i / 24.0, v = j / 24.0;
      const Eigen::Vector3d p = sim.evaluate(u, v).position, q = sim.evaluate(u, 1.0 - v).position;
      const double r = p.norm();
      rMin = std::min(rMin, r);
      rMax = std::max(rMax, r);
      // north-south mirror symmetry and rotational symmetry about z
      asym = std::max(asym, std::abs(p.z() + q.z()) + std::abs(std::hypot(p.x(), p.y()) - std::hypot(q.x(), q.y())));
      asym = std::max(asym, std::abs(std::hypot(p.x(), p.y()) -
                                     std::hypot(sim.evaluate(std::fmod(u + 1.0 / 15, 1.0), v).position.x(),
                                                sim.evaluate(std::fmod(u + 1.0 / 15, 1.0), v).position.y())) *
                                (std::abs(u * 15 - std::round(u * 15)) < 1e-9));
      outward = std::min(outward, (p - sim.space().evaluate(sim.rest(), u, v, 0).position).dot(p.normalized()));
    }
  INFO("radius from " << rMin << " to " << rMax << ", asymmetry " << asym);
  CHECK(outward > 0.0);         // every point moved out
  CHECK(asym < 1e-10);          // mirror and rotation symmetric
  CHECK(rMax > 0.505);          // inflated beyond the rest radius 0.5
}
