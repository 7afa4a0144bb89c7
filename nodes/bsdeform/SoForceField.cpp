// SPDX-License-Identifier: MIT
#include "bsdeform/SoForceField.h"

#include <Inventor/SoDB.h>
#include <Inventor/engines/SoFieldConverter.h>
#include <Inventor/fields/SoMFDouble.h>
#include <Inventor/fields/SoMFFloat.h>
#include <Inventor/fields/SoMFVec2d.h>
#include <Inventor/fields/SoMFVec2f.h>
#include <Inventor/fields/SoMFVec3d.h>
#include <Inventor/fields/SoSFFloat.h>
#include <Inventor/fields/SoSFShort.h>
#include <Inventor/fields/SoSFTime.h>
#include <Inventor/fields/SoSFVec2f.h>
#include <Inventor/lists/SoFieldList.h>
#include <muParser.h>

#include <cmath>
#include <sstream>

#include "bsdeform/CoinEigen.h"
#include "bsdeform/forces/Force.h"
#include "bsdeform/contact/BarrierContact.h"
#include "bsdeform/contact/Contact.h"
#include "bsdeform/forces/ForceLaws.h"
#include "bsdeform/FieldInfo.h"
#include "bsdeform/SceneText.h"

/// Field converter into SoSFDouble and SoSFVec2d. Coin 4.0's built-in converter (SoConvertAll)
/// knows no double field except SoSFVec3d, so without it `magnitude 0 = Calculator { } . oa`
/// fails to connect ("no converter for MFFloat to SFDouble"). Coin creates one instance per
/// connection (default constructor), asks for the input matching the master's type and the
/// output matching the slave's, and later asks again with a bad type (disconnecting), which must
/// return the same ones.
class SoForceFieldDoubleConverter : public SoFieldConverter {
  using inherited = SoFieldConverter;
  SO_ENGINE_HEADER(SoForceFieldDoubleConverter);

 public:
  static void initClass();
  SoForceFieldDoubleConverter();

  SoSFFloat sfFloat;
  SoMFFloat mfFloat;
  SoSFTime sfTime;
  SoSFInt32 sfInt32;
  SoSFShort sfShort;
  SoSFBool sfBool;
  SoMFDouble mfDouble;
  SoSFVec2f sfVec2f;
  SoMFVec2f mfVec2f;
  SoMFVec2d mfVec2d;
  SoMFVec3d mfVec3d;
  SoEngineOutput doubleOut;  ///< (SoSFDouble)
  SoEngineOutput vec2dOut;   ///< (SoSFVec2d)
  SoEngineOutput vec3dOut;   ///< (SoSFVec3d)

  /// Registers the class and its conversions (those Coin does not have already).
  static void registerConversions();

 protected:
  ~SoForceFieldDoubleConverter() override = default;
  SoField* getInput(SoType type) override;
  SoEngineOutput* getOutput(SoType type) override;
  void evaluate() override;

 private:
  SoField* m_input = nullptr;
  SoEngineOutput* m_output = nullptr;
};

SO_ENGINE_SOURCE(SoForceFieldDoubleConverter);

void SoForceFieldDoubleConverter::initClass() {
  if (getClassTypeId() != SoType::badType()) return;
  SO_ENGINE_INIT_CLASS(SoForceFieldDoubleConverter, SoFieldConverter, "FieldConverter");
}

SoForceFieldDoubleConverter::SoForceFieldDoubleConverter() {
  SO_ENGINE_CONSTRUCTOR(SoForceFieldDoubleConverter);
  SO_ENGINE_ADD_INPUT(sfFloat, (0.0f));
  SO_ENGINE_ADD_INPUT(mfFloat, (0.0f));
  SO_ENGINE_ADD_INPUT(sfTime, (SbTime::zero()));
  SO_ENGINE_ADD_INPUT(sfInt32, (0));
  SO_ENGINE_ADD_INPUT(sfShort, (0));
  SO_ENGINE_ADD_INPUT(sfBool, (FALSE));
  SO_ENGINE_ADD_INPUT(mfDouble, (0.0));
  SO_ENGINE_ADD_INPUT(sfVec2f, (0.0f, 0.0f));
  SO_ENGINE_ADD_INPUT(mfVec2f, (0.0f, 0.0f));
  SO_ENGINE_ADD_INPUT(mfVec2d, (0.0, 0.0));
  SO_ENGINE_ADD_INPUT(mfVec3d, (0.0, 0.0, 0.0));
  SO_ENGINE_ADD_OUTPUT(doubleOut, SoSFDouble);
  SO_ENGINE_ADD_OUTPUT(vec2dOut, SoSFVec2d);
  SO_ENGINE_ADD_OUTPUT(vec3dOut, SoSFVec3d);
}

