// SPDX-License-Identifier: MIT
// The classified squared distances against brute force: the minimum over a fine sampling of the
// primitives' parameters (never below it, and within the sampling's resolution of it). Their
// gradients and Hessians against central differences, formula by formula and class by class.
#include <catch2/catch.hpp>

#include <Eigen/Geometry>
#include <array>
#include <functional>
#include <random>

#include "../support/FixedDifferences.h"
#include "bsdeform/contact/Distance.h"

using bsdeform::EdgeEdgeType;
using bsdeform::PointTriangleType;
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

namespace {

using bsdeform::test::Mat;
using bsdeform::test::pointOf;
using bsdeform::test::Vec;

/// The step of the central differences: its truncation error h² f''' and rounding error ε f / h
/// are both near 1e-10 for the O(1) configurations below, far under the tolerance.
constexpr double kStep = 1e-5;
constexpr double kTolerance = 1e-6;
/// Gradients and Hessians smaller than this are compared absolutely (points almost on the plane).
constexpr double kFloor = 1e-3;

/// Checks a formula's value, gradient and Hessian against differences at x.
template <int N>
void checkFormula(const std::function<double(const Vec<N>&)>& value,
                  const std::function<double(const Vec<N>&, Vec<N>&, Mat<N>&)>& derivatives, const Vec<N>& x) {
  Vec<N> g;
  Mat<N> h;
  const double d = derivatives(x, g, h);
  CHECK(d == Approx(value(x)).epsilon(1e-12));
  CHECK(bsdeform::test::relativeError(g, bsdeform::test::differenceGradient<N>(value, x, kStep), kFloor) < kTolerance);
  const std::function<Vec<N>(const Vec<N>&)> gradient = [&](const Vec<N>& y) {
    Vec<N> gy;
    Mat<N> hy;
    derivatives(y, gy, hy);
    return gy;
  };
  CHECK(bsdeform::test::relativeError(h, bsdeform::test::differenceJacobian<N>(gradient, x, kStep), kFloor) <
        kTolerance);
  CHECK((h - h.transpose()).norm() <= 1e-12 * h.norm());
}

Vec<12> randomCoordinates(std::mt19937& rng) {
  Vec<12> x;
  for (int i = 0; i < 4; ++i) x.segment<3>(3 * i) = randomPoint(rng);
  return x;
}

}  // namespace

TEST_CASE("Distance: the four formulas' gradients and Hessians equal central differences", "[contact]") {
  std::mt19937 rng(23);
  int checked[4] = {0, 0, 0, 0};
  for (int trial = 0; trial < 100; ++trial) {
    const Vec<12> x = randomCoordinates(rng);
    const Vector3d p0 = pointOf<12>(x, 0), p1 = pointOf<12>(x, 1), p2 = pointOf<12>(x, 2), p3 = pointOf<12>(x, 3);
    checkFormula<6>(
        [](const Vec<6>& z) { return bsdeform::pointPointDistanceSquared(pointOf<6>(z, 0), pointOf<6>(z, 1)); },
        [](const Vec<6>& z, Vec<6>& g, Mat<6>& h) {
          return bsdeform::pointPointDistanceSquaredDerivatives(pointOf<6>(z, 0), pointOf<6>(z, 1), g, &h);
        },
        x.head<6>());
    ++checked[0];
    // Well-conditioned configurations only: the formulas divide by |e1 - e0|² and |n|².
    if ((p2 - p1).norm() > 0.3) {
      checkFormula<9>(
          [](const Vec<9>& z) {
            return bsdeform::pointLineDistanceSquared(pointOf<9>(z, 0), pointOf<9>(z, 1), pointOf<9>(z, 2));
          },
          [](const Vec<9>& z, Vec<9>& g, Mat<9>& h) {
            return bsdeform::pointLineDistanceSquaredDerivatives(pointOf<9>(z, 0), pointOf<9>(z, 1), pointOf<9>(z, 2),
                                                                 g, &h);
          },
          x.head<9>());
      ++checked[1];
    }
    if ((p2 - p1).cross(p3 - p1).norm() > 0.2) {
      checkFormula<12>(
          [](const Vec<12>& z) {
            return bsdeform::pointPlaneDistanceSquared(pointOf<12>(z, 0), pointOf<12>(z, 1), pointOf<12>(z, 2),
                                                       pointOf<12>(z, 3));
          },
          [](const Vec<12>& z, Vec<12>& g, Mat<12>& h) {
            return bsdeform::pointPlaneDistanceSquaredDerivatives(pointOf<12>(z, 0), pointOf<12>(z, 1),
                                                                  pointOf<12>(z, 2), pointOf<12>(z, 3), g, &h);
          },
          x);
      ++checked[2];
    }
    if ((p1 - p0).cross(p3 - p2).norm() > 0.2) {
      checkFormula<12>(
          [](const Vec<12>& z) {
            return bsdeform::lineLineDistanceSquared(pointOf<12>(z, 0), pointOf<12>(z, 1), pointOf<12>(z, 2),
                                                     pointOf<12>(z, 3));
          },
          [](const Vec<12>& z, Vec<12>& g, Mat<12>& h) {
            return bsdeform::lineLineDistanceSquaredDerivatives(pointOf<12>(z, 0), pointOf<12>(z, 1),
                                                                pointOf<12>(z, 2), pointOf<12>(z, 3), g, &h);
          },
          x);
      ++checked[3];
    }
  }
  for (int k = 0; k < 4; ++k) CHECK(checked[k] >= 30);
}

