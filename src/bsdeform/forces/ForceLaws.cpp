// SPDX-License-Identifier: MIT
#include "bsdeform/forces/ForceLaws.h"
#include "bsdeform/base/NumberText.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace bsdeform {

namespace {
// The checks return their argument so that they can run in a base-class initialiser, before
// the base class sees the value. Messages: "<what> must be ..., got <value>".
std::string text(double x) { return numberText(x); }
std::string text(const Eigen::Vector3d& v) { return "(" + text(v.x()) + ", " + text(v.y()) + ", " + text(v.z()) + ")"; }

double parameter(double x, const char* what) {
  if (!std::isfinite(x) || x < 0.0 || x > 1.0)
    throw std::invalid_argument(std::string(what) + " must be a parameter in [0,1], got " + text(x));
  return x;
}
double finite(double x, const char* what) {
  if (!std::isfinite(x)) throw std::invalid_argument(std::string(what) + " must be finite, got " + text(x));
  return x;
}
double nonNegative(double x, const char* what) {
  if (!std::isfinite(x) || x < 0.0)
    throw std::invalid_argument(std::string(what) + " must be finite and >= 0, got " + text(x));
  return x;
}
double positive(double x, const char* what) {
  if (!std::isfinite(x) || x <= 0.0)
    throw std::invalid_argument(std::string(what) + " must be finite and > 0, got " + text(x));
  return x;
}
const Eigen::Vector3d& finite(const Eigen::Vector3d& v, const char* what) {
  if (!v.allFinite()) throw std::invalid_argument(std::string(what) + " must be finite, got " + text(v));
  return v;
}
Eigen::Vector3d unit(const Eigen::Vector3d& v, const char* what) {
  const double n = v.norm();
  if (!v.allFinite() || !(n > 0.0) || !std::isfinite(n))
    throw std::invalid_argument(std::string(what) + " must be a finite non-zero vector, got " + text(v));
  return v / n;
}

double area(const MassContext& ctx) { return ctx.space.basisU().spacing() * ctx.space.basisV().spacing(); }
}  // namespace

// ---------------------------------------------------------------------------------------------

SpringForce::SpringForce(double u0, double v0, const Eigen::Vector3d& anchor, double stiffness)
    : SpringForce(u0, v0, std::make_shared<const Eigen::Vector3d>(finite(anchor, "spring anchor")), stiffness) {
  m_movable = false;
}

SpringForce::SpringForce(double u0, double v0, std::shared_ptr<const Eigen::Vector3d> anchor, double stiffness)
    : PointForce(parameter(u0, "spring point u"), parameter(v0, "spring point v"),
                 [a = anchor, k = nonNegative(stiffness, "spring stiffness")](const SurfaceSample& s) {
                   return Eigen::Vector3d(k * (*a - s.position));
                 },
                 kDependsOnPosition, stiffness),
      m_anchor(std::move(anchor)),
      m_stiffness(stiffness) {
  if (!m_anchor || !m_anchor->allFinite()) throw std::invalid_argument("spring anchor must be finite");
  setHasPointDerivatives();
}

bool SpringForce::storedEnergy(const LoadContext& ctx, double& value) const {
  value = 0.0;
  return !m_movable && PointForce::storedEnergy(ctx, value);
}

void SpringForce::pointDerivatives(const SurfaceSample& s, Eigen::Matrix3d& Kx, Eigen::Matrix3d& Kv, double& phi) const {
  Kx = m_stiffness * Eigen::Matrix3d::Identity();
  Kv.setZero();
  phi = 0.5 * m_stiffness * (*m_anchor - s.position).squaredNorm();
}

// ---------------------------------------------------------------------------------------------

DragForce::DragForce(double coefficient)
    : DistributedForce([c = nonNegative(coefficient, "drag coefficient")](
                           const SurfaceSample& s) { return Eigen::Vector3d(-c * s.velocity); },
                       kDependsOnVelocity),
      m_coefficient(coefficient) {
  setHasDensityDerivatives();
}