SoField* SoForceFieldDoubleConverter::getInput(SoType type) {
  for (SoField* f : std::initializer_list<SoField*>{&sfFloat, &mfFloat, &sfTime, &sfInt32, &sfShort, &sfBool,
                                                    &mfDouble, &sfVec2f, &mfVec2f, &mfVec2d, &mfVec3d})
    if (f->getTypeId() == type) return m_input = f;
  return m_input;  // a bad type: the one connected
}

SoEngineOutput* SoForceFieldDoubleConverter::getOutput(SoType type) {
  if (type == SoSFDouble::getClassTypeId()) return m_output = &doubleOut;
  if (type == SoSFVec2d::getClassTypeId()) return m_output = &vec2dOut;
  if (type == SoSFVec3d::getClassTypeId()) return m_output = &vec3dOut;
  return m_output;
}

void SoForceFieldDoubleConverter::evaluate() {
  // A multiple-value master gives its first value (as Coin's own MF -> SF conversions do);
  // an empty one gives nothing.
  if (m_output == &doubleOut) {
    double x;
    if (m_input == &sfFloat) x = sfFloat.getValue();
    else if (m_input == &mfFloat && mfFloat.getNum()) x = mfFloat[0];
    else if (m_input == &sfTime) x = sfTime.getValue().getValue();
    else if (m_input == &sfInt32) x = sfInt32.getValue();
    else if (m_input == &sfShort) x = sfShort.getValue();
    else if (m_input == &sfBool) x = sfBool.getValue() ? 1.0 : 0.0;
    else if (m_input == &mfDouble && mfDouble.getNum()) x = mfDouble[0];
    else return;
    SO_ENGINE_OUTPUT(doubleOut, SoSFDouble, setValue(x));
  } else if (m_output == &vec2dOut) {
    SbVec2d x;
    if (m_input == &sfVec2f) x = SbVec2d(sfVec2f.getValue());
    else if (m_input == &mfVec2f && mfVec2f.getNum()) x = SbVec2d(mfVec2f[0]);
    else if (m_input == &mfVec2d && mfVec2d.getNum()) x = mfVec2d[0];
    else return;
    SO_ENGINE_OUTPUT(vec2dOut, SoSFVec2d, setValue(x));
  } else if (m_output == &vec3dOut && m_input == &mfVec3d && mfVec3d.getNum()) {
    const SbVec3d x = mfVec3d[0];
    SO_ENGINE_OUTPUT(vec3dOut, SoSFVec3d, setValue(x));
  }
}

void SoForceFieldDoubleConverter::registerConversions() {
  initClass();
  const SoType self = getClassTypeId();
  auto add = [self](SoType from, SoType to) {
    if (SoDB::getConverter(from, to) == SoType::badType()) SoDB::addConverter(from, to, self);
  };
  for (SoType from : {SoSFFloat::getClassTypeId(), SoMFFloat::getClassTypeId(), SoSFTime::getClassTypeId(),
                      SoSFInt32::getClassTypeId(), SoSFShort::getClassTypeId(), SoSFBool::getClassTypeId(),
                      SoMFDouble::getClassTypeId()})
    add(from, SoSFDouble::getClassTypeId());
  for (SoType from : {SoSFVec2f::getClassTypeId(), SoMFVec2f::getClassTypeId(), SoMFVec2d::getClassTypeId()})
    add(from, SoSFVec2d::getClassTypeId());
  add(SoMFVec3d::getClassTypeId(), SoSFVec3d::getClassTypeId());
}

