// SPDX-License-Identifier: MIT
#pragma once
/// @file SoBSplineDeformSurface.h
/// A shape node that owns, animates and draws one B-spline finite-element surface
/// (bsdeform::Simulation). Its fields hold everything needed to rebuild the simulation,
/// including the current state, so a running scene written to .iv resumes where it was.
///
/// \code
/// #Inventor V2.1 ascii
/// SoBSplineDeformSurface {
///   numUControlPoints 6  numVControlPoints 6
///   forces [ SoForceField { type UNIFORM force 0 0 20 } ]
/// }
/// \endcode
///
/// FILE FORMAT/DEFAULTS (paper symbols in brackets):
/// \code
/// SoBSplineDeformSurface {
///   numUControlPoints 5   numVControlPoints 5     # [N1, N2] free control points, >= 1
///   uDegree 3             vDegree 3               # [n1, n2] B-spline degree, 1..7
///   w10 0.1  w01 0.1  w11 0.01  w20 0.01  w02 0.01 # [omega] energy weights, >= 0
///   energy PAPER          # PAPER: the paper's eq. 7 with the weights above | SHELL: the
///                         #   Kirchhoff–Love thin shell of the material below (SI units;
///                         #   mass rho t per rest area, damping a rate in 1/s, loads per m²)
///   material SAINT_VENANT_KIRCHHOFF # SHELL: SAINT_VENANT_KIRCHHOFF (S = C:E) | NEO_HOOKEAN
///                         #   (compressible, plane stress, through the thickness; large strains)
///   youngsModulus 1e6     # SHELL: E (Pa), > 0
///   poissonRatio 0.3      # SHELL: nu, in [0, 0.5)
///   thickness 0.001       # SHELL: t (m), > 0
///   density 1000          # SHELL: rho (kg/m³), > 0
///   massModel NODAL       # NODAL: M = m I (per point) | LUMPED: M = m h1 h2 I (per area)
///   mass 1                # [m] > 0
///   damping 0.5           # [c] >= 0, same convention as mass
///   timeStep 0.1          # [Delta t] simulated seconds per step, > 0
///   integrator EXPLICIT   # EXPLICIT (central differences, sub-stepped) | IMPLICIT (Newmark) |
///                         # BACKWARD_EULER (either energy: incremental potential, forces in Newton; cloth)
///   maxSubSteps 10000     # EXPLICIT: a step needing more sub-steps is refused, not run for minutes
///   newtonTolerance 1e-8  # BACKWARD_EULER, SHELL IMPLICIT and static: Newton's relative residual
///   maxNewtonIterations 30 # BACKWARD_EULER, SHELL IMPLICIT: more iterations fail the step (reported)
///   newtonVelocityTolerance 1e-4 # BACKWARD_EULER: converged when max update / dt is below (m/s)
///   nonlinearSolver NEWTON # BACKWARD_EULER: NEWTON (tangent factorised at the iterates) | LBFGS
///                         #   (quasi-Newton on one matrix per model: cloth at interactive speed)
///   reference REST        # REST: energy of S - S_rest | ABSOLUTE: the paper's energy of S
///   boundaryUMin CLAMPED  # side u = 0: CLAMPED (n outer layers held, the paper) | FREE
///   boundaryUMax CLAMPED  #   (natural boundary) | PERIODIC (both sides of a direction; needs
///   boundaryVMin CLAMPED  #   a rest net that closes: the last n layers repeat the first n) |
///   boundaryVMax CLAMPED  #   SIMPLY_SUPPORTED (edge curve held, a hinge) | BUILT_IN (edge curve
///                         #   and cross derivative held, an engineering clamp) | SYMMETRY (SHELL,
///                         #   static, arc length, BACKWARD_EULER, IMPLICIT: a symmetry plane
///                         #   through the edge); u = 1, v = 0, v = 1 alike
///   holdUMin (X | Y | Z)  # SHELL: the components a SIMPLY_SUPPORTED or BUILT_IN side holds (a rigid
///   holdUMax (X | Y | Z)  #   diaphragm: two of them, a roller: one); holdUMax, holdVMin,
///   holdVMin (X | Y | Z)  #   holdVMax alike
///   holdVMax (X | Y | Z)
///   holdPins (X | Y | Z)  # SHELL, static, arc length, BACKWARD_EULER, IMPLICIT: the components
///                         #   the pins hold (one pin holding Y: a roof's last free slide)
///   motionUMin (identity) # SHELL, BACKWARD_EULER: a CLAMPED side's held layers follow this
///   motionUMax (identity) #   map of their rest positions (connect a ComposeMatrix driven by the
///   motionVMin (identity) #   clock: a sheet twisted by turning one edge); read before each
///   motionVMax (identity) #   step, reached at its end; motionUMax, ... alike
///   pins [ ]              # (u, v) in [0,1]^2: each holds the control points of its knot span
///   start SECOND_ORDER    # SECOND_ORDER: P(-dt) = P(0) + dt^2/2 a(0) | PAPER: P(-dt) = P(0)
///   restShape PLANE       # rest net when restNet is empty: PLANE (u, v, 0) | CYLINDER | CONE |
///                         #   SPHERE | ELLIPSOID | TORUS, centred at the origin, axis z (u goes
///                         #   round: u PERIODIC; SPHERE/ELLIPSOID v sides CLAMPED on the poles,
///                         #   CONE v = 1 CLAMPED on the apex, TORUS v PERIODIC; these override
///                         #   the boundary fields). A given restNet wins over the shape's net.
///   radius 0.5            # R: CYLINDER, CONE base, SPHERE, TORUS (to the tube's centre)
///   height 1              # H: CYLINDER, CONE (z from -H/2 to H/2)
///   minorRadius 0.2       # r: TORUS tube
///   radii 0.6 0.45 0.35   # (a, b, c): ELLIPSOID semi-axes along x, y, z
///   on TRUE               # animate with Coin's realTime (whoever drives it: a viewer, a runner)
///   speed 1               # simulated seconds per second of realTime (at most 10000 steps at once)
///   reset                 # trigger: back to the rest state
///   restNet [ ]           # (N1+2n1)(N2+2n2) points, u-major; empty: the plane (u, v, 0)
///   controlNet [ ]        # current state; empty: the rest net
///   previousNet [ ]       # state one sub-step earlier; empty: controlNet (at rest)
///   simulationTime 0      # [t] simulated time of controlNet
///   stepCount 0           # steps taken
///   forceState [ ]        # what the forces adapt between steps (barrier contact's stiffness)
///   forces [ ]            # SoForceField engines acting on the surface
/// }
/// \endcode

