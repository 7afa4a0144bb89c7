// SPDX-License-Identifier: MIT
#include "bsdeform/Simulation.h"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace bsdeform {

struct Simulation::ImplicitSolver {
  Eigen::SparseMatrix<double> Aii;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> K;
};

namespace {

std::string num(double x) {
  std::ostringstream os;
  os.precision(17);
  os << x;
  return os.str();
}

void require(bool ok, const std::string& message) {
  if (!ok) throw std::invalid_argument(message);
}

const ModelParameters& validated(const ModelParameters& p) {
  // Degrees and counts are checked (with their names) by SplineSpace; the rest here.
  require(std::isfinite(p.timeStep) && p.timeStep > 0.0, "timeStep must be finite and > 0, got " + num(p.timeStep));
  require(std::isfinite(p.mass) && p.mass > 0.0, "mass must be finite and > 0, got " + num(p.mass));
  require(std::isfinite(p.damping) && p.damping >= 0.0, "damping must be finite and >= 0, got " + num(p.damping));
  require(std::isfinite(p.stabilitySafety) && p.stabilitySafety > 0.0 && p.stabilitySafety <= 1.0,
          "stabilitySafety must be in (0, 1], got " + num(p.stabilitySafety));
  require(std::isfinite(p.divergenceLimit) && p.divergenceLimit > 0.0,
          "divergenceLimit must be finite and > 0, got " + num(p.divergenceLimit));
  const long long points = static_cast<long long>(p.numU) * p.numV;
  require(points <= (1LL << 28), "numU * numV must be at most 2^28, got " + std::to_string(points));
  return p;
}

void requireNet(const SplineSpace& s, const ControlNet& net, const char* name) {
  require(net.rows() == s.netSize(),
          std::string(name) + " must have (numU + 2 degreeU) * (numV + 2 degreeV) = " + std::to_string(s.netSize()) +
              " points, got " + std::to_string(net.rows()));
  for (Eigen::Index i = 0; i < net.rows(); ++i)
    require(net.row(i).allFinite(), std::string(name) + " point " + std::to_string(i) + " is not finite (" +
                                        num(net(i, 0)) + ", " + num(net(i, 1)) + ", " + num(net(i, 2)) + ")");
}

}  // namespace

Simulation::Simulation(const ModelParameters& params)
    : m_params(validated(params)),
      m_space(params.degreeU, params.degreeV, params.numU, params.numV),
      m_stencil(m_space, params.weights) {
  m_rest = m_space.grevillePlane();
  init();
}

Simulation::Simulation(const ModelParameters& params, const ControlNet& rest)
    : m_params(validated(params)),
      m_space(params.degreeU, params.degreeV, params.numU, params.numV),
      m_stencil(m_space, params.weights) {
  requireNet(m_space, rest, "rest net");
  m_rest = rest;
  init();
}

Simulation::~Simulation() = default;

double Simulation::massPerPoint() const {
  return m_params.massModel == MassModel::Nodal
             ? m_params.mass
             : m_params.mass * m_space.basisU().spacing() * m_space.basisV().spacing();
}

double Simulation::dampingPerPoint() const {
  return m_params.massModel == MassModel::Nodal
             ? m_params.damping
             : m_params.damping * m_space.basisU().spacing() * m_space.basisV().spacing();
}

void Simulation::init() {
  m_current = m_rest;
  m_previous = m_rest;
  m_divergenceLimit = m_params.divergenceLimit * (1.0 + m_rest.cwiseAbs().maxCoeff());

  ControlNet fixedOnly = m_rest;
  for (Eigen::Index f = 0; f < m_space.numFree(); ++f) fixedOnly.row(m_space.freeToNet(f)).setZero();
  m_stencil.applyFree(fixedOnly, m_boundaryTerm);
  if (m_params.reference == ElasticReference::Rest)
    m_stencil.applyFree(m_rest, m_restOffset);
  else
    m_restOffset = ControlNet::Zero(m_space.numFree(), 3);

  m_stencilLambda = m_stencil.eigenvalueBound();
  if (m_params.integrator == Integrator::Implicit) {
    m_implicit = std::make_unique<ImplicitSolver>();
    m_implicit->Aii = m_stencil.interiorMatrix();
    const double dt = m_params.timeStep, m = massPerPoint(), c = dampingPerPoint();
    Eigen::SparseMatrix<double> K = 0.25 * m_implicit->Aii;
    Eigen::SparseMatrix<double> D(K.rows(), K.cols());
    D.setIdentity();
    K += (m / (dt * dt) + c / (2.0 * dt)) * D;
    m_implicit->K.compute(K);
    if (m_implicit->K.info() != Eigen::Success)
      throw std::runtime_error("implicit integrator: factorisation of the system matrix failed");
  }
  rebuildConstantLoad();
  updateSubSteps();
}

