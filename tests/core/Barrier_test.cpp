// SPDX-License-Identifier: MIT
// The IPC barrier (docs/math.md §18): b(s) and its s-derivatives; the pair potentials' gradients
// against differences of their values and their exact Hessians against differences of the
// gradients (point–triangle, edge–edge, mollified near-parallel edges); the PSD projection; the
// barrier's shape in d (zero from ξ + d̂ on, positive and decreasing below, unbounded at ξ); the
// mollified edge–edge barrier's continuity as the edges become parallel; the adaptive stiffness.
#include <catch2/catch.hpp>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <limits>
#include <random>

#include "../support/FixedDifferences.h"
#include "bsdeform/contact/Barrier.h"
#include "bsdeform/contact/Distance.h"

using bsdeform::BarrierHessian;
using bsdeform::BarrierParameters;
using bsdeform::Matrix12d;
using bsdeform::Vector12d;
using bsdeform::test::pointOf;
using bsdeform::test::relativeError;
using Eigen::Vector3d;
using Vec12 = bsdeform::test::Vec<12>;

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// Lengths in the unit box; a d̂ and ξ large enough that random configurations fall in the
/// barrier's range often, small enough that the classes vary.
const BarrierParameters kParameters{0.05, 0.2, 3.0};
/// The central differences' step and the tolerance on the relative error.
constexpr double kStep = 1e-6;
constexpr double kTolerance = 1e-6;

Vector3d randomPoint(std::mt19937& rng, double scale = 1.0) {
  std::uniform_real_distribution<double> d(-scale, scale);
  return {d(rng), d(rng), d(rng)};
}

/// s / ŝ of a configuration, for picking those inside the barrier's range.
double pointTriangleActivation(const Vec12& x) {
  const double d2 = bsdeform::pointTriangleDistanceSquared(pointOf<12>(x, 0), pointOf<12>(x, 1), pointOf<12>(x, 2),
                                                           pointOf<12>(x, 3));
  return (d2 - kParameters.offset * kParameters.offset) / bsdeform::barrierSquaredActivation(kParameters);
}
double edgeEdgeActivation(const Vec12& x) {
  const double d2 =
      bsdeform::edgeEdgeDistanceSquared(pointOf<12>(x, 0), pointOf<12>(x, 1), pointOf<12>(x, 2), pointOf<12>(x, 3));
  return (d2 - kParameters.offset * kParameters.offset) / bsdeform::barrierSquaredActivation(kParameters);
}

/// Whether every ±kStep move of one coordinate keeps the class.
template <class Classify>
bool classIsStable(const Classify& classify, const Vec12& x) {
  const auto type = classify(x);
  for (int i = 0; i < 12; ++i)
    for (double sign : {-1.0, 1.0}) {
      Vec12 y = x;
      y[i] += sign * kStep;
      if (classify(y) != type) return false;
    }
  return true;
}

/// A pair potential as a function of 12 coordinates: value, and gradient and Hessian when asked.
using Potential = std::function<double(const Vec12&, Vector12d*, Matrix12d*, BarrierHessian)>;

/// The projected Hessian P of H: P is V max(Λ, 0) Vᵀ for the eigenpairs (Λ, V) of H, i.e. P v = λ v
/// for λ > 0 and P v = 0 otherwise.
void checkProjection(const Matrix12d& exact, const Matrix12d& projected) {
  const double scale = std::max(exact.norm(), 1e-300);
  const Eigen::SelfAdjointEigenSolver<Matrix12d> eigen(exact);
  for (int i = 0; i < 12; ++i) {
    const double lambda = eigen.eigenvalues()[i];
    const Vector12d v = eigen.eigenvectors().col(i);
    CHECK((projected * v - std::max(lambda, 0.0) * v).norm() <= 1e-10 * scale);
  }
  CHECK(Eigen::SelfAdjointEigenSolver<Matrix12d>(projected).eigenvalues().minCoeff() >= -1e-12 * scale);
  if (eigen.eigenvalues().minCoeff() >= 0.0) CHECK(projected == exact);
}

