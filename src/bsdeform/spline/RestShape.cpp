// SPDX-License-Identifier: MIT
#include "bsdeform/spline/RestShape.h"

#include "bsdeform/base/ParameterError.h"
#include "bsdeform/base/NumberText.h"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "bsdeform/spline/GaussLegendre.h"

namespace bsdeform {

namespace {
constexpr double kPi = 3.14159265358979323846;
// Weight of the curvature term of the profile fit: 1 removes the latitude bands a plain L2 fit
// shows in shading (its error oscillates away from the held pole layers) for about twice the
// geometric error (sphere R = 0.5, 16 x 16: 1.1e-2 instead of 5.9e-3).
constexpr double kProfileSmoothing = 1.0;

std::string num(double x) { return numberText(x); }

// `parameter`: the ShapeSize member (radii for each of its components, named in `label`)
void checkSize(double x, const char* parameter, const char* label = "") {
  requireParameter(std::isfinite(x) && x > 0.0, parameter, "must be finite and > 0, got " + num(x), label);
}

// Scale that puts the periodic B-spline with control points on the unit regular M-gon (angles
// 2 pi xi_k) through the unit circle at every Greville parameter xi_i: there
// S(xi_i) = e^{i theta_i} sum_d b^n((n+1)/2 + d) e^{-2 pi i d / M}, a real sum.
double circleScale(int n, int M) {
  double phi = 0.0;
  for (int d = -n - 1; d <= n + 1; ++d) phi += cardinalBSpline(n, 0.5 * (n + 1) + d) * std::cos(2 * kPi * d / M);
  return 1.0 / phi;
}

// Unit-circle control points of a periodic direction, one per net layer: circleScale times
// (cos, sin) of 2 pi xi_(k mod M), so that copies are bit-identical to what they repeat.
std::vector<Eigen::Vector2d> circlePoints(const BSplineBasis1D& basis) {
  const int M = basis.numSpans(), n = basis.degree();
  const double scale = circleScale(n, M);
  std::vector<Eigen::Vector2d> points;
  for (int k = -n; k < M; ++k) {
    const int kk = ((k % M) + M) % M;
    const double angle = 2 * kPi * (kk + 0.5 * (n + 1)) / M;
    points.push_back(scale * Eigen::Vector2d(std::cos(angle), std::sin(angle)));
  }
  return points;
}

// A 2-D profile (rho, z) along a non-periodic direction: layers in `held` get their given
// value; the others are the least-squares (L2) fit of `target` over [0,1] with the held ones
// fixed. Returns one (rho, z) per net layer.
template <typename Target>
std::vector<Eigen::Vector2d> fitProfile(const BSplineBasis1D& basis, const std::vector<bool>& held,
                                        const std::vector<Eigen::Vector2d>& heldValue, Target&& target,
                                        double smoothing) {
  const int layers = basis.numTotal(), n = basis.degree();
  std::vector<int> unknown(layers, -1);
  int count = 0;
  for (int l = 0; l < layers; ++l)
    if (!held[l]) unknown[l] = count++;
  std::vector<Eigen::Triplet<double>> t;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(count, 2);
  const QuadratureRule& rule = gaussLegendre(n + 4);
  LocalBasis b;
  for (int s = 0; s < basis.numSpans(); ++s)
    for (size_t q = 0; q < rule.nodes.size(); ++q) {
      const double v = (s + rule.nodes[q]) * basis.spacing(), w = rule.weights[q] * basis.spacing();
      basis.evaluateInSpan(s, v, 2, b);
      // smoothing * |S''|^2 (scaled by h^4, so its weight does not depend on the net size) damps
      // the oscillation that the held pole layers start in a plain L2 fit
      const double ws = smoothing * std::pow(basis.spacing(), 4) * w;
      Eigen::Vector2d r = target(v);
      Eigen::Vector2d r2 = Eigen::Vector2d::Zero();
      for (int a = 0; a < b.count; ++a) {
        const int l = b.first + a + n;
        if (held[l]) {
          r -= b.d[0][a] * heldValue[l];
          r2 -= b.d[2][a] * heldValue[l];
        }
      }
      for (int a = 0; a < b.count; ++a) {
        const int ia = unknown[b.first + a + n];
        if (ia < 0) continue;
        rhs.row(ia) += w * b.d[0][a] * r.transpose() + ws * b.d[2][a] * r2.transpose();
        for (int c = 0; c < b.count; ++c) {
          const int ic = unknown[b.first + c + n];
          if (ic >= 0) t.emplace_back(ia, ic, w * b.d[0][a] * b.d[0][c] + ws * b.d[2][a] * b.d[2][c]);
        }
      }
    }
  Eigen::SparseMatrix<double> G(count, count);
  G.setFromTriplets(t.begin(), t.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(G);
  const Eigen::MatrixXd x = solver.solve(rhs);
  std::vector<Eigen::Vector2d> out(layers);
  for (int l = 0; l < layers; ++l) out[l] = held[l] ? heldValue[l] : Eigen::Vector2d(x.row(unknown[l]).transpose());
  return out;
}
}  // namespace

const char* shapeName(ShapeKind kind) {
  switch (kind) {
    case ShapeKind::Plane: return "PLANE";
    case ShapeKind::Cylinder: return "CYLINDER";
    case ShapeKind::Cone: return "CONE";
    case ShapeKind::Sphere: return "SPHERE";
    case ShapeKind::Ellipsoid: return "ELLIPSOID";
    case ShapeKind::Torus: return "TORUS";
  }
  return "?";
}

Boundaries shapeBoundaries(ShapeKind kind, const Boundaries& requested) {
  Boundaries b = requested;
  if (kind == ShapeKind::Plane) return b;
  b.uMin = b.uMax = Boundary::Periodic;
  switch (kind) {
    case ShapeKind::Cone: b.vMax = Boundary::Clamped; break;
    case ShapeKind::Sphere:
    case ShapeKind::Ellipsoid: b.vMin = b.vMax = Boundary::Clamped; break;
    case ShapeKind::Torus: b.vMin = b.vMax = Boundary::Periodic; break;
    default: break;
  }
  // a direction the shape leaves open cannot stay half periodic
  if (kind == ShapeKind::Cylinder || kind == ShapeKind::Cone) {
    if (b.vMin == Boundary::Periodic) b.vMin = Boundary::Clamped;
    if (b.vMax == Boundary::Periodic) b.vMax = Boundary::Clamped;
  }
  return b;
}

Eigen::Vector3d exactShapePoint(ShapeKind kind, const ShapeSize& s, double u, double v) {
  const double cu = std::cos(2 * kPi * u), su = std::sin(2 * kPi * u);
  switch (kind) {
    case ShapeKind::Plane: return Eigen::Vector3d(u, v, 0);
    case ShapeKind::Cylinder: return Eigen::Vector3d(s.radius * cu, s.radius * su, s.height * (v - 0.5));
    case ShapeKind::Cone: return Eigen::Vector3d(s.radius * (1 - v) * cu, s.radius * (1 - v) * su, s.height * (v - 0.5));
    case ShapeKind::Sphere:
      return s.radius * Eigen::Vector3d(std::sin(kPi * v) * cu, std::sin(kPi * v) * su, -std::cos(kPi * v));
    case ShapeKind::Ellipsoid:
      return Eigen::Vector3d(s.radii.x() * std::sin(kPi * v) * cu, s.radii.y() * std::sin(kPi * v) * su,
                             -s.radii.z() * std::cos(kPi * v));
    case ShapeKind::Torus: {
      const double ring = s.radius + s.minorRadius * std::cos(2 * kPi * v);
      return Eigen::Vector3d(ring * cu, ring * su, s.minorRadius * std::sin(2 * kPi * v));
    }
  }
  return Eigen::Vector3d::Zero();
}

ControlNet shapeRestNet(ShapeKind kind, const ShapeSize& size, const SplineSpace& space) {
  checkSize(size.radius, "radius");
  checkSize(size.height, "height");
  checkSize(size.minorRadius, "minorRadius");
  checkSize(size.radii.x(), "radii", "radii x");
  checkSize(size.radii.y(), "radii", "radii y");
  checkSize(size.radii.z(), "radii", "radii z");
  const Boundaries expect = shapeBoundaries(kind, space.boundaries());
  const Boundaries& got = space.boundaries();
  if (expect.uMin != got.uMin || expect.uMax != got.uMax || expect.vMin != got.vMin || expect.vMax != got.vMax)
    throw std::invalid_argument(std::string("rest shape ") + shapeName(kind) +
                                " needs the boundaries given by shapeBoundaries()");
  if (kind == ShapeKind::Plane) return space.grevillePlane();

  const BSplineBasis1D &bu = space.basisU(), &bv = space.basisV();
  const int n2 = space.degreeV(), layersV = bv.numTotal();
  ControlNet net(space.netSize(), 3);
  auto put = [&](int k1, int k2, const Eigen::Vector3d& p) { net.row(space.netIndex(k1, k2)) = p.transpose(); };

  const std::vector<Eigen::Vector2d> circleU = circlePoints(bu);  // per u layer
  if (kind == ShapeKind::Torus) {
    const std::vector<Eigen::Vector2d> circleV = circlePoints(bv);
    for (int k1 = -space.degreeU(); k1 < space.numU() + space.degreeU(); ++k1)
      for (int k2 = -n2; k2 < space.numV() + n2; ++k2) {
        const Eigen::Vector2d &a = circleU[size_t(k1 + space.degreeU())], &b = circleV[size_t(k2 + n2)];
        const double ring = size.radius + size.minorRadius * b.x();
        put(k1, k2, Eigen::Vector3d(ring * a.x(), ring * a.y(), size.minorRadius * b.y()));
      }
    return net;
  }

  // Surfaces of revolution: the unit circle in u times a profile (rho, z) in v.
  std::vector<Eigen::Vector2d> profile(layersV);
  if (kind == ShapeKind::Cylinder) {
    for (int l = 0; l < layersV; ++l)
      profile[l] = Eigen::Vector2d(size.radius, size.height * (space.grevilleV(l - n2) - 0.5));
  } else {
    std::vector<bool> held(layersV, false);
    std::vector<Eigen::Vector2d> value(layersV, Eigen::Vector2d::Zero());
    const bool sphere = kind != ShapeKind::Cone;
    for (int l = 0; l < n2; ++l) {
      const int top = layersV - 1 - l;  // the n2 layers of v = 1: apex or north pole
      held[top] = true;
      value[top] = sphere ? Eigen::Vector2d(0, 1) : Eigen::Vector2d(0, 0.5 * size.height);
      if (sphere) {  // the n2 layers of v = 0: south pole
        held[l] = true;
        value[l] = Eigen::Vector2d(0, -1);
      }
    }
    if (sphere)
      profile = fitProfile(bv, held, value, [](double v) { return Eigen::Vector2d(std::sin(kPi * v), -std::cos(kPi * v)); },
                           kProfileSmoothing);
    else
      profile = fitProfile(bv, held, value,
                           [&](double v) { return Eigen::Vector2d(size.radius * (1 - v), size.height * (v - 0.5)); },
                           kProfileSmoothing);
  }
  const Eigen::Vector3d scale =
      kind == ShapeKind::Sphere ? Eigen::Vector3d::Constant(size.radius)
                                : kind == ShapeKind::Ellipsoid ? size.radii : Eigen::Vector3d::Ones();
  for (int k1 = -space.degreeU(); k1 < space.numU() + space.degreeU(); ++k1) {
    const Eigen::Vector2d& a = circleU[size_t(k1 + space.degreeU())];
    for (int l = 0; l < layersV; ++l) {
      const Eigen::Vector2d& p = profile[l];
      put(k1, l - n2, scale.cwiseProduct(Eigen::Vector3d(p.x() * a.x(), p.x() * a.y(), p.y())));
    }
  }
  return net;
}

double shapeDistance(ShapeKind kind, const ShapeSize& s, const Eigen::Vector3d& p) {
  const double rho = std::hypot(p.x(), p.y());
  switch (kind) {
    case ShapeKind::Plane: return std::abs(p.z());
    case ShapeKind::Cylinder: return std::abs(rho - s.radius);
    case ShapeKind::Cone: {
      // distance in the meridian plane to the generator from (R, -H/2) to (0, H/2)
      const Eigen::Vector2d a(s.radius, -0.5 * s.height), b(0.0, 0.5 * s.height), q(rho, p.z());
      const double t = std::clamp((q - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
      return (q - (a + t * (b - a))).norm();
    }
    case ShapeKind::Sphere: return std::abs(p.norm() - s.radius);
    case ShapeKind::Ellipsoid: {
      const Eigen::Vector3d r2 = s.radii.cwiseProduct(s.radii);
      const double g = p.cwiseProduct(p).cwiseQuotient(r2).sum() - 1.0;
      const double grad = 2.0 * p.cwiseQuotient(r2).norm();
      return grad > 0.0 ? std::abs(g) / grad : std::abs(g);
    }
    case ShapeKind::Torus: return std::abs(std::hypot(rho - s.radius, p.z()) - s.minorRadius);
  }
  return 0.0;
}

double shapeGeometricError(ShapeKind kind, const ShapeSize& size, const SplineSpace& space, const ControlNet& net,
                           int samples) {
  double err = 0.0;
  for (int i = 0; i < samples; ++i)
    for (int j = 0; j < samples; ++j) {
      const double u = double(i) / (samples - 1), v = double(j) / (samples - 1);
      err = std::max(err, shapeDistance(kind, size, space.evaluate(net, u, v, 0).position));
    }
  return err;
}

}  // namespace bsdeform
