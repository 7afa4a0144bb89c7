// SPDX-License-Identifier: MIT
#pragma once
/// @file SoForceField.h
/// One external force acting on SoBSplineDeformSurface nodes, as an Inventor engine.
///
/// A surface lists the force fields acting on it in its `forces` field; one force field can act
/// on several surfaces (DEF/USE). Field changes — from code, from a file or through a field
/// connection (e.g. `magnitude = ElapsedTime {} . timeOut`) — take effect on the next step.
/// The node only converts its fields: each type maps to one core class (bsdeform/forces/Force.h,
/// bsdeform/forces/ForceLaws.h), which validates the values and holds the formula.
///
/// \code
/// SoBSplineDeformSurface {
///   forces [ DEF Push SoForceField { type REGION  force 0 0 1  magnitude 100
///                                    regionMin 0.4 0.4  regionMax 0.6 0.6 } ]
/// }
/// \endcode
///
/// Numbers are doubles (SoSFDouble, SoSFVec2d, SoSFVec3d), read and written like the surface's:
/// `point 0.97 0.5` acts at u = 0.97 exactly. Connections from single-precision engine outputs
/// (SoSFFloat, SoMFFloat, SoSFTime, SoSFInt32, SoSFShort, SoSFBool -> SoSFDouble; SoSFVec2f,
/// SoMFVec2f -> SoSFVec2d) go through a converter that initClass() registers, because Coin 4.0
/// has none for double fields (SoSFVec3f -> SoSFVec3d it has); such values carry float precision.
///
/// FILE FORMAT/DEFAULTS:
/// \code
/// SoForceField {
///   type UNIFORM          # UNIFORM POINT REGION EXPRESSION GRAVITY SPRING DRAG PRESSURE
///                         # PLANE_COLLISION SPHERE_COLLISION
///   on TRUE
///   force 0 0 1           # SFVec3d: force density / point force / gravity acceleration (direction)
///   magnitude 1           # SFDouble: scales force, expression, gravity; the PRESSURE p
///   point 0.5 0.5         # SFVec2d: (u, v) of POINT and SPRING
///   regionMin 0.4 0.4     # SFVec2d: (u0, v0) of REGION
///   regionMax 0.6 0.6     # SFVec2d: (u1, v1) of REGION
///   expression [ "0", "0", "0" ]   # x, y, z force density in u v x y z t (muParser syntax, pi)
///   anchor 0.5 0.5 1      # SFVec3d: SPRING anchor
///   center 0 0 0          # SFVec3d: PLANE_COLLISION point on plane / SPHERE_COLLISION centre
///   normal 0 0 1          # SFVec3d: PLANE_COLLISION plane normal (the free side)
///   radius 0.25           # SFDouble: SPHERE_COLLISION radius
///   stiffness 10          # SFDouble: SPRING constant, collision penalty per unit area and depth
///   coefficient 1         # SFDouble: DRAG: force density = -coefficient * velocity
///   frame WORLD           # WORLD LOCAL: the frame of force, anchor, center, normal, radius, expression
/// }
/// \endcode
///
/// | type             | core class                          | arguments                                  |
/// |------------------|-------------------------------------|--------------------------------------------|
/// | UNIFORM          | DistributedForce                    | magnitude * force                          |
/// | POINT            | PointForce                          | point, magnitude * force                   |
/// | REGION           | DistributedForce                    | magnitude * force, regionMin..regionMax    |
/// | EXPRESSION       | DistributedForce (muParser callable)| magnitude * (x, y, z formulas)             |
/// | GRAVITY          | GravityForce                        | surface mass density, magnitude * force    |
/// | SPRING           | SpringForce                         | point, anchor, stiffness                   |
/// | DRAG             | DragForce                           | coefficient                                |
/// | PRESSURE         | PressureForce                       | magnitude                                  |
/// | PLANE_COLLISION  | PlaneContactForce                   | center, normal, stiffness                  |
/// | SPHERE_COLLISION | SphereContactForce                  | center, radius, stiffness                  |
/// | COLLISION        | CollisionForce (bsdeform/contact/Contact.h) | obstacles, obstacleNames, thickness, stiffness, damping, friction |
///
/// COLLISION: each entry of `obstacles` is any subgraph (DEF/USE a Separator with a Transform
/// and a Cube, an IndexedFaceSet, a NurbsSurface, another SoBSplineDeformSurface). Its
/// triangles are gathered in world coordinates (bsdeform/SceneObstacles.h says how frames are
/// found) and re-gathered only when Coin reports a change. `obstacleNames` adds nodes by DEF
/// name, found in the surface's scene when gathering: a file cannot USE a node before its
/// definition, so two surfaces that collide both ways name each other (or the first is listed
/// in `obstacles` of the second and the second named by the first).

