// SPDX-License-Identifier: MIT
#include "bsdeform/SurfaceModel.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>

#include <Inventor/fields/SoSFTrigger.h>
#include <Inventor/lists/SoFieldList.h>

#include "bsdeform/FieldInfo.h"
#include "bsdeform/base/HugePages.h"
#include "bsdeform/base/ParameterError.h"
#include "bsdeform/dynamics/SimulationState.h"
#include "bsdeform/spline/RestShape.h"
#include "bsdeform/SceneObstacles.h"
#include "bsdeform/SceneText.h"
#include "bsdeform/SoForceField.h"

namespace bsdeform {

namespace {

using Surface = SoBSplineDeformSurface;

// The shortest text that reads back to x (a pin read as 0.97 is said as 0.97, not 0.96999999999999997)
std::string num(double x) {
  char buf[32];
  return std::string(buf, std::to_chars(buf, buf + sizeof buf, x).ptr);
}

Boundary sideOf(const SoSFEnum& f) {
  switch (f.getValue()) {
    case Surface::FREE: return Boundary::Free;
    case Surface::PERIODIC: return Boundary::Periodic;
    case Surface::SIMPLY_SUPPORTED: return Boundary::SimplySupported;
    case Surface::BUILT_IN: return Boundary::BuiltIn;
    case Surface::SYMMETRY: return Boundary::Free;  // the constraint: ModelParameters::sideSupports
    default: return Boundary::Clamped;
  }
}

}  // namespace

std::string nameOf(const SoBase* b) {
  const SbName name = b->getName();
  return name.getLength() ? name.getString() : "<unnamed>";
}

ControlNet netFromField(const SoMFVec3d& f) {
  ControlNet net(f.getNum(), 3);
  const SbVec3d* v = f.getValues(0);
  for (int i = 0; i < f.getNum(); ++i) net.row(i) << v[i][0], v[i][1], v[i][2];
  return net;
}

void netToField(const ControlNet& net, SoMFVec3d& f) {
  f.setNum(int(net.rows()));
  SbVec3d* v = f.startEditing();
  // a new array of a large net is not touched yet: on huge pages (HugePages.h)
  adviseHugePages(v, sizeof(SbVec3d) * size_t(net.rows()));
  for (Eigen::Index i = 0; i < net.rows(); ++i) v[i].setValue(snap15(net(i, 0)), snap15(net(i, 1)), snap15(net(i, 2)));
  f.finishEditing();
}

FieldRefusal refusalOf(const ParameterError& e) {
  const FieldInfo* f = surfaceFieldOfParameter(e.parameter());
  if (!f) return {"", e.what()};
  return {f->name, "field '" + std::string(f->name) + "' " + e.detail()};
}

bool modelFromFields(const Surface& n, ModelParameters& p, ControlNet& rest, FieldRefusal& refusal) {
  auto check = [&](bool ok, const char* field, const std::string& message) {
    if (!ok && refusal.message.empty()) refusal = {field, message};
  };
  auto unknown = [](const char* field, int value) {
    return std::string("field '") + field + "' has an unknown value " + std::to_string(value);
  };
  const int nu = n.uDegree.getValue(), nv = n.vDegree.getValue();
  const int Nu = n.numUControlPoints.getValue(), Nv = n.numVControlPoints.getValue();
  check(n.massModel.getValue() == Surface::NODAL || n.massModel.getValue() == Surface::LUMPED, "massModel",
        unknown("massModel", n.massModel.getValue()));
  check(n.energy.getValue() == Surface::PAPER_ENERGY || n.energy.getValue() == Surface::SHELL, "energy",
        unknown("energy", n.energy.getValue()));
  check(n.material.getValue() == Surface::SAINT_VENANT_KIRCHHOFF || n.material.getValue() == Surface::NEO_HOOKEAN,
        "material", unknown("material", n.material.getValue()));
  check(n.integrator.getValue() == Surface::EXPLICIT || n.integrator.getValue() == Surface::IMPLICIT ||
            n.integrator.getValue() == Surface::BACKWARD_EULER,
        "integrator",
        unknown("integrator", n.integrator.getValue()));
  check(n.nonlinearSolver.getValue() == Surface::NEWTON || n.nonlinearSolver.getValue() == Surface::LBFGS,
        "nonlinearSolver", unknown("nonlinearSolver", n.nonlinearSolver.getValue()));
  check(n.reference.getValue() == Surface::REST || n.reference.getValue() == Surface::ABSOLUTE, "reference",
        unknown("reference", n.reference.getValue()));
  check(n.start.getValue() == Surface::PAPER || n.start.getValue() == Surface::SECOND_ORDER, "start",
        unknown("start", n.start.getValue()));
  const std::pair<const SoSFEnum*, const char*> sides[] = {{&n.boundaryUMin, "boundaryUMin"},
                                                           {&n.boundaryUMax, "boundaryUMax"},
                                                           {&n.boundaryVMin, "boundaryVMin"},
                                                           {&n.boundaryVMax, "boundaryVMax"}};
  for (const auto& side : sides)
    check(side.first->getValue() >= Surface::CLAMPED && side.first->getValue() <= Surface::SYMMETRY, side.second,
          unknown(side.second, side.first->getValue()));
  // holdUMin ... : a SIMPLY_SUPPORTED side's components (SHELL); left at X | Y | Z elsewhere
  const SoSFBitMask* holds[] = {&n.holdUMin, &n.holdUMax, &n.holdVMin, &n.holdVMax};
  const char* holdNames[] = {"holdUMin", "holdUMax", "holdVMin", "holdVMax"};
  const unsigned all = Surface::X | Surface::Y | Surface::Z;
  for (int k = 0; k < 4; ++k) {
    const unsigned mask = unsigned(holds[k]->getValue());
    check((mask & ~all) == 0, holdNames[k], "field '" + std::string(holdNames[k]) + "' has an unknown value " + std::to_string(mask));
    if (mask == all) continue;
    check(sides[k].first->getValue() == Surface::SIMPLY_SUPPORTED || sides[k].first->getValue() == Surface::BUILT_IN,
          holdNames[k],
          "field '" + std::string(holdNames[k]) + "' holds chosen components of a SIMPLY_SUPPORTED or BUILT_IN side; " +
              sides[k].second + " is neither (leave " + holdNames[k] + " at X | Y | Z)");
    check(mask != 0, holdNames[k], "field '" + std::string(holdNames[k]) + "' holds no component: make " +
                                       sides[k].second + " FREE instead");
    check(n.energy.getValue() == Surface::SHELL, holdNames[k],
          "field '" + std::string(holdNames[k]) + "' (components of a side): only the SHELL energy takes them");
  }
  for (const auto& side : sides)
    check(side.first->getValue() != Surface::SYMMETRY || n.energy.getValue() == Surface::SHELL, side.second,
          std::string("field '") + side.second + "' SYMMETRY: only the SHELL energy takes symmetry sides");
  // motionUMin ... : a CLAMPED side moved by a map (SHELL, BACKWARD_EULER)
  const SoSFMatrix* motions[] = {&n.motionUMin, &n.motionUMax, &n.motionVMin, &n.motionVMax};
  const char* motionNames[] = {"motionUMin", "motionUMax", "motionVMin", "motionVMax"};
  for (int k = 0; k < 4; ++k) {
    if (!sideMotionSet(*motions[k])) continue;
    const char* field = motionNames[k];
    const SbMatrix& m = motions[k]->getValue();
    bool finite = true;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) finite &= std::isfinite(m[i][j]);
    check(finite && m[0][3] == 0.0f && m[1][3] == 0.0f && m[2][3] == 0.0f && m[3][3] == 1.0f, field,
          "field '" + std::string(field) + "' must be an affine map (last column 0 0 0 1, every entry finite)");
    check(sides[k].first->getValue() == Surface::CLAMPED, field,
          "field '" + std::string(field) + "' moves the layers a CLAMPED side holds; " + sides[k].second + " is not CLAMPED");
    check(n.energy.getValue() == Surface::SHELL && n.integrator.getValue() == Surface::BACKWARD_EULER, field,
          "field '" + std::string(field) + "' (a moved side): only the SHELL energy's integrator BACKWARD_EULER takes it");
  }
  const unsigned pinMask = unsigned(n.holdPins.getValue());
  check((pinMask & ~all) == 0 && pinMask != 0, "holdPins",
        "field 'holdPins' must hold one or more of X, Y, Z, got " + std::to_string(pinMask));
  check(pinMask == all || n.energy.getValue() == Surface::SHELL, "holdPins",
        "field 'holdPins' (components of the pins): only the SHELL energy takes them");
  for (int i = 0; i < n.pins.getNum(); ++i) {
    const SbVec2d q = n.pins[i];
    check(q[0] >= 0.0 && q[0] <= 1.0 && q[1] >= 0.0 && q[1] <= 1.0, "pins",
          "field 'pins' [" + std::to_string(i) + "] (" + num(q[0]) + ", " + num(q[1]) + ") must lie in [0,1]^2");
  }
  const long long expected = (static_cast<long long>(Nu) + 2LL * nu) * (static_cast<long long>(Nv) + 2LL * nv);
  for (const auto& net : {std::make_pair(&n.restNet, "restNet"), std::make_pair(&n.controlNet, "controlNet"),
                          std::make_pair(&n.previousNet, "previousNet")}) {
    const int count = net.first->getNum();
    check(count == 0 || count == expected || nu < 1 || nv < 1 || Nu < 1 || Nv < 1, net.second,
          std::string("field '") + net.second + "' must be empty or have " + std::to_string(expected) +
              " points ((numU + 2 uDegree)(numV + 2 vDegree)), got " + std::to_string(count));
  }
  const int shapeValue = n.restShape.getValue();
  check(shapeValue >= Surface::PLANE && shapeValue <= Surface::TORUS, "restShape", unknown("restShape", shapeValue));
  if (!refusal.message.empty()) return false;