#include <Inventor/fields/SoMFEngine.h>
#include <Inventor/fields/SoMFVec2d.h>
#include <Inventor/fields/SoSFVec3d.h>
#include <Inventor/fields/SoMFDouble.h>
#include <Inventor/fields/SoMFVec3d.h>
#include <Inventor/fields/SoSFBitMask.h>
#include <Inventor/fields/SoSFBool.h>
#include <Inventor/fields/SoSFDouble.h>
#include <Inventor/fields/SoSFEnum.h>
#include <Inventor/fields/SoSFFloat.h>
#include <Inventor/fields/SoSFInt32.h>
#include <Inventor/fields/SoSFMatrix.h>
#include <Inventor/fields/SoSFTrigger.h>
#include <Inventor/nodes/SoShape.h>
#include <Inventor/nodes/SoSubNode.h>

#include <cstdint>
#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bsdeform/spline/Tessellation.h"

namespace bsdeform {
class ForceSlots;
class SceneRunner;
class Simulation;
class Force;
class SceneObstacles;
class SurfaceBuffers;
struct StaticResult;
struct ArcLengthOptions;
struct Diagnostics;
struct SimulationState;
}  // namespace bsdeform

class SoFieldSensor;
class SoNodeSensor;
class SoSensor;
class SoPickedPoint;

class SoBSplineDeformSurface : public SoShape {
  using inherited = SoShape;
  SO_NODE_HEADER(SoBSplineDeformSurface);

 public:
  enum MassModel { NODAL, LUMPED };
  enum Integrator { EXPLICIT, IMPLICIT, BACKWARD_EULER };
  /// The `nonlinearSolver` field (BACKWARD_EULER).
  enum NonlinearSolver { NEWTON, LBFGS };
  enum Reference { REST, ABSOLUTE };
  enum Boundary { CLAMPED, FREE, PERIODIC, SIMPLY_SUPPORTED, BUILT_IN, SYMMETRY };
  /// The world components of holdUMin ... holdVMax and holdPins (an SFBitMask).
  enum Components { X = 1, Y = 2, Z = 4 };
  enum Start { PAPER, SECOND_ORDER };
  enum Shape { PLANE, CYLINDER, CONE, SPHERE, ELLIPSOID, TORUS };
  /// The `energy` field; its values are spelt PAPER and SHELL in files (PAPER_ENERGY only in
  /// C++, where Start already has a PAPER).
  enum Energy { PAPER_ENERGY = 0, SHELL = 1 };
  /// The `material` field (SHELL): the strain energy per volume.
  enum Material { SAINT_VENANT_KIRCHHOFF = 0, NEO_HOOKEAN = 1 };

