// SPDX-License-Identifier: MIT
#include "bsdeform/ForceLaws.h"
#include "bsdeform/NumberText.h"

#include <cmath>
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
    : PointForce(parameter(u0, "spring point u"), parameter(v0, "spring point v"),
                 [a = finite(anchor, "spring anchor"), k = nonNegative(stiffness, "spring stiffness")](
                     const SurfaceSample& s) { return Eigen::Vector3d(k * (a - s.position)); },
                 kDependsOnPosition, stiffness),
      m_anchor(anchor),
      m_stiffness(stiffness) {}

// ---------------------------------------------------------------------------------------------

DragForce::DragForce(double coefficient)
    : DistributedForce([c = nonNegative(coefficient, "drag coefficient")](
                           const SurfaceSample& s) { return Eigen::Vector3d(-c * s.velocity); },
                       kDependsOnVelocity),
      m_coefficient(coefficient) {}

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
      m_stiffness(stiffness) {}

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
      m_stiffness(stiffness) {}

// ---------------------------------------------------------------------------------------------

GravityForce::GravityForce(double massDensity, const Eigen::Vector3d& acceleration)
    : DistributedForce(nonNegative(massDensity, "gravity mass density") *
                       finite(acceleration, "gravity acceleration")),
      m_massDensity(massDensity),
      m_acceleration(acceleration) {}

}  // namespace bsdeform
