// SPDX-License-Identifier: MIT
#pragma once
/// @file Contact.h
/// Penalty contact of a surface with obstacle meshes of any shape, with damping and Coulomb
/// friction (docs/math.md §14). The scene layer gathers the obstacles' triangles in world
/// coordinates into a ContactWorld and keeps it current; CollisionForce reads it in every step.

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "bsdeform/forces/Force.h"
#include "bsdeform/contact/TriangleTree.h"

namespace bsdeform {

/// The obstacles of one surface, in world coordinates, and the surface's own frame:
/// a point x of the surface's coordinates is at A x + b in the world.
struct ContactWorld {
  struct Obstacle {
    std::shared_ptr<const TriangleTree> tree;
    /// Closed and consistently wound (every edge in two triangles, in opposite directions):
    /// the inside is known and contact is one-sided; otherwise two-sided (a shell).
    bool closed = false;
    /// What messages call it (the scene's node: its type and name, "Cube 'Box'"); empty: its
    /// number in `obstacles`, from 1
    std::string name;
  };
  std::vector<Obstacle> obstacles;
  Eigen::Matrix3d linear = Eigen::Matrix3d::Identity();  ///< A
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();       ///< b
};

/// Whether a ContactWorld's obstacles or frame have moved: the obstacles' versions and the frame
/// when first asked. A moving obstacle does work on the surface, so a contact force stores energy
/// only while nothing moved.
class ContactWorldSnapshot {
 public:
  /// Takes the snapshot at the first call; afterwards whether `w` is as it was then.
  bool unchangedSinceFirst(const ContactWorld& w);

 private:
  bool m_taken = false;
  std::vector<std::uint64_t> m_versions;
  Eigen::Matrix3d m_linear = Eigen::Matrix3d::Zero();
  Eigen::Vector3d m_offset = Eigen::Vector3d::Zero();
};

/// Contact law parameters (world units; densities per unit parameter area as every
/// DistributedForce).
struct ContactParameters {
  double thickness = 0.01;  ///< tau > 0: contact starts at this distance from an obstacle
  double stiffness = 1e4;   ///< k >= 0: normal force per unit depth
  double damping = 0.0;     ///< c >= 0: normal damping on the approach speed
  double friction = 0.0;    ///< mu >= 0: Coulomb coefficient
  double massDensity = 1.0; ///< rho > 0: the surface's mass per unit parameter area (friction and damping caps)
  /// a > 0: the surface's world area per unit parameter area (its rest area, surfaceArea() of the
  /// rest net). The law above is per unit world area (stiffness: pressure per depth), so the
  /// density per unit parameter area is a times it; two surfaces in contact then press on each
  /// other equally whatever their sizes (to within their stretch from rest).
  double areaScale = 1.0;
  /// Whether massDensity and areaScale are the model's, read at every evaluation from the load
  /// context (LoadContext::massPerArea, restArea) instead of the two values above: a model rebuilt
  /// with another mass or rest shape keeps the same force (what the nodes do).
  bool modelMass = false;
};

/// Whether a mesh is closed and consistently wound (each undirected edge in exactly two
/// triangles, once in each direction). Vertices are compared by index.
bool isClosedMesh(const TriangleMesh& mesh);

/// Float rounding a weld forgives by default: Coin's geometry is single precision, and the two
/// copies of a seam vertex (a Sphere's at 0 and 2 pi, a Cone's apex) come out of float sine,
/// cosine and matrix products a few units in the last place apart.
constexpr double kWeldUlps = 8.0;

/// Merges vertices (triangles gathered face by face repeat them) that agree to within
/// `tolerance` in every coordinate: each vertex joins a kept vertex within the tolerance, or is
/// kept (so groups do not chain, and the kept positions are input positions). A negative tolerance means
/// kWeldUlps float epsilons of the largest coordinate magnitude; 0 merges only identical
/// coordinates. Non-finite vertices merge only when identical. Triangles keep their order;
/// one whose corners weld together stays in the list (TriangleTree drops it as degenerate).
TriangleMesh weldVertices(const TriangleMesh& mesh, double tolerance = -1.0);

/// One evaluation of the contact law in world coordinates at point x moving with velocity v:
/// with s the (signed, for closed obstacles) distance to the closest point and n the unit
/// direction away from the obstacle, depth = tau - s > 0 gives the normal density
/// f_n = max(0, k depth - c' (v.n)) and the friction density -min(mu f_n, 0.3 rho |v_t| / dt)
/// v_t / |v_t|, with c' = min(c, 0.3 rho / dt). Summed over the obstacles in contact.
/// Obstacles are searched within 3 tau (deeper points of a closed obstacle get no force).
/// @param depth  if not null, receives the largest depth tau - s (0 out of contact; > tau past
///               the obstacle's surface)
Eigen::Vector3d contactDensity(const ContactWorld& world, const ContactParameters& p, const Eigen::Vector3d& x,
                               const Eigen::Vector3d& v, double dt, double* depth = nullptr);

/// The same law for a surface whose own coordinates map to the world by `frame` (A) and whose
/// density will be multiplied by `scale` (a gamma) and mapped by A^T: the damping and friction
/// caps are set so that, in the surface's own terms, their rates stay within 0.3 rho / dt:
/// damping c' = min(c, 0.3 rho / (dt scale |A^T n|^2)), friction at most
/// 0.3 rho |v_t| / (dt scale lambda_max(A^T P_t A)) (P_t the projection on the tangent plane).
/// With A = I and scale 1 this is the law above.
Eigen::Vector3d contactDensity(const ContactWorld& world, const ContactParameters& p, const Eigen::Vector3d& x,
                               const Eigen::Vector3d& v, double dt, const Eigen::Matrix3d& frame, double scale,
                               double* depth = nullptr);

/// Contact with the obstacles of a ContactWorld as a distributed force on the surface: the
/// density above at S(u, v) (caps in the surface's own terms, see the frame overload), times the world area per
/// unit parameter area, mapped to the surface's coordinates: f = a gamma A^T f_world, with a the
/// rest area scale and gamma = |cof(A) n| the world area per local area of the frame at the
/// point (s^2 for a frame A = s R).
class CollisionForce : public Force {
 public:
  /// @throws std::invalid_argument naming the parameter and the value
  CollisionForce(std::shared_ptr<const ContactWorld> world, const ContactParameters& p);