/// Gradient against differences of the value, exact Hessian against differences of the gradient,
/// projected Hessian against the exact one.
void checkPotential(const Potential& potential, const Vec12& x) {
  Vector12d grad;
  Matrix12d exact, projected;
  const double value = potential(x, &grad, &exact, BarrierHessian::Exact);
  REQUIRE(std::isfinite(value));
  CHECK(value > 0.0);
  CHECK(potential(x, nullptr, nullptr, BarrierHessian::Exact) == value);
  const std::function<double(const Vec12&)> f = [&](const Vec12& y) {
    return potential(y, nullptr, nullptr, BarrierHessian::Exact);
  };
  const std::function<Vec12(const Vec12&)> g = [&](const Vec12& y) {
    Vector12d gy;
    potential(y, &gy, nullptr, BarrierHessian::Exact);
    return Vec12(gy);
  };
  // Absolute floors: a gradient or Hessian far below the potential's own scale is compared as zero.
  CHECK(relativeError(grad, bsdeform::test::differenceGradient<12>(f, x, kStep), 1e-6) < kTolerance);
  CHECK(relativeError(exact, bsdeform::test::differenceJacobian<12>(g, x, kStep), 1e-6) < kTolerance);
  CHECK((exact - exact.transpose()).norm() <= 1e-12 * exact.norm());
  Vector12d grad2;
  potential(x, &grad2, &projected, BarrierHessian::ProjectedPsd);
  CHECK(grad2 == grad);
  checkProjection(exact, projected);
}

const Potential kPointTriangle = [](const Vec12& x, Vector12d* g, Matrix12d* h, BarrierHessian which) {
  return bsdeform::pointTriangleBarrier(pointOf<12>(x, 0), pointOf<12>(x, 1), pointOf<12>(x, 2), pointOf<12>(x, 3),
                                        kParameters, g, h, which);
};

/// The edge–edge potential with the mollifier threshold of given rest edges.
Potential edgeEdgePotential(double threshold) {
  return [threshold](const Vec12& x, Vector12d* g, Matrix12d* h, BarrierHessian which) {
    return bsdeform::edgeEdgeBarrier(pointOf<12>(x, 0), pointOf<12>(x, 1), pointOf<12>(x, 2), pointOf<12>(x, 3),
                                     threshold, kParameters, g, h, which);
  };
}

double thresholdOf(const Vec12& rest) {
  return bsdeform::edgeEdgeMollifierThreshold(pointOf<12>(rest, 0), pointOf<12>(rest, 1), pointOf<12>(rest, 2),
                                              pointOf<12>(rest, 3));
}

}  // namespace

TEST_CASE("Barrier: b' and b'' equal differences of b and b', b is 0 from ŝ on and +inf from 0 down", "[contact]") {
  for (double sHat : {1e-6, 0.06, 1.0}) {
    for (double u = 0.01; u < 1.0; u += 0.0245) {
      const double s = u * sHat, h = 1e-6 * s;
      const double b1 = bsdeform::barrierFirstDerivative(s, sHat), b2 = bsdeform::barrierSecondDerivative(s, sHat);
      const double fd1 = (bsdeform::barrier(s + h, sHat) - bsdeform::barrier(s - h, sHat)) / (2.0 * h);
      const double fd2 =
          (bsdeform::barrierFirstDerivative(s + h, sHat) - bsdeform::barrierFirstDerivative(s - h, sHat)) / (2.0 * h);
      CHECK(std::abs(fd1 - b1) <= 1e-6 * std::abs(b1));
      CHECK(std::abs(fd2 - b2) <= 1e-6 * std::abs(b2));
      CHECK(bsdeform::barrier(s, sHat) > 0.0);
      CHECK(b1 < 0.0);
      CHECK(b2 > 0.0);
    }
    // C² at ŝ: b and b' vanish there from below (and b''(ŝ) = 3 - 0 - 3 = 0).
    CHECK(bsdeform::barrier(sHat, sHat) == 0.0);
    CHECK(bsdeform::barrier(2.0 * sHat, sHat) == 0.0);
    CHECK(std::abs(bsdeform::barrier(sHat * (1.0 - 1e-6), sHat)) <= 1e-17 * sHat * sHat);
    CHECK(std::abs(bsdeform::barrierFirstDerivative(sHat * (1.0 - 1e-6), sHat)) <= 1e-11 * sHat);
    CHECK(bsdeform::barrierFirstDerivative(sHat, sHat) == 0.0);
    CHECK(bsdeform::barrierSecondDerivative(sHat, sHat) == 0.0);
    CHECK(bsdeform::barrier(0.0, sHat) == kInfinity);
    CHECK(bsdeform::barrier(-sHat, sHat) == kInfinity);
  }
}

