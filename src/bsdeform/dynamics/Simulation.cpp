// SPDX-License-Identifier: MIT
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/dynamics/MassMatrix.h"

#include "bsdeform/dynamics/EdgeMass.h"
#include "bsdeform/base/HugePages.h"
#include "bsdeform/base/NumberText.h"
#include "bsdeform/base/Parallel.h"
#include "bsdeform/dynamics/StepperView.h"
#include "bsdeform/dynamics/TimeStepper.h"

#include <Eigen/SVD>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>

#include "bsdeform/base/ParameterError.h"

namespace bsdeform {

namespace {

std::string num(double x) { return numberText(x); }

void require(bool ok, const std::string& message) {
  if (!ok) throw std::invalid_argument(message);
}

const ModelParameters& validated(const ModelParameters& p) {
  // Degrees, counts, their limits and the boundary pairs first (SplineSpace names them), then
  // the rest here; weights are checked by StiffnessStencil.
  (void)SplineSpace(p.degreeU, p.degreeV, p.numU, p.numV, p.boundaries);
  requireParameter(std::isfinite(p.mass) && p.mass > 0.0, "mass", "must be finite and > 0, got " + num(p.mass));
  requireParameter(std::isfinite(p.damping) && p.damping >= 0.0, "damping", "must be finite and >= 0, got " + num(p.damping));
  requireParameter(std::isfinite(p.timeStep) && p.timeStep > 0.0, "timeStep", "must be finite and > 0, got " + num(p.timeStep));
  requireParameter(std::isfinite(p.stabilitySafety) && p.stabilitySafety > 0.0 && p.stabilitySafety <= 1.0,
                   "stabilitySafety", "must be in (0, 1], got " + num(p.stabilitySafety));
  requireParameter(std::isfinite(p.divergenceLimit) && p.divergenceLimit > 0.0, "divergenceLimit",
                   "must be finite and > 0, got " + num(p.divergenceLimit));
  requireParameter(p.maxSubSteps >= 1, "maxSubSteps", "must be >= 1, got " + std::to_string(p.maxSubSteps));
  requireParameter(std::isfinite(p.solverTolerance) && p.solverTolerance > 0.0 && p.solverTolerance < 1.0,
                   "solverTolerance", "must be in (0, 1), got " + num(p.solverTolerance));
  requireParameter(p.maxSolverIterations >= 1, "maxSolverIterations",
                   "must be >= 1, got " + std::to_string(p.maxSolverIterations));
  requireParameter(std::isfinite(p.newtonTolerance) && p.newtonTolerance > 0.0 && p.newtonTolerance < 1.0,
                   "newtonTolerance", "must be in (0, 1), got " + num(p.newtonTolerance));
  requireParameter(std::isfinite(p.newtonVelocityTolerance) && p.newtonVelocityTolerance > 0.0,
                   "newtonVelocityTolerance", "must be a finite number > 0, got " + num(p.newtonVelocityTolerance));
  requireParameter(p.maxNewtonIterations >= 1, "maxNewtonIterations",
                   "must be >= 1, got " + std::to_string(p.maxNewtonIterations));
  for (size_t i = 0; i < p.pins.size(); ++i) {
    const Eigen::Vector2d& q = p.pins[i];
    requireParameter(q.allFinite() && q.x() >= 0.0 && q.x() <= 1.0 && q.y() >= 0.0 && q.y() <= 1.0, "pins",
                     std::to_string(i) + " (" + num(q.x()) + ", " + num(q.y()) + ") must lie in [0,1]^2", "pin");
  }
  return p;
}

// `parameter`: restNet, controlNet or previousNet (as the nodes spell the state), `name` as the
// messages do ("rest net")
void requireNet(const SplineSpace& s, const ControlNet& net, const char* parameter, const char* name) {
  requireParameter(net.rows() == s.netSize(), parameter,
                   "must have (numU + 2 degreeU) * (numV + 2 degreeV) = " + std::to_string(s.netSize()) +
                       " points, got " + std::to_string(net.rows()),
                   name);
  for (Eigen::Index i = 0; i < net.rows(); ++i)
    requireParameter(net.row(i).allFinite(), parameter,
                     "point " + std::to_string(i) + " is not finite (" + num(net(i, 0)) + ", " + num(net(i, 1)) +
                         ", " + num(net(i, 2)) + ")",
                     name);
}

}  // namespace

Simulation::Simulation(const ModelParameters& params)
    : m_params(validated(params)),
      m_space(params.degreeU, params.degreeV, params.numU, params.numV, params.boundaries),
      m_stencil(m_space, params.weights) {
  require(!m_space.periodicU() && !m_space.periodicV(),
          std::string("a PERIODIC direction (") + (m_space.periodicU() ? "u" : "v") +
              ") needs a rest net that closes; the plane does not");
  m_rest = m_space.grevillePlane();
  init();
}

Simulation::Simulation(const ModelParameters& params, const ControlNet& rest)
    : m_params(validated(params)),
      m_space(params.degreeU, params.degreeV, params.numU, params.numV, params.boundaries),
      m_stencil(m_space, params.weights) {
  requireNet(m_space, rest, "restNet", "rest net");
  m_rest = rest;
  m_seamMismatch = m_space.closePeriodic(m_rest);
  init();
}

Simulation::~Simulation() = default;

StepperModel& Simulation::stepperView() {
  if (!m_view) m_view = std::make_unique<StepperView>(*this);
  return *m_view;
}

int Simulation::lastNewtonIterations() const { return m_stepper->newtonIterations(); }

const ImplicitSystem* Simulation::implicitSystem() const { return m_stepper->implicitSystem(); }

double Simulation::massPerPoint() const {
  if (m_params.energy == EnergyModel::Shell)
    return m_params.material.density * m_params.material.thickness * m_space.basisU().spacing() *
           m_space.basisV().spacing();
  return m_params.massModel == MassModel::Nodal
             ? m_params.mass
             : m_params.mass * m_space.basisU().spacing() * m_space.basisV().spacing();
}

const MassMatrix& Simulation::massMatrix() const {
  if (m_mass) return *m_mass;
  // the paper's model: m I, the lumped masses, or T^T W T next to derived layers (EdgeMass)
  const Eigen::Index n = m_space.numMoving();
  std::vector<char> pinned(size_t(n), 0);
  for (Eigen::Index f = 0; f < n; ++f) pinned[size_t(f)] = m_pinMask[size_t(m_space.movingToNet(f))];
  if (m_edgeMass) {
    std::vector<Eigen::Triplet<double>> t = m_edgeMass->offDiagonal(1.0);
    for (Eigen::Index f = 0; f < n; ++f) {
      const Eigen::Index r = m_space.movingToNet(f);
      t.emplace_back(f, f, m_edgeMass->diagonal(int(r / m_space.netCols()), int(r % m_space.netCols())));
    }
    Eigen::SparseMatrix<double> M(n, n);
    M.setFromTriplets(t.begin(), t.end());
    m_mass = std::make_unique<MassMatrix>(std::move(M), std::move(pinned));
  } else {
    m_mass = std::make_unique<MassMatrix>(
        m_uniformMass ? Eigen::VectorXd::Constant(n, massPerPoint()) : Eigen::VectorXd(m_massMoving), std::move(pinned));
  }
  return *m_mass;
}

double Simulation::dampingRatio() const {
  // C = c M for SHELL; the paper's C = c I (NODAL) or c h1 h2 I (LUMPED) is (c / m) M alike,
  // its damping per point over its mass per point
  if (m_shell) return m_params.damping;
  return dampingPerPoint() / massPerPoint();
}

double Simulation::massPerArea() const {
  if (m_params.energy == EnergyModel::Shell) return m_params.material.density * m_params.material.thickness;
  const double perPoint = m_space.basisU().spacing() * m_space.basisV().spacing();
  return m_params.massModel == MassModel::Nodal ? m_params.mass / perPoint : m_params.mass;
}

double Simulation::restArea() const {
  if (m_restArea < 0.0) m_restArea = surfaceArea(m_space, m_rest);
  return m_restArea;
}

double Simulation::usableRestArea() const {
  const double a = restArea();
  return std::isfinite(a) && a > 0.0 ? a : 1.0;
}

bool Simulation::restIsClosed() const {
  if (m_restClosed < 0) m_restClosed = isClosedSurface(m_space, m_rest) ? 1 : 0;
  return m_restClosed == 1;
}

double Simulation::massAt(int i, int j) const {
  if (m_shellModel) return m_shellModel->netMass()[Eigen::Index(i) * m_space.netCols() + j];
  if (m_params.massModel == MassModel::Nodal) return m_params.mass;
  const GramRows1D &gu = m_stencil.gramU(), &gv = m_stencil.gramV();
  return m_params.mass * gu.rowSum(gu.rowType(i)) * gv.rowSum(gv.rowType(j));
}

void Simulation::holdPins(ControlNet& net) const {
  for (Eigen::Index r : m_pinned)
    for (int c = 0; c < 3; ++c)
      if (m_params.pinComponents & (1u << c)) net(r, c) = m_rest(r, c);
  for (const ModelParameters::HeldCoordinate& h : m_params.heldCoordinates) net(h.point, h.axis) = m_rest(h.point, h.axis);
}

void Simulation::setSideMotion(int side, const Eigen::Matrix3d& linear, const Eigen::Vector3d& offset) {
  require(side >= 0 && side < 4, "setSideMotion: side must be 0..3, got " + std::to_string(side));
  static const char* names[4] = {"u = 0", "u = 1", "v = 0", "v = 1"};
  const Boundary kinds[4] = {m_space.boundaries().uMin, m_space.boundaries().uMax, m_space.boundaries().vMin,
                             m_space.boundaries().vMax};
  require(kinds[side] == Boundary::Clamped, std::string("side ") + names[side] + " is " + boundaryName(kinds[side]) +
                                                ": only a CLAMPED side (its n layers held) can be moved");
  require(linear.allFinite() && offset.allFinite(), std::string("the motion of side ") + names[side] + " is not finite");
  m_sideMoved[size_t(side)] = true;
  m_sideMap[size_t(side)] << linear, offset;
  updateHeldTarget();
}

void Simulation::clearSideMotion(int side) {
  require(side >= 0 && side < 4, "clearSideMotion: side must be 0..3, got " + std::to_string(side));
  if (!m_sideMoved[size_t(side)]) return;
  m_sideMoved[size_t(side)] = false;
  updateHeldTarget();
}

void Simulation::updateHeldTarget() {
  m_heldTarget = m_rest;
  for (int side = 0; side < 4; ++side)
    if (m_sideMoved[size_t(side)]) {
      const Eigen::Matrix3d linear = m_sideMap[size_t(side)].leftCols<3>();
      const Eigen::Vector3d offset = m_sideMap[size_t(side)].col(3);
      for (Eigen::Index r : m_sideRows[size_t(side)])
        m_heldTarget.row(r) = (linear * m_rest.row(r).transpose() + offset).transpose();
    }
}

bool Simulation::heldRowsMoved(const ControlNet& net) const {
  for (const std::vector<Eigen::Index>& rows : m_sideRows)
    for (Eigen::Index r : rows)
      if (net.row(r) != m_heldTarget.row(r)) return true;
  return false;
}

void Simulation::placeHeldRows(const ControlNet& from, double alpha, ControlNet& net) const {
  for (const std::vector<Eigen::Index>& rows : m_sideRows)
    for (Eigen::Index r : rows) {
      if (alpha >= 1.0)
        net.row(r) = m_heldTarget.row(r);
      else
        net.row(r) = from.row(r) + alpha * (m_heldTarget.row(r) - from.row(r));
    }
}

void Simulation::copyHeldRows(const ControlNet& from, ControlNet& net) const {
  for (const std::vector<Eigen::Index>& rows : m_sideRows)
    for (Eigen::Index r : rows) net.row(r) = from.row(r);
}

double Simulation::dampingPerPoint() const {
  if (m_params.energy == EnergyModel::Shell) return m_params.damping * massPerPoint();
  return m_params.massModel == MassModel::Nodal
             ? m_params.damping
             : m_params.damping * m_space.basisU().spacing() * m_space.basisV().spacing();
}

void Simulation::init() {
  static std::atomic<std::uint64_t> serials{0};
  m_serial = ++serials;
  // Pins: the (n1+1)(n2+1) B-splines of the knot span that contains (u, v), through the moving
  // point each stands for (held already if it lies in a clamped layer).
  m_pinMask.assign(size_t(m_space.netSize()), 0);
  m_pinned.clear();
  for (const Eigen::Vector2d& pin : m_params.pins) {
    const int su = m_space.basisU().span(pin.x()), sv = m_space.basisV().span(pin.y());
    for (int k1 = su - m_space.degreeU(); k1 <= su; ++k1)
      for (int k2 = sv - m_space.degreeV(); k2 <= sv; ++k2) {
        const Eigen::Index m = m_space.movingIndex(k1, k2);
        if (m < 0) continue;
        const Eigen::Index r = m_space.movingToNet(m);
        if (!m_pinMask[size_t(r)]) m_pinned.push_back(r);
        m_pinMask[size_t(r)] = 1;
      }
  }

  m_heldMask.assign(size_t(3 * m_space.numMoving()), 0);
  for (Eigen::Index f = 0; f < m_space.numMoving(); ++f)
    if (m_pinMask[size_t(m_space.movingToNet(f))])
      for (int c = 0; c < 3; ++c)
        if (m_params.pinComponents & (1u << c)) m_heldMask[size_t(3 * f + c)] = 1;
  require((m_params.pinComponents & ~7u) == 0 && (m_params.pinComponents & 7u) != 0,
          "pinComponents: the pins must hold one or more of x, y, z");
  require(m_params.pinComponents == 7u || m_params.energy == EnergyModel::Shell,
          "pinComponents: only the SHELL energy's pins hold chosen components");
  if (!m_params.heldCoordinates.empty()) {
    require(m_params.energy == EnergyModel::Shell, "heldCoordinates: only the SHELL energy holds single coordinates");
    require(!m_space.hasDerived(),
            "heldCoordinates: not with SIMPLY_SUPPORTED or BUILT_IN sides (their mass couples the coordinates)");
    std::vector<Eigen::Index> movingOf(size_t(m_space.netSize()), -1);
    for (Eigen::Index f = 0; f < m_space.numMoving(); ++f) movingOf[size_t(m_space.movingToNet(f))] = f;
    for (size_t k = 0; k < m_params.heldCoordinates.size(); ++k) {
      const ModelParameters::HeldCoordinate& h = m_params.heldCoordinates[k];
      require(h.axis >= 0 && h.axis <= 2, "heldCoordinates[" + std::to_string(k) + "]: axis must be 0, 1 or 2, got " +
                                              std::to_string(h.axis));
      require(h.point >= 0 && h.point < m_space.netSize() && movingOf[size_t(h.point)] >= 0,
              "heldCoordinates[" + std::to_string(k) + "]: net row " + std::to_string(h.point) +
                  " is not a moving control point");
      m_heldMask[size_t(3 * movingOf[size_t(h.point)] + h.axis)] = 1;
    }
  }

  m_components.reset();
  m_tangentHeldMask = m_heldMask;
  bool anySupport = false;
  for (const SideSupport& side : m_params.sideSupports) anySupport |= side.kind != SideSupport::Kind::None;
  if (anySupport) {
    require(m_params.energy == EnergyModel::Shell,
            "supports per component (holdUMin ...) and SYMMETRY sides: only the SHELL energy takes them");
    m_components = std::make_unique<ComponentConstraints>(m_space, m_rest, m_params.sideSupports);
    for (Eigen::Index d = 0; d < 3 * m_space.numMoving(); ++d)
      if (m_components->constrained(d)) m_heldMask[size_t(d)] = 1;
  }

  // the layers each side holds, from its edge inwards (EdgeLayers::held), and where: at rest
  const Boundary kinds[4] = {m_space.boundaries().uMin, m_space.boundaries().uMax, m_space.boundaries().vMin,
                             m_space.boundaries().vMax};
  for (int side = 0; side < 4; ++side) {
    std::vector<Eigen::Index>& rows = m_sideRows[size_t(side)];
    rows.clear();
    const bool alongU = side < 2;
    const int held = edgeLayers(kinds[side], alongU ? m_space.degreeU() : m_space.degreeV()).held;
    const int layers = alongU ? m_space.netRows() : m_space.netCols();
    for (int k = 0; k < held; ++k) {
      const int layer = side % 2 == 0 ? k : layers - 1 - k;
      if (alongU)
        for (int j = 0; j < m_space.netCols(); ++j) rows.push_back(Eigen::Index(layer) * m_space.netCols() + j);
      else
        for (int i = 0; i < m_space.netRows(); ++i) rows.push_back(Eigen::Index(i) * m_space.netCols() + layer);
    }
    m_sideMoved[size_t(side)] = false;
  }
  m_heldTarget = m_rest;

  allocateNet(m_current, m_rest.rows());
  allocateNet(m_previous, m_rest.rows());
  m_current = m_rest;
  m_previous = m_rest;
  m_startPending = true;
  m_divergenceLimit = m_params.divergenceLimit * (1.0 + m_rest.cwiseAbs().maxCoeff());
  if (m_params.energy == EnergyModel::Shell) {
    initShell();
    rebuildConstantLoad();
    updateSubSteps();
    return;
  }

  m_stencilLambda = m_stencil.eigenvalueBound();
  auto paper = std::make_unique<PaperEnergy>(m_space, m_stencil, m_rest, m_params.reference == ElasticReference::Rest,
                                             m_params.massModel == MassModel::Lumped, m_params.mass);
  m_paper = paper.get();
  m_energy = std::move(paper);
  m_shellModel = nullptr;
  m_shell = nullptr;
  // M = T^T W T next to derived layers (SIMPLY_SUPPORTED, BUILT_IN: EdgeMass); whether M is a
  // multiple of the identity is the energy's rule (PaperEnergy::uniformMass()).
  m_edgeMass.reset();
  m_derivedRows.clear();
  if (m_space.hasDerived()) {
    m_edgeMass = std::make_unique<EdgeMass>(m_space, m_stencil.gramU(), m_stencil.gramV(),
                                            m_params.massModel == MassModel::Lumped, m_params.mass);
    for (int i = 0; i < m_space.netRows(); ++i)
      for (int j = 0; j < m_space.netCols(); ++j)
        if (m_space.isDerived(i, j)) m_derivedRows.push_back(Eigen::Index(i) * m_space.netCols() + j);
    m_edgeMass->setPinned(pinnedMoving());
  }
  m_uniformMass = m_paper->uniformMass();
  m_elasticLambda = m_energy->eigenvalueBound(m_current);
  if (m_uniformMass) {
    m_massMoving.resize(0);
  } else {
    m_massMoving.resize(m_space.numMoving());
    for (Eigen::Index f = 0; f < m_space.numMoving(); ++f) {
      const Eigen::Index r = m_space.movingToNet(f);
      m_massMoving[f] = massAt(int(r / m_space.netCols()), int(r % m_space.netCols()));
    }
  }
  m_mass.reset();  // built when a scheme asks (massMatrix()): the fused kernels do not
  if (m_params.integrator == Integrator::Implicit)
    m_stepper = std::make_unique<PaperImplicitStepper>(stepperView());
  else if (m_params.integrator == Integrator::BackwardEuler)
    m_stepper = std::make_unique<BackwardEulerStepper>(stepperView());
  else
    m_stepper = std::make_unique<PaperExplicitStepper>(stepperView());
  rebuildConstantLoad();
  updateSubSteps();
}

ControlNet Simulation::boundaryTerm() const {
  ControlNet heldOnly = m_rest;
  for (Eigen::Index f = 0; f < m_space.numMoving(); ++f) {
    const Eigen::Index r = m_space.movingToNet(f);
    if (!m_pinMask[size_t(r)]) heldOnly.row(r).setZero();
  }
  // derived layers at their value for zero unknowns (pins included): the constant part of T x + y0
  m_space.completeNet(heldOnly, &m_rest);
  ControlNet term;
  m_stencil.applyMoving(heldOnly, term);
  return term;
}

Eigen::SparseMatrix<double> Simulation::activeMatrix() const {
  Eigen::SparseMatrix<double> A = m_stencil.movingMatrix();
  if (!m_pinned.empty()) {
    // pinned rows and columns leave the system (their coupling is held-point coupling, A_IB)
    std::vector<char> pinned(size_t(m_space.numMoving()), 0);
    for (Eigen::Index f = 0; f < m_space.numMoving(); ++f) pinned[size_t(f)] = m_pinMask[size_t(m_space.movingToNet(f))];
    A.prune([&](Eigen::Index r, Eigen::Index c, double) { return !pinned[size_t(r)] && !pinned[size_t(c)]; });
  }
  return A;
}

ControlNet Simulation::restOffset() const {
  if (m_paper) return m_paper->restOffset();
  ControlNet c0;
  allocateNet(c0, m_space.numMoving());
  c0.setZero();
  return c0;
}

void Simulation::rebuildConstantLoad() {
  // c0, then the constant forces in their order: the same sums as addForce() makes one force
  // at a time
  m_constantLoad = restOffset();
  m_hasVariableForces = false;
  const LoadContext ctx = loadContext(m_current, m_previous, subStepSize(), m_time);
  for (const auto& f : m_forces) {
    if (f->dependence() == kConstant)
      f->addLoad(ctx, m_constantLoad);
    else
      m_hasVariableForces = true;
  }
}

void Simulation::updateSubSteps() {
  const MassContext mc{m_space, massPerPoint(), [this](int i, int j) { return massAt(i, j); }, usableRestArea()};
  double forceLambda = 0.0;
  for (const auto& f : m_forces) forceLambda += f->eigenvalueBound(mc);
  m_lambdaMax = m_elasticLambda + forceLambda;
  const double oldStep = subStepSize();
  int n = 1;
  m_subStepsNeeded = 1.0;
  if (m_params.integrator == Integrator::Explicit && m_params.autoSubstep && m_lambdaMax > 0.0) {
    const double safe = m_params.stabilitySafety * stabilityLimit();
    // In double first: timeStep 1e12, w20 1e300 or mass 1e-300 need more sub-steps than an int
    // holds (or infinitely many); such a step is refused by step(), see refusal().
    m_subStepsNeeded = std::max(1.0, std::ceil(m_params.timeStep / safe));
    n = m_subStepsNeeded <= double(m_params.maxSubSteps) ? static_cast<int>(m_subStepsNeeded) : m_params.maxSubSteps;
  }
  m_subSteps = n;
  const double newStep = subStepSize();
  // Before the first step (m_startPending) the state is at rest, previous == current: nothing
  // to rescale (and a 2048^2 net is not swept for nothing).
  if (newStep != oldStep && !m_startPending)
    m_previous = m_current - (m_current - m_previous) * (newStep / oldStep);
}

double Simulation::stabilityLimit() const {
  return m_lambdaMax > 0.0 ? 2.0 / std::sqrt(m_lambdaMax) : std::numeric_limits<double>::infinity();
}

void Simulation::addForce(std::shared_ptr<const Force> force) {
  if (!force) throw std::invalid_argument("addForce: null force");
  m_forces.push_back(std::move(force));
  ++m_forcesVersion;
  if (m_forces.back()->dependence() == kConstant) {
    const LoadContext ctx = loadContext(m_current, m_previous, subStepSize(), m_time);
    m_forces.back()->addLoad(ctx, m_constantLoad);
  } else {
    m_hasVariableForces = true;  // evaluated every sub-step; the constant load stays
  }
  if (m_stepper) m_stepper->forcesChanged();
  updateSubSteps();
}

bool Simulation::removeForce(const Force* force) {
  auto it = std::find_if(m_forces.begin(), m_forces.end(), [force](const auto& p) { return p.get() == force; });
  if (it == m_forces.end()) return false;
  const bool constant = (*it)->dependence() == kConstant;
  m_forces.erase(it);
  ++m_forcesVersion;
  if (constant) {
    rebuildConstantLoad();
  } else {
    m_hasVariableForces = std::any_of(m_forces.begin(), m_forces.end(),
                                      [](const auto& f) { return f->dependence() != kConstant; });
  }
  m_stepper->forcesChanged();
  updateSubSteps();
  return true;
}

void Simulation::clearForces() {
  m_forces.clear();
  ++m_forcesVersion;
  rebuildConstantLoad();
  m_stepper->forcesChanged();
  updateSubSteps();
}

const ControlNet& Simulation::effectiveLoad(double t, double stepSize) {
  if (!m_hasVariableForces) return m_constantLoad;
  allocateNet(m_load, m_constantLoad.rows());
  m_load = m_constantLoad;
  const LoadContext ctx = loadContext(m_current, m_previous, stepSize > 0.0 ? stepSize : subStepSize(), t);
  // sub-steps of the step [m_time, m_time + T]: loads of time alone interpolated from its ends
  const double T = m_params.timeStep;
  const bool interpolate = m_subSteps > 1 && t >= m_time && t <= m_time + T;
  bool timeOnly = false;
  for (const auto& f : m_forces) {
    const unsigned dep = f->dependence();
    if (dep == kConstant) continue;
    if (interpolate && dep == kDependsOnTime)
      timeOnly = true;
    else
      f->addLoad(ctx, m_load);
  }
  if (timeOnly) {
    const double alpha = (t - m_time) / T;
    if (alpha > 0.0) m_load += alpha * timeLoad(stepEnd());  // the next step's start: kept
    if (alpha < 1.0) m_load += (1.0 - alpha) * timeLoad(m_time);
  }
  return m_load;
}

const ControlNet& Simulation::timeLoad(double t) {
  for (const TimeLoadCache& c : m_timeLoads)
    if (c.forces == m_forcesVersion && c.time == t) return c.load;
  // replace an entry of an older force list, else the earlier time (the later one is the next
  // step's start)
  TimeLoadCache* slot = &m_timeLoads[0];
  if (m_timeLoads[0].forces == m_forcesVersion &&
      (m_timeLoads[1].forces != m_forcesVersion || m_timeLoads[1].time < m_timeLoads[0].time))
    slot = &m_timeLoads[1];
  TimeLoadCache& c = *slot;
  c.load = ControlNet::Zero(m_constantLoad.rows(), 3);
  const LoadContext ctx = loadContext(m_current, m_previous, subStepSize(), t);
  for (const auto& f : m_forces)
    if (f->dependence() == kDependsOnTime) f->addLoad(ctx, c.load);
  c.time = t;
  c.forces = m_forcesVersion;
  return c.load;
}

ControlNet Simulation::loadVector() const {
  ControlNet load = ControlNet::Zero(m_space.numMoving(), 3);
  const LoadContext ctx = loadContext(m_current, m_previous, subStepSize(), m_time);
  for (const auto& f : m_forces) f->addLoad(ctx, load);
  return load;
}

void Simulation::fail(Status s, std::string message) {
  m_status = s;
  m_statusMessage = std::move(message);
}

void Simulation::applyStartRule() {
  m_startPending = false;
  // backward Euler starts from the velocity zero itself (P- = P)
  if (m_params.start != StartRule::SecondOrder || m_params.integrator == Integrator::BackwardEuler) return;
  // P(-delta) = P(0) + delta^2/2 a(0), a(0) = M^-1 (L - (A P(0) - c0)), the velocity being zero:
  // the Taylor expansion of a release from rest, exact to O(delta^3).
  const ControlNet& load = effectiveLoad(m_time);
  ControlNet elastic;
  if (m_shell)
    m_energy->gradient(m_current, elastic);
  else
    m_stencil.applyMoving(m_current, elastic);  // c0 is in the load
  const double delta = subStepSize();
  ControlNet acceleration = load - elastic;
  if (m_shell) {
    m_mass->solve(acceleration);
    for (Eigen::Index f = 0; f < m_space.numMoving(); ++f) {
      const Eigen::Index r = m_space.movingToNet(f);
      if (!m_pinMask[size_t(r)]) m_previous.row(r) = m_current.row(r) + (0.5 * delta * delta) * acceleration.row(f);
    }
    holdPins(m_previous);  // held coordinates
    if (m_components) {  // the coordinates supports per component constrain follow the others
      ControlNet x = m_space.gatherMoving(m_previous);
      completeUnknowns(x, m_previous);
    } else {
      m_space.completeNet(m_previous, &m_rest);
    }
    m_stepper->invalidate();
    return;
  }
  if (m_edgeMass) m_edgeMass->solve(acceleration);
  for (Eigen::Index f = 0; f < m_space.numMoving(); ++f) {
    const Eigen::Index r = m_space.movingToNet(f);
    if (m_pinMask[size_t(r)]) continue;
    const double m = m_edgeMass ? 1.0 : m_uniformMass ? massPerPoint() : m_massMoving[f];
    m_previous.row(r) = m_current.row(r) + (0.5 * delta * delta / m) * acceleration.row(f);
  }
  m_space.completeNet(m_previous, &m_rest);
}

std::string Simulation::refusal() const {
  const bool partial = (m_params.pinComponents != 7u && !m_params.pins.empty()) || m_components;
  if (partial && m_params.integrator == Integrator::Explicit)
    return "supports per component (holdUMin ..., SIMPLY_SUPPORTED or BUILT_IN holding some of X, Y, Z), SYMMETRY "
           "sides and pins holding some components (holdPins) are taken by the static solve, arc length and the "
           "integrators BACKWARD_EULER and IMPLICIT, not yet by EXPLICIT";
  if (m_params.integrator != Integrator::BackwardEuler)
    for (const auto& f : m_forces)
      if (const char* why = f->backwardEulerOnly()) return why;
  static const char* motionFields[4] = {"motionUMin", "motionUMax", "motionVMin", "motionVMax"};
  for (int side = 0; side < 4; ++side) {
    if (!m_sideMoved[size_t(side)]) continue;
    if (m_params.integrator != Integrator::BackwardEuler || m_params.energy != EnergyModel::Shell)
      return std::string("a moved side (") + motionFields[side] +
             ") is taken by the SHELL energy's integrator BACKWARD_EULER only";
    if (m_components)
      return std::string("a moved side (") + motionFields[side] +
             ") is not taken beside supports per component or SYMMETRY sides";
    // the corners: rows both this side and a neighbour hold, or derive
    const Boundary kinds[4] = {m_space.boundaries().uMin, m_space.boundaries().uMax, m_space.boundaries().vMin,
                               m_space.boundaries().vMax};
    for (int other : side < 2 ? std::array<int, 2>{2, 3} : std::array<int, 2>{0, 1}) {
      const Boundary k = kinds[other];
      if (k == Boundary::Free || k == Boundary::Periodic) continue;
      if (m_sideMoved[size_t(other)] && m_sideMap[size_t(other)] == m_sideMap[size_t(side)]) continue;
      return std::string("the side moved by ") + motionFields[side] + " shares its corners with the " +
             boundaryName(k) + " side of " + motionFields[other] +
             ", which does not move with it: make that side FREE, or move it by the same map";
    }
  }
  std::ostringstream os;
  os.precision(6);
  const double dt = m_params.timeStep;
  if (!(m_subStepsNeeded <= double(m_params.maxSubSteps))) {
    os << "a step of timeStep " << dt << " needs " << m_subStepsNeeded << " sub-steps below the stability limit "
       << stabilityLimit() << " (at most maxSubSteps = " << m_params.maxSubSteps
       << "); lower timeStep or the stiffness, or raise maxSubSteps";
    return os.str();
  }
  const double advanced = (m_time + dt) - m_time;
  if (!(std::abs(advanced - dt) <= 1e-4 * dt)) {
    os << "at simulationTime " << num(m_time) << " a step of timeStep " << dt
       << " no longer advances the clock in double precision (it moves by " << num(advanced)
       << "); reset the simulation or start from a smaller simulationTime";
    return os.str();
  }
  return std::string();
}

double Simulation::dragStiffness() const {
  if (!m_shell) return m_stencilLambda;
  const double twoPiF = 2.0 * 3.14159265358979323846 * 5.0;
  return m_mass->diagonal().sum() * twoPiF * twoPiF;
}

Status Simulation::step() {
  if (m_status != Status::Ok) return m_status;
  if (std::string why = refusal(); !why.empty()) {
    fail(Status::Refused, "step refused: " + why);
    return m_status;
  }
  if (m_startPending) applyStartRule();
  const CostTimer timer(&m_costs.total);
  ++m_costs.steps;
  const double dt = subStepSize();
  m_stepper->clearFailure();
  for (int s = 0; s < m_subSteps; ++s) {
    const double t = m_time + s * dt;
    const bool ok = m_stepper->subStep(t);
    if (!ok && m_stepper->startRefused()) {
      // a force refused the state the step starts from (a surface inside an obstacle's offset,
      // or curved so much that its proxy may be a thickness off): bad input or a setting to
      // change, not a blow-up; the state is the one the step started from, its velocity with it
      m_stepper->invalidate();
      std::ostringstream os;
      os << "step refused at t = " << t << " (step " << m_steps + 1 << "): " << m_stepper->solveFailure() << ".";
      fail(Status::Refused, os.str());
      return m_status;
    }
    if (!ok) {
      // m_current holds the rejected state, m_previous the last good one.
      const bool finite = m_current.allFinite();
      m_current = m_previous;
      m_stepper->invalidate();
      std::ostringstream os;
      os << (finite ? "diverged" : "non-finite state") << " at t = " << t + dt << " (step " << m_steps + 1
         << ", sub-step " << s + 1 << " of " << m_subSteps << "); last valid state kept. ";
      if (!m_stepper->solveFailure().empty())
        os << "The implicit solve failed: " << m_stepper->solveFailure() << ".";
      else if (finite)
        os << "A coordinate exceeded " << m_divergenceLimit << ".";
      os << " Stability limit " << stabilityLimit() << ", sub-step " << dt << ".";
      fail(finite ? Status::Diverged : Status::NonFinite, os.str());
      return m_status;
    }
  }
  ++m_steps;
  m_time = stepEnd();
  roundState();
  // The shell's stiffness depends on the state: its bound is taken again after every step, at
  // the state the next step starts from (previous rescaled to the new sub-step). So a state
  // saved between steps, with its previous net, is at the sub-step its own bound gives, and a
  // run resumed from it takes the same sub-steps as the uninterrupted one.
  if (m_shell && m_params.integrator == Integrator::Explicit) {
    const double before = subStepSize();
    shellUpdateBound();
    if (subStepSize() != before) roundState();  // previous rescaled to the new sub-step
  }
  return m_status;
}

void Simulation::setStateRounding(double (*round)(double)) { m_stateRounding = round; }

double Simulation::stepEnd() const {
  const double end = m_time + m_params.timeStep;
  return m_stateRounding ? m_stateRounding(end) : end;
}

void Simulation::roundState() {
  if (!m_stateRounding) return;
  m_current = m_current.unaryExpr(m_stateRounding);
  m_previous = m_previous.unaryExpr(m_stateRounding);
  holdState(m_current, m_previous, HeldPoints::Reset);
  for (const auto& f : m_forces) f->roundAdaptedState(m_stateRounding);
  m_stepper->stateRounded();
}

Status Simulation::advance(long steps) {
  for (long i = 0; i < steps && m_status == Status::Ok; ++i) step();
  return m_status;
}

void Simulation::reset() {
  m_stepper->invalidate();
  if (m_shell && m_params.integrator == Integrator::Explicit) {
    m_current = m_rest;
    m_startPending = true;
    shellUpdateBound();
  }
  m_current = m_rest;
  m_previous = m_rest;
  m_time = 0.0;
  m_steps = 0;
  m_status = Status::Ok;
  m_statusMessage.clear();
  m_startPending = true;
  for (const auto& f : m_forces) f->setAdaptedState({});  // what they adapted belongs to the old run
}

// Held points back at the rest net's values exactly (after the check `held` asks for: a state
// read back from text differs from the computed rest in the last digits, so they are compared
// to 1e-12), derived layers recomputed from their sources, held coordinates and periodic copies
// restored. setState() and roundState() both end with it, so that a rounded state and the same
// state read back from a file hold the same bits.
void Simulation::holdState(ControlNet& cur, ControlNet& prev, HeldPoints held) const {
  // (the layers of a side setSideMotion() moves may be anywhere: they move to its map from there)
  std::vector<char> movedRow(size_t(m_space.netSize()), 0);
  for (int side = 0; side < 4; ++side)
    if (m_sideMoved[size_t(side)])
      for (Eigen::Index r : m_sideRows[size_t(side)]) movedRow[size_t(r)] = 1;
  for (int i = 0; i < m_space.netRows(); ++i)
    for (int j = 0; j < m_space.netCols(); ++j) {
      const int mi = m_space.movingLayerU(i), mj = m_space.movingLayerV(j);
      const bool sideHeld = m_space.foldU(i).empty() || m_space.foldV(j).empty();
      if (!sideHeld && (mi < 0 || mj < 0)) continue;  // derived: checked below
      const bool isHeld = sideHeld || m_pinMask[size_t(mi) * m_space.netCols() + mj];
      // ("clamped": held by its side, CLAMPED or SIMPLY_SUPPORTED/BUILT_IN of low degree)
      if (!isHeld) continue;
      const Eigen::Index r = Eigen::Index(i) * m_space.netCols() + j;
      if (movedRow[size_t(r)]) {
        // a moved side's layer: where the state has it, exactly where its map puts it when it is
        // there to 1e-12 (read back from text, or rounded: see roundState)
        const double tol = 1e-12 * (1.0 + m_heldTarget.row(r).cwiseAbs().maxCoeff());
        if ((cur.row(r) - m_heldTarget.row(r)).cwiseAbs().maxCoeff() <= tol) cur.row(r) = m_heldTarget.row(r);
        continue;
      }
      // a pin holds the components pinComponents names; its free ones are state
      const unsigned components = sideHeld ? 7u : m_params.pinComponents;
      const double tol = 1e-12 * (1.0 + m_rest.row(r).cwiseAbs().maxCoeff());
      for (int c = 0; c < 3; ++c) {
        if (!(components & (1u << c))) continue;
        if (held == HeldPoints::Check)
          require(std::abs(cur(r, c) - m_rest(r, c)) <= tol && std::abs(prev(r, c) - m_rest(r, c)) <= tol,
                  std::string(mi < 0 || mj < 0 ? "clamped" : "pinned") + " control point (" +
                      std::to_string(i - m_space.degreeU()) + ", " + std::to_string(j - m_space.degreeV()) +
                      ") of the state differs from the rest net" +
                      (components == 7u ? std::string() : std::string(" in ") + "xyz"[c]));
        cur(r, c) = m_rest(r, c);
        prev(r, c) = m_rest(r, c);
      }
    }
  // Derived layers (SIMPLY_SUPPORTED, BUILT_IN sides) must follow their sources, then are
  // recomputed exactly.
  if (m_space.hasDerived()) {
    if (held == HeldPoints::Check) {
      const double worst = std::max(m_space.derivedMismatch(cur, m_rest), m_space.derivedMismatch(prev, m_rest));
      require(worst <= 1e-12, "the control points next to a SIMPLY_SUPPORTED or BUILT_IN side do not hold the edge "
                              "at its rest position (relative mismatch " + num(worst) + ")");
    }
    m_space.completeNet(cur, &m_rest);
    m_space.completeNet(prev, &m_rest);
  }
  if (!m_params.heldCoordinates.empty()) {  // restored exactly (no derived layers: refused in init())
    holdPins(cur);
    holdPins(prev);
    m_space.refreshPeriodicCopies(cur);
    m_space.refreshPeriodicCopies(prev);
  }
}

void Simulation::setState(const ControlNet& current, const ControlNet& previous, double time, long steps,
                          double previousStepSize, HeldPoints held) {
  requireNet(m_space, current, "controlNet", "current net");
  requireNet(m_space, previous, "previousNet", "previous net");
  requireParameter(std::isfinite(time), "simulationTime", "must be finite, got " + num(time), "time");
  requireParameter(steps >= 0, "stepCount", "must be >= 0, got " + std::to_string(steps), "step count");
  require(std::isfinite(previousStepSize) && previousStepSize >= 0.0,
          "previous step size must be finite and >= 0, got " + num(previousStepSize));
  ControlNet cur = current, prev = previous;
  const double seam = std::max(m_space.closePeriodic(cur), m_space.closePeriodic(prev));
  holdState(cur, prev, held);
  m_seamMismatch = std::max(m_seamMismatch, seam);
  m_current = std::move(cur);
  m_previous = std::move(prev);
  if (m_shell && m_params.integrator == Integrator::Explicit) {
    // the sub-step of this state (the one the uninterrupted run's next step takes, see step())
    m_startPending = true;  // nothing to rescale yet: `previous` is read at this sub-step below
    shellUpdateBound();
  }
  const double h = subStepSize();
  if (previousStepSize > 0.0 && previousStepSize != h)
    m_previous = m_current - (m_current - m_previous) * (h / previousStepSize);
  m_time = time;
  m_steps = steps;
  m_status = Status::Ok;
  m_statusMessage.clear();
  m_startPending = false;
  m_stepper->invalidate();
}

void Simulation::setState(const ControlNet& current, double time, long steps, HeldPoints held) {
  setState(current, current, time, steps, 0.0, held);
  m_startPending = true;
}

double Simulation::deformationNorm() const {
  double sum = 0.0;
  for (Eigen::Index f = 0; f < m_space.numMoving(); ++f) {
    const Eigen::Index r = m_space.movingToNet(f);
    sum += (m_current.row(r) - m_rest.row(r)).squaredNorm();
  }
  return std::sqrt(sum);
}

double Simulation::kineticEnergy() const {
  const double dt = subStepSize();
  if (m_shell) {
    const ControlNet v = m_space.gatherMoving(m_current) - m_space.gatherMoving(m_previous);
    return m_mass->kineticEnergy(v) / (dt * dt);
  }
  if (m_uniformMass) {
    double sum = 0.0;
    for (Eigen::Index f = 0; f < m_space.numMoving(); ++f) {
      const Eigen::Index r = m_space.movingToNet(f);
      sum += (m_current.row(r) - m_previous.row(r)).squaredNorm();
    }
    return 0.5 * massPerPoint() * sum / (dt * dt);
  }
  double sum = derivedVelocitySum(m_current, m_previous);
  for (Eigen::Index f = 0; f < m_space.numMoving(); ++f) {
    const Eigen::Index r = m_space.movingToNet(f);
    sum += m_massMoving[f] * (m_current.row(r) - m_previous.row(r)).squaredNorm();
  }
  return 0.5 * sum / (dt * dt);
}

StrainEnergy Simulation::strainEnergy() const {
  if (m_shell) {
    StrainEnergy e;
    e.total = m_shell->energy(m_current).total();
    return e;
  }
  const ControlNet D = m_current - m_rest;  // held points: exactly zero
  const ControlNet Dm = m_space.gatherMoving(D);
  auto energy = [&](const Weights& w) {
    ControlNet AD;
    StiffnessStencil(m_space, w).applyMoving(D, AD);
    return 0.5 * Dm.cwiseProduct(AD).sum();
  };
  const Weights& w = m_params.weights;
  StrainEnergy e;
  e.w10 = energy({w.w10, 0, 0, 0, 0});
  e.w01 = energy({0, w.w01, 0, 0, 0});
  e.w11 = energy({0, 0, w.w11, 0, 0});
  e.w20 = energy({0, 0, 0, w.w20, 0});
  e.w02 = energy({0, 0, 0, 0, w.w02});
  e.total = e.w10 + e.w01 + e.w11 + e.w20 + e.w02;
  return e;
}

double Simulation::derivedVelocitySum(const ControlNet& current, const ControlNet& previous) const {
  // derived control points move and keep their own mass (EdgeMass): sum W |P - P_prev|^2
  double sum = 0.0;
  for (Eigen::Index r : m_derivedRows)
    sum += m_edgeMass->layerMass(int(r / m_space.netCols()), int(r % m_space.netCols())) *
           (current.row(r) - previous.row(r)).squaredNorm();
  return sum;
}

Diagnostics Simulation::diagnostics() const {
  if (m_shell) {
    Diagnostics d;
    d.norm = deformationNorm();
    d.kinetic = kineticEnergy();
    const ShellEnergies e = m_shell->energy(m_current);
    d.membrane = e.membrane;
    d.bending = e.bending;
    d.strain.total = e.total();
    return d;
  }
  DiagnosticSums sums =
      diagnosticSums(m_space, m_stencil, m_current, m_rest, m_previous, m_uniformMass ? nullptr : m_massMoving.data());
  sums.velocity += derivedVelocitySum(m_current, m_previous);
  return diagnosticsFromSums(sums, m_params.weights, m_uniformMass ? massPerPoint() : 1.0, subStepSize());
}

Simulation::PointMasses Simulation::pointMasses() const {
  PointMasses m;
  if (m_uniformMass)
    m.uniform = massPerPoint();
  else
    m.perPoint = m_massMoving.data();
  return m;
}

ControlNet Simulation::staticSolution() const {
  if (m_shell) return solveStatic(1e-10, 100).net;
  Eigen::SparseMatrix<double> A = activeMatrix();
  ControlNet rhs = loadVector() + restOffset() - boundaryTerm();
  for (Eigen::Index f = 0; f < m_space.numMoving(); ++f) {
    const Eigen::Index r = m_space.movingToNet(f);
    if (!m_pinMask[size_t(r)]) continue;
    A.coeffRef(f, f) = 1.0;  // a pinned point stays at rest
    rhs.row(f) = m_rest.row(r);
  }
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(A);
  if (solver.info() != Eigen::Success)
    throw std::runtime_error("static solve: A_II is singular (all weights zero, or nothing holds the surface?)");
  ControlNet x = solver.solve(rhs);
  // LDLT of a singular PSD matrix can "succeed" with a zero pivot; check the residual.
  const double res = (A * x - rhs).norm(), scale = rhs.norm() + 1e-300;
  if (!x.allFinite() || res > 1e-8 * scale + 1e-12)
    throw std::runtime_error("static solve: A_II is singular (all weights zero, or nothing holds the surface?), residual " +
                             num(res));
  ControlNet net = m_rest;
  m_space.scatterMoving(x, net);
  m_space.completeNet(net, &m_rest);
  return net;
}

std::vector<Eigen::Index> Simulation::pinnedMoving() const {
  std::vector<Eigen::Index> out;
  for (Eigen::Index f = 0; f < m_space.numMoving(); ++f)
    if (m_pinMask[size_t(m_space.movingToNet(f))]) out.push_back(f);
  return out;
}

ControlNet Simulation::loadAt(const ControlNet& net, double t) const {
  ControlNet load = ControlNet::Zero(m_space.numMoving(), 3);
  const LoadContext ctx = loadContext(net, net, subStepSize(), t);
  for (const auto& f : m_forces) f->addLoad(ctx, load);
  return load;
}

std::string Simulation::freeMotions() const {
  // Candidates: the displacements 1, u, v of every control point (Greville coordinates), which
  // the paper's energy leaves at zero cost when its membrane weights are zero (1 always). A
  // combination is free if it vanishes on every held point, follows the derived layers, and A
  // maps it to zero.
  const int rows = m_space.netRows(), cols = m_space.netCols();
  ControlNet cand[3];
  for (int c = 0; c < 3; ++c) {
    cand[c] = ControlNet::Zero(m_space.netSize(), 3);
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < cols; ++j) {
        const double x = c == 0 ? 1.0 : c == 1 ? m_space.grevilleU(i - m_space.degreeU()) : m_space.grevilleV(j - m_space.degreeV());
        cand[c].row(Eigen::Index(i) * cols + j).setConstant(x);
      }
  }
  // constraint rows: values on held points, mismatch of the derived layers, and A z
  std::vector<Eigen::VectorXd> cols3(3);
  for (int c = 0; c < 3; ++c) {
    std::vector<double> r;
    ControlNet completed = cand[c];
    m_space.completeNet(completed, nullptr);
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < cols; ++j) {
        const Eigen::Index n = Eigen::Index(i) * cols + j;
        const bool held = m_space.foldU(i).empty() || m_space.foldV(j).empty() || m_pinMask[size_t(n)];
        if (held) r.push_back(cand[c](n, 0));
        else r.push_back(completed(n, 0) - cand[c](n, 0));  // zero unless derived
      }
    ControlNet Az;
    m_stencil.applyMoving(completed, Az);
    for (Eigen::Index f = 0; f < Az.rows(); ++f) r.push_back(Az(f, 0));
    cols3[size_t(c)] = Eigen::Map<Eigen::VectorXd>(r.data(), Eigen::Index(r.size()));
  }
  Eigen::MatrixXd C(cols3[0].size(), 3);
  Eigen::Vector3d columnScale;
  for (int c = 0; c < 3; ++c) {
    columnScale[c] = 1.0 / std::max(1.0, cand[c].cwiseAbs().maxCoeff());
    C.col(c) = cols3[size_t(c)] * columnScale[c];
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(C, Eigen::ComputeFullV);
  const Eigen::VectorXd sv = svd.singularValues();
  const double scale = std::max(1.0, m_stencil.gershgorinBound());
  std::vector<int> nullCols;
  for (int k = 0; k < 3; ++k)
    if (sv[k] <= 1e-9 * scale) nullCols.push_back(k);
  std::vector<std::string> motions;
  // is the constant (a translation) among them? its projection on the null space is itself
  double constantPart = 0.0;
  for (int k : nullCols) constantPart += std::pow(svd.matrixV()(0, k), 2);
  const bool translations = constantPart > 1.0 - 1e-9;
  if (translations) motions.push_back("translations (every point moving alike)");
  if (translations && nullCols.size() > 1) {
    motions.push_back("rotations (displacements linear in u and v)");
  } else if (!translations) {
    for (int k : nullCols) {
      // the coefficients of 1, u, v: the null vector of the scaled columns, scaled back
      Eigen::Vector3d a = svd.matrixV().col(k).cwiseProduct(columnScale);
      a /= a.cwiseAbs().maxCoeff();
      for (int c = 0; c < 3; ++c)
        if (std::abs(a[c]) < 1e-9) a[c] = 0.0;
      if (a[1] < 0.0 || (a[1] == 0.0 && a[2] < 0.0)) a = -a;  // the u (else v) coefficient positive
      motions.push_back("rotations about the line " + num(a[0]) + " + " + num(a[1]) + " u + " + num(a[2]) +
                        " v = 0 (displacements growing linearly from it)");
    }
  }
  std::string out;
  for (const std::string& m : motions) out += (out.empty() ? "" : "; ") + m;
  return out;
}