  p.degreeU = nu;
  p.degreeV = nv;
  p.numU = Nu;
  p.numV = Nv;
  p.weights = Weights{n.w10.getValue(), n.w01.getValue(), n.w11.getValue(), n.w20.getValue(), n.w02.getValue()};
  p.massModel = n.massModel.getValue() == Surface::LUMPED ? MassModel::Lumped : MassModel::Nodal;
  p.mass = n.mass.getValue();
  p.damping = n.damping.getValue();
  p.timeStep = n.timeStep.getValue();
  p.integrator = n.integrator.getValue() == Surface::IMPLICIT         ? Integrator::Implicit
                 : n.integrator.getValue() == Surface::BACKWARD_EULER ? Integrator::BackwardEuler
                                                                      : Integrator::Explicit;
  p.maxSubSteps = n.maxSubSteps.getValue();
  p.energy = n.energy.getValue() == Surface::SHELL ? EnergyModel::Shell : EnergyModel::Paper;
  p.material.youngsModulus = n.youngsModulus.getValue();
  p.material.poissonRatio = n.poissonRatio.getValue();
  p.material.thickness = n.thickness.getValue();
  p.material.density = n.density.getValue();
  p.material.law = n.material.getValue() == Surface::NEO_HOOKEAN ? ShellMaterialLaw::NeoHookean
                                                                  : ShellMaterialLaw::SaintVenantKirchhoff;
  p.newtonTolerance = n.newtonTolerance.getValue();
  p.maxNewtonIterations = n.maxNewtonIterations.getValue();
  p.newtonVelocityTolerance = n.newtonVelocityTolerance.getValue();
  p.nonlinearSolver =
      n.nonlinearSolver.getValue() == Surface::LBFGS ? NonlinearSolver::LBFGS : NonlinearSolver::Newton;
  p.reference = n.reference.getValue() == Surface::ABSOLUTE ? ElasticReference::Absolute : ElasticReference::Rest;
  p.start = n.start.getValue() == Surface::PAPER ? StartRule::Paper : StartRule::SecondOrder;
  p.boundaries = {sideOf(n.boundaryUMin), sideOf(n.boundaryUMax), sideOf(n.boundaryVMin), sideOf(n.boundaryVMax)};
  // SYMMETRY and SIMPLY_SUPPORTED holding some components: FREE in the space, the constraint on
  // the unknowns (bsdeform/dynamics/SideSupports.h)
  {
    Boundary* space[] = {&p.boundaries.uMin, &p.boundaries.uMax, &p.boundaries.vMin, &p.boundaries.vMax};
    for (int k = 0; k < 4; ++k) {
      const unsigned mask = unsigned(holds[k]->getValue());
      if (sides[k].first->getValue() == Surface::SYMMETRY) {
        *space[k] = Boundary::Free;
        p.sideSupports[size_t(k)] = SideSupport{SideSupport::Kind::Symmetry, all};
      } else if (sides[k].first->getValue() == Surface::SIMPLY_SUPPORTED && mask != all) {
        *space[k] = Boundary::Free;
        p.sideSupports[size_t(k)] = SideSupport{SideSupport::Kind::Hinge, mask};
      } else if (sides[k].first->getValue() == Surface::BUILT_IN && mask != all) {
        *space[k] = Boundary::Free;
        p.sideSupports[size_t(k)] = SideSupport{SideSupport::Kind::Clamp, mask};
      }
    }
  }
  p.pinComponents = pinMask;
  for (int i = 0; i < n.pins.getNum(); ++i) p.pins.emplace_back(n.pins[i][0], n.pins[i][1]);
  const auto shape = static_cast<ShapeKind>(shapeValue);
  p.boundaries = shapeBoundaries(shape, p.boundaries);
  rest.resize(0, 3);
  if (n.restNet.getNum()) {
    rest = netFromField(n.restNet);
  } else if (shape != ShapeKind::Plane) {
    const ShapeSize size{n.radius.getValue(), n.height.getValue(), n.minorRadius.getValue(),
                         Eigen::Vector3d(n.radii.getValue()[0], n.radii.getValue()[1], n.radii.getValue()[2])};
    const std::string prefix = std::string("field 'restShape' ") + shapeName(shape) + ": ";
    try {
      rest = shapeRestNet(shape, size, SplineSpace(nu, nv, Nu, Nv, p.boundaries));
    } catch (const ParameterError& e) {
      const FieldRefusal r = refusalOf(e);
      refusal = {r.field.empty() ? "restShape" : r.field, prefix + r.message};
      return false;
    } catch (const std::exception& e) {
      refusal = {"restShape", prefix + e.what()};
      return false;
    }
  }
  if (rest.rows() == 0 && (p.boundaries.uMin == Boundary::Periodic || p.boundaries.vMin == Boundary::Periodic)) {
    const char* side = p.boundaries.uMin == Boundary::Periodic ? "boundaryUMin" : "boundaryVMin";
    refusal = {side, std::string("field '") + side +
                         "' is PERIODIC but field 'restNet' is empty: a periodic direction needs a rest net that "
                         "closes (or a rest shape)"};
    return false;
  }
  return true;
}

