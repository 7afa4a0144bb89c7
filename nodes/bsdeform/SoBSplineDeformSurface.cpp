// SPDX-License-Identifier: MIT
#include "bsdeform/SoBSplineDeformSurface.h"

#include <Inventor/SbTime.h>
#include <Inventor/SoDB.h>
#include <Inventor/SoPickedPoint.h>
#include <Inventor/SoPrimitiveVertex.h>
#include <Inventor/actions/SoGLRenderAction.h>
#include <Inventor/actions/SoWriteAction.h>
#include <Inventor/bundles/SoMaterialBundle.h>
#include <Inventor/elements/SoComplexityElement.h>
#include <Inventor/elements/SoLazyElement.h>
#include <Inventor/errors/SoDebugError.h>
#include <Inventor/misc/SoNotification.h>
#include <Inventor/SoPath.h>
#include <Inventor/fields/SoSFTime.h>
#include <Inventor/sensors/SoFieldSensor.h>
#include <Inventor/sensors/SoNodeSensor.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "bsdeform/base/ParameterError.h"
#include "bsdeform/SceneRunner.h"
#include "bsdeform/SceneText.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/contact/BarrierContact.h"
#include "bsdeform/contact/CollisionProxy.h"
#include "bsdeform/dynamics/SimulationState.h"
#include "bsdeform/spline/Tessellation.h"
#include "bsdeform/SoForceField.h"
#include "bsdeform/SurfaceBuffers.h"
#include "bsdeform/SurfaceModel.h"

using bsdeform::snap15;

SO_NODE_SOURCE(SoBSplineDeformSurface);

void SoBSplineDeformSurface::initClass() {
  // Idempotent (Coin asserts on a second init). Also initialises SoForceField, so that Coin's
  // dynamic loader, which calls only this function for a surface, knows the engine too.
  SoForceField::initClass();
  if (getClassTypeId() != SoType::badType()) return;
  SO_NODE_INIT_CLASS(SoBSplineDeformSurface, SoShape, "Shape");
}