TEST_CASE("Distance: x = |(a1 - a0) x (b1 - b0)|² derivatives equal central differences", "[contact]") {
  std::mt19937 rng(29);
  for (int trial = 0; trial < 50; ++trial)
    checkFormula<12>(
        [](const Vec<12>& z) {
          return (pointOf<12>(z, 1) - pointOf<12>(z, 0)).cross(pointOf<12>(z, 3) - pointOf<12>(z, 2)).squaredNorm();
        },
        [](const Vec<12>& z, Vec<12>& g, Mat<12>& h) {
          return bsdeform::edgeEdgeCrossSquaredNormDerivatives(pointOf<12>(z, 0), pointOf<12>(z, 1), pointOf<12>(z, 2),
                                                               pointOf<12>(z, 3), g, &h);
        },
        randomCoordinates(rng));
}

namespace {

/// Whether every ±kStep move of one coordinate keeps the class (then the classified distance is
/// one formula on the whole difference stencil).
template <class Classify>
bool classIsStable(const Classify& classify, const Vec<12>& x) {
  const auto type = classify(x);
  for (int i = 0; i < 12; ++i)
    for (double sign : {-1.0, 1.0}) {
      Vec<12> y = x;
      y[i] += sign * kStep;
      if (classify(y) != type) return false;
    }
  return true;
}

}  // namespace

TEST_CASE("Distance: point-triangle derivatives of every class equal differences of the classified distance",
          "[contact]") {
  std::mt19937 rng(31);
  const auto classify = [](const Vec<12>& z) {
    return bsdeform::pointTriangleType(pointOf<12>(z, 0), pointOf<12>(z, 1), pointOf<12>(z, 2), pointOf<12>(z, 3));
  };
  // The classified distance itself: the classifier runs again at each perturbed configuration, so
  // the derivatives must be those of the formula the class selects, at the right points.
  const std::function<double(const Vec<12>&)> value = [](const Vec<12>& z) {
    return pointTriangleDistanceSquared(pointOf<12>(z, 0), pointOf<12>(z, 1), pointOf<12>(z, 2), pointOf<12>(z, 3));
  };
  const std::function<double(const Vec<12>&, Vec<12>&, Mat<12>&)> derivatives = [&](const Vec<12>& z, Vec<12>& g,
                                                                                     Mat<12>& h) {
    return bsdeform::pointTriangleDistanceSquaredDerivatives(pointOf<12>(z, 0), pointOf<12>(z, 1), pointOf<12>(z, 2),
                                                             pointOf<12>(z, 3), classify(z), g, &h);
  };
  std::array<int, 7> seen{};
  for (int trial = 0; trial < 3000; ++trial) {
    Vec<12> x = randomCoordinates(rng);
    x.head<3>() *= 2.0;  // points outside the triangle's prism too, for the vertex and edge classes
    const Vector3d t0 = pointOf<12>(x, 1), t1 = pointOf<12>(x, 2), t2 = pointOf<12>(x, 3);
    if ((t1 - t0).cross(t2 - t0).norm() < 0.2 || (t1 - t0).norm() < 0.3 || (t2 - t1).norm() < 0.3 ||
        (t0 - t2).norm() < 0.3)
      continue;
    if (!classIsStable(classify, x)) continue;
    const int type = static_cast<int>(classify(x));
    if (seen[type] >= 15) continue;
    ++seen[type];
    checkFormula<12>(value, derivatives, x);
  }
  for (int count : seen) CHECK(count >= 5);
}