  static void initClass();
  SoBSplineDeformSurface();

  SoSFInt32 numUControlPoints;  ///< N1 free control points along u; 5
  SoSFInt32 numVControlPoints;  ///< N2 free control points along v; 5
  SoSFInt32 uDegree;            ///< n1, 1..7; 3
  SoSFInt32 vDegree;            ///< n2, 1..7; 3
  SoSFDouble w10;               ///< omega_10 stretching along u; 0.1
  SoSFDouble w01;               ///< omega_01 stretching along v; 0.1
  SoSFDouble w11;               ///< omega_11 twist; 0.01
  SoSFDouble w20;               ///< omega_20 bending along u; 0.01
  SoSFDouble w02;               ///< omega_02 bending along v; 0.01
  SoSFEnum energy;              ///< PAPER (eq. 7, the weights above) or SHELL (Kirchhoff–Love); PAPER
  SoSFEnum material;            ///< SHELL: SAINT_VENANT_KIRCHHOFF or NEO_HOOKEAN; SAINT_VENANT_KIRCHHOFF
  SoSFDouble youngsModulus;     ///< SHELL: E in Pa; 1e6
  SoSFDouble poissonRatio;      ///< SHELL: nu in [0, 0.5); 0.3
  SoSFDouble thickness;         ///< SHELL: t in m; 0.001
  SoSFDouble density;           ///< SHELL: rho in kg/m^3 (mass rho t per rest area); 1000
  SoSFEnum massModel;           ///< NODAL or LUMPED; NODAL
  SoSFDouble mass;              ///< m: per control point (NODAL) or per unit area (LUMPED); 1
  SoSFDouble damping;           ///< c, same convention; 0.5
  SoSFDouble timeStep;          ///< Delta t in simulated seconds; 0.1
  SoSFEnum integrator;          ///< EXPLICIT, IMPLICIT or BACKWARD_EULER; EXPLICIT
  SoSFInt32 maxSubSteps;        ///< explicit: more sub-steps per step are refused (>= 1); 10000
  SoSFDouble newtonTolerance;   ///< BACKWARD_EULER, SHELL implicit and static: Newton's relative residual; 1e-8
  SoSFInt32 maxNewtonIterations;  ///< BACKWARD_EULER, SHELL implicit: a step needing more iterations fails; 30
  SoSFDouble newtonVelocityTolerance;  ///< BACKWARD_EULER: max update / dt at convergence (m/s); 1e-4
  SoSFEnum nonlinearSolver;     ///< BACKWARD_EULER: NEWTON or LBFGS; NEWTON
  SoSFEnum reference;           ///< REST or ABSOLUTE; REST
  SoSFEnum boundaryUMin;        ///< side u = 0: CLAMPED, FREE, PERIODIC, SIMPLY_SUPPORTED or BUILT_IN; CLAMPED
  SoSFEnum boundaryUMax;        ///< side u = 1; CLAMPED
  SoSFEnum boundaryVMin;        ///< side v = 0; CLAMPED
  SoSFEnum boundaryVMax;        ///< side v = 1; CLAMPED
  /// SHELL: the world components a SIMPLY_SUPPORTED or BUILT_IN side holds (X | Y | Z)
  SoSFBitMask holdUMin;
  SoSFBitMask holdUMax;         ///< as holdUMin, side u = 1
  SoSFBitMask holdVMin;         ///< as holdUMin, side v = 0
  SoSFBitMask holdVMax;         ///< as holdUMin, side v = 1
  SoSFBitMask holdPins;         ///< SHELL (static, arc length, BACKWARD_EULER, IMPLICIT): the world components pins hold (X | Y | Z)
  /// SHELL, BACKWARD_EULER: the map (row vectors, as SoTransform's) whose image of their rest
  /// positions the n layers a CLAMPED side u = 0 holds are held at; identity and unconnected:
  /// held at rest. Read before every step, reached at its end (Simulation::setSideMotion).
  SoSFMatrix motionUMin;
  SoSFMatrix motionUMax;  ///< as motionUMin, side u = 1
  SoSFMatrix motionVMin;  ///< as motionUMin, side v = 0
  SoSFMatrix motionVMax;  ///< as motionUMin, side v = 1
  SoMFVec2d pins;               ///< pinned parameter points (u, v); empty
  SoSFEnum start;               ///< SECOND_ORDER (consistent release from rest) or PAPER; SECOND_ORDER
  SoSFEnum restShape;           ///< rest net generated when restNet is empty; PLANE
  SoSFDouble radius;            ///< R of CYLINDER, CONE (base), SPHERE, TORUS; 0.5
  SoSFDouble height;            ///< H of CYLINDER, CONE; 1
  SoSFDouble minorRadius;       ///< r of TORUS (tube); 0.2
  SoSFVec3d radii;              ///< (a, b, c) of ELLIPSOID; 0.6 0.45 0.35
  SoSFBool on;                  ///< animate with Coin's realTime; TRUE
  SoSFFloat speed;              ///< simulated seconds per second of realTime; 1
  SoSFTrigger reset;            ///< back to the rest state
  SoMFVec3d restNet;            ///< rest net, empty for the plane S = (u, v, 0)
  SoMFVec3d controlNet;         ///< current net (state), empty for the rest net
  SoMFVec3d previousNet;        ///< net one sub-step before (state), empty for controlNet
  SoSFDouble simulationTime;    ///< simulated time of the current state (live: set after every step and reset); 0
  SoSFInt32 stepCount;          ///< steps taken (live, like simulationTime); 0
  /// What the forces adapt between steps (state, written with the nets: a barrier's stiffness),
  /// per force its count and its values (bsdeform::forceStatesOf()); empty: as made
  SoMFDouble forceState;
  SoMFEngine forces;            ///< SoForceField engines acting on this surface