SoBSplineDeformSurface::SoBSplineDeformSurface() {
  SO_NODE_CONSTRUCTOR(SoBSplineDeformSurface);
  SO_NODE_ADD_FIELD(numUControlPoints, (5));
  SO_NODE_ADD_FIELD(numVControlPoints, (5));
  SO_NODE_ADD_FIELD(uDegree, (3));
  SO_NODE_ADD_FIELD(vDegree, (3));
  SO_NODE_ADD_FIELD(w10, (0.1));
  SO_NODE_ADD_FIELD(w01, (0.1));
  SO_NODE_ADD_FIELD(w11, (0.01));
  SO_NODE_ADD_FIELD(w20, (0.01));
  SO_NODE_ADD_FIELD(w02, (0.01));
  SO_NODE_ADD_FIELD(energy, (PAPER_ENERGY));
  SO_NODE_ADD_FIELD(material, (SAINT_VENANT_KIRCHHOFF));
  SO_NODE_ADD_FIELD(youngsModulus, (1.0e6));
  SO_NODE_ADD_FIELD(poissonRatio, (0.3));
  SO_NODE_ADD_FIELD(thickness, (0.001));
  SO_NODE_ADD_FIELD(density, (1000.0));
  SO_NODE_ADD_FIELD(massModel, (NODAL));
  SO_NODE_ADD_FIELD(mass, (1.0));
  SO_NODE_ADD_FIELD(damping, (0.5));
  SO_NODE_ADD_FIELD(timeStep, (0.1));
  SO_NODE_ADD_FIELD(integrator, (EXPLICIT));
  SO_NODE_ADD_FIELD(maxSubSteps, (10000));
  SO_NODE_ADD_FIELD(newtonTolerance, (1e-8));
  SO_NODE_ADD_FIELD(maxNewtonIterations, (30));
  SO_NODE_ADD_FIELD(newtonVelocityTolerance, (1e-4));
  SO_NODE_ADD_FIELD(nonlinearSolver, (NEWTON));
  SO_NODE_ADD_FIELD(reference, (REST));
  SO_NODE_ADD_FIELD(boundaryUMin, (CLAMPED));
  SO_NODE_ADD_FIELD(boundaryUMax, (CLAMPED));
  SO_NODE_ADD_FIELD(boundaryVMin, (CLAMPED));
  SO_NODE_ADD_FIELD(boundaryVMax, (CLAMPED));
  SO_NODE_ADD_FIELD(holdUMin, (X | Y | Z));
  SO_NODE_ADD_FIELD(holdUMax, (X | Y | Z));
  SO_NODE_ADD_FIELD(holdVMin, (X | Y | Z));
  SO_NODE_ADD_FIELD(holdVMax, (X | Y | Z));
  SO_NODE_ADD_FIELD(holdPins, (X | Y | Z));
  SO_NODE_ADD_FIELD(motionUMin, (SbMatrix::identity()));
  SO_NODE_ADD_FIELD(motionUMax, (SbMatrix::identity()));
  SO_NODE_ADD_FIELD(motionVMin, (SbMatrix::identity()));
  SO_NODE_ADD_FIELD(motionVMax, (SbMatrix::identity()));
  SO_NODE_ADD_FIELD(pins, (SbVec2d(0, 0)));
  SO_NODE_ADD_FIELD(start, (SECOND_ORDER));
  SO_NODE_ADD_FIELD(restShape, (PLANE));
  SO_NODE_ADD_FIELD(radius, (0.5));
  SO_NODE_ADD_FIELD(height, (1.0));
  SO_NODE_ADD_FIELD(minorRadius, (0.2));
  SO_NODE_ADD_FIELD(radii, (SbVec3d(0.6, 0.45, 0.35)));
  SO_NODE_ADD_FIELD(on, (TRUE));
  SO_NODE_ADD_FIELD(speed, (1.0f));
  SO_NODE_ADD_FIELD(reset, ());
  SO_NODE_ADD_FIELD(restNet, (SbVec3d(0, 0, 0)));
  SO_NODE_ADD_FIELD(controlNet, (SbVec3d(0, 0, 0)));
  SO_NODE_ADD_FIELD(previousNet, (SbVec3d(0, 0, 0)));
  SO_NODE_ADD_FIELD(simulationTime, (0.0));
  SO_NODE_ADD_FIELD(stepCount, (0));
  SO_NODE_ADD_FIELD(forceState, (0.0));
  SO_NODE_ADD_FIELD(forces, (nullptr));
  fieldData->addEnumValue("Energy", "PAPER", PAPER_ENERGY);
  SO_NODE_DEFINE_ENUM_VALUE(Energy, SHELL);
  SO_NODE_SET_SF_ENUM_TYPE(energy, Energy);
  SO_NODE_DEFINE_ENUM_VALUE(Material, SAINT_VENANT_KIRCHHOFF);
  SO_NODE_DEFINE_ENUM_VALUE(Material, NEO_HOOKEAN);
  SO_NODE_SET_SF_ENUM_TYPE(material, Material);
  SO_NODE_DEFINE_ENUM_VALUE(MassModel, NODAL);
  SO_NODE_DEFINE_ENUM_VALUE(MassModel, LUMPED);
  SO_NODE_SET_SF_ENUM_TYPE(massModel, MassModel);
  SO_NODE_DEFINE_ENUM_VALUE(Integrator, EXPLICIT);
  SO_NODE_DEFINE_ENUM_VALUE(Integrator, IMPLICIT);
  SO_NODE_DEFINE_ENUM_VALUE(Integrator, BACKWARD_EULER);
  SO_NODE_SET_SF_ENUM_TYPE(integrator, Integrator);
  SO_NODE_DEFINE_ENUM_VALUE(NonlinearSolver, NEWTON);
  SO_NODE_DEFINE_ENUM_VALUE(NonlinearSolver, LBFGS);
  SO_NODE_SET_SF_ENUM_TYPE(nonlinearSolver, NonlinearSolver);
  SO_NODE_DEFINE_ENUM_VALUE(Reference, REST);
  SO_NODE_DEFINE_ENUM_VALUE(Reference, ABSOLUTE);
  SO_NODE_SET_SF_ENUM_TYPE(reference, Reference);
  SO_NODE_DEFINE_ENUM_VALUE(Boundary, CLAMPED);
  SO_NODE_DEFINE_ENUM_VALUE(Boundary, FREE);
  SO_NODE_DEFINE_ENUM_VALUE(Boundary, PERIODIC);
  SO_NODE_DEFINE_ENUM_VALUE(Boundary, SIMPLY_SUPPORTED);
  SO_NODE_DEFINE_ENUM_VALUE(Boundary, BUILT_IN);
  SO_NODE_DEFINE_ENUM_VALUE(Boundary, SYMMETRY);
  SO_NODE_DEFINE_ENUM_VALUE(Components, X);
  SO_NODE_DEFINE_ENUM_VALUE(Components, Y);
  SO_NODE_DEFINE_ENUM_VALUE(Components, Z);
  SO_NODE_SET_SF_ENUM_TYPE(holdUMin, Components);
  SO_NODE_SET_SF_ENUM_TYPE(holdUMax, Components);
  SO_NODE_SET_SF_ENUM_TYPE(holdVMin, Components);
  SO_NODE_SET_SF_ENUM_TYPE(holdVMax, Components);
  SO_NODE_SET_SF_ENUM_TYPE(holdPins, Components);
  SO_NODE_SET_SF_ENUM_TYPE(boundaryUMin, Boundary);
  SO_NODE_SET_SF_ENUM_TYPE(boundaryUMax, Boundary);
  SO_NODE_SET_SF_ENUM_TYPE(boundaryVMin, Boundary);
  SO_NODE_SET_SF_ENUM_TYPE(boundaryVMax, Boundary);
  SO_NODE_DEFINE_ENUM_VALUE(Start, PAPER);
  SO_NODE_DEFINE_ENUM_VALUE(Start, SECOND_ORDER);
  SO_NODE_SET_SF_ENUM_TYPE(start, Start);
  SO_NODE_DEFINE_ENUM_VALUE(Shape, PLANE);
  SO_NODE_DEFINE_ENUM_VALUE(Shape, CYLINDER);
  SO_NODE_DEFINE_ENUM_VALUE(Shape, CONE);
  SO_NODE_DEFINE_ENUM_VALUE(Shape, SPHERE);
  SO_NODE_DEFINE_ENUM_VALUE(Shape, ELLIPSOID);
  SO_NODE_DEFINE_ENUM_VALUE(Shape, TORUS);
  SO_NODE_SET_SF_ENUM_TYPE(restShape, Shape);
  pins.setNum(0);
  pins.setDefault(TRUE);
  // Empty multi-fields mean "derived" (plane / rest / current); start empty and default.
  for (SoMFVec3d* f : {&restNet, &controlNet, &previousNet}) {
    f->setNum(0);
    f->setDefault(TRUE);
  }
  forceState.setNum(0);
  forceState.setDefault(TRUE);
  forces.setNum(0);
  forces.setDefault(TRUE);

  m_forces = std::make_unique<bsdeform::ForceSlots>();
  m_forcesChanged.setContainer(this);
  m_clock = new SoFieldSensor(clockCallback, this);
  updateClock();
}