// ---------------------------------------------------------------------------------------------

SO_ENGINE_SOURCE(SoForceField);

void SoForceField::initClass() {
  // Idempotent: Coin asserts when a class is initialised twice, and both initNodes() and
  // Coin's dynamic loader may call this.
  if (getClassTypeId() != SoType::badType()) return;
  SO_ENGINE_INIT_CLASS(SoForceField, SoEngine, "Engine");
  SoForceFieldDoubleConverter::registerConversions();
}

SoForceField::SoForceField() {
  SO_ENGINE_CONSTRUCTOR(SoForceField);
  SO_ENGINE_ADD_INPUT(type, (UNIFORM));
  SO_ENGINE_ADD_INPUT(on, (TRUE));
  SO_ENGINE_ADD_INPUT(force, (0.0, 0.0, 1.0));
  SO_ENGINE_ADD_INPUT(magnitude, (1.0));
  SO_ENGINE_ADD_INPUT(point, (0.5, 0.5));
  SO_ENGINE_ADD_INPUT(regionMin, (0.4, 0.4));
  SO_ENGINE_ADD_INPUT(regionMax, (0.6, 0.6));
  SO_ENGINE_ADD_INPUT(expression, (""));
  SO_ENGINE_ADD_INPUT(anchor, (0.5, 0.5, 1.0));
  SO_ENGINE_ADD_INPUT(center, (0.0, 0.0, 0.0));
  SO_ENGINE_ADD_INPUT(normal, (0.0, 0.0, 1.0));
  SO_ENGINE_ADD_INPUT(radius, (0.25));
  SO_ENGINE_ADD_INPUT(stiffness, (10.0));
  SO_ENGINE_ADD_INPUT(coefficient, (1.0));
  SO_ENGINE_ADD_INPUT(obstacles, (nullptr));
  SO_ENGINE_ADD_INPUT(obstacleNames, (""));
  SO_ENGINE_ADD_INPUT(thickness, (0.02));
  SO_ENGINE_ADD_INPUT(damping, (0.0));
  SO_ENGINE_ADD_INPUT(friction, (0.0));
  SO_ENGINE_ADD_INPUT(method, (PENALTY));
  SO_ENGINE_ADD_INPUT(dhat, (0.001));
  SO_ENGINE_ADD_INPUT(selfContact, (FALSE));
  SO_ENGINE_ADD_INPUT(proxySamples, (2));
  SO_ENGINE_ADD_INPUT(epsv, (0.001));
  SO_ENGINE_ADD_INPUT(frame, (WORLD));
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
  SO_ENGINE_DEFINE_ENUM_VALUE(Type, COLLISION);
  SO_ENGINE_SET_SF_ENUM_TYPE(type, Type);
  SO_ENGINE_DEFINE_ENUM_VALUE(Frame, WORLD);
  SO_ENGINE_DEFINE_ENUM_VALUE(Frame, LOCAL);
  SO_ENGINE_SET_SF_ENUM_TYPE(frame, Frame);
  SO_ENGINE_DEFINE_ENUM_VALUE(Method, PENALTY);
  SO_ENGINE_DEFINE_ENUM_VALUE(Method, BARRIER);
  SO_ENGINE_SET_SF_ENUM_TYPE(method, Method);

  // three components by default, so that the written form is a complete expression
  expression.setNum(3);
  for (int i = 0; i < 3; ++i) expression.set1Value(i, "0");
  expression.setDefault(TRUE);
  obstacles.setNum(0);
  obstacles.setDefault(TRUE);
  obstacleNames.setNum(0);
  obstacleNames.setDefault(TRUE);
}

SoForceField::~SoForceField() = default;

void SoForceField::inputChanged(SoField* which) {
  if (which == &obstacles || which == &obstacleNames)
    ++m_geometryRevision;  // the list or something inside an obstacle: re-gather, same force
  else
    ++m_revision;
}

void SoForceField::evaluate() { SO_ENGINE_OUTPUT(revision, SoSFInt32, setValue(m_revision)); }

