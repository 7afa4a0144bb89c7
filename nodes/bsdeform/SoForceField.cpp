// SPDX-License-Identifier: MIT
#include "bsdeform/SoForceField.h"

#include <muParser.h>

#include <cmath>
#include <sstream>

#include "bsdeform/Force.h"

SO_ENGINE_SOURCE(SoForceField);

void SoForceField::initClass() {
  // Idempotent: Coin asserts when a class is initialised twice, and both initNodes() and
  // Coin's dynamic loader may call this.
  if (getClassTypeId() != SoType::badType()) return;
  SO_ENGINE_INIT_CLASS(SoForceField, SoEngine, "Engine");
}

SoForceField::SoForceField() {
  SO_ENGINE_CONSTRUCTOR(SoForceField);
  SO_ENGINE_ADD_INPUT(type, (UNIFORM));
  SO_ENGINE_ADD_INPUT(on, (TRUE));
  SO_ENGINE_ADD_INPUT(force, (0.0f, 0.0f, 1.0f));
  SO_ENGINE_ADD_INPUT(magnitude, (1.0f));
  SO_ENGINE_ADD_INPUT(point, (0.5f, 0.5f));
  SO_ENGINE_ADD_INPUT(regionMin, (0.4f, 0.4f));
  SO_ENGINE_ADD_INPUT(regionMax, (0.6f, 0.6f));
  SO_ENGINE_ADD_INPUT(expression, (""));
  SO_ENGINE_ADD_INPUT(anchor, (0.5f, 0.5f, 1.0f));
  SO_ENGINE_ADD_INPUT(center, (0.0f, 0.0f, 0.0f));
  SO_ENGINE_ADD_INPUT(normal, (0.0f, 0.0f, 1.0f));
  SO_ENGINE_ADD_INPUT(radius, (0.25f));
  SO_ENGINE_ADD_INPUT(stiffness, (10.0f));
  SO_ENGINE_ADD_INPUT(coefficient, (1.0f));
  SO_ENGINE_ADD_OUTPUT(revision, SoSFInt32);

  SO_ENGINE_DEFINE_ENUM_VALUE(Type, UNIFORM);
  SO_ENGINE_DEFINE_ENUM_VALUE(Type, POINT);
  SO_ENGINE_DEFINE_ENUM_VALUE(Type, REGION);
  SO_ENGINE_DEFINE_ENUM_VALUE(Type, EXPRESSION);
  SO_ENGINE_DEFINE_ENUM_VALUE(Type, GRAVITY);
  SO_ENGINE_DEFINE_ENUM_VALUE(Type, SPRING);
  SO_ENGINE_DEFINE_ENUM_VALUE(Type, DRAG);
  SO_ENGINE_DEFINE_ENUM_VALUE(Type, PRESSURE);
  SO_ENGINE_DEFINE_ENUM_VALUE(Type, PLANE_COLLISION);
  SO_ENGINE_DEFINE_ENUM_VALUE(Type, SPHERE_COLLISION);
  SO_ENGINE_SET_SF_ENUM_TYPE(type, Type);

  // three components by default, so that the written form is a complete expression
  expression.setNum(3);
  for (int i = 0; i < 3; ++i) expression.set1Value(i, "0");
  expression.setDefault(TRUE);
}

SoForceField::~SoForceField() = default;

void SoForceField::inputChanged(SoField*) { ++m_revision; }

void SoForceField::evaluate() { SO_ENGINE_OUTPUT(revision, SoSFInt32, setValue(m_revision)); }