SoBSplineDeformSurface::~SoBSplineDeformSurface() {
  m_forcesChanged.disconnect();
  delete m_clock;
  delete m_rootSensor;
}

// ---------------------------------------------------------------------------------------------
// The scene (for the frames of contact, SceneObstacles.h)

void SoBSplineDeformSurface::setScene(SoNode* root) {
  m_sceneGiven = root != nullptr;
  if (root == m_sceneRoot) return;
  m_sceneRoot = root;
  if (!m_rootSensor) {
    m_rootSensor = new SoNodeSensor;  // no callback: only its delete callback is used
    m_rootSensor->setPriority(0);
    m_rootSensor->setDeleteCallback(
        [](void* data, SoSensor*) {
          auto* self = static_cast<SoBSplineDeformSurface*>(data);
          self->m_sceneRoot = nullptr;
          self->m_sceneGiven = false;
        },
        this);
  }
  m_rootSensor->detach();
  if (root) m_rootSensor->attach(root);
}

int SoBSplineDeformSurface::obstacleBuilds() const { return m_forces->obstacleBuilds(); }
int SoBSplineDeformSurface::obstacleRefits() const { return m_forces->obstacleRefits(); }

// ---------------------------------------------------------------------------------------------
// Fields -> simulation

void SoBSplineDeformSurface::report(Problem::Kind kind, const std::string& field, const std::string& message,
                                    const std::string& node) {
  using bsdeform::nameOf;
  Problem p{kind, node.empty() ? nameOf(this) : node, field, message};
  if (p.kind == m_problem.kind && p.node == m_problem.node && p.field == m_problem.field && p.message == m_problem.message)
    return;  // once per distinct problem
  m_problem = std::move(p);
  ++m_reports;
  SoDebugError::postWarning("SoBSplineDeformSurface", "node '%s': %s", nameOf(this).c_str(), message.c_str());
  tell(PROBLEM_CHANGED);
}

void SoBSplineDeformSurface::clearProblem() {
  if (m_problem.kind == Problem::NONE) return;
  m_problem = Problem();
  tell(PROBLEM_CHANGED);
}

int SoBSplineDeformSurface::addCallback(Callback callback) {
  m_callbacks.emplace_back(m_nextCallback, std::move(callback));
  return m_nextCallback++;
}

void SoBSplineDeformSurface::removeCallback(int id) {
  m_callbacks.erase(std::remove_if(m_callbacks.begin(), m_callbacks.end(), [id](const auto& c) { return c.first == id; }),
                    m_callbacks.end());
}