void Simulation::rebuildConstantLoad() {
  m_constantLoad = m_restOffset;
  m_hasVariableForces = false;
  const LoadContext ctx{m_space, m_current, m_previous, subStepSize(), m_time};
  for (const auto& f : m_forces) {
    if (f->dependence() == kConstant)
      f->addLoad(ctx, m_constantLoad);
    else
      m_hasVariableForces = true;
  }
}

void Simulation::updateSubSteps() {
  double forceStiffness = 0.0;
  for (const auto& f : m_forces) forceStiffness += f->stiffnessBound(m_space);
  m_lambdaMax = (m_stencilLambda + forceStiffness) / massPerPoint();
  const double oldStep = subStepSize();
  int n = 1;
  if (m_params.integrator == Integrator::Explicit && m_params.autoSubstep && m_lambdaMax > 0.0) {
    const double safe = m_params.stabilitySafety * stabilityLimit();
    n = static_cast<int>(std::max(1.0, std::ceil(m_params.timeStep / safe)));
  }
  m_subSteps = n;
  const double newStep = subStepSize();
  if (newStep != oldStep) m_previous = m_current - (m_current - m_previous) * (newStep / oldStep);
}

double Simulation::stabilityLimit() const {
  return m_lambdaMax > 0.0 ? 2.0 / std::sqrt(m_lambdaMax) : std::numeric_limits<double>::infinity();
}

void Simulation::addForce(std::shared_ptr<const Force> force) {
  if (!force) throw std::invalid_argument("addForce: null force");
  m_forces.push_back(std::move(force));
  rebuildConstantLoad();
  updateSubSteps();
}

bool Simulation::removeForce(const Force* force) {
  auto it = std::find_if(m_forces.begin(), m_forces.end(), [force](const auto& p) { return p.get() == force; });
  if (it == m_forces.end()) return false;
  m_forces.erase(it);
  rebuildConstantLoad();
  updateSubSteps();
  return true;
}

void Simulation::clearForces() {
  m_forces.clear();
  rebuildConstantLoad();
  updateSubSteps();
}

const ControlNet& Simulation::effectiveLoad(double t) {
  if (!m_hasVariableForces) return m_constantLoad;
  m_load = m_constantLoad;
  const LoadContext ctx{m_space, m_current, m_previous, subStepSize(), t};
  for (const auto& f : m_forces)
    if (f->dependence() != kConstant) f->addLoad(ctx, m_load);
  return m_load;
}

ControlNet Simulation::loadVector() const {
  ControlNet load = ControlNet::Zero(m_space.numFree(), 3);
  const LoadContext ctx{m_space, m_current, m_previous, subStepSize(), m_time};
  for (const auto& f : m_forces) f->addLoad(ctx, load);
  return load;
}

void Simulation::fail(Status s, std::string message) {
  m_status = s;
  m_statusMessage = std::move(message);
}

bool Simulation::explicitSubStep(double t) {
  const ControlNet& load = effectiveLoad(t);
  const double dt = subStepSize(), m = massPerPoint(), c = dampingPerPoint();
  const double g = 2.0 * m + dt * c;
  const double alpha = 2.0 * dt * dt / g, gamma = (2.0 * m - dt * c) / g;
  // The new state overwrites the previous one (same buffer); fixed points are equal in both.
  const bool ok = m_stencil.centralDifferenceUpdate(m_current, m_previous, load, alpha, gamma, m_divergenceLimit);
  m_current.swap(m_previous);
  return ok;
}

bool Simulation::implicitSubStep(double t) {
  const ControlNet& load = effectiveLoad(t);
  const double dt = m_params.timeStep, m = massPerPoint(), c = dampingPerPoint();
  const ControlNet P = m_space.gatherFree(m_current);
  const ControlNet Pm = m_space.gatherFree(m_previous);
  // (M/dt^2 + C/(2dt) + A/4) P+ = R + 2M/dt^2 P - (M/dt^2 - C/(2dt)) P- - A (2P + P-)/4
  const ControlNet W = 0.25 * (2.0 * P + Pm);
  ControlNet rhs = load - m_boundaryTerm + (2.0 * m / (dt * dt)) * P - (m / (dt * dt) - c / (2.0 * dt)) * Pm;
  rhs -= m_implicit->Aii * W;
  const ControlNet next = m_implicit->K.solve(rhs);
  bool ok = true;
  for (Eigen::Index i = 0; i < next.size(); ++i) ok &= std::abs(next.data()[i]) <= m_divergenceLimit;
  m_space.scatterFree(next, m_previous);
  m_current.swap(m_previous);
  return ok;
}