TEST_CASE("Barrier: the point-triangle potential's derivatives equal differences, every class", "[contact]") {
  std::mt19937 rng(41);
  const auto classify = [](const Vec12& z) {
    return bsdeform::pointTriangleType(pointOf<12>(z, 0), pointOf<12>(z, 1), pointOf<12>(z, 2), pointOf<12>(z, 3));
  };
  int seen[7] = {0, 0, 0, 0, 0, 0, 0};
  for (int trial = 0; trial < 20000; ++trial) {
    Vec12 x;
    for (int i = 1; i < 4; ++i) x.segment<3>(3 * i) = randomPoint(rng);
    const Vector3d t0 = pointOf<12>(x, 1), t1 = pointOf<12>(x, 2), t2 = pointOf<12>(x, 3);
    if ((t1 - t0).cross(t2 - t0).norm() < 0.2) continue;
    // A point near the triangle: a point of its plane (barycentric coordinates in [-0.3, 1.3]) lifted
    // off it by up to ±0.3.
    std::uniform_real_distribution<double> bary(-0.3, 1.3), lift(-0.3, 0.3);
    const double u = bary(rng), v = bary(rng);
    x.head<3>() = t0 + u * (t1 - t0) + v * (t2 - t0) + lift(rng) * (t1 - t0).cross(t2 - t0).normalized();
    const double activation = pointTriangleActivation(x);
    if (activation < 0.02 || activation > 0.98 || !classIsStable(classify, x)) continue;
    const int type = static_cast<int>(classify(x));
    if (seen[type] >= 10) continue;
    ++seen[type];
    checkPotential(kPointTriangle, x);
  }
  for (int count : seen) CHECK(count >= 5);
}

