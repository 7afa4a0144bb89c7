// SPDX-License-Identifier: MIT
// The tensor-product spline space (SplineSpace.h): the Greville plane, parameter and size
// validation, and the bookkeeping of moving points, periodic copies and held layers for every
// side kind.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>
#include <utility>

#include "bsdeform/spline/RestShape.h"
#include "bsdeform/spline/SplineSpace.h"

using namespace bsdeform;

TEST_CASE("SplineSpace: the Greville plane is exactly S(u,v) = (u, v, 0)", "[core]") {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (int n1 = 1; n1 <= kMaxDegree; n1 += 2)
    for (int n2 = 1; n2 <= 4; ++n2) {
      SplineSpace s(n1, n2, 5, 7);
      const ControlNet net = s.grevillePlane();
      for (int t = 0; t < 30; ++t) {
        const double u = U(rng), v = U(rng);
        const SurfacePoint p = s.evaluate(net, u, v, 2);
        CHECK((p.position - Eigen::Vector3d(u, v, 0)).norm() < 1e-14);
        CHECK((p.du - Eigen::Vector3d(1, 0, 0)).norm() < 1e-12);
        CHECK((p.dv - Eigen::Vector3d(0, 1, 0)).norm() < 1e-12);
        CHECK(p.duu.norm() < 1e-9);
        CHECK(p.duv.norm() < 1e-9);
        CHECK(p.dvv.norm() < 1e-9);
        CHECK((p.normal() - Eigen::Vector3d(0, 0, 1)).norm() < 1e-12);
      }
    }
}

TEST_CASE("SplineSpace: bad degrees and counts are rejected with the parameter and value", "[core]") {
  CHECK_THROWS_WITH(SplineSpace(0, 3, 5, 5), Catch::Contains("degreeU") && Catch::Contains("got 0"));
  CHECK_THROWS_WITH(SplineSpace(3, 8, 5, 5), Catch::Contains("degreeV") && Catch::Contains("got 8"));
  CHECK_THROWS_WITH(SplineSpace(3, 3, 0, 5), Catch::Contains("numU") && Catch::Contains("got 0"));
  CHECK_THROWS_WITH(SplineSpace(3, 3, 5, -2), Catch::Contains("numV") && Catch::Contains("got -2"));
}

TEST_CASE("SplineSpace: the size limits are checked here, named, and never overflow", "[core]") {
  CHECK_NOTHROW(SplineSpace(3, 3, 2048, 2048));
  CHECK_NOTHROW(SplineSpace(3, 3, 65536, 64));
  CHECK_THROWS_WITH(SplineSpace(3, 3, 2049, 2048),
                    Catch::Contains("numU * numV must be at most 4194304") && Catch::Contains("got 4196352"));
  CHECK_THROWS_WITH(SplineSpace(3, 3, 65537, 1), Catch::Contains("numU must be at most 65536"));
  // extreme values are refused by name, before any product is formed
  const int huge = std::numeric_limits<int>::max(), tiny = std::numeric_limits<int>::min();
  CHECK_THROWS_WITH(SplineSpace(tiny, 3, 5, 5), Catch::Contains("degreeU"));
  CHECK_THROWS_WITH(SplineSpace(3, huge, 5, 5), Catch::Contains("degreeV"));
  CHECK_THROWS_WITH(SplineSpace(3, 3, huge, huge), Catch::Contains("numU must be at most"));
  CHECK_THROWS_WITH(SplineSpace(3, 3, 5, tiny), Catch::Contains("numV"));
}

