// SPDX-License-Identifier: MIT
#pragma once
/// @file SurfaceModel.h
/// How an SoBSplineDeformSurface's fields become a bsdeform::Simulation: the model parameters
/// and rest net its fields describe, the state a new model starts from, and the forces of its
/// force fields. The node (SoBSplineDeformSurface.cpp) is the Coin plumbing around these: when
/// to rebuild, what to tell, how to draw. Not installed: the nodes' own.

#include <Inventor/fields/SoMFEngine.h>
#include <Inventor/fields/SoMFVec3d.h>

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/SoBSplineDeformSurface.h"

class SoNode;

namespace bsdeform {

class Force;
class ParameterError;
class SceneObstacles;

/// A node's or engine's DEF name, "<unnamed>" without one (as problems name them).
std::string nameOf(const SoBase* b);

/// A field the node refuses and why (the sentence names the field).
struct FieldRefusal {
  std::string field;
  std::string message;
};

/// The model parameters and the rest net (empty: the plane) that the fields of `node` describe.
/// Numbers and their limits are the core's to check when the Simulation is made (it throws a
/// ParameterError); here only what is the node's own: enumerations, the sizes of its nets, pins,
/// the rest shape's net, a periodic direction without a rest net. Returns false with `refusal`
/// set when a field is refused.
bool modelFromFields(const SoBSplineDeformSurface& node, ModelParameters& p, ControlNet& rest, FieldRefusal& refusal);

/// Every field of `node` refused as its values stand, each once, first the one modelFromFields or
/// the Simulation constructor names first. Found on a scratch copy of the fields (the node and
/// its model are not touched): each refused field in turn goes back to its default until the
/// model is taken, so one refusal does not hide the next. A net whose size a reset field changed
/// is not listed (the reset made it wrong, not the file). Empty when the model is taken.
std::vector<FieldRefusal> fieldRefusals(const SoBSplineDeformSurface& node);

/// The core's refusal named by the node's field that sets the parameter (FieldInfo).
FieldRefusal refusalOf(const ParameterError& e);

/// Starts the new model `sim`: from the state fields when they were read (`stateFromFields`,
/// a file or a script set them), else from `old`'s motion when the net and the rest shape are
/// the same (a live edit of the model: held points go back to rest; a state still released from
/// rest stays so, the new start rule applying), else at rest. Returns whether `old`'s motion
/// was carried over.
bool startState(Simulation& sim, const SoBSplineDeformSurface& node, bool stateFromFields, const Simulation* old);

/// Whether a side's motion field (motionUMin ...) moves it: connected (to an engine, a clock) or
/// set to other than the identity.
bool sideMotionSet(const SoSFMatrix& field);
/// Hands `node`'s motionUMin ... to `sim` (Simulation::setSideMotion, clearSideMotion): the
/// pose its moved sides reach at the end of the next step. modelFromFields has checked them.
void applySideMotions(Simulation& sim, const SoBSplineDeformSurface& node);

/// The paper's static problem solved for `sim`'s current loads (SHELL: Newton to
/// newtonTolerance; the paper's model: the linear solve to 1e-10), in `loadSteps` increments,
/// `each` called with every increment while the state holds it; the last becomes the state.
/// Throws what Simulation::solveStatic throws, leaving the state alone. With `arcLength`
/// (SHELL), the path by arc-length continuation instead (Simulation::solveStaticArcLength): one
/// increment per converged point, the last becoming the state.
StaticResult solveStaticInto(Simulation& sim, int loadSteps,
                             const std::function<void(const StaticResult&, size_t, const Diagnostics&)>& each,
                             const ArcLengthOptions* arcLength = nullptr);

/// Whole steps of `dt` due after `seconds` of realTime at `speed`, the remainder kept in `owed`
/// for the next call. A slow frame is not made up: a quarter second at most per call, 10000 steps
/// at most (a budget beyond them is dropped, not owed).
int stepsDue(double seconds, double speed, double dt, double& owed);

/// After Coin read `node`: the doubles and nets it read snapped to their 15-digit form (Coin's
/// reader is off by a few ulps; snap15 makes write -> read -> write a fixed point), unnotified.
void snapReadValues(SoBSplineDeformSurface& node);

/// A net field as a control net, and back (values snapped to their 15-digit form, snap15:
/// write -> read -> write is a fixed point).
ControlNet netFromField(const SoMFVec3d& f);
void netToField(const ControlNet& net, SoMFVec3d& f);

/// The core forces of one surface: one slot per entry of its `forces` field, each with the
/// force made from that force field and, for COLLISION, the obstacles it gathered.
class ForceSlots {
 public:
  using Report = std::function<void(SoBSplineDeformSurface::Problem::Kind kind, const std::string& field,
                                    const std::string& message, const std::string& node)>;
  /// Brings the slots in line with `forces` and, when any changed, gives `sim` their forces and
  /// then `transient`. The obstacles are brought up to date every time (a moved Transform is
  /// refitted); a force field is compared with its slot only when `stale` (one told of a
  /// change, or `sim` is a new model) or the list changed. Returns the forces made.
  int update(Simulation& sim, const SoMFEngine& forces, SoNode* scene, SoNode* self, bool stale,
             const std::vector<std::shared_ptr<const Force>>& transient, const Report& report);
  void swap(ForceSlots& other) { std::swap(*this, other); }
  bool empty() const { return m_slots.empty(); }
  /// Before a new model of the same surface: the forces stay (they read the model's mass and rest
  /// area at every step, LoadContext), and so do the gathered obstacles; the COLLISION forces are
  /// made again, since theirs are caches of the old model's net (proxy, clearances, lagged
  /// friction pairs). The next update gives the forces to the new model.
  void keepForNewModel();
  /// Obstacle trees built and refitted (tests).
  int obstacleBuilds() const;
  int obstacleRefits() const;

 private:
  struct Slot {
    void* engine = nullptr;
    int revision = -1;  ///< the force field's revision the force was made from
    std::shared_ptr<const Force> force;
    std::shared_ptr<SceneObstacles> obstacles;  ///< COLLISION: the gathered obstacles
    int geometryRevision = -1;
  };
  std::vector<Slot> m_slots;
  const Simulation* m_given = nullptr;  ///< the model the forces were last given to
  Eigen::Matrix3d m_linear = Eigen::Matrix3d::Identity();  ///< the surface's world frame the forces were made in
  Eigen::Vector3d m_offset = Eigen::Vector3d::Zero();
};

}  // namespace bsdeform