StaticResult Simulation::solveStatic(double tolerance, int maxLoadIterations, LinearSolver solver,
                                     int loadSteps) const {
  if (loadSteps < 1) throw std::invalid_argument("load steps must be >= 1, got " + std::to_string(loadSteps));
  for (const auto& f : m_forces)
    if (const char* why = f->backwardEulerOnly()) throw std::runtime_error(std::string("static solve: ") + why);
  if (std::find(m_sideMoved.begin(), m_sideMoved.end(), true) != m_sideMoved.end())
    throw std::runtime_error("static solve: a moved side (motionUMin ...) belongs to a BACKWARD_EULER run; the static "
                             "solve holds every side at rest");
  if (m_shell) return solveStaticShell(tolerance, maxLoadIterations, loadSteps);
  StaticResult result;
  for (int step = 1; step <= loadSteps; ++step) {
    const double factor = double(step) / loadSteps;
    StaticResult r = solveStaticPaper(tolerance, maxLoadIterations, solver, factor);
    StaticResult::Increment inc;
    inc.loadFactor = factor;
    inc.net = r.net;
    inc.residual = r.residual;
    inc.iterations = r.loadIterations;
    result.net = std::move(r.net);
    result.residual = r.residual;
    result.loadIterations = r.loadIterations;
    result.method = r.method;
    result.increments.push_back(std::move(inc));
  }
  return result;
}