TEST_CASE("Barrier: the edge-edge potential's derivatives equal differences, mollified and near-parallel included",
          "[contact]") {
  std::mt19937 rng(43);
  const auto classify = [](const Vec12& z) {
    return bsdeform::edgeEdgeType(pointOf<12>(z, 0), pointOf<12>(z, 1), pointOf<12>(z, 2), pointOf<12>(z, 3));
  };
  int seen[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  int mollified = 0, nearParallelLines = 0;
  std::uniform_real_distribution<double> angle(0.003, 0.04), unit(0.0, 1.0);
  for (int trial = 0; trial < 40000; ++trial) {
    Vec12 x;
    x.segment<3>(0) = randomPoint(rng);
    x.segment<3>(3) = randomPoint(rng);
    x.segment<3>(6) = x.segment<3>(unit(rng) < 0.5 ? 0 : 3) + randomPoint(rng, 0.3);
    const Vector3d ea = x.segment<3>(3) - x.segment<3>(0);
    if (ea.norm() < 0.3) continue;
    // Every third configuration: edge b within a few degrees of parallel to a (sin² θ around and
    // below the mollifier's 1e-3), in a plane parallel to a's at a height in the barrier's range,
    // shifted sideways so that about half of them cross a in projection (the line–line class).
    const bool nearParallel = trial % 3 == 0;
    if (nearParallel) {
      const Vector3d along = ea.normalized(), normal = along.cross(randomPoint(rng)).normalized();
      const Vector3d side = normal.cross(along);
      const double theta = angle(rng), length = 0.5 + unit(rng);
      const double sideways = (2.0 * unit(rng) - 0.5) * length * std::sin(theta);
      x.segment<3>(6) = x.segment<3>(0) + (1.3 * unit(rng) - 0.3) * ea + (0.06 + 0.18 * unit(rng)) * normal -
                        sideways * side;
      x.segment<3>(9) = x.segment<3>(6) + length * (std::cos(theta) * along + std::sin(theta) * side);
    } else {
      x.segment<3>(9) = randomPoint(rng);
    }
    // Either end of b may be the one near a's end.
    if (unit(rng) < 0.5) x.segment<3>(6).swap(x.segment<3>(9));
    const Vector3d eb = x.segment<3>(9) - x.segment<3>(6);
    if (eb.norm() < 0.3) continue;
    const double activation = edgeEdgeActivation(x);
    if (activation < 0.02 || activation > 0.98 || !classIsStable(classify, x)) continue;
    const int type = static_cast<int>(classify(x));
    // The rest shape: these edges moved a little, so ε_x is of the current lengths.
    Vec12 rest = x;
    for (int i = 0; i < 4; ++i) rest.segment<3>(3 * i) += randomPoint(rng, 0.05);
    const double threshold = thresholdOf(rest);
    const bool isMollified = ea.cross(eb).squaredNorm() < threshold;
    const bool isParallelLines = isMollified && type == static_cast<int>(bsdeform::EdgeEdgeType::EA_EB);
    if (isParallelLines ? nearParallelLines >= 15 : (isMollified ? mollified >= 40 : seen[type] >= 10)) continue;
    ++seen[type];
    mollified += isMollified;
    nearParallelLines += isParallelLines;
    checkPotential(edgeEdgePotential(threshold), x);
  }
  for (int k = 0; k < 9; ++k) {
    INFO("class " << k);
    CHECK(seen[k] >= 5);
  }
  CHECK(mollified >= 20);
  CHECK(nearParallelLines >= 5);
}

TEST_CASE("Barrier: the mollifier's derivatives equal differences, m is C1 at x = ε", "[contact]") {
  std::mt19937 rng(47);
  int checked = 0;
  for (int trial = 0; trial < 400 && checked < 30; ++trial) {
    Vec12 x;
    for (int i = 0; i < 4; ++i) x.segment<3>(3 * i) = randomPoint(rng);
    const Vector3d ea = x.segment<3>(3) - x.segment<3>(0);
    // b nearly parallel to a: rotate a by up to 0.04 rad (sin² θ up to 1.6e-3, the threshold 1e-3).
    const Vector3d axis = ea.cross(randomPoint(rng)).normalized();
    x.segment<3>(9) = x.segment<3>(6) + 0.8 * (Eigen::AngleAxisd(0.04 * (trial % 10 + 1) / 10.0, axis) * ea);
    const double eps = thresholdOf(x);
    const double xCross = ea.cross(x.segment<3>(9) - x.segment<3>(6)).squaredNorm();
    if (xCross >= eps * (1.0 - 1e-3) || ea.norm() < 0.3) continue;  // off the difference stencil's kink
    ++checked;
    const std::function<double(const Vec12&)> m = [eps](const Vec12& y) {
      return bsdeform::edgeEdgeMollifier(pointOf<12>(y, 0), pointOf<12>(y, 1), pointOf<12>(y, 2), pointOf<12>(y, 3), eps,
                                         nullptr, nullptr);
    };
    const std::function<Vec12(const Vec12&)> gm = [eps](const Vec12& y) {
      Vector12d g;
      bsdeform::edgeEdgeMollifier(pointOf<12>(y, 0), pointOf<12>(y, 1), pointOf<12>(y, 2), pointOf<12>(y, 3), eps, &g,
                                  nullptr);
      return Vec12(g);
    };
    Vector12d g;
    Matrix12d h;
    const double value =
        bsdeform::edgeEdgeMollifier(pointOf<12>(x, 0), pointOf<12>(x, 1), pointOf<12>(x, 2), pointOf<12>(x, 3), eps, &g, &h);
    CHECK(value == Approx(bsdeform::edgeEdgeMollifier(xCross, eps)).epsilon(1e-12));
    CHECK(value < 1.0);
    CHECK(relativeError(g, bsdeform::test::differenceGradient<12>(m, x, kStep), 1e-3) < kTolerance);
    CHECK(relativeError(h, bsdeform::test::differenceJacobian<12>(gm, x, kStep), 1e-3) < kTolerance);
  }
  CHECK(checked >= 20);
  // m(ε) = 1 from both sides with slope 0: (m(ε) - m(ε(1 - δ))) / (εδ) -> 0.
  const double eps = 2.5e-4, delta = 1e-6;
  CHECK(bsdeform::edgeEdgeMollifier(eps, eps) == 1.0);
  CHECK(bsdeform::edgeEdgeMollifier(0.0, eps) == 0.0);
  CHECK((1.0 - bsdeform::edgeEdgeMollifier(eps * (1.0 - delta), eps)) / (eps * delta) < 1e-6 / eps);
}

TEST_CASE("Barrier: projectToPsd keeps a positive definite matrix bit for bit and clamps negative eigenvalues",
          "[contact]") {
  std::mt19937 rng(53);
  std::normal_distribution<double> n(0.0, 1.0);
  Matrix12d a;
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j) a(i, j) = n(rng);
  const Matrix12d spd = a.transpose() * a + 1e-3 * Matrix12d::Identity();
  Matrix12d copy = spd;
  bsdeform::projectToPsd(copy);
  CHECK(copy == spd);
  const Matrix12d indefinite = 0.5 * (a + a.transpose());
  REQUIRE(Eigen::SelfAdjointEigenSolver<Matrix12d>(indefinite).eigenvalues().minCoeff() < 0.0);
  Matrix12d projected = indefinite;
  bsdeform::projectToPsd(projected);
  checkProjection(indefinite, projected);
}