void DragForce::densityDerivatives(const SurfaceSample& s, Eigen::Matrix3d& Kx, Eigen::Matrix3d& Kv, double& phi) const {
  Kx.setZero();
  Kv = m_coefficient * Eigen::Matrix3d::Identity();
  phi = 0.5 * m_coefficient * s.stepSize * s.velocity.squaredNorm();
}

double DragForce::dampingRateBound(const MassContext& ctx) const {
  return m_coefficient * area(ctx) / ctx.interiorMass;
}

// ---------------------------------------------------------------------------------------------

PressureForce::PressureForce(double pressure, double minStretch)
    : DistributedForce([p = finite(pressure, "pressure")](const SurfaceSample& s) { return Eigen::Vector3d(p * s.normal); },
                       kDependsOnNormal),
      m_pressure(pressure),
      m_minStretch(positive(minStretch, "pressure minStretch")) {
  setPerCurrentArea();
}

void PressureForce::addJacobian(const LoadContext& ctx, double, JacobianSink& sink) const {
  const SplineSpace& sp = ctx.space;
  const int cols = sp.netCols();
  const bool perRest = ctx.rest != nullptr;
  forEachGaussPoint(ctx, kDependsOnNormal, [&](const SurfaceSample& smp, double w, const LocalBasis& bu, const LocalBasis& bv) {
    const SurfacePoint pt = sp.evaluate(ctx.current, bu, bv, 1);
    const Eigen::Vector3d N = pt.du.cross(pt.dv);
    const double nn = N.norm();
    if (!(nn > 0.0)) return;
    auto cross = [](const Eigen::Vector3d& x) {
      Eigen::Matrix3d X;
      X << 0, -x.z(), x.y(), x.z(), 0, -x.x(), -x.y(), x.x(), 0;
      return X;
    };
    const Eigen::Matrix3d Cu = cross(pt.du), Cv = cross(pt.dv);
    // dN = (B_{m,v} [S_u]x - B_{m,u} [S_v]x) dx_m; per unit rest area the weight w holds |N|
    // (w = wq |N|), so the load is p N wq; per parameter area it is p N/|N| wq
    Eigen::Matrix3d post;
    double wq;
    if (perRest) {
      wq = w / nn;
      post = Eigen::Matrix3d::Identity();
    } else {
      wq = w;
      const Eigen::Vector3d n = N / nn;
      post = (Eigen::Matrix3d::Identity() - n * n.transpose()) / nn;
    }
    (void)smp;
    for (int a = 0; a < bu.count; ++a)
      for (int b = 0; b < bv.count; ++b) {
        const double Bk = bu.d[0][a] * bv.d[0][b];
        if (Bk == 0.0) continue;
        const Eigen::Index p = Eigen::Index(bu.first + a + sp.degreeU()) * cols + bv.first + b + sp.degreeV();
        for (int c = 0; c < bu.count; ++c)
          for (int d = 0; d < bv.count; ++d) {
            const double Bmu = bu.d[1][c] * bv.d[0][d], Bmv = bu.d[0][c] * bv.d[1][d];
            const Eigen::Index q = Eigen::Index(bu.first + c + sp.degreeU()) * cols + bv.first + d + sp.degreeV();
            sink.add(p, q, (-m_pressure * wq * Bk) * (post * (Bmv * Cu - Bmu * Cv)));
          }
      }
  });
}

double PressureForce::eigenvalueBound(const MassContext& ctx) const {
  const double h1 = ctx.space.basisU().spacing(), h2 = ctx.space.basisV().spacing();
  return 2.0 * std::abs(m_pressure) * (h1 + h2) / (m_minStretch * ctx.interiorMass);
}

// ---------------------------------------------------------------------------------------------