StaticResult Simulation::solveStaticPaper(double tolerance, int maxLoadIterations, LinearSolver solver,
                                          double loadFactor) const {
  bool dependsOnPosition = false;
  for (const auto& f : m_forces) dependsOnPosition |= (f->dependence() & (kDependsOnPosition | kDependsOnNormal)) != 0;
  const std::string free = freeMotions();
  if (!free.empty())
    throw std::runtime_error("static solve: nothing holds the surface against " + free +
                             ": its equilibrium is not unique. Hold a side (CLAMPED, BUILT_IN, SIMPLY_SUPPORTED) or pin "
                             "points (pins), or run the dynamics with damping" +
                             (dependsOnPosition ? std::string(" (contact, springs and pressure do not count as holds here: "
                                                              "the elastic model itself must be held)")
                                                : std::string()));
  // K = D + A_act/4 with D a negligible positive diagonal (the implicit system's form): CHOLMOD
  // or multigrid-preconditioned CG on A itself; defect correction with the exact stencil
  // removes the effect of D.
  const double delta = 1e-14 * std::max(m_stencil.movingDiagonal().maxCoeff(), 1e-300);
  const std::vector<Eigen::Index> pinned = pinnedMoving();
  if (solver == LinearSolver::Automatic)
    solver = m_space.numMoving() <= kAutomaticDirectPoints ? LinearSolver::Direct : LinearSolver::Multigrid;
  ImplicitSystem K(m_space, m_stencil, Eigen::VectorXd::Constant(m_space.numMoving(), delta), pinned, solver,
                   std::min(1e-6, tolerance), 20000);
  StaticResult result;
  result.method = K.method() == LinearSolver::Direct ? "CHOLMOD Cholesky"
                  : K.method() == LinearSolver::Multigrid ? "multigrid-preconditioned CG"
                                                          : "Jacobi-preconditioned CG";
  const ControlNet c0 = restOffset();
  ControlNet net = m_rest;
  ControlNet x = m_space.gatherMoving(net);
  ControlNet load = loadFactor * loadAt(net, 0.0);
  ControlNet ax, r, d;
  const ControlNet xRest = m_space.gatherMoving(m_rest);
  const double normA = m_stencil.eigenvalueBound();
  auto residualOf = [&](const ControlNet& L) {
    // r = L + c0 - A P on the unpinned unknowns, relative to what it is made of (the normwise
    // backward error: a smooth bending solution at 1024^2 cannot do better than eps kappa
    // relative to ||L|| alone)
    m_stencil.applyMoving(net, ax);
    r = L + c0 - ax;
    for (Eigen::Index f : pinned) r.row(f).setZero();
    return r.norm() / std::max(normA * (x - xRest).norm() + L.norm() + c0.norm(), 1e-300);
  };
  double res = 0.0;
  int outer = 0;
  for (;;) {
    ++outer;
    // linear solve for this load, by defect correction
    // (defect correction goes on while ||r|| relative to the load falls by half or more: the
    // backward error alone stops too early for ill-conditioned bending)
    res = residualOf(load);
    double loadRelative = r.norm() / std::max(load.norm() + c0.norm(), 1e-300);
    for (int k = 0; k < 12 && loadRelative > 0.01 * tolerance; ++k) {
      d = ControlNet::Zero(r.rows(), 3);
      r *= 0.25;  // K d = r / 4  <=>  (4 D + A) d = r
      K.solve(r, d);
      if (!d.allFinite()) throw std::runtime_error("static solve: the linear solve failed (non-finite values)");
      x += d;
      m_space.scatterMoving(x, net);
      m_space.completeNet(net, &m_rest);
      res = residualOf(load);
      const double next = r.norm() / std::max(load.norm() + c0.norm(), 1e-300);
      if (!(next < 0.5 * loadRelative)) break;
      loadRelative = next;
    }
    if (!dependsOnPosition) break;
    const ControlNet newLoad = loadFactor * loadAt(net, 0.0);
    res = residualOf(newLoad);
    load = newLoad;
    if (res <= tolerance) break;
    if (outer >= maxLoadIterations)
      throw std::runtime_error("static solve: the loads that depend on the position (pressure, contact, springs) did not "
                               "settle after " + std::to_string(outer) + " fixed-point iterations (relative residual " +
                               num(res) + ", tolerance " + num(tolerance) +
                               "); run the dynamics with damping to find this equilibrium");
  }
  if (!(res <= tolerance))
    throw std::runtime_error("static solve: the equilibrium was not reached (relative residual " + num(res) +
                             "); the system is singular or too ill-conditioned");
  result.net = net;
  result.residual = res;
  result.loadIterations = outer;
  return result;
}

}  // namespace bsdeform