std::vector<FieldRefusal> fieldRefusals(const Surface& node) {
  std::vector<FieldRefusal> out;
  // Two field holders outside any scene: `scratch` gets the node's fields (not its forces, which
  // the model's parameters do not need), `defaults` supplies the value a refused field goes back to.
  auto* scratch = new Surface;
  scratch->ref();
  auto* defaults = new Surface;
  defaults->ref();
  // The scratch node only holds values: it is never notified (a copied trigger would reset it).
  scratch->enableNotify(FALSE);
  SoFieldList fields;
  const int count = node.getFields(fields);
  for (int i = 0; i < count; ++i) {
    SbName name;
    node.getFieldName(fields[i], name);
    if (name == "forces" || fields[i]->isOfType(SoSFTrigger::getClassTypeId())) continue;
    if (SoField* f = scratch->getField(name)) f->copyFrom(*fields[i]);
  }
  bool sizeReset = false;  // a field that sets the nets' size went back to its default
  for (int tries = 0; tries < count; ++tries) {
    ModelParameters p;
    ControlNet rest;
    FieldRefusal r;
    if (modelFromFields(*scratch, p, rest, r)) {
      try {
        const auto sim = rest.rows() ? std::make_unique<Simulation>(p, rest) : std::make_unique<Simulation>(p);
        break;  // taken
      } catch (const ParameterError& e) {
        r = refusalOf(e);
      } catch (const std::exception& e) {
        r = {"", e.what()};
      }
    }
    const bool netSize = r.field == "restNet" || r.field == "controlNet" || r.field == "previousNet";
    if (netSize && sizeReset) break;
    if (std::any_of(out.begin(), out.end(), [&r](const FieldRefusal& o) { return o.field == r.field; })) break;
    out.push_back(r);
    SoField* f = r.field.empty() ? nullptr : scratch->getField(SbName(r.field.c_str()));
    if (!f) break;  // nothing to reset: what follows cannot be found
    f->copyFrom(*defaults->getField(SbName(r.field.c_str())));
    sizeReset |= r.field == "numUControlPoints" || r.field == "numVControlPoints" || r.field == "uDegree" ||
                 r.field == "vDegree" || r.field.rfind("boundary", 0) == 0 || r.field == "restShape";
  }
  scratch->unref();
  defaults->unref();
  return out;
}