void SoBSplineDeformSurface::tell(Event event) {
  // a copy: a callback may add or remove callbacks
  const std::vector<std::pair<int, Callback>> callbacks = m_callbacks;
  for (const auto& c : callbacks) c.second(this, event);
}

bool SoBSplineDeformSurface::rebuildSimulation() {
  bsdeform::ModelParameters p;
  bsdeform::ControlNet rest;
  bsdeform::FieldRefusal refusal;
  auto refuse = [this](const bsdeform::FieldRefusal& r) {
    m_refusals.clear();
    for (const bsdeform::FieldRefusal& each : bsdeform::fieldRefusals(*this))
      m_refusals.push_back({Problem::FIELD, bsdeform::nameOf(this), each.field, each.message});
    if (m_refusals.empty() || m_refusals.front().field != r.field)
      m_refusals.insert(m_refusals.begin(), Problem{Problem::FIELD, bsdeform::nameOf(this), r.field, r.message});
    report(Problem::FIELD, r.field, r.message + "; keeping the last valid state");
    return false;
  };
  if (!bsdeform::modelFromFields(*this, p, rest, refusal)) return refuse(refusal);
  bsdeform::ForceSlots oldSlots;  // the last valid model's, kept if the new one fails
  long reportedBefore = 0;        // a problem of the new model's forces is not cleared below
  try {
    std::unique_ptr<bsdeform::Simulation> sim = rest.rows() ? std::make_unique<bsdeform::Simulation>(p, rest)
                                                            : std::make_unique<bsdeform::Simulation>(p);
    // the state kept at what the scene writes of it (snap15): a run resumed from a written scene
    // starts from the very bits the run that wrote it goes on from
    sim->setStateRounding(&bsdeform::snap15);
    // Another surface that lists this one as an obstacle and is built while this one gathers
    // it asks for this surface's triangles: they come from the model being built (no rebuild
    // within the rebuild).
    struct Building {
      const bsdeform::Simulation*& slot;
      ~Building() { slot = nullptr; }
    } building{m_building};
    m_building = sim.get();
    // Forces first: their stiffness sets the sub-step, and a state is restored at its own
    // sub-step (a force added afterwards would rescale the previous net as if it were older).
    oldSlots = *m_forces;
    m_forces->keepForNewModel();
    reportedBefore = m_reports;
    updateForces(*sim);
    bsdeform::applySideMotions(*sim, *this);  // before the state: a moved side's layers are the state's
    m_stateKept = bsdeform::startState(*sim, *this, m_stateDirty, m_sim.get());
    m_sim = std::move(sim);
  } catch (const bsdeform::ParameterError& e) {
    m_forces->swap(oldSlots);
    return refuse(bsdeform::refusalOf(e));
  } catch (const std::exception& e) {
    m_forces->swap(oldSlots);
    return refuse({"", e.what()});
  }
  m_refusals.clear();
  if (m_reports == reportedBefore) clearProblem();
  const double seam = m_sim->seamMismatch();
  if (seam > 1e-9 * (1.0 + m_sim->rest().cwiseAbs().maxCoeff())) {
    std::ostringstream os;
    os.precision(17);
    os << "the last n layers of a periodic direction differ from the first n (by up to " << seam
       << ") in 'restNet', 'controlNet' or 'previousNet'; the first were used";
    report(Problem::STATE, "restNet", os.str());
  }
  return true;
}

void SoBSplineDeformSurface::collisionProxyMesh(std::vector<Eigen::Vector3d>& vertices,
                                                std::vector<Eigen::Vector3i>& triangles) {
  if (!m_building) ensureSimulation();
  const bsdeform::Simulation& sim = m_building ? *m_building : *m_sim;
  int samples = bsdeform::BarrierContactParameters().samplesPerSpan;
  for (int i = 0; i < forces.getNum(); ++i) {
    SoEngine* e = forces[i];
    if (!e || !e->isOfType(SoForceField::getClassTypeId())) continue;
    const auto* ff = static_cast<const SoForceField*>(e);
    if (ff->type.getValue() == SoForceField::COLLISION && ff->method.getValue() == SoForceField::BARRIER) {
      samples = int(ff->proxySamples.getValue());
      break;
    }
  }
  vertices.clear();
  triangles.clear();
  std::unique_ptr<bsdeform::CollisionProxy> made;
  try {
    made = std::make_unique<bsdeform::CollisionProxy>(sim.space(), samples);
  } catch (const std::invalid_argument&) {
    return;  // a proxySamples the core refuses: that force field is refused by name, no triangles here
  }
  const bsdeform::CollisionProxy& proxy = *made;
  Eigen::MatrixX3d at;
  // asked for while this surface is being built (another surface gathering it from within our
  // rebuild): the simulation is still at rest, its state not yet put back; the state is the
  // fields' then (a file's controlNet)
  if (m_building && m_stateDirty && controlNet.getNum() == int(sim.current().rows()))
    proxy.positions(bsdeform::netFromField(controlNet), at);
  else
    proxy.positions(sim.current(), at);
  vertices.resize(size_t(at.rows()));
  for (Eigen::Index i = 0; i < at.rows(); ++i) vertices[size_t(i)] = at.row(i).transpose();
  const Eigen::MatrixX3i& t = proxy.triangles();
  triangles.resize(size_t(t.rows()));
  for (Eigen::Index i = 0; i < t.rows(); ++i) triangles[size_t(i)] = t.row(i).transpose();
}