TEST_CASE("Barrier: 0 from d = ξ + d̂ on, positive and decreasing below, unbounded as d -> ξ", "[contact]") {
  const double xi = kParameters.offset, dhat = kParameters.dhat, kappa = kParameters.stiffness;
  const double sHat = bsdeform::barrierSquaredActivation(kParameters);
  // Point–vertex (exact d² = d·d), point–face and crossing edges (line–line class).
  const Vector3d t0(0, 0, 0), t1(1, 0, 0), t2(0, 1, 0);
  const auto vertexPair = [&](double d, Vector12d* g) {
    return bsdeform::pointTriangleBarrier(Vector3d(-d, 0, 0), t0, t1, t2, kParameters, g, nullptr);
  };
  const auto facePair = [&](double d, Vector12d* g) {
    return bsdeform::pointTriangleBarrier(Vector3d(0.25, 0.25, d), t0, t1, t2, kParameters, g, nullptr);
  };
  const auto edgePair = [&](double d, Vector12d* g) {
    const Vector3d a0(-1, 0, 0), a1(1, 0, 0), b0(0, -1, d), b1(0, 1, d);
    return bsdeform::edgeEdgeBarrier(a0, a1, b0, b1, bsdeform::edgeEdgeMollifierThreshold(a0, a1, b0, b1), kParameters,
                                     g, nullptr);
  };
  const std::function<double(double, Vector12d*)> pairs[] = {vertexPair, facePair, edgePair};
  Vector12d g;
  CHECK(vertexPair(xi + dhat, &g) == 0.0);
  CHECK(g.isZero(0.0));
  for (const auto& pair : pairs) {
    for (double beyond : {1.0 + 1e-9, 1.5, 10.0}) {
      CHECK(pair((xi + dhat) * beyond, &g) == 0.0);
      CHECK(g.isZero(0.0));
    }
    double previous = 0.0;
    for (int k = 1; k < 100; ++k) {
      const double d = xi + dhat * (1.0 - k / 100.0);
      const double value = pair(d, nullptr);
      CHECK(value > previous);
      previous = value;
    }
    // b ≈ κ ŝ² ln(ŝ / s) for s << ŝ: each tenfold smaller gap adds about κ ŝ² ln 10, without bound.
    double last = pair(xi + 1e-3 * dhat, nullptr);
    for (int k = 4; k <= 10; ++k) {
      const double value = pair(xi + std::pow(10.0, -k) * dhat, nullptr);
      CHECK(value - last > 0.9 * kappa * sHat * sHat * std::log(10.0));
      last = value;
    }
    CHECK(pair(xi, &g) == kInfinity);
    CHECK(g.isZero(0.0));
    CHECK(pair(0.5 * xi, nullptr) == kInfinity);
  }
}