TEST_CASE("Distance: edge-edge derivatives of every class equal differences of the classified distance",
          "[contact]") {
  std::mt19937 rng(37);
  const auto classify = [](const Vec<12>& z) {
    return bsdeform::edgeEdgeType(pointOf<12>(z, 0), pointOf<12>(z, 1), pointOf<12>(z, 2), pointOf<12>(z, 3));
  };
  const std::function<double(const Vec<12>&)> value = [](const Vec<12>& z) {
    return edgeEdgeDistanceSquared(pointOf<12>(z, 0), pointOf<12>(z, 1), pointOf<12>(z, 2), pointOf<12>(z, 3));
  };
  const std::function<double(const Vec<12>&, Vec<12>&, Mat<12>&)> derivatives = [&](const Vec<12>& z, Vec<12>& g,
                                                                                     Mat<12>& h) {
    return bsdeform::edgeEdgeDistanceSquaredDerivatives(pointOf<12>(z, 0), pointOf<12>(z, 1), pointOf<12>(z, 2),
                                                        pointOf<12>(z, 3), classify(z), g, &h);
  };
  std::array<int, 9> seen{};
  for (int trial = 0; trial < 6000; ++trial) {
    const Vec<12> x = randomCoordinates(rng);
    const Vector3d a0 = pointOf<12>(x, 0), a1 = pointOf<12>(x, 1), b0 = pointOf<12>(x, 2), b1 = pointOf<12>(x, 3);
    if ((a1 - a0).norm() < 0.3 || (b1 - b0).norm() < 0.3 || (a1 - a0).cross(b1 - b0).norm() < 0.1) continue;
    if (!classIsStable(classify, x)) continue;
    const int type = static_cast<int>(classify(x));
    if (seen[type] >= 15) continue;
    ++seen[type];
    checkFormula<12>(value, derivatives, x);
  }
  for (int count : seen) CHECK(count >= 5);
}

TEST_CASE("Distance: a gradient asked without the Hessian has the bits of the one with it", "[contact]") {
  // The barrier's loads ask for gradients alone (no Hessian products); the Jacobian asks for both.
  // Both must describe the same function: the same gradient to the last bit, in every class.
  std::mt19937 rng(41);
  std::array<int, 7> pointTriangle{};
  std::array<int, 9> edgeEdge{};
  for (int trial = 0; trial < 4000; ++trial) {
    Vec<12> x = randomCoordinates(rng);
    x.head<3>() *= 2.0;
    const Vector3d p0 = pointOf<12>(x, 0), p1 = pointOf<12>(x, 1), p2 = pointOf<12>(x, 2), p3 = pointOf<12>(x, 3);
    // one formula's value and gradient asked with the Hessian and without it
    const auto checkAlone = [](const auto& derivatives) {
      Vec<12> g, gAlone;
      Mat<12> h;
      CHECK(derivatives(g, &h) == derivatives(gAlone, nullptr));
      CHECK((g.array() == gAlone.array()).all());
    };
    const auto pt = bsdeform::pointTriangleType(p0, p1, p2, p3);
    checkAlone([&](Vec<12>& g, Mat<12>* h) {
      return bsdeform::pointTriangleDistanceSquaredDerivatives(p0, p1, p2, p3, pt, g, h);
    });
    ++pointTriangle[static_cast<size_t>(pt)];
    const auto ee = bsdeform::edgeEdgeType(p0, p1, p2, p3);
    checkAlone([&](Vec<12>& g, Mat<12>* h) {
      return bsdeform::edgeEdgeDistanceSquaredDerivatives(p0, p1, p2, p3, ee, g, h);
    });
    ++edgeEdge[static_cast<size_t>(ee)];
    checkAlone([&](Vec<12>& g, Mat<12>* h) {
      return bsdeform::edgeEdgeCrossSquaredNormDerivatives(p0, p1, p2, p3, g, h);
    });
  }
  for (int count : pointTriangle) CHECK(count > 0);
  for (int count : edgeEdge) CHECK(count > 0);
}