void SoBSplineDeformSurface::ensureSimulation() {
  if (m_building) return;  // asked for from within rebuildSimulation (see there)
  if (m_modelDirty || m_stateDirty || !m_sim) {
    const bool rebuilt = rebuildSimulation();
    if (!rebuilt && !m_sim) m_sim = std::make_unique<bsdeform::Simulation>(bsdeform::ModelParameters());
    m_modelDirty = m_stateDirty = false;
    m_tessValid = false;
    if (rebuilt) tell(m_stateKept ? MODEL_CHANGED : STATE_CHANGED);
  }
}

const bsdeform::Simulation& SoBSplineDeformSurface::simulation() {
  ensureSimulation();
  return *m_sim;
}

void SoBSplineDeformSurface::updateForces(bsdeform::Simulation& sim) {
  int fields = 0;  // a copy of the node (SoNode::copy) has the list, not the connections
  for (int i = 0; i < forces.getNum(); ++i) fields += forces[i] && forces[i]->isOfType(SoForceField::getClassTypeId());
  if (m_forcesChanged.getNumConnections() != fields) connectForces();
  // Force fields are compared with the slots only after one told of a change (m_forcesChanged,
  // notify()), the list changed or the model is new; obstacles are kept current every step.
  const bool stale = m_forcesStale || &sim != m_sim.get();
  m_forcesStale = false;
  m_forcesMade += m_forces->update(sim, forces, m_sceneRoot, this, stale, m_transient,
                                  [this](Problem::Kind kind, const std::string& field, const std::string& message,
                                         const std::string& node) { report(kind, field, message, node); });
}

// ---------------------------------------------------------------------------------------------
// Time

bool SoBSplineDeformSurface::stepSimulation(int steps) {
  ensureSimulation();
  updateForces(*m_sim);
  // the moved sides' poses at the end of these steps (reached in the first: the clock read once);
  // not on the stand-in of a model the fields describe wrongly (refused, named already)
  if (m_refusals.empty()) {
    try {
      bsdeform::applySideMotions(*m_sim, *this);
    } catch (const std::invalid_argument& e) {  // a side the rest shape made other than CLAMPED
      report(Problem::FIELD, "motionUMin", e.what());
      return false;
    }
  }
  bool ok = true;
  if (steps > 0) {
    // one at a time when someone listens (the same numbers: Simulation::advance steps one by
    // one); decided once, whatever a callback adds or removes on the way
    const bool oneByOne = !m_callbacks.empty();
    for (int k = 0; k < steps && ok; k += oneByOne ? 1 : steps) {
      ok = m_sim->advance(oneByOne ? 1 : steps) == bsdeform::Status::Ok;
      if (!ok) report(Problem::STOPPED, "", "simulation stopped: " + m_sim->statusMessage());
      if (oneByOne) {
        m_tessValid = false;  // a listener may draw or pick
        syncClockFields();
        tell(STEPPED);
      }
    }
    m_tessValid = false;
    syncClockFields();
    touch();
  }
  return ok;
}

int SoBSplineDeformSurface::advanceRealTime(double seconds) {
  ensureSimulation();
  if (m_sim->status() != bsdeform::Status::Ok) return 0;
  const int steps = bsdeform::stepsDue(seconds, speed.getValue(), m_sim->parameters().timeStep, m_timeBudget);
  if (steps > 0) stepSimulation(steps);
  return steps;
}

void SoBSplineDeformSurface::resetSimulation() {
  ensureSimulation();
  m_sim->reset();
  stateReplaced();
}

bsdeform::SimulationState SoBSplineDeformSurface::state() {
  ensureSimulation();
  return bsdeform::stateOf(*m_sim);
}