namespace {

Eigen::Vector3d toEigen(const SbVec3f& v) { return Eigen::Vector3d(v[0], v[1], v[2]); }

std::string fmt(const SbVec3f& v) {
  std::ostringstream os;
  os << v[0] << " " << v[1] << " " << v[2];
  return os.str();
}

bool finite(const SbVec3f& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

// The three component formulas, parsed once; variables bound to members.
struct ExpressionDensity {
  mu::Parser parser[3];
  double u = 0, v = 0, x = 0, y = 0, z = 0, t = 0;
  unsigned dependence = bsdeform::kConstant;
};

}  // namespace

std::shared_ptr<const bsdeform::Force> SoForceField::makeForce(const SurfaceInfo& info, std::string& error) {
  using namespace bsdeform;
  error.clear();
  if (!on.getValue()) return nullptr;
  const double mag = magnitude.getValue();
  if (!std::isfinite(mag)) {
    error = "field 'magnitude' is not finite";
    return nullptr;
  }
  auto requireVec = [&](const SoSFVec3f& f, const char* name) {
    if (finite(f.getValue())) return true;
    error = std::string("field '") + name + "' is not finite: " + fmt(f.getValue());
    return false;
  };
  auto requireParam = [&](const SbVec2f& p, const char* name) {
    for (int i = 0; i < 2; ++i)
      if (!(p[i] >= 0.0f && p[i] <= 1.0f)) {
        std::ostringstream os;
        os << "field '" << name << "' must lie in [0,1]^2, got " << p[0] << " " << p[1];
        error = os.str();
        return false;
      }
    return true;
  };
  auto requireNonNegative = [&](const SoSFFloat& f, const char* name) {
    if (std::isfinite(f.getValue()) && f.getValue() >= 0.0f) return true;
    std::ostringstream os;
    os << "field '" << name << "' must be finite and >= 0, got " << f.getValue();
    error = os.str();
    return false;
  };

  try {
    switch (type.getValue()) {
      case UNIFORM:
        if (!requireVec(force, "force")) return nullptr;
        return std::make_shared<DistributedForce>(mag * toEigen(force.getValue()));
      case POINT:
        if (!requireVec(force, "force") || !requireParam(point.getValue(), "point")) return nullptr;
        return std::make_shared<PointForce>(point.getValue()[0], point.getValue()[1], mag * toEigen(force.getValue()));
      case REGION: {
        if (!requireVec(force, "force") || !requireParam(regionMin.getValue(), "regionMin") ||
            !requireParam(regionMax.getValue(), "regionMax"))
          return nullptr;
        const SbVec2f a = regionMin.getValue(), b = regionMax.getValue();
        if (a[0] > b[0] || a[1] > b[1]) {
          std::ostringstream os;
          os << "fields 'regionMin' " << a[0] << " " << a[1] << " and 'regionMax' " << b[0] << " " << b[1]
             << " do not form a rectangle (min > max)";
          error = os.str();
          return nullptr;
        }
        return std::make_shared<DistributedForce>(mag * toEigen(force.getValue()), ParamRect{a[0], b[0], a[1], b[1]});
      }
      case GRAVITY:
        if (!requireVec(force, "force")) return nullptr;
        return std::make_shared<DistributedForce>(info.massDensity * mag * toEigen(force.getValue()));
      case SPRING: {
        if (!requireVec(anchor, "anchor") || !requireParam(point.getValue(), "point") ||
            !requireNonNegative(stiffness, "stiffness"))
          return nullptr;
        const Eigen::Vector3d target = toEigen(anchor.getValue());
        const double k = stiffness.getValue();
        return std::make_shared<PointForce>(
            point.getValue()[0], point.getValue()[1],
            [target, k](const SurfaceSample& s) { return Eigen::Vector3d(k * (target - s.position)); },
            kDependsOnPosition, k);
      }
      case DRAG: {
        if (!requireNonNegative(coefficient, "coefficient")) return nullptr;
        const double c = coefficient.getValue();
        return std::make_shared<DistributedForce>(
            [c](const SurfaceSample& s) { return Eigen::Vector3d(-c * s.velocity); }, kDependsOnVelocity);
      }
      case PRESSURE:
        return std::make_shared<DistributedForce>([mag](const SurfaceSample& s) { return Eigen::Vector3d(mag * s.normal); },
                                                  kDependsOnNormal);
      case PLANE_COLLISION: {
        if (!requireVec(center, "center") || !requireVec(normal, "normal") || !requireNonNegative(stiffness, "stiffness"))
          return nullptr;
        Eigen::Vector3d n = toEigen(normal.getValue());
        if (n.norm() == 0.0) {
          error = "field 'normal' must not be the zero vector";
          return nullptr;
        }
        n.normalize();
        const Eigen::Vector3d c = toEigen(center.getValue());
        const double k = stiffness.getValue();
        return std::make_shared<DistributedForce>(
            [n, c, k](const SurfaceSample& s) {
              const double depth = -(s.position - c).dot(n);
              return Eigen::Vector3d(depth > 0.0 ? Eigen::Vector3d(k * depth * n) : Eigen::Vector3d::Zero());
            },
            kDependsOnPosition, ParamRect{}, 2, k);
      }
      case SPHERE_COLLISION: {
        if (!requireVec(center, "center") || !requireNonNegative(radius, "radius") ||
            !requireNonNegative(stiffness, "stiffness"))
          return nullptr;
        const Eigen::Vector3d c = toEigen(center.getValue());
        const double r = radius.getValue(), k = stiffness.getValue();
        return std::make_shared<DistributedForce>(
            [c, r, k](const SurfaceSample& s) {
              const Eigen::Vector3d d = s.position - c;
              const double len = d.norm();
              if (len >= r || len == 0.0) return Eigen::Vector3d(Eigen::Vector3d::Zero());
              return Eigen::Vector3d(k * (r - len) * d / len);
            },
            kDependsOnPosition, ParamRect{}, 2, k);
      }
      case EXPRESSION: {
        if (expression.getNum() != 3) {
          error = "field 'expression' needs 3 formulas (x, y, z), got " + std::to_string(expression.getNum());
          return nullptr;
        }
        auto ex = std::make_shared<ExpressionDensity>();
        static const char* names[3] = {"x", "y", "z"};
        for (int i = 0; i < 3; ++i) {
          mu::Parser& p = ex->parser[i];
          p.DefineConst("pi", 3.14159265358979323846);
          p.DefineVar("u", &ex->u);
          p.DefineVar("v", &ex->v);
          p.DefineVar("x", &ex->x);
          p.DefineVar("y", &ex->y);
          p.DefineVar("z", &ex->z);
          p.DefineVar("t", &ex->t);
          const std::string text = expression[i].getString();
          try {
            p.SetExpr(text.empty() ? "0" : text);
            p.Eval();  // parses; unknown names and syntax errors throw here
            for (const auto& used : p.GetUsedVar()) {
              if (used.first == "x" || used.first == "y" || used.first == "z") ex->dependence |= kDependsOnPosition;
              if (used.first == "t") ex->dependence |= kDependsOnTime;
            }
          } catch (const mu::Parser::exception_type& e) {
            std::ostringstream os;
            os << "field 'expression' [" << i << "] (" << names[i] << " component) \"" << text
               << "\" does not parse at position " << e.GetPos() << ": " << e.GetMsg();
            error = os.str();
            return nullptr;
          }
        }
        const double m = mag;
        return std::make_shared<DistributedForce>(
            [ex, m](const SurfaceSample& s) {
              ex->u = s.u;
              ex->v = s.v;
              ex->x = s.position.x();
              ex->y = s.position.y();
              ex->z = s.position.z();
              ex->t = s.t;
              return Eigen::Vector3d(m * ex->parser[0].Eval(), m * ex->parser[1].Eval(), m * ex->parser[2].Eval());
            },
            ex->dependence);
      }
    }
    error = "field 'type' has an unknown value " + std::to_string(type.getValue());
  } catch (const std::exception& e) {
    error = e.what();
  }
  return nullptr;
}