bool startState(Simulation& sim, const Surface& n, bool stateFromFields, const Simulation* old) {
  if (stateFromFields) {
    if (n.controlNet.getNum()) {
      const ControlNet cur = netFromField(n.controlNet);
      if (n.previousNet.getNum())
        sim.setState(cur, netFromField(n.previousNet), n.simulationTime.getValue(), n.stepCount.getValue());
      else  // released from rest at controlNet
        sim.setState(cur, n.simulationTime.getValue(), n.stepCount.getValue());
    }
    restoreForceStates(sim, std::vector<double>(n.forceState.getValues(0), n.forceState.getValues(0) + n.forceState.getNum()));
    return false;
  }
  if (!old || old->current().rows() != sim.current().rows() || old->rest() != sim.rest()) return false;
  // a live edit of the model: keep the motion going from where it is (newly held points, e.g. a
  // pin added, go back to their rest positions). A state still released from rest (not stepped
  // since it was built or reset) stays so: the new model's start rule applies, as if the file
  // had held the new values.
  if (old->startPending())
    sim.setState(old->current(), old->time(), old->stepCount(), HeldPoints::Reset);
  else
    sim.setState(old->current(), old->previous(), old->time(), old->stepCount(), old->subStepSize(), HeldPoints::Reset);
  return true;
}