PlaneContactForce::PlaneContactForce(const Eigen::Vector3d& point, const Eigen::Vector3d& normal, double stiffness)
    : DistributedForce(
          [c = finite(point, "plane contact point"), n = unit(normal, "plane contact normal"),
           k = nonNegative(stiffness, "plane contact stiffness")](const SurfaceSample& s) {
            const double depth = -(s.position - c).dot(n);
            return Eigen::Vector3d(depth > 0.0 ? Eigen::Vector3d(k * depth * n) : Eigen::Vector3d::Zero());
          },
          kDependsOnPosition, ParamRect{}, 2, stiffness),
      m_point(point),
      m_normal(normal.normalized()),
      m_stiffness(stiffness) {
  setHasDensityDerivatives();
}

void PlaneContactForce::densityDerivatives(const SurfaceSample& s, Eigen::Matrix3d& Kx, Eigen::Matrix3d& Kv,
                                           double& phi) const {
  Kv.setZero();
  const double depth = -(s.position - m_point).dot(m_normal);
  if (depth > 0.0) {
    Kx = m_stiffness * m_normal * m_normal.transpose();
    phi = 0.5 * m_stiffness * depth * depth;
  } else {
    Kx.setZero();
    phi = 0.0;
  }
}

// ---------------------------------------------------------------------------------------------

SphereContactForce::SphereContactForce(const Eigen::Vector3d& center, double radius, double stiffness)
    : DistributedForce(
          [c = finite(center, "sphere contact center"), r = nonNegative(radius, "sphere contact radius"),
           k = nonNegative(stiffness, "sphere contact stiffness")](const SurfaceSample& s) {
            const Eigen::Vector3d d = s.position - c;
            const double len = d.norm();
            if (len >= r || len == 0.0) return Eigen::Vector3d(Eigen::Vector3d::Zero());
            return Eigen::Vector3d(k * (r - len) * d / len);
          },
          kDependsOnPosition, ParamRect{}, 2, stiffness),
      m_center(center),
      m_radius(radius),
      m_stiffness(stiffness) {
  setHasDensityDerivatives();
}

void SphereContactForce::densityDerivatives(const SurfaceSample& s, Eigen::Matrix3d& Kx, Eigen::Matrix3d& Kv,
                                            double& phi) const {
  Kv.setZero();
  const Eigen::Vector3d d = s.position - m_center;
  const double len = d.norm();
  if (len >= m_radius || len == 0.0) {
    Kx.setZero();
    phi = 0.0;
    return;
  }
  const Eigen::Vector3d n = d / len;
  const Eigen::Matrix3d nn = n * n.transpose();
  Kx = m_stiffness * nn - m_stiffness * (m_radius / len - 1.0) * (Eigen::Matrix3d::Identity() - nn);
  phi = 0.5 * m_stiffness * (m_radius - len) * (m_radius - len);
}

// ---------------------------------------------------------------------------------------------

GravityForce::GravityForce(const Eigen::Vector3d& acceleration)
    : DistributedForce(finite(acceleration, "gravity acceleration")),
      m_massDensity(std::numeric_limits<double>::quiet_NaN()),
      m_acceleration(acceleration) {}

GravityForce::GravityForce(double massDensity, const Eigen::Vector3d& acceleration)
    : DistributedForce(nonNegative(massDensity, "gravity mass density") *
                       finite(acceleration, "gravity acceleration")),
      m_massDensity(massDensity),
      m_acceleration(acceleration) {}

void GravityForce::addLoad(const LoadContext& ctx, ControlNet& load) const {
  if (!modelDensity()) {
    DistributedForce::addLoad(ctx, load);
    return;
  }
  // the load of g per unit mass, times the model's rho (a constant load: computed once per model)
  ControlNet unit = ControlNet::Zero(load.rows(), load.cols());
  DistributedForce::addLoad(ctx, unit);
  load += ctx.massPerArea * unit;
}

}  // namespace bsdeform