#include <Eigen/Core>
#include <Inventor/engines/SoEngine.h>
#include <Inventor/engines/SoSubEngine.h>
#include <Inventor/fields/SoMFNode.h>
#include <Inventor/fields/SoMFString.h>
#include <Inventor/fields/SoSFBool.h>
#include <Inventor/fields/SoSFEnum.h>
#include <Inventor/fields/SoSFDouble.h>
#include <Inventor/fields/SoSFInt32.h>
#include <Inventor/fields/SoSFVec2d.h>
#include <Inventor/fields/SoSFVec3d.h>

#include <memory>
#include <string>
#include <vector>

namespace bsdeform {
class Force;
struct ContactWorld;
}

class SoForceField : public SoEngine {
  using inherited = SoEngine;
  SO_ENGINE_HEADER(SoForceField);

 public:
  enum Type {
    UNIFORM,           ///< constant density `magnitude * force` on the whole surface (DistributedForce)
    POINT,             ///< point force `magnitude * force` at `point` (PointForce)
    REGION,            ///< constant density on the rectangle regionMin..regionMax (DistributedForce)
    EXPRESSION,        ///< density given by `expression` (three formulas) times magnitude (DistributedForce)
    GRAVITY,           ///< surface mass density times acceleration `magnitude * force` (GravityForce)
    SPRING,            ///< `stiffness * (anchor - S(point))` at `point` (SpringForce)
    DRAG,              ///< viscous density `-coefficient * velocity` (DragForce)
    PRESSURE,          ///< density `magnitude * unit normal` (PressureForce)
    PLANE_COLLISION,   ///< penalty `stiffness * depth * normal` below the plane (PlaneContactForce)
    SPHERE_COLLISION,  ///< penalty pushing out of the sphere (center, radius) (SphereContactForce)
    COLLISION,         ///< penalty, damping and friction against the `obstacles` (CollisionForce)
  };
  /// COLLISION: how contact is enforced.
  enum Method {
    PENALTY,  ///< a force proportional to the depth at quadrature points (CollisionForce); every integrator
    BARRIER   ///< IPC's barrier on a collision proxy with CCD-bounded steps (BarrierContactForce); BACKWARD_EULER
  };
  /// In which frame the vectors and points of the fields are given.
  enum Frame {
    WORLD,  ///< the world's, whatever Transforms are above the surface (default)
    LOCAL   ///< the surface's own coordinates (its control net's), as before issue 37
  };

  static void initClass();
  SoForceField();