TEST_CASE("Distance: the lower bounds never call a pair within r farther than r, and are tight where they should be",
          "[contact]") {
  using bsdeform::edgeEdgeFartherThan;
  using bsdeform::pointTriangleFartherThan;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> factor(0.3, 1.7), scale(-4.0, 1.0);
  int pointTriangleClaims = 0, edgeEdgeClaims = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    // random pairs at scales from 10⁻⁴ to 10 (slivers and near-parallel edges among them)
    const double s = std::pow(10.0, scale(rng));
    Vector3d p = s * randomPoint(rng), t0 = s * randomPoint(rng), t1 = s * randomPoint(rng), t2 = s * randomPoint(rng);
    if (trial % 5 == 0) t2 = t0 + (1.0 + 1e-9 * factor(rng)) * (t1 - t0) + 1e-12 * s * randomPoint(rng);  // a sliver
    if (trial % 7 == 0) t2 = t0 + 1e-3 * (t2 - t0);  // a thin one
    const double dt = std::sqrt(pointTriangleDistanceSquared(p, t0, t1, t2));
    const double rt = factor(rng) * dt;
    if (pointTriangleFartherThan(p, t0, t1, t2, rt)) {
      ++pointTriangleClaims;
      CHECK(dt > rt);
    }
    Vector3d b1 = t2;
    if (trial % 3 == 0) b1 = t2 + (t1 - t0) * (1.0 + 1e-8 * factor(rng));  // near parallel to a0 a1
    const double de = std::sqrt(edgeEdgeDistanceSquared(t0, t1, t2, b1));
    const double re = factor(rng) * de;
    if (edgeEdgeFartherThan(t0, t1, t2, b1, re)) {
      ++edgeEdgeClaims;
      CHECK(de > re);
    }
    // within r: never farther (r with a margin for the rounding of coordinates of size s: a
    // bounding sphere's test is exact for collinear segments end to end)
    CHECK_FALSE(pointTriangleFartherThan(p, t0, t1, t2, dt * (1.0 + 1e-6) + 1e-12 * s));
    CHECK_FALSE(edgeEdgeFartherThan(t0, t1, t2, b1, de * (1.0 + 1e-6) + 1e-12 * s));
  }
  // they do claim (random pairs in a cube, r from 0.3 to 1.7 of the distance: 5 477 and 925 of
  // the 20 000 with this seed; segments whose lines pass near each other are many)
  CAPTURE(pointTriangleClaims, edgeEdgeClaims);
  CHECK(pointTriangleClaims > 2500);
  CHECK(edgeEdgeClaims > 450);
  // tight where the bound is the distance: a point over the triangle's inside, crossing edges
  const Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  CHECK(pointTriangleFartherThan(Vector3d(0.2, 0.2, 0.05), a, b, c, 0.0499));
  CHECK_FALSE(pointTriangleFartherThan(Vector3d(0.2, 0.2, 0.05), a, b, c, 0.0501));
  const Vector3d e0(-1, 0, 0), e1(1, 0, 0), f0(0, -1, 0.03), f1(0, 1, 0.03);
  CHECK(edgeEdgeFartherThan(e0, e1, f0, f1, 0.0299));
  CHECK_FALSE(edgeEdgeFartherThan(e0, e1, f0, f1, 0.0301));
  // far apart: the spheres' bound, also for parallel edges and a degenerate triangle
  CHECK(edgeEdgeFartherThan(Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(0, 5, 0), Vector3d(1, 5, 0), 3.0));
  CHECK(pointTriangleFartherThan(Vector3d(9, 9, 9), a, b, 0.5 * (a + b), 5.0));
}