  unsigned dependence() const override { return kDependsOnPosition | kDependsOnVelocity; }

  /// The penalty's stiffness through the frame: a sigma_1 sigma_2 k ||A||_2^2 h1 h2 / m_interior (as
  /// PlaneContactForce with k ||A||^2). Damping and friction are capped (0.3 rho / dt) so that
  /// they stay within the margin the sub-step sizing leaves (see DragForce).
  double eigenvalueBound(const MassContext& ctx) const override;
  /// The normal penalty's stiffness and the normal damping's (times velocityScale) at every
  /// quadrature point in contact, through the frame: \f$a\gamma A^T (k + s c') n n^T A\f$ (exact
  /// inside an obstacle's faces; at an edge or vertex the part along n only, positive
  /// semidefinite; the frame's area factor \f$\gamma\f$ taken as constant, exact for a
  /// similarity), and friction's derivative with respect to the tangential velocity (viscous at
  /// the rate cap, Coulomb's \f$\mu f_n (I - nn^T - tt^T)/|v_t|\f$ else; its dependence on
  /// \f$f_n\f$ left out). No potential (damping and friction are not conservative).
  bool hasJacobian() const override { return true; }
  void addJacobian(const LoadContext& ctx, double velocityScale, JacobianSink& sink) const override;
  /// The normal penalty's energy, \f$\sum_g w_g\, a\gamma\, \tfrac12 k\, \mathrm{depth}^2\f$ (the
  /// deepest obstacle at each point; damping and friction only dissipate); false once an
  /// obstacle or the frame has changed since the first call (a moving obstacle does work).
  bool storedEnergy(const LoadContext& ctx, double& value) const override;
  const ContactParameters& parameters() const { return m_params; }
  /// parameters(), with the model's mass density and area from `ctx` where modelMass is set.
  ContactParameters parametersFor(const LoadContext& ctx) const;
  const ContactWorld& world() const { return *m_world; }

  /// The load: the same quadrature as DistributedForce (degree + 3 Gauss points per span and
  /// direction), evaluated only on the elements (knot spans) that may be within the search
  /// distance 3 tau of an obstacle, which gives the same load as evaluating everywhere: every
  /// point of an element lies in the box of its control points (convex hull), so an element
  /// whose box is farther than 3 tau from every triangle gets exactly zero. The clearance of each
  /// element is measured at a reference net; while the net has moved less than the clearance
  /// since (the largest control-point displacement, through ||A||), the element is skipped
  /// without a query. The reference is renewed when that displacement exceeds a skin (3 tau plus
  /// an element's diagonal), or the obstacles or the frame change (a tree's update(), another
  /// tree, another A or b).
  ///
  /// Within an evaluated element each quadrature point keeps a clearance of its own the same
  /// way: the distance it may move before an obstacle can act on it (outside an obstacle: its
  /// distance minus tau; inside a closed one, or with nothing within the search: its distance
  /// minus 3 tau), less the net's motion since the reference when it was measured. Its queries
  /// search as far as the skin, starting from the triangle it found last (TriangleTree's hint).
  /// A resting or sliding cloth then queries only the points within tau of an obstacle. The
  /// load is the same as without either skip (tested against the density at every point).
  void addLoad(const LoadContext& ctx, ControlNet& load) const override;

  /// What the last addLoad did (for benchmarks and tests).
  struct Counters {
    long long loads = 0;          ///< addLoad calls
    long long references = 0;     ///< reference nets taken (clearance of every element measured)
    long long elementQueries = 0; ///< clearance queries (one per element and obstacle, per reference)
    long long pointQueries = 0;   ///< quadrature points evaluated (one closest-point query per obstacle)
    long long pointsSkipped = 0;  ///< quadrature points of evaluated elements skipped by their clearance
    int activeElements = 0;       ///< elements evaluated in the last addLoad
    int elements = 0;             ///< elements of the surface
  };
  const Counters& counters() const;

 private:
  struct Cache;
  std::shared_ptr<const ContactWorld> m_world;
  ContactParameters m_params;
  std::shared_ptr<Cache> m_cache;  // mutable state of addLoad (the force is const in a step)
  /// The obstacles' versions and the frame when storedEnergy() was first asked.
  std::shared_ptr<ContactWorldSnapshot> m_seen;
};

}  // namespace bsdeform