TEST_CASE("Barrier: the mollified edge-edge barrier is continuous as the edges become parallel", "[contact]") {
  // Edge b in the plane z = 0.1 (inside ξ + d̂ of edge a), turning to parallel with a: the
  // line–line distance stays 0.1, so without the mollifier the potential would stay at κ b(s) > 0
  // while the parallel pair (which takes an endpoint class) must be approached continuously.
  const Vector3d a0(0, 0, 0), a1(1, 0, 0);
  const double z = 0.1;
  // (the explicit return type: an Eigen expression of temporaries would dangle)
  const auto bEnd = [&](double theta) -> Vector3d {
    return Vector3d(0.2, 0, z) + 0.8 * Vector3d(std::cos(theta), std::sin(theta), 0);
  };
  const Vector3d b0(0.2, 0, z);
  const double threshold = bsdeform::edgeEdgeMollifierThreshold(a0, a1, b0, bEnd(0.0));
  Vector12d gParallel;
  const double parallel = bsdeform::edgeEdgeBarrier(a0, a1, b0, bEnd(0.0), threshold, kParameters, &gParallel, nullptr);
  CHECK(parallel == 0.0);  // m(0) = 0
  const double unmollified =
      kParameters.stiffness * bsdeform::barrier(z * z - kParameters.offset * kParameters.offset,
                                                bsdeform::barrierSquaredActivation(kParameters));
  REQUIRE(unmollified > 0.0);
  double previous = kInfinity, previousGrad = kInfinity;
  for (int k = 2; k <= 8; ++k) {
    const double theta = std::pow(10.0, -k);
    Vector12d g;
    const double value = bsdeform::edgeEdgeBarrier(a0, a1, b0, bEnd(theta), threshold, kParameters, &g, nullptr);
    // m = (2 - x/ε) x/ε ≤ 2x/ε with x = |ea x eb|² ∝ sin² θ: the potential vanishes like θ², its
    // gradient like θ.
    const double x = (a1 - a0).cross(bEnd(theta) - b0).squaredNorm();
    CHECK(value < previous);
    CHECK(value - parallel <= 2.0 * x / threshold * unmollified * (1.0 + 1e-12));
    CHECK(value - parallel >= 1.9 * x / threshold * unmollified);
    CHECK((g - gParallel).norm() < previousGrad);
    previous = value;
    previousGrad = (g - gParallel).norm();
  }
  CHECK(previous < 1e-10 * unmollified);
  // Continuous where the mollifier switches off (x = ε): sin² θ = 1e-3 × |ea|²|eb|² / (|ea|²|eb|²).
  const double thetaEps = std::asin(std::sqrt(1e-3));
  const double below = bsdeform::edgeEdgeBarrier(a0, a1, b0, bEnd(thetaEps * (1 - 1e-7)), threshold, kParameters,
                                                 nullptr, nullptr);
  const double above = bsdeform::edgeEdgeBarrier(a0, a1, b0, bEnd(thetaEps * (1 + 1e-7)), threshold, kParameters,
                                                 nullptr, nullptr);
  CHECK(above == Approx(unmollified).epsilon(1e-12));
  CHECK(std::abs(above - below) <= 1e-9 * unmollified);
}

TEST_CASE("Barrier: initial adaptive stiffness balances the gradients within κ_min to 100 κ_min", "[contact]") {
  const double bbox = 2.0, dhat = 1e-3, mass = 0.5;
  // κ_min by IPC's rule, written out: d0 = 1e-8 bbox, s0 = d0², ŝ = d̂², r = ŝ / s0,
  // b''(s0) = r² + 2r - 2 ln(1/r) - 3.
  const double s0 = 1e-16 * bbox * bbox, r = dhat * dhat / s0;
  const double expectedMin = 1e11 * mass / (4.0 * s0 * (r * r + 2.0 * r + 2.0 * std::log(r) - 3.0));
  Eigen::VectorXd gradBarrier(3), gradEnergy(3);
  gradBarrier << 1.0, -2.0, 0.5;
  double maxStiffness = 0.0;
  gradEnergy.setZero();
  CHECK(bsdeform::initialBarrierStiffness(bbox, dhat, mass, gradEnergy, gradBarrier, maxStiffness) ==
        Approx(expectedMin).epsilon(1e-10));
  CHECK(maxStiffness == Approx(100.0 * expectedMin).epsilon(1e-10));
  // -∇E = 5 κ_min ∇B: the balance is 5 κ_min; 500 κ_min clamps to the maximum; a barrier pushing
  // along the energy's descent clamps to the minimum.
  for (const auto& [factor, expected] : {std::pair{5.0, 5.0}, std::pair{500.0, 100.0}, std::pair{-3.0, 1.0}}) {
    gradEnergy = -factor * expectedMin * gradBarrier;
    CHECK(bsdeform::initialBarrierStiffness(bbox, dhat, mass, gradEnergy, gradBarrier, maxStiffness) ==
          Approx(expected * expectedMin).epsilon(1e-10));
  }
  // A zero barrier gradient: κ_min.
  CHECK(bsdeform::initialBarrierStiffness(bbox, dhat, mass, gradEnergy, Eigen::VectorXd::Zero(3), maxStiffness) ==
        Approx(expectedMin).epsilon(1e-10));
  // With an offset the reference gap is measured from ξ: d0 = ξ + 1e-8 bbox, s0 = d0² - ξ².
  const double xi = 1e-2;
  const double d0 = xi + 1e-8 * bbox, s0Offset = d0 * d0 - xi * xi;
  const double sHat = (xi + dhat) * (xi + dhat) - xi * xi;
  const double expectedOffset =
      1e11 * mass / (4.0 * d0 * d0 * bsdeform::barrierSecondDerivative(s0Offset, sHat));
  CHECK(bsdeform::initialBarrierStiffness(bbox, dhat, mass, gradEnergy, Eigen::VectorXd::Zero(3), maxStiffness, 1e11,
                                          xi) == Approx(expectedOffset).epsilon(1e-10));
}