StaticResult solveStaticInto(Simulation& sim, int loadSteps,
                             const std::function<void(const StaticResult&, size_t, const Diagnostics&)>& each,
                             const ArcLengthOptions* arcLength) {
  // at most 100 Newton iterations per increment (SHELL) or fixed-point iterations of the
  // position-dependent loads (the paper's model)
  const ModelParameters& mp = sim.parameters();
  const bool shell = mp.energy == EnergyModel::Shell;
  StaticResult r = arcLength ? sim.solveStaticArcLength(*arcLength)
                             : sim.solveStatic(shell ? mp.newtonTolerance : 1e-10, 100, LinearSolver::Automatic, loadSteps);
  if (each)
    for (size_t k = 0; k < r.increments.size(); ++k) {
      sim.setState(r.increments[k].net, r.increments[k].net, 0.0, 0, 0.0, HeldPoints::Check);
      each(r, k, sim.diagnostics());
    }
  sim.setState(r.net, r.net, 0.0, 0, 0.0, HeldPoints::Check);
  return r;
}

bool sideMotionSet(const SoSFMatrix& field) {
  return field.isConnected() || field.getValue() != SbMatrix::identity();
}

void applySideMotions(Simulation& sim, const Surface& n) {
  const SoSFMatrix* motions[] = {&n.motionUMin, &n.motionUMax, &n.motionVMin, &n.motionVMax};
  for (int side = 0; side < 4; ++side) {
    if (!sideMotionSet(*motions[side])) {
      if (sim.sideMoved(side)) sim.clearSideMotion(side);
      continue;
    }
    // Coin's matrices act on row vectors (x' = x m): the linear part is m's upper 3 x 3
    // transposed, the offset its last row
    const SbMatrix& m = motions[side]->getValue();
    Eigen::Matrix3d linear;
    Eigen::Vector3d offset;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) linear(r, c) = m[c][r];
      offset(r) = m[3][r];
    }
    sim.setSideMotion(side, linear, offset);
  }
}

int stepsDue(double seconds, double speed, double dt, double& owed) {
  if (!(seconds > 0.0) || !(speed > 0.0)) return 0;
  owed += std::min(seconds, 0.25) * speed;
  // In double first: speed 1e30 or a tiny timeStep ask for more steps than an int holds.
  constexpr int kMaxSteps = 10000;
  const double wanted = std::floor(owed / dt + 1e-9);
  const int steps = wanted <= kMaxSteps ? static_cast<int>(std::max(0.0, wanted)) : kMaxSteps;
  owed = wanted <= kMaxSteps ? std::max(0.0, owed - steps * dt) : 0.0;
  return steps;
}

void snapReadValues(Surface& n) { snapReadDoubles(n); }

int ForceSlots::obstacleBuilds() const {
  int n = 0;
  for (const Slot& s : m_slots)
    if (s.obstacles) n += s.obstacles->builds();
  return n;
}

