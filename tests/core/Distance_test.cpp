// SPDX-License-Identifier: MIT
// The classified squared distances against brute force: the minimum over a fine sampling of the
// primitives' parameters (never below it, and within the sampling's resolution of it).
#include <catch2/catch.hpp>

#include <Eigen/Geometry>
#include <random>

#include "bsdeform/contact/Distance.h"

using bsdeform::edgeEdgeDistanceSquared;
using bsdeform::pointTriangleDistanceSquared;
using Eigen::Vector3d;

namespace {
Vector3d randomPoint(std::mt19937& rng) {
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  return {d(rng), d(rng), d(rng)};
}
}  // namespace

TEST_CASE("Distance: point-triangle equals the sampled minimum", "[contact]") {
  std::mt19937 rng(7);
  const int n = 200;
  for (int trial = 0; trial < 200; ++trial) {
    const Vector3d p = randomPoint(rng), t0 = randomPoint(rng), t1 = randomPoint(rng), t2 = randomPoint(rng);
    if ((t1 - t0).cross(t2 - t0).norm() < 1e-2) continue;
    double best = 1e300;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const Vector3d q = t0 + (t1 - t0) * (double(i) / n) + (t2 - t0) * (double(j) / n);
        best = std::min(best, (p - q).squaredNorm());
      }
    const double d2 = pointTriangleDistanceSquared(p, t0, t1, t2);
    CHECK(d2 <= best + 1e-12);
    CHECK(std::sqrt(best) - std::sqrt(d2) < 4.0 / n);
  }
}

TEST_CASE("Distance: edge-edge equals the sampled minimum, parallel pairs included", "[contact]") {
  std::mt19937 rng(11);
  const int n = 400;
  for (int trial = 0; trial < 300; ++trial) {
    const Vector3d a0 = randomPoint(rng), a1 = randomPoint(rng), b0 = randomPoint(rng);
    Vector3d b1 = randomPoint(rng);
    if (trial % 5 == 0) b1 = b0 + 0.7 * (a1 - a0);  // parallel
    double best = 1e300;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j) {
        const Vector3d pa = a0 + (a1 - a0) * (double(i) / n), pb = b0 + (b1 - b0) * (double(j) / n);
        best = std::min(best, (pa - pb).squaredNorm());
      }
    const double d2 = edgeEdgeDistanceSquared(a0, a1, b0, b1);
    CHECK(d2 <= best + 1e-12);
    CHECK(std::sqrt(best) - std::sqrt(d2) < 4.0 / n);
  }
}
