// SPDX-License-Identifier: MIT
#include <catch2/catch.hpp>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "bsdeform/spline/SplineSpace.h"
#include "bsdeform/spline/Tessellation.h"

using namespace bsdeform;

namespace {
ControlNet randomNet(const SplineSpace& sp, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> noise(-0.02, 0.02);
  ControlNet net(sp.netSize(), 3);  // a plane, jittered, with bumps no steeper than about 1
  for (int i = 0; i < sp.netRows(); ++i)
    for (int j = 0; j < sp.netCols(); ++j)
      net.row(i * sp.netCols() + j) << i / double(sp.netRows()) + noise(rng), j / double(sp.netCols()) + noise(rng),
          0.1 * std::sin(3.0 * i + 2.0 * j) + noise(rng);
  return net;
}
Eigen::Vector3d at(const std::vector<float>& a, size_t vertex) {
  return Eigen::Vector3d(a[vertex * 3], a[vertex * 3 + 1], a[vertex * 3 + 2]);
}
}  // namespace

TEST_CASE("Tessellation: vertices, normals, triangles and box of the grid", "[core]") {
  const SplineSpace sp(3, 2, 7, 6);
  const ControlNet net = randomNet(sp, 1);
  SurfaceGrid g;
  const int segU = 13, segV = 9;
  tessellate(sp, net, segU, segV, g);
  REQUIRE(g.vertices.size() == size_t(segU + 1) * (segV + 1) * 3);
  REQUIRE(g.indices.size() == size_t(segU) * segV * 6);
  double worstPoint = 0.0, worstNormal = 0.0;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
  for (int i = 0; i <= segU; ++i)
    for (int j = 0; j <= segV; ++j) {
      const size_t k = size_t(i) * (segV + 1) + j;
      const SurfacePoint p = sp.evaluate(net, double(i) / segU, double(j) / segV, 1);
      worstPoint = std::max(worstPoint, (at(g.vertices, k) - p.position).norm());
      worstNormal = std::max(worstNormal, (at(g.normals, k) - p.du.cross(p.dv).normalized()).norm());
      lo = lo.cwiseMin(at(g.vertices, k));
      hi = hi.cwiseMax(at(g.vertices, k));
      CHECK(g.texCoords[k * 2] == Approx(double(i) / segU));
      CHECK(g.texCoords[k * 2 + 1] == Approx(double(j) / segV));
    }
  CHECK(worstPoint < 1e-6);   // float rounding of values of order 1
  CHECK(worstNormal < 1e-6);
  for (int c = 0; c < 3; ++c) {  // the box is exactly that of the vertices
    CHECK(g.boundsMin[c] == float(lo[c]));
    CHECK(g.boundsMax[c] == float(hi[c]));
  }
  // every triangle is counter-clockwise seen from the side the normals point to
  int wrongWinding = 0;
  for (size_t t = 0; t < g.indices.size(); t += 3) {
    const Eigen::Vector3d a = at(g.vertices, g.indices[t]), b = at(g.vertices, g.indices[t + 1]),
                          c = at(g.vertices, g.indices[t + 2]);
    const Eigen::Vector3d n = at(g.normals, g.indices[t]) + at(g.normals, g.indices[t + 1]) + at(g.normals, g.indices[t + 2]);
    wrongWinding += (b - a).cross(c - a).dot(n) <= 0.0;
  }
  CHECK(wrongWinding == 0);
}

TEST_CASE("Tessellation: a new net at the same size reuses the grid's memory", "[core]") {
  // An animation tessellates every frame: at the same size nothing may be allocated (the
  // buffers keep their addresses) and the result is that of a fresh grid.
  const SplineSpace sp(3, 3, 9, 9);
  SurfaceGrid g;
  tessellate(sp, randomNet(sp, 2), 20, 24, g);
  const float* vertices = g.vertices.data();
  const float* normals = g.normals.data();
  const unsigned* indices = g.indices.data();
  const double* scratch = g.scratch.rawNormal.data();
  const ControlNet other = randomNet(sp, 3);
  tessellate(sp, other, 20, 24, g);
  CHECK(g.vertices.data() == vertices);
  CHECK(g.normals.data() == normals);
  CHECK(g.indices.data() == indices);
  CHECK(g.scratch.rawNormal.data() == scratch);
  SurfaceGrid fresh;
  tessellate(sp, other, 20, 24, fresh);
  CHECK(g.vertices == fresh.vertices);
  CHECK(g.normals == fresh.normals);
  CHECK(g.indices == fresh.indices);
  for (int c = 0; c < 3; ++c) {
    CHECK(g.boundsMin[c] == fresh.boundsMin[c]);
    CHECK(g.boundsMax[c] == fresh.boundsMax[c]);
  }
  tessellate(sp, other, 10, 12, g);  // another size: new indices
  CHECK(g.indices.size() == size_t(10) * 12 * 6);
}