  SoSFEnum type;            ///< the kind of force, UNIFORM by default
  SoSFBool on;              ///< FALSE switches the force off; TRUE by default
  SoSFVec3d force;          ///< force (density) vector or gravity acceleration; (0, 0, 1)
  SoSFDouble magnitude;     ///< scale of force / expression / gravity; the pressure p; 1
  SoSFVec2d point;          ///< (u, v) parameter point of POINT and SPRING; (0.5, 0.5)
  SoSFVec2d regionMin;      ///< (u0, v0) of REGION; (0.4, 0.4)
  SoSFVec2d regionMax;      ///< (u1, v1) of REGION; (0.6, 0.6)
  SoMFString expression;    ///< x, y, z density formulas of u v x y z t; ["0","0","0"]
  SoSFVec3d anchor;         ///< SPRING anchor point (world units of the surface); (0.5, 0.5, 1)
  SoSFVec3d center;         ///< plane point / sphere centre; (0, 0, 0)
  SoSFVec3d normal;         ///< plane normal (the free side); (0, 0, 1)
  SoSFDouble radius;        ///< sphere radius; 0.25
  SoSFDouble stiffness;     ///< spring constant k / penalty per unit area and depth (COLLISION: world area); 10
  SoSFDouble coefficient;   ///< drag coefficient c per unit parameter area; 1
  SoMFNode obstacles;       ///< COLLISION: subgraphs the surface collides with; []
  /// COLLISION: DEF names of further obstacles, looked up in the surface's scene (first match,
  /// depth first) each time the obstacles are gathered: the way a file lists a node defined
  /// after it (two surfaces that collide both ways); []
  SoMFString obstacleNames;
  SoSFDouble thickness;     ///< COLLISION: contact offset (world units); 0.02
  SoSFDouble damping;       ///< COLLISION: normal damping, per unit world area (pressure per approach speed); 0
  SoSFDouble friction;      ///< COLLISION: Coulomb coefficient mu; 0
  SoSFEnum method;          ///< COLLISION: PENALTY (default) or BARRIER
  SoSFDouble dhat;          ///< COLLISION BARRIER: the barrier acts from thickness to thickness + dhat (m); 0.001
  SoSFBool selfContact;     ///< COLLISION BARRIER: the surface also collides with itself; FALSE
  SoSFInt32 proxySamples;   ///< COLLISION BARRIER: collision proxy intervals per knot span and direction; 2
  SoSFDouble epsv;          ///< COLLISION BARRIER: friction's velocity threshold ε_v (m/s), slower slips are static; 0.001
  /// WORLD: force, anchor, center, normal, radius and the EXPRESSION's x y z and result are in
  /// world coordinates, converted through the Transforms above the surface; LOCAL: in the
  /// surface's own coordinates. WORLD by default. (COLLISION is always in the world.)
  SoSFEnum frame;

  /// Revision of the input values: changes whenever an input changes (a surface rebuilds its
  /// core force when it sees a new revision).
  SoEngineOutput revision;  ///< (SoSFInt32)

  /// What a surface tells a force field when it builds its core force. The model's mass per area
  /// and rest area are not in it: GRAVITY and COLLISION read them from the model at every step
  /// (bsdeform::LoadContext), so a model rebuilt with another mass keeps its forces.
  struct SurfaceInfo {
    /// COLLISION: the obstacles as the surface keeps them (SceneObstacles)
    std::shared_ptr<const bsdeform::ContactWorld> contact;
    /// The surface's world transform, x_world = linear x_local + offset (frame WORLD)
    Eigen::Matrix3d linear = Eigen::Matrix3d::Identity();
    Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  };
  /// Builds the core force for the current field values. Returns null when the force is off.
  /// @param[out] error set to a message naming the field and value when the values are bad
  ///             (the caller warns and keeps its previous force)
  std::shared_ptr<const bsdeform::Force> makeForce(const SurfaceInfo& info, std::string& error);

  /// A field whose value makes no force, and why.
  struct Refusal {
    std::string field;    ///< "" when no one field is at fault (the values together are refused)
    std::string message;  ///< makeForce's sentence for that value
  };
  /// Every field whose value makeForce refuses, each once: each field the current type reads is
  /// tried alone, the others at their defaults, on a scratch force field (this one is not
  /// touched). When no single field is refused but the values together are, one Refusal without
  /// a field. Empty when makeForce takes the values.
  std::vector<Refusal> refusedFields(const SurfaceInfo& info);
  std::vector<Refusal> refusedFields();  ///< with a SurfaceInfo() (COLLISION is then refused whole)

  /// Current revision without going through an engine connection.
  int getRevision() const { return m_revision; }
  /// Changes when `obstacles`, `obstacleNames` or anything inside the listed nodes changes (the surfaces re-gather
  /// the triangles; the force itself is not rebuilt).
  int getGeometryRevision() const { return m_geometryRevision; }

 protected:
  ~SoForceField() override;
  void inputChanged(SoField* which) override;
  void evaluate() override;
  /// Snaps the doubles read to their 15-digit value (bsdeform::snap15), as the surface does.
  SbBool readInstance(SoInput* in, unsigned short flags) override;

 private:
  int m_revision = 0;
  int m_geometryRevision = 0;
};