  /// What is wrong with the surface now: a front end shows it at its place from these fields
  /// (nobody reads the message's words). Also posted once, as a Coin warning, when it appears.
  struct Problem {
    enum Kind {
      NONE,
      FIELD,        ///< a field's value is refused (`field` names it): the last valid model runs on
      FORCE_FIELD,  ///< a force field's value is refused (its previous force acts) or `forces`
                    ///< holds something else; `node` names it
      OBSTACLE,     ///< a COLLISION force's obstacle is missing or has no usable geometry
      STATE,        ///< the state fields were adjusted (a periodic net whose seam did not close)
      STOPPED       ///< the simulation stopped: it blew up or a step was refused (Simulation::status())
    };
    Kind kind = NONE;
    std::string node;     ///< the node at fault (this surface's or the force field's name, "<unnamed>")
    std::string field;    ///< the field at fault; "" when no one field is
    std::string message;  ///< the sentence for the user
  };
  /// The current problem (kind NONE when there is none).
  const Problem& problem() const { return m_problem; }
  /// Every field refused as the values stand (kind FIELD, each once, the first being the one
  /// problem() named when it was reported): one refused value does not hide another. Empty
  /// when the model takes the fields. Kept apart from problem(), which a force field's or an
  /// obstacle's problem may replace.
  const std::vector<Problem>& refusals() const { return m_refusals; }
  /// The current problem's message ("" when there is none).
  const std::string& lastWarning() const { return m_problem.message; }

  /// What a surface tells the functions registered with addCallback().
  enum Event {
    STEPPED,        ///< one step was taken (after every step, also one that failed)
    STATE_CHANGED,  ///< the state was replaced: reset, static solve, the state fields read, or a
                    ///< model rebuilt from rest
    MODEL_CHANGED,  ///< the model was rebuilt from changed fields, the motion going on from where it was
    PROBLEM_CHANGED ///< problem() changed
  };
  using Callback = std::function<void(SoBSplineDeformSurface*, Event)>;
  /// Registers `callback` (as an engine's evaluate callbacks are); returns its id for
  /// removeCallback(). Called on the thread that steps, in registration order.
  int addCallback(Callback callback);
  void removeCallback(int id);

  /// The scene this surface is in: COLLISION forces find their obstacles and their frames there
  /// (SceneObstacles.h). SceneRunner and the front ends give it; a surface that was given none
  /// (a plain Coin viewer that only reads the file) takes the head of the first render
  /// traversal's path once. Not ref'ed: forgotten when that node is deleted.
  void setScene(SoNode* root);
  SoNode* scene() const { return m_sceneRoot; }