bool SoBSplineDeformSurface::restoreState(const bsdeform::SimulationState& state, std::string* error) {
  ensureSimulation();
  updateForces(*m_sim);  // the forces set the sub-step the state is put back at
  try {
    bsdeform::restoreState(*m_sim, state);
  } catch (const std::exception& e) {
    if (error) *error = e.what();
    return false;
  }
  stateReplaced();
  return true;
}

void SoBSplineDeformSurface::stateReplaced() {
  m_timeBudget = 0.0;
  // a new state ends a stop; a refused value or a missing obstacle belongs to the fields and
  // stays until they change
  if (m_problem.kind == Problem::STOPPED || m_problem.kind == Problem::STATE) clearProblem();
  m_tessValid = false;
  syncClockFields();
  touch();
  tell(STATE_CHANGED);
}

bool SoBSplineDeformSurface::solveStatic(bsdeform::StaticResult* result, std::string* error) {
  return solveStatic(result, error, 1, {});
}

bool SoBSplineDeformSurface::solveStatic(
    bsdeform::StaticResult* result, std::string* error, int loadSteps,
    const std::function<void(const bsdeform::StaticResult&, size_t, const bsdeform::Diagnostics&)>& each,
    const bsdeform::ArcLengthOptions* arcLength) {
  ensureSimulation();
  updateForces(*m_sim);
  try {
    bsdeform::StaticResult r = bsdeform::solveStaticInto(*m_sim, loadSteps, each, arcLength);
    if (result) *result = std::move(r);
  } catch (const std::exception& e) {
    if (error) *error = e.what();
    return false;
  }
  stateReplaced();
  return true;
}

void SoBSplineDeformSurface::addTransientForce(std::shared_ptr<const bsdeform::Force> force) {
  ensureSimulation();
  m_transient.push_back(force);
  m_sim->addForce(std::move(force));
}

void SoBSplineDeformSurface::removeTransientForce(const bsdeform::Force* force) {
  auto it = std::find_if(m_transient.begin(), m_transient.end(), [force](const auto& f) { return f.get() == force; });
  if (it == m_transient.end()) return;
  m_transient.erase(it);
  if (m_sim) m_sim->removeForce(force);
}

// ---------------------------------------------------------------------------------------------
// The clock: like SoElapsedTime, the surface reads Coin's global realTime field, through its own
// sensor (not a field connection: that would make every change of realTime a notification of
// the scene, and renders would run free). Whoever sets realTime drives the surface: Coin's own
// real-time sensor and scene manager in a plain viewer, bsdeform-viewer's Play / Pause and
// speed, a test. A SceneRunner drives the surfaces it holds itself (m_drivers).

void SoBSplineDeformSurface::updateClock() {
  SoSFTime* realTime = bsdeform::realTimeField();
  const bool listen = on.getValue() && m_drivers == 0 && realTime;
  if (listen && !m_clock->getAttachedField()) {
    m_lastTick = realTime->getValue().getValue();  // the time from here on counts
    m_clock->attach(realTime);
  } else if (!listen && m_clock->getAttachedField()) {
    m_clock->detach();
  }
}

namespace {
bool catchUpWithRealTime = false;
}

void SoBSplineDeformSurface::setRealTimeCatchUp(bool catchUp) { catchUpWithRealTime = catchUp; }
bool SoBSplineDeformSurface::realTimeCatchUp() { return catchUpWithRealTime; }

void SoBSplineDeformSurface::clockCallback(void* data, SoSensor*) {
  auto* self = static_cast<SoBSplineDeformSurface*>(data);
  const SoSFTime* realTime = bsdeform::realTimeField();
  if (!realTime) return;
  const double now = realTime->getValue().getValue();
  // a clock set back (a driver that restarted) is a new origin, not time to make up
  if (self->m_lastTick >= 0.0 && now > self->m_lastTick) {
    self->ensureSimulation();
    const double dt = self->m_sim->parameters().timeStep;
    // Steps that cannot keep up with realTime: one per tick, the rest of the time dropped, so
    // that a frame follows every step instead of a quarter second of steps (setRealTimeCatchUp).
    // (with a quarter of margin for the frame drawn after the steps: a step that takes about its
    // own time leaves none for the drawing)
    const bool behind = !catchUpWithRealTime && self->m_stepWallSeconds * self->speed.getValue() > 0.75 * dt;
    const auto start = std::chrono::steady_clock::now();
    // Behind, a step waits for the frame of the one before (two clock ticks can come between
    // two frames), unless no frame comes (a surface nobody draws: a tenth of a second at most).
    const bool waitForFrame = behind && !self->m_drawnSinceStep &&
                              std::chrono::duration<double>(start - self->m_lastStepAt).count() < 0.1;
    int steps = 0;
    if (!behind) {
      steps = self->advanceRealTime(now - self->m_lastTick);
    } else if (self->m_sim->status() == bsdeform::Status::Ok &&
               bsdeform::stepsDue(now - self->m_lastTick, self->speed.getValue(), dt, self->m_timeBudget) > 0) {
      self->m_timeBudget = 0.0;  // the time due is dropped, not owed
      if (!waitForFrame) {
        self->stepSimulation(1);
        steps = 1;
      }
    }
    if (steps > 0) {
      self->m_lastStepAt = std::chrono::steady_clock::now();
      // averaged over the last steps, so that a step near the limit does not flip the mode
      const double cost = std::chrono::duration<double>(self->m_lastStepAt - start).count() / steps;
      self->m_stepWallSeconds = self->m_stepWallSeconds > 0.0 ? 0.7 * self->m_stepWallSeconds + 0.3 * cost : cost;
      self->m_drawnSinceStep = false;
    }
  }
  self->m_lastTick = now;
}