TEST_CASE("Barrier: adaptive stiffness doubles while the smallest gap shrinks below 1e-9 bbox, up to the maximum",
          "[contact]") {
  const double bbox = 3.0, eps = 1e-9 * bbox, maxStiffness = 100.0;
  double kappa = 10.0;
  CHECK(bsdeform::updateBarrierStiffness(0.9 * eps, 0.5 * eps, maxStiffness, kappa, bbox));
  CHECK(kappa == 20.0);
  CHECK_FALSE(bsdeform::updateBarrierStiffness(0.5 * eps, 0.9 * eps, maxStiffness, kappa, bbox));  // growing
  CHECK_FALSE(bsdeform::updateBarrierStiffness(2.0 * eps, 0.5 * eps, maxStiffness, kappa, bbox));  // was above
  CHECK_FALSE(bsdeform::updateBarrierStiffness(0.5 * eps, 0.5 * eps, maxStiffness, kappa, bbox));  // not shrinking
  CHECK(kappa == 20.0);
  CHECK(bsdeform::updateBarrierStiffness(0.9 * eps, 0.5 * eps, maxStiffness, kappa, bbox));
  CHECK(bsdeform::updateBarrierStiffness(0.9 * eps, 0.5 * eps, maxStiffness, kappa, bbox));
  CHECK(kappa == 80.0);
  CHECK(bsdeform::updateBarrierStiffness(0.9 * eps, 0.5 * eps, maxStiffness, kappa, bbox));
  CHECK(kappa == maxStiffness);
  CHECK_FALSE(bsdeform::updateBarrierStiffness(0.9 * eps, 0.5 * eps, maxStiffness, kappa, bbox));
  // A larger epsilon scale widens the band.
  CHECK(bsdeform::updateBarrierStiffness(0.9e-6 * bbox, 0.5e-6 * bbox, 1e3, kappa, bbox, 1e-6));
}