  /// The simulation built from the fields (rebuilt lazily after field changes); never null.
  const bsdeform::Simulation& simulation();
  /// The surface's collision proxy now, in its own coordinates: the triangles its barrier contact
  /// keeps the offset with (bsdeform::CollisionProxy at the `proxySamples` of its first COLLISION
  /// force field with method BARRIER, 2 without one). Another surface's barrier contact sees this
  /// surface through them (SceneObstacles), so that both measure the same distances.
  void collisionProxyMesh(std::vector<Eigen::Vector3d>& vertices, std::vector<Eigen::Vector3i>& triangles);
  /// Advances by `steps` steps of Delta t now, whatever `on` says. Returns false on blow-up.
  bool stepSimulation(int steps = 1);
  /// Advances by `seconds` of realTime (times `speed`) in whole steps of Delta t, keeping the
  /// remainder for the next call; a quarter second at most per call (a slow frame is not made
  /// up). This is what the surface's realTime sensor calls. Returns the steps taken.
  int advanceRealTime(double seconds);
  /// How the realTime sensor treats a surface whose steps cost more wall time than they
  /// simulate (the recent steps' mean cost times `speed` above 3/4 of timeStep, the rest left
  /// for drawing): `false` (the default, for
  /// interaction) takes one step per change of realTime and drops the rest of the time due, so
  /// the picture is redrawn after every step (frames never fewer than steps) and simulated time
  /// falls behind realTime; `true` takes every step due, as advanceRealTime() does (a driver
  /// that sets realTime to simulated times, such as a test, wants the exact count). Steps that
  /// keep up are taken the same either way. Falling behind, a tick before the last step was
  /// drawn takes none (two ticks can come between two frames), unless no frame came for a tenth
  /// of a second (a surface nobody draws). Process-wide.
  static void setRealTimeCatchUp(bool catchUp);
  static bool realTimeCatchUp();
  /// Back to the rest state (same as touching `reset`).
  void resetSimulation();
  /// The paper's static problem: the equilibrium of the current loads at t = 0 with zero
  /// velocity (bsdeform::Simulation::solveStatic) becomes the state, controlNet and
  /// previousNet both the equilibrium, simulationTime and stepCount 0, so that a saved file
  /// opens at rest there. On failure (nothing holds the surface, loads that do not settle)
  /// nothing changes, `error` says why and false is returned.
  bool solveStatic(bsdeform::StaticResult* result, std::string* error);
  /// The same in `loadSteps` equal load increments (SHELL: Newton from each equilibrium to the
  /// next, a load-displacement curve); `each` (if set) is called with every increment and its
  /// diagnostics (the result, the increment's number in result.increments), in order, before
  /// the last becomes the state. With `arcLength` (SHELL), the equilibrium path by arc-length
  /// continuation instead (bsdeform::Simulation::solveStaticArcLength; loadSteps unused).
  bool solveStatic(bsdeform::StaticResult* result, std::string* error, int loadSteps,
                   const std::function<void(const bsdeform::StaticResult&, size_t, const bsdeform::Diagnostics&)>& each,
                   const bsdeform::ArcLengthOptions* arcLength = nullptr);
  /// Adds / removes a force that is not part of the scene (not written to file), e.g. the
  /// viewer's mouse spring.
  void addTransientForce(std::shared_ptr<const bsdeform::Force> force);
  void removeTransientForce(const bsdeform::Force* force);
  /// The simulation's state now (bsdeform/dynamics/SimulationState.h): what restoreState() takes back.
  bsdeform::SimulationState state();
  /// Puts back a state taken with state() from this surface or one built alike (the viewer's
  /// timeline, a bsdeform-run --keep-states file) into the current model, which stays (no
  /// rebuild): the state is then the same bits and the next steps are those taken from it
  /// before. The listeners are told STATE_CHANGED. A state that does not fit this model (another
  /// net size, moved held points) changes nothing: false, and `error` says why.
  bool restoreState(const bsdeform::SimulationState& state, std::string* error);
  /// Writes the simulation state into controlNet, previousNet, simulationTime, stepCount.
  /// simulationTime and stepCount are kept current after every step and reset anyway (a
  /// field editor or a script reads them); the nets are written here, on write().
  void syncStateFields();
  /// (u, v) of a picked point on a surface (false if the pick is not on one). Computed from the
  /// picked point in object space, so texture transforms in the scene do not matter.
  static bool pickedParameter(const SoPickedPoint* pp, float& u, float& v);
  /// (u, v) of the point of the current surface closest to `p` (object space): nearest
  /// tessellation vertex, refined by Gauss-Newton on |S(u,v) - p|^2 (bsdeform::closestParameter).
  void closestParameter(const SbVec3f& p, float& u, float& v);
  /// Whether the surface is closed (periodic in both directions, or a sphere/ellipsoid): it is
  /// then lit on one side only; open surfaces are lit on both.
  bool isClosed();
  /// Obstacle trees built and refitted by this surface's COLLISION force fields (tests).
  int obstacleBuilds() const;
  int obstacleRefits() const;
  /// Core forces made from the force fields so far (tests: a force is remade only when its
  /// force field tells of a change).
  int forcesMade() const { return m_forcesMade; }