TEST_CASE("SplineSpace: moving points gather and scatter back, map to their B-splines, and periodic copies follow",
          "[core]") {
  using B = Boundary;
  const Boundaries sideSets[] = {Boundaries{},
                                 Boundaries{B::Free, B::Free, B::Free, B::Free},
                                 Boundaries{B::Free, B::Clamped, B::Clamped, B::Free},
                                 Boundaries{B::Periodic, B::Periodic, B::Clamped, B::Free},
                                 Boundaries{B::Periodic, B::Periodic, B::Periodic, B::Periodic},
                                 Boundaries{B::SimplySupported, B::BuiltIn, B::Free, B::Clamped}};
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> X(-1.0, 1.0);
  for (const Boundaries& sides : sideSets)
    for (const auto& [n1, n2] : {std::pair{3, 2}, std::pair{1, 4}}) {
      const SplineSpace s(n1, n2, 6, 5, sides);
      INFO("degrees " << n1 << ", " << n2 << "; sides " << boundaryName(sides.uMin) << " " << boundaryName(sides.uMax)
                      << " " << boundaryName(sides.vMin) << " " << boundaryName(sides.vMax));
      CHECK(s.numMoving() == Eigen::Index(s.movingU().count) * s.movingV().count);
      const bool clamped = sides.uMin == B::Clamped && sides.uMax == B::Clamped && sides.vMin == B::Clamped && sides.vMax == B::Clamped;
      if (clamped) CHECK(s.numMoving() == Eigen::Index(s.numU()) * s.numV());  // the paper's free points
      // every moving point is moving where it sits, and its B-spline maps back to it
      for (Eigen::Index f = 0; f < s.numMoving(); ++f) {
        const Eigen::Index r = s.movingToNet(f);
        const int i = int(r / s.netCols()), j = int(r % s.netCols());
        CHECK(s.isMoving(i, j));
        CHECK(s.movingLayerU(i) == i);
        CHECK(s.movingLayerV(j) == j);
        CHECK(s.movingIndex(i - s.degreeU(), j - s.degreeV()) == f);
        CHECK(s.foldU(i).size() == 1);
        CHECK(s.foldU(i).front().layer == i);
      }
      // gather after scatter is the identity; scatter writes nothing but moving points and copies
      ControlNet P(s.numMoving(), 3);
      for (Eigen::Index k = 0; k < P.size(); ++k) P.data()[k] = X(rng);
      ControlNet net = ControlNet::Constant(s.netSize(), 3, 7.0);
      s.scatterMoving(P, net);
      CHECK(s.gatherMoving(net) == P);
      for (int i = 0; i < s.netRows(); ++i)
        for (int j = 0; j < s.netCols(); ++j) {
          const int mi = s.movingLayerU(i), mj = s.movingLayerV(j);
          const Eigen::RowVector3d p = net.row(Eigen::Index(i) * s.netCols() + j);
          if (mi >= 0 && mj >= 0) {  // a moving point or a periodic copy of one: the copy's value
            CHECK(s.movingIndex(i - s.degreeU(), j - s.degreeV()) >= 0);
            CHECK(p == net.row(Eigen::Index(mi) * s.netCols() + mj));
          } else {
            CHECK(s.movingIndex(i - s.degreeU(), j - s.degreeV()) == -1);
            CHECK(p == Eigen::RowVector3d::Constant(7.0));
          }
        }
    }
}

TEST_CASE("SplineSpace: a surface is closed when it has no boundary curve: sphere, ellipsoid and torus but not plane, cylinder or cone",
          "[core]") {
  const ShapeSize size{0.5, 1.0, 0.2, Eigen::Vector3d(0.6, 0.45, 0.35)};
  const std::pair<ShapeKind, bool> kinds[] = {{ShapeKind::Plane, false},  {ShapeKind::Cylinder, false},
                                              {ShapeKind::Cone, false},   {ShapeKind::Sphere, true},
                                              {ShapeKind::Ellipsoid, true}, {ShapeKind::Torus, true}};
  for (const auto& k : kinds) {
    INFO(shapeName(k.first));
    const SplineSpace space(3, 3, 10, 8, shapeBoundaries(k.first, Boundaries{}));
    const ControlNet net = shapeRestNet(k.first, size, space);
    CHECK(isClosedSurface(space, net) == k.second);
  }
  // one end of the tube collapsed to a point (a cone's apex): the other end is still a curve
  const SplineSpace tube(3, 3, 10, 8, shapeBoundaries(ShapeKind::Cylinder, Boundaries{}));
  ControlNet capped = shapeRestNet(ShapeKind::Cylinder, size, tube);
  for (Eigen::Index i = 0; i < tube.netRows(); ++i)
    for (int j = 0; j < tube.degreeV() + 1; ++j) capped.row(i * tube.netCols() + j) = Eigen::RowVector3d(0, 0, -0.5);
  CHECK(!isClosedSurface(tube, capped));
}

TEST_CASE("SplineSpace: surfaceArea of the plane is 1 and of the sphere 4 pi R^2 to the net's geometric error", "[core]") {
  const SplineSpace plane(3, 2, 6, 5);
  CHECK(surfaceArea(plane, plane.grevillePlane()) == Approx(1.0).epsilon(1e-13));
  const ShapeSize size{0.5, 1.0, 0.2, Eigen::Vector3d(0.6, 0.45, 0.35)};
  const SplineSpace sphere(3, 3, 24, 16, shapeBoundaries(ShapeKind::Sphere, Boundaries{}));
  const double area = surfaceArea(sphere, shapeRestNet(ShapeKind::Sphere, size, sphere));
  CHECK(area == Approx(4.0 * M_PI * 0.25).epsilon(2e-2));
}