TEST_CASE("projectBlockToPsd: the block nearest in Frobenius norm among PSD ones and zero elsewhere", "[contact]") {
  // The nearest PSD matrix to a symmetric B is V max(Λ, 0) Vᵀ (Higham 1988): checked here against
  // a separate (dynamic-size) eigen-decomposition of the block alone, for the blocks the barrier projects (a point's
  // 3 x 3 against an obstacle: rank one, edge- and corner-like; 6 x 6 and 9 x 9 random ones).
  std::mt19937 rng(53);
  std::normal_distribution<double> normal(0.0, 1.0);
  auto randomVector = [&](int n) {
    Eigen::VectorXd v(n);
    for (int i = 0; i < n; ++i) v[i] = normal(rng);
    return v;
  };
  int projected = 0, kept = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const int n = trial % 3 == 0 ? 6 : (trial % 3 == 1 ? 9 : 3);
    const int first = n == 9 ? 3 : (n == 6 ? 6 : 0);
    Eigen::MatrixXd b(n, n);
    const Eigen::VectorXd r = randomVector(n), e = randomVector(n).normalized();
    const double scale = std::pow(10.0, normal(rng) * 3.0);  // barrier Hessians span many decades
    switch (trial % 4) {
      case 0: b = scale * r * r.transpose(); break;  // a point on a face: rank one, PSD
      case 1:  // a point by an edge: alpha r rᵀ + beta (I - e eᵀ), beta < 0 (b' < 0)
        b = scale * (r * r.transpose() - 0.3 * (Eigen::MatrixXd::Identity(n, n) - e * e.transpose()));
        break;
      case 2: {  // a corner (b' < 0: indefinite) or a positive definite block
        const double shift = (trial / 4) % 2 == 0 ? -0.5 : 0.5;
        b = scale * (r * r.transpose() + shift * Eigen::MatrixXd::Identity(n, n));
        break;
      }
      default: {
        const Eigen::MatrixXd a = Eigen::MatrixXd::NullaryExpr(n, n, [&]() { return normal(rng); });
        b = scale * (a + a.transpose());
      }
    }
    Matrix12d h = Matrix12d::NullaryExpr([&]() { return normal(rng); });
    h = (h + h.transpose()).eval();
    h.block(first, first, n, n) = b;
    bsdeform::projectBlockToPsd(h, first, n);
    Matrix12d outside = h;
    outside.block(first, first, n, n).setZero();
    CHECK(outside.isZero(0.0));
    const Eigen::MatrixXd p = h.block(first, first, n, n);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> reference(b);
    const Eigen::MatrixXd expected = reference.eigenvectors() * reference.eigenvalues().cwiseMax(0.0).asDiagonal() *
                                     reference.eigenvectors().transpose();
    CHECK((p - expected).norm() <= 1e-12 * b.norm());
    CHECK(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(p).eigenvalues().minCoeff() >= -1e-12 * b.norm());
    if (reference.eigenvalues().minCoeff() < 0.0) ++projected;
    // a positive definite block is left as it is, bit for bit (a rank-one one may or may not be
    // reconstructed, as the decomposition's rounding of its zero eigenvalues falls)
    if (reference.eigenvalues().minCoeff() > 1e-12 * b.norm()) {
      CHECK(p == b);
      ++kept;
    }
  }
  CHECK(projected > 50);
  CHECK(kept > 10);
}

TEST_CASE("pointStaticTriangleBarrier: the point's block of pointTriangleBarrier in every class - value and d² "
          "bit for bit - and its PSD projection in closed form",
          "[contact]") {
  std::mt19937 rng(59);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  BarrierParameters bp;
  bp.offset = 0.05;
  bp.dhat = 0.5;
  bp.stiffness = 3.7;
  const Vector3d t0(0.0, 0.0, 0.0), t1(1.0, 0.1, 0.05), t2(0.2, 0.9, -0.1);
  std::array<int, 7> seen{};
  for (int trial = 0; trial < 3000; ++trial) {
    const Vector3d p(-0.6 + 2.2 * unit(rng), -0.6 + 2.2 * unit(rng), -0.5 + unit(rng));
    double d2Generic = 0.0, d2 = 0.0;
    Vector12d g12;
    Matrix12d hExact12, hPsd12;
    const double generic = bsdeform::pointTriangleBarrier(p, t0, t1, t2, bp, &g12, &hExact12, BarrierHessian::Exact,
                                                          &d2Generic);
    Eigen::Vector3d g;
    Eigen::Matrix3d hExact, hPsd;
    const double value = bsdeform::pointStaticTriangleBarrier(p, t0, t1, t2, bp, &g, &hExact, BarrierHessian::Exact, &d2);
    bsdeform::pointStaticTriangleBarrier(p, t0, t1, t2, bp, nullptr, &hPsd, BarrierHessian::ProjectedPsd);
    CHECK(value == generic);
    CHECK(d2 == d2Generic);
    if (!(value > 0.0) || !std::isfinite(value)) {
      CHECK(g.isZero(0.0));
      CHECK(hExact.isZero(0.0));
      continue;
    }
    ++seen[static_cast<size_t>(bsdeform::pointTriangleType(p, t0, t1, t2))];
    const double scale = hExact12.topLeftCorner<3, 3>().norm() + 1e-300;
    CHECK((g - g12.head<3>()).norm() <= 1e-12 * g12.head<3>().norm());
    CHECK((hExact - hExact12.topLeftCorner<3, 3>()).norm() <= 1e-11 * scale);
    hPsd12 = hExact12;
    bsdeform::projectBlockToPsd(hPsd12, 0, 3);
    CHECK((hPsd - hPsd12.topLeftCorner<3, 3>()).norm() <= 1e-11 * scale);
    CHECK(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(hPsd).eigenvalues().minCoeff() >= -1e-12 * scale);
  }
  for (int count : seen) CHECK(count >= 5);
}