  void GLRender(SoGLRenderAction* action) override;
  void write(SoWriteAction* action) override;

 protected:
  ~SoBSplineDeformSurface() override;
  void notify(SoNotList* list) override;
  SbBool readInstance(SoInput* in, unsigned short flags) override;
  void generatePrimitives(SoAction* action) override;
  void computeBBox(SoAction* action, SbBox3f& box, SbVec3f& center) override;

 private:
  friend class bsdeform::SceneRunner;
  void ensureSimulation();
  bool rebuildSimulation();
  void syncClockFields();
  /// After the state was replaced (reset, static solve): the clock's remainder, the problem,
  /// the drawing and the live fields follow, and the listeners are told.
  void stateReplaced();
  void updateForces(bsdeform::Simulation& sim);
  /// Makes `problem` the current one (posted as a Coin warning when it is new).
  void report(Problem::Kind kind, const std::string& field, const std::string& message, const std::string& node = {});
  void clearProblem();
  void tell(Event event);
  /// Listens to realTime while `on` is TRUE and no SceneRunner drives the surface.
  void updateClock();
  static void clockCallback(void* data, SoSensor*);
  /// Connects m_forcesChanged from the `revision` output of every force field in `forces`.
  void connectForces();
  void tessellate(SoState* state);

  std::unique_ptr<bsdeform::Simulation> m_sim;
  const bsdeform::Simulation* m_building = nullptr;  ///< the model rebuildSimulation() is making
  bool m_modelDirty = true;
  bool m_stateDirty = true;
  bool m_syncing = false;
  bool m_stateKept = false;  ///< the last rebuild kept the motion going (MODEL_CHANGED)
  std::unique_ptr<bsdeform::ForceSlots> m_forces;  ///< the forces of `forces` (SurfaceModel.h, not installed)
  std::vector<std::shared_ptr<const bsdeform::Force>> m_transient;
  /// Not a field of the file (not in the field data): the slave of every force field's
  /// `revision` output, so that a changed force field notifies this node (notify()).
  SoSFInt32 m_forcesChanged;
  bool m_forcesStale = true;  ///< a force field told of a change: its force is remade before the next step
  int m_forcesMade = 0;
  Problem m_problem;
  std::vector<Problem> m_refusals;
  long m_reports = 0;  ///< problems reported so far
  std::vector<std::pair<int, Callback>> m_callbacks;
  int m_nextCallback = 0;
  bsdeform::SurfaceGrid m_tess;
  std::uint64_t m_tessRevision = 0;                 ///< counts tessellations (the buffers' uploads)
  std::unique_ptr<bsdeform::SurfaceBuffers> m_buffers;  ///< GL buffers of m_tess, per context
  SoNode* m_sceneRoot = nullptr;        ///< setScene() (not ref'ed)
  bool m_sceneGiven = false;            ///< setScene() was called: no traversal changes the scene
  SoNodeSensor* m_rootSensor = nullptr; ///< clears m_sceneRoot when that node is deleted
  bool m_tessValid = false;
  SoFieldSensor* m_clock = nullptr;     ///< on Coin's global realTime field
  int m_drivers = 0;                    ///< SceneRunners driving this surface (its sensor is off)
  double m_lastTick = -1.0;             ///< realTime at the last tick, -1 before the first
  double m_timeBudget = 0.0;
  double m_stepWallSeconds = 0.0;       ///< wall time per step of the realTime sensor's recent steps (moving mean)
  std::chrono::steady_clock::time_point m_lastStepAt;  ///< when the realTime sensor last stepped
  bool m_drawnSinceStep = true;         ///< rendered since the realTime sensor's last step
};