Status Simulation::step() {
  if (m_status != Status::Ok) return m_status;
  const double dt = subStepSize();
  for (int s = 0; s < m_subSteps; ++s) {
    const double t = m_time + s * dt;
    const bool ok = (m_params.integrator == Integrator::Explicit) ? explicitSubStep(t) : implicitSubStep(t);
    if (!ok) {
      // m_current holds the rejected state, m_previous the last good one.
      const bool finite = m_current.allFinite();
      m_current = m_previous;
      std::ostringstream os;
      os << (finite ? "diverged" : "non-finite state") << " at t = " << t + dt << " (step " << m_steps + 1
         << ", sub-step " << s + 1 << " of " << m_subSteps << "); last valid state kept. ";
      if (finite)
        os << "A coordinate exceeded " << m_divergenceLimit << ".";
      os << " Stability limit " << stabilityLimit() << ", sub-step " << dt << ".";
      fail(finite ? Status::Diverged : Status::NonFinite, os.str());
      return m_status;
    }
  }
  ++m_steps;
  m_time += m_params.timeStep;
  return m_status;
}

Status Simulation::advance(long steps) {
  for (long i = 0; i < steps && m_status == Status::Ok; ++i) step();
  return m_status;
}

void Simulation::reset() {
  m_current = m_rest;
  m_previous = m_rest;
  m_time = 0.0;
  m_steps = 0;
  m_status = Status::Ok;
  m_statusMessage.clear();
}

void Simulation::setState(const ControlNet& current, const ControlNet& previous, double time, long steps,
                          double previousStepSize) {
  requireNet(m_space, current, "current net");
  requireNet(m_space, previous, "previous net");
  require(std::isfinite(time), "time must be finite, got " + num(time));
  require(steps >= 0, "step count must be >= 0, got " + std::to_string(steps));
  require(std::isfinite(previousStepSize) && previousStepSize >= 0.0,
          "previous step size must be finite and >= 0, got " + num(previousStepSize));
  // Fixed points must be the rest net's. A state read back from text differs from the computed
  // rest in the last digits, so they are compared to 1e-12 and then restored exactly.
  for (int i = 0; i < m_space.netRows(); ++i)
    for (int j = 0; j < m_space.netCols(); ++j) {
      if (m_space.isFree(i, j)) continue;
      const Eigen::Index r = Eigen::Index(i) * m_space.netCols() + j;
      const double tol = 1e-12 * (1.0 + m_rest.row(r).cwiseAbs().maxCoeff());
      require((current.row(r) - m_rest.row(r)).cwiseAbs().maxCoeff() <= tol &&
                  (previous.row(r) - m_rest.row(r)).cwiseAbs().maxCoeff() <= tol,
              "fixed control point (" + std::to_string(i - m_space.degreeU()) + ", " +
                  std::to_string(j - m_space.degreeV()) + ") of the state differs from the rest net");
    }
  m_current = m_rest;
  m_previous = m_rest;
  for (Eigen::Index f = 0; f < m_space.numFree(); ++f) {
    const Eigen::Index r = m_space.freeToNet(f);
    m_current.row(r) = current.row(r);
    m_previous.row(r) = previous.row(r);
  }
  const double h = subStepSize();
  if (previousStepSize > 0.0 && previousStepSize != h)
    m_previous = m_current - (m_current - m_previous) * (h / previousStepSize);
  m_time = time;
  m_steps = steps;
  m_status = Status::Ok;
  m_statusMessage.clear();
}

double Simulation::deformationNorm() const {
  double sum = 0.0;
  for (Eigen::Index f = 0; f < m_space.numFree(); ++f) {
    const Eigen::Index r = m_space.freeToNet(f);
    sum += (m_current.row(r) - m_rest.row(r)).squaredNorm();
  }
  return std::sqrt(sum);
}

double Simulation::kineticEnergy() const {
  double sum = 0.0;
  for (Eigen::Index f = 0; f < m_space.numFree(); ++f) {
    const Eigen::Index r = m_space.freeToNet(f);
    sum += (m_current.row(r) - m_previous.row(r)).squaredNorm();
  }
  const double dt = subStepSize();
  return 0.5 * massPerPoint() * sum / (dt * dt);
}

StrainEnergy Simulation::strainEnergy() const {
  const ControlNet D = m_current - m_rest;  // fixed points: exactly zero
  const ControlNet Df = m_space.gatherFree(D);
  auto energy = [&](const Weights& w) {
    ControlNet AD;
    StiffnessStencil(m_space, w).applyFree(D, AD);
    return 0.5 * Df.cwiseProduct(AD).sum();
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

ControlNet Simulation::staticSolution() const {
  const Eigen::SparseMatrix<double> A = m_implicit ? m_implicit->Aii : m_stencil.interiorMatrix();
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(A);
  if (solver.info() != Eigen::Success) throw std::runtime_error("static solve: A_II is singular (all weights zero?)");
  ControlNet rhs = loadVector() + m_restOffset - m_boundaryTerm;
  ControlNet x = solver.solve(rhs);
  // LDLT of a singular PSD matrix can "succeed" with a zero pivot; check the residual.
  const double res = (A * x - rhs).norm(), scale = rhs.norm() + 1e-300;
  if (!x.allFinite() || res > 1e-8 * scale + 1e-12)
    throw std::runtime_error("static solve: A_II is singular (all weights zero?), residual " + num(res));
  ControlNet net = m_rest;
  m_space.scatterFree(x, net);
  return net;
}

}  // namespace bsdeform
