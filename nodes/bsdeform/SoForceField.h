// SPDX-License-Identifier: MIT
#pragma once
/// @file SoForceField.h
/// One external force acting on SoBSplineDeformSurface nodes, as an Inventor engine.
///
/// A surface lists the force fields acting on it in its `forces` field; one force field can act
/// on several surfaces (DEF/USE). Field changes — from code, from a file or through a field
/// connection (e.g. `magnitude = ElapsedTime {} . timeOut`) — take effect on the next step.
///
/// \code
/// SoBSplineDeformSurface {
///   forces [ DEF Push SoForceField { type REGION  force 0 0 1  magnitude 100
///                                    regionMin 0.4 0.4  regionMax 0.6 0.6 } ]
/// }
/// \endcode
///
/// FILE FORMAT/DEFAULTS:
/// \code
/// SoForceField {
///   type UNIFORM          # UNIFORM POINT REGION EXPRESSION GRAVITY SPRING DRAG PRESSURE
///                         # PLANE_COLLISION SPHERE_COLLISION
///   on TRUE
///   force 0 0 1           # force density / point force / gravity acceleration (direction)
///   magnitude 1           # scales force, expression, pressure
///   point 0.5 0.5         # (u, v) of POINT and SPRING
///   regionMin 0.4 0.4     # (u0, v0) of REGION
///   regionMax 0.6 0.6     # (u1, v1) of REGION
///   expression [ "0", "0", "0" ]   # x, y, z force density in u v x y z t (muParser syntax, pi)
///   anchor 0.5 0.5 1      # SPRING anchor
///   center 0 0 0          # PLANE_COLLISION point on plane / SPHERE_COLLISION centre
///   normal 0 0 1          # PLANE_COLLISION plane normal (the free side)
///   radius 0.25           # SPHERE_COLLISION radius
///   stiffness 10          # SPRING constant, collision penalty per unit area and depth
///   coefficient 1         # DRAG: force density = -coefficient * velocity
/// }
/// \endcode

#include <Inventor/engines/SoEngine.h>
#include <Inventor/engines/SoSubEngine.h>
#include <Inventor/fields/SoMFString.h>
#include <Inventor/fields/SoSFBool.h>
#include <Inventor/fields/SoSFEnum.h>
#include <Inventor/fields/SoSFFloat.h>
#include <Inventor/fields/SoSFInt32.h>
#include <Inventor/fields/SoSFVec2f.h>
#include <Inventor/fields/SoSFVec3f.h>

#include <memory>
#include <string>

namespace bsdeform {
class Force;
}

class SoForceField : public SoEngine {
  using inherited = SoEngine;
  SO_ENGINE_HEADER(SoForceField);

 public:
  enum Type {
    UNIFORM,           ///< constant density `magnitude * force` on the whole surface
    POINT,             ///< point force `magnitude * force` at `point`
    REGION,            ///< constant density on the parameter rectangle regionMin..regionMax
    EXPRESSION,        ///< density given by `expression` (three formulas) times magnitude
    GRAVITY,           ///< mass density of the surface times acceleration `magnitude * force`
    SPRING,            ///< `stiffness * (anchor - S(point))` at `point` (the drag of the mouse)
    DRAG,              ///< viscous density `-coefficient * velocity`
    PRESSURE,          ///< density `magnitude * unit normal`
    PLANE_COLLISION,   ///< penalty `stiffness * depth * normal` below the plane (center, normal)
    SPHERE_COLLISION,  ///< penalty pushing out of the sphere (center, radius)
  };

  static void initClass();
  SoForceField();

  SoSFEnum type;            ///< the kind of force, UNIFORM by default
  SoSFBool on;              ///< FALSE switches the force off; TRUE by default
  SoSFVec3f force;          ///< force (density) vector or gravity acceleration; (0, 0, 1)
  SoSFFloat magnitude;      ///< scale of force / expression / pressure; 1
  SoSFVec2f point;          ///< (u, v) parameter point of POINT and SPRING; (0.5, 0.5)
  SoSFVec2f regionMin;      ///< (u0, v0) of REGION; (0.4, 0.4)
  SoSFVec2f regionMax;      ///< (u1, v1) of REGION; (0.6, 0.6)
  SoMFString expression;    ///< x, y, z density formulas of u v x y z t; ["0","0","0"]
  SoSFVec3f anchor;         ///< SPRING anchor point (world units of the surface); (0.5, 0.5, 1)
  SoSFVec3f center;         ///< plane point / sphere centre; (0, 0, 0)
  SoSFVec3f normal;         ///< plane normal; (0, 0, 1)
  SoSFFloat radius;         ///< sphere radius; 0.25
  SoSFFloat stiffness;      ///< spring constant / penalty stiffness; 10
  SoSFFloat coefficient;    ///< drag coefficient per unit area; 1

  /// Revision of the input values: changes whenever an input changes (a surface rebuilds its
  /// core force when it sees a new revision).
  SoEngineOutput revision;  ///< (SoSFInt32)

  /// What a surface tells a force field when it builds its core force.
  struct SurfaceInfo {
    double massDensity = 1.0;  ///< mass per unit parameter area (for GRAVITY)
  };
  /// Builds the core force for the current field values. Returns null when the force is off.
  /// @param[out] error set to a message naming the field and value when the values are bad
  ///             (the caller warns and keeps its previous force)
  std::shared_ptr<const bsdeform::Force> makeForce(const SurfaceInfo& info, std::string& error);

  /// Current revision without going through an engine connection.
  int getRevision() const { return m_revision; }

 protected:
  ~SoForceField() override;
  void inputChanged(SoField* which) override;
  void evaluate() override;

 private:
  int m_revision = 0;
};