SbBool SoForceField::readInstance(SoInput* in, unsigned short flags) {
  const SbBool ok = inherited::readInstance(in, flags);
  // Coin's reader is off by up to a few ulps (SceneText.h); snapping what was read to its
  // 15-digit value makes `point 0.97 0.5` act at 0.97 and write -> read -> write a fixed point.
  // Connected fields get their values from the connection.
  bsdeform::snapReadDoubles(*this);
  return ok;
}

namespace {

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
  // Field values -> core classes; the core validates them and names the bad parameter.
  const double mag = magnitude.getValue();
  const Eigen::Vector2d p = toEigen(point.getValue());
  // WORLD: vectors and points come into the surface's own coordinates, in which it moves:
  // x_local = A^-1 (x_world - offset); a direction (force, acceleration) by A^-1, a plane's
  // normal by A^T (normals go with the inverse transpose), a length by A's mean scale.
  const bool world = frame.getValue() == WORLD && type.getValue() != COLLISION;
  const Eigen::Matrix3d& A = info.linear;
  const double det = A.determinant();
  if (world && !(std::isfinite(det) && std::abs(det) > 1e-300 && A.allFinite() && info.offset.allFinite())) {
    error = "frame WORLD: the transform above the surface is singular or not finite";
    return nullptr;
  }
  const Eigen::Matrix3d Ainv = world ? Eigen::Matrix3d(A.inverse()) : Eigen::Matrix3d::Identity();
  auto direction = [&](const Eigen::Vector3d& v) { return world ? Eigen::Vector3d(Ainv * v) : v; };
  auto position = [&](const Eigen::Vector3d& x) { return world ? Eigen::Vector3d(Ainv * (x - info.offset)) : x; };
  auto planeNormal = [&](const Eigen::Vector3d& n) { return world ? Eigen::Vector3d(A.transpose() * n) : n; };
  const double lengthScale = world ? std::cbrt(std::abs(det)) : 1.0;
  const Eigen::Vector3d f = direction(toEigen(force.getValue()));
  try {
    switch (type.getValue()) {
      case UNIFORM:
        return std::make_shared<DistributedForce>(mag * f);
      case POINT:
        return std::make_shared<PointForce>(p.x(), p.y(), mag * f);
      case REGION: {
        const Eigen::Vector2d a = toEigen(regionMin.getValue()), b = toEigen(regionMax.getValue());
        return std::make_shared<DistributedForce>(mag * f, ParamRect{a.x(), b.x(), a.y(), b.y()});
      }
      case GRAVITY:
        return std::make_shared<GravityForce>(mag * f);  // rho: the model's
      case SPRING:
        return std::make_shared<SpringForce>(p.x(), p.y(), position(toEigen(anchor.getValue())), stiffness.getValue());
      case DRAG:
        return std::make_shared<DragForce>(coefficient.getValue());
      case PRESSURE:
        return std::make_shared<PressureForce>(mag);
      case PLANE_COLLISION:
        return std::make_shared<PlaneContactForce>(position(toEigen(center.getValue())), planeNormal(toEigen(normal.getValue())),
                                                   stiffness.getValue());
      case SPHERE_COLLISION:
        return std::make_shared<SphereContactForce>(position(toEigen(center.getValue())), radius.getValue() / lengthScale,
                                                    stiffness.getValue());
      case COLLISION: {
        if (!info.contact) {
          error = "COLLISION needs the surface's obstacles";
          return nullptr;
        }
        if (method.getValue() == BARRIER) {
          BarrierContactParameters bp;
          bp.offset = thickness.getValue();
          bp.dhat = dhat.getValue();
          bp.selfContact = selfContact.getValue();
          bp.samplesPerSpan = proxySamples.getValue();
          bp.friction = friction.getValue();
          bp.epsv = epsv.getValue();
          bp.modelMass = true;
          return std::make_shared<BarrierContactForce>(info.contact, bp);
        }
        ContactParameters cp;
        cp.thickness = thickness.getValue();
        cp.stiffness = stiffness.getValue();
        cp.damping = damping.getValue();
        cp.friction = friction.getValue();
        cp.modelMass = true;
        return std::make_shared<CollisionForce>(info.contact, cp);
      }
      case EXPRESSION: {
        if (!std::isfinite(mag)) {
          std::ostringstream os;
          os << "field 'magnitude' must be finite, got " << mag;
          error = os.str();
          return nullptr;
        }
        if (expression.getNum() != 3) {
          error = "field 'expression' needs 3 formulas (x, y, z), got " + std::to_string(expression.getNum());
          return nullptr;
        }
        auto ex = std::make_shared<ExpressionDensity>();
        static const char* names[3] = {"x", "y", "z"};
        for (int i = 0; i < 3; ++i) {
          mu::Parser& parser = ex->parser[i];
          parser.DefineConst("pi", 3.14159265358979323846);
          parser.DefineVar("u", &ex->u);
          parser.DefineVar("v", &ex->v);
          parser.DefineVar("x", &ex->x);
          parser.DefineVar("y", &ex->y);
          parser.DefineVar("z", &ex->z);
          parser.DefineVar("t", &ex->t);
          const std::string text = expression[i].getString();
          try {
            parser.SetExpr(text.empty() ? "0" : text);
            parser.Eval();  // parses; unknown names and syntax errors throw here
            for (const auto& used : parser.GetUsedVar()) {
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
        // The user's formula, evaluated by muParser: the one density that stays a callable.
        // WORLD: the formulas see world x y z and give a world vector
        const Eigen::Matrix3d toWorld = world ? A : Eigen::Matrix3d::Identity();
        const Eigen::Vector3d offset = world ? info.offset : Eigen::Vector3d::Zero();
        return std::make_shared<DistributedForce>(
            [ex, mag, toWorld, offset, Ainv](const SurfaceSample& s) {
              const Eigen::Vector3d x = toWorld * s.position + offset;
              ex->u = s.u;
              ex->v = s.v;
              ex->x = x.x();
              ex->y = x.y();
              ex->z = x.z();
              ex->t = s.t;
              const Eigen::Vector3d w(mag * ex->parser[0].Eval(), mag * ex->parser[1].Eval(), mag * ex->parser[2].Eval());
              return Eigen::Vector3d(Ainv * w);
            },
            ex->dependence);
      }
    }
    error = "field 'type' has an unknown value " + std::to_string(type.getValue());
  } catch (const std::exception& e) {
    SbName name;
    type.getEnum(type.getValue(), name);
    error = std::string("type ") + name.getString() + ": " + e.what();
  }
  return nullptr;
}

std::vector<SoForceField::Refusal> SoForceField::refusedFields(const SurfaceInfo& info) {
  std::string whole;
  makeForce(info, whole);
  if (whole.empty()) return {};
  auto* scratch = new SoForceField;
  scratch->ref();
  scratch->enableNotify(FALSE);  // it only holds values
  auto* defaults = new SoForceField;
  defaults->ref();
  scratch->type.setValue(type.getValue());
  std::string error;
  scratch->makeForce(info, error);
  std::vector<Refusal> out;
  if (error.empty()) {  // this type's defaults make a force: try each field alone
    SoFieldList fields;
    const int count = getFields(fields);
    for (int i = 0; i < count; ++i) {
      SbName name;
      getFieldName(fields[i], name);
      if (name == "type" || name == "on" || fields[i]->isOfType(SoSFTime::getClassTypeId())) continue;
      if (!bsdeform::forceFieldUses(type.getValue(), name.getString())) continue;
      SoField* f = scratch->getField(name);
      if (!f || f->isSame(*fields[i])) continue;
      f->copyFrom(*fields[i]);
      scratch->makeForce(info, error);
      if (!error.empty()) out.push_back({name.getString(), error});
      f->copyFrom(*defaults->getField(name));
    }
  }
  if (out.empty()) out.push_back({"", whole});
  scratch->unref();
  defaults->unref();
  return out;
}

std::vector<SoForceField::Refusal> SoForceField::refusedFields() { return refusedFields(SurfaceInfo()); }