int ForceSlots::obstacleRefits() const {
  int n = 0;
  for (const Slot& s : m_slots)
    if (s.obstacles) n += s.obstacles->refits();
  return n;
}

void ForceSlots::keepForNewModel() {
  for (Slot& slot : m_slots)
    if (slot.engine && static_cast<SoEngine*>(slot.engine)->isOfType(SoForceField::getClassTypeId()) &&
        static_cast<SoForceField*>(slot.engine)->type.getValue() == SoForceField::COLLISION) {
      slot.force.reset();
      slot.revision = -1;
    }
  m_given = nullptr;
}

int ForceSlots::update(Simulation& sim, const SoMFEngine& forces, SoNode* scene, SoNode* self, bool stale,
                       const std::vector<std::shared_ptr<const Force>>& transient, const Report& report) {
  using Problem = Surface::Problem;
  SoForceField::SurfaceInfo info;
  int made = 0;
  bool changed = int(m_slots.size()) != forces.getNum() || &sim != m_given;
  stale |= changed;
  // The surface's world frame, for the force fields whose vectors are in the world (frame
  // WORLD): looked up before every step, and a changed frame (a Transform above the surface
  // moved) remakes their forces.
  bool worldFields = false;
  for (int i = 0; i < forces.getNum(); ++i)
    if (SoEngine* e = forces[i]; e && e->isOfType(SoForceField::getClassTypeId())) {
      auto* ff = static_cast<SoForceField*>(e);
      worldFields |= ff->frame.getValue() == SoForceField::WORLD && ff->type.getValue() != SoForceField::COLLISION;
    }
  bool frameChanged = false;
  if (worldFields) {
    surfaceFrame(scene, self, info.linear, info.offset);
    frameChanged = info.linear != m_linear || info.offset != m_offset;
    m_linear = info.linear;
    m_offset = info.offset;
    stale |= frameChanged;
  }
  m_slots.resize(forces.getNum());
  for (int i = 0; i < forces.getNum(); ++i) {
    SoEngine* e = forces[i];
    Slot& slot = m_slots[i];
    if (!e || !e->isOfType(SoForceField::getClassTypeId())) {
      if (slot.engine != e) {
        if (e)
          report(Problem::FORCE_FIELD, "forces",
                 "field 'forces' [" + std::to_string(i) + "] is a " + e->getTypeId().getName().getString() +
                     ", not an SoForceField; ignored",
                 "");
        slot = Slot{e, -1, nullptr, nullptr, -1};
        changed = true;
      }
      continue;
    }
    auto* ff = static_cast<SoForceField*>(e);
    if (ff->type.getValue() == SoForceField::COLLISION) {
      // the obstacles are kept current before every step; the force reads them in place
      if (!slot.obstacles || slot.engine != ff) slot.obstacles = std::make_shared<SceneObstacles>();
      std::vector<std::string> problems;
      slot.obstacles->update(scene, self, ff->obstacles, ff->obstacleNames,
                             stale && slot.geometryRevision != ff->getGeometryRevision(), problems,
                             ff->method.getValue() == SoForceField::BARRIER);
      slot.geometryRevision = ff->getGeometryRevision();
      for (const std::string& p : problems)
        report(Problem::OBSTACLE, "obstacles", "SoForceField '" + nameOf(ff) + "': " + p, nameOf(ff));
      info.contact = slot.obstacles->world();
    } else {
      slot.obstacles.reset();
      info.contact.reset();
    }
    const bool frameMatters = ff->frame.getValue() == SoForceField::WORLD && ff->type.getValue() != SoForceField::COLLISION;
    if (!stale || (slot.engine == ff && slot.revision == ff->getRevision() && !(frameChanged && frameMatters))) continue;
    std::string error;
    auto force = ff->makeForce(info, error);
    ++made;
    slot.engine = ff;
    slot.revision = ff->getRevision();
    changed = true;
    if (!error.empty()) {
      report(Problem::FORCE_FIELD, "", "SoForceField '" + nameOf(ff) + "': " + error + "; keeping its previous force",
             nameOf(ff));
      continue;  // keep slot.force
    }
    slot.force = std::move(force);
  }
  if (changed) {
    sim.clearForces();
    for (const Slot& s : m_slots)
      if (s.force) sim.addForce(s.force);
    for (const auto& f : transient) sim.addForce(f);
    m_given = &sim;
  }
  return made;
}

}  // namespace bsdeform