void SoBSplineDeformSurface::connectForces() {
  m_forcesChanged.disconnect();
  for (int i = 0; i < forces.getNum(); ++i)
    if (forces[i] && forces[i]->isOfType(SoForceField::getClassTypeId()))
      m_forcesChanged.appendConnection(&static_cast<SoForceField*>(forces[i])->revision);
  m_forcesStale = true;
}

void SoBSplineDeformSurface::notify(SoNotList* list) {
  SoField* f = list->getLastField();
  if (f && !m_syncing) {
    if (f == &controlNet || f == &previousNet || f == &simulationTime || f == &stepCount || f == &forceState) {
      m_stateDirty = true;
    } else if (f == &reset) {
      resetSimulation();  // touch()es: the notification goes on from there
      return;
    } else if (f == &on || f == &speed) {
      updateClock();
    } else if (f == &motionUMin || f == &motionUMax || f == &motionVMin || f == &motionVMax) {
      // a moved side's pose: read before the next step; nothing to rebuild or draw yet (a
      // clock-driven engine would otherwise ask for a redraw at every tick while paused)
      const int side = f == &motionUMin ? 0 : f == &motionUMax ? 1 : f == &motionVMin ? 2 : 3;
      if (m_sim && bsdeform::sideMotionSet(*static_cast<SoSFMatrix*>(f)) == m_sim->sideMoved(side)) return;
      m_modelDirty = true;  // moved or no longer: the fields are checked again (a side that is not CLAMPED)
    } else if (f == &forces) {
      connectForces();  // the slots are compared with the list before the next step
    } else if (f == &m_forcesChanged) {
      m_forcesStale = true;  // a force field changed: its force is remade before the next step
      return;                // nothing to draw differently yet
    } else {
      m_modelDirty = true;
    }
  }
  inherited::notify(list);
}

// ---------------------------------------------------------------------------------------------
// File I/O

void SoBSplineDeformSurface::syncStateFields() {
  ensureSimulation();
  m_syncing = true;
  const bsdeform::Simulation& s = *m_sim;
  const bool atRest = s.stepCount() == 0 && s.time() == 0.0 && s.current() == s.rest() && s.previous() == s.rest();
  if (atRest) {
    controlNet.setNum(0);
    previousNet.setNum(0);
    simulationTime.setValue(0.0);
    stepCount.setValue(0);
    forceState.setNum(0);
    for (SoField* f : {static_cast<SoField*>(&controlNet), static_cast<SoField*>(&previousNet),
                       static_cast<SoField*>(&simulationTime), static_cast<SoField*>(&stepCount),
                       static_cast<SoField*>(&forceState)})
      f->setDefault(TRUE);
  } else {
    bsdeform::netToField(s.current(), controlNet);
    bsdeform::netToField(s.previous(), previousNet);
    simulationTime.setValue(snap15(s.time()));
    stepCount.setValue(int(s.stepCount()));
    const std::vector<double> adapted = bsdeform::forceStatesOf(s);
    forceState.setValues(0, int(adapted.size()), adapted.data());
    forceState.setNum(int(adapted.size()));
    forceState.setDefault(adapted.empty());
  }
  m_syncing = false;
}


void SoBSplineDeformSurface::syncClockFields() {
  // Only the two scalars: the nets are large and written only when the scene is (write()).
  // m_syncing keeps these from marking the state dirty (the simulation already holds it).
  m_syncing = true;
  if (simulationTime.getValue() != m_sim->time()) simulationTime.setValue(m_sim->time());
  if (stepCount.getValue() != int(m_sim->stepCount())) stepCount.setValue(int(m_sim->stepCount()));
  m_syncing = false;
}

SbBool SoBSplineDeformSurface::readInstance(SoInput* in, unsigned short flags) {
  const SbBool ok = inherited::readInstance(in, flags);
  bsdeform::snapReadValues(*this);
  m_modelDirty = m_stateDirty = true;
  connectForces();
  return ok;
}

void SoBSplineDeformSurface::write(SoWriteAction* action) {
  syncStateFields();
  inherited::write(action);
}

// ---------------------------------------------------------------------------------------------
// Geometry

void SoBSplineDeformSurface::tessellate(SoState* state) {
  ensureSimulation();
  const bsdeform::Simulation& sim = m_building ? *m_building : *m_sim;
  const bsdeform::SplineSpace& sp = sim.space();
  const float complexity = state ? SoComplexityElement::get(state) : 0.5f;
  const int segU = bsdeform::tessellationSegments(complexity, sp.basisU().numSpans());
  const int segV = bsdeform::tessellationSegments(complexity, sp.basisV().numSpans());
  if (m_tessValid && m_tess.segU == segU && m_tess.segV == segV) return;
  bsdeform::tessellate(sp, sim.current(), segU, segV, m_tess);
  ++m_tessRevision;
  m_tessValid = !m_building;
}

void SoBSplineDeformSurface::GLRender(SoGLRenderAction* action) {
  if (!m_sceneGiven && !m_sceneRoot) {  // a plain Coin viewer: its scene, once (setScene())
    const SoPath* path = action->getCurPath();
    if (path && path->getLength()) {
      setScene(path->getHead());
      m_sceneGiven = false;  // taken, not given: a later setScene() wins
    }
  }
  if (!shouldGLRender(action)) return;
  m_drawnSinceStep = true;
  SoState* state = action->getState();
  tessellate(state);
  // An open surface shows both sides: light the back faces too. A closed one has none to show.
  state->push();
  if (!isClosed()) SoLazyElement::setTwosideLighting(state, TRUE);
  SoMaterialBundle mb(action);
  mb.sendFirst();
  if (!m_buffers) m_buffers = std::make_unique<bsdeform::SurfaceBuffers>();
  m_buffers->draw(state, m_tess, m_tessRevision);
  state->pop();
}

bool SoBSplineDeformSurface::isClosed() {
  ensureSimulation();
  return m_sim->restIsClosed();
}

void SoBSplineDeformSurface::generatePrimitives(SoAction* action) {
  tessellate(action->getState());
  SoPrimitiveVertex pv;
  beginShape(action, TRIANGLES);
  for (unsigned idx : m_tess.indices) {
    const float* p = &m_tess.vertices[size_t(idx) * 3];
    const float* n = &m_tess.normals[size_t(idx) * 3];
    const float* t = &m_tess.texCoords[size_t(idx) * 2];
    pv.setPoint(SbVec3f(p[0], p[1], p[2]));
    pv.setNormal(SbVec3f(n[0], n[1], n[2]));
    pv.setTextureCoords(SbVec4f(t[0], t[1], 0.0f, 1.0f));
    shapeVertex(&pv);
  }
  endShape();
}

void SoBSplineDeformSurface::computeBBox(SoAction* action, SbBox3f& box, SbVec3f& center) {
  // The box of the drawn vertices, found as tessellate() writes them (a hull of the control net
  // would be larger: a uniform B-spline's control points lie beyond the surface's edges).
  tessellate(action->getState());
  box.makeEmpty();
  const float* lo = m_tess.boundsMin;
  const float* hi = m_tess.boundsMax;
  if (lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2]) {  // not when every vertex is NaN
    box.extendBy(SbVec3f(lo[0], lo[1], lo[2]));
    box.extendBy(SbVec3f(hi[0], hi[1], hi[2]));
  }
  center = box.getCenter();
}

bool SoBSplineDeformSurface::pickedParameter(const SoPickedPoint* pp, float& u, float& v) {
  if (!pp || !pp->getPath() || !pp->getPath()->getTail()->isOfType(getClassTypeId())) return false;
  static_cast<SoBSplineDeformSurface*>(pp->getPath()->getTail())->closestParameter(pp->getObjectPoint(), u, v);
  return true;
}

void SoBSplineDeformSurface::closestParameter(const SbVec3f& p, float& u, float& v) {
  if (!m_tessValid) tessellate(nullptr);
  const Eigen::Vector2d uv = bsdeform::closestParameter(m_sim->space(), m_sim->current(), m_tess, Eigen::Vector3d(p[0], p[1], p[2]));
  u = float(uv.x());
  v = float(uv.y());
}
