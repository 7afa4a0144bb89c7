// SPDX-License-Identifier: MIT
// The SHELL model's part of Simulation (docs/math.md §16): the unknowns' mass and force through
// T (moving points, periodic copies, derived layers), the Newton tangent, the explicit step's
// bound at the state, and the nonlinear static problem by Newton with load increments. Its
// time steppers are in TimeStepper.cpp.
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "bsdeform/base/HugePages.h"
#include "bsdeform/base/NumberText.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/dynamics/MassMatrix.h"
#include "bsdeform/dynamics/NewtonMinimizer.h"
#include "bsdeform/dynamics/TimeStepper.h"

namespace bsdeform {

LoadContext Simulation::loadContext(const ControlNet& current, const ControlNet& previous, double stepSize,
                                    double t) const {
  LoadContext ctx{m_space, current, previous, stepSize, t};
  if (m_shell) ctx.rest = &m_rest;
  ctx.restShape = &m_rest;
  ctx.massPerArea = massPerArea();
  ctx.restArea = usableRestArea();
  return ctx;
}

void Simulation::initShell() {
  auto model = std::make_unique<ShellModelEnergy>(m_space, m_rest, m_params.material);
  m_shellModel = model.get();
  m_shell = &model->shell();
  m_energy = std::move(model);
  m_paper = nullptr;
  std::vector<char> pinned(size_t(m_space.numMoving()), 0);
  for (Eigen::Index f = 0; f < m_space.numMoving(); ++f) pinned[size_t(f)] = m_pinMask[size_t(m_space.movingToNet(f))];
  try {
    m_mass = MassMatrix::folded(m_space, m_shellModel->netMass(), std::move(pinned));
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string("SHELL: ") + e.what());
  }
  const int cols = m_space.netCols();
  m_uniformMass = false;
  m_massMoving = m_mass->diagonal();
  if (m_params.integrator == Integrator::BackwardEuler)
    m_stepper = std::make_unique<BackwardEulerStepper>(stepperView());
  else if (m_params.integrator == Integrator::Implicit)
    m_stepper = std::make_unique<ShellImplicitStepper>(stepperView());
  else
    m_stepper = std::make_unique<ShellExplicitStepper>(stepperView());
  m_edgeMass.reset();
  m_derivedRows.clear();
  for (int i = 0; i < m_space.netRows(); ++i)
    for (int j = 0; j < cols; ++j)
      if (m_space.isDerived(i, j)) m_derivedRows.push_back(Eigen::Index(i) * cols + j);
  m_stencilLambda = 0.0;
  m_elasticLambda = m_energy->eigenvalueBound(m_current);
}

ControlNet Simulation::elasticForce() const {
  ControlNet f;
  m_energy->gradient(m_current, f);
  return -f;
}

ShellEnergies Simulation::shellEnergies() const { return m_shell ? m_shell->energy(m_current) : ShellEnergies(); }

namespace {
/// Forces' Jacobian blocks into the tangent, symmetrised: ½ B at (p, q) and ½ Bᵀ at (q, p).
class TangentSink final : public JacobianSink {
 public:
  TangentSink(TangentMatrix& K, double scale) : m_K(K), m_scale(scale) {}
  void add(Eigen::Index p, Eigen::Index q, const Eigen::Matrix3d& B) override {
    m_K.addNetBlock(p, q, (0.5 * m_scale) * B);
    m_K.addNetBlock(q, p, (0.5 * m_scale) * B.transpose());
  }
  // every block of a symmetric Jacobian comes: the lower triangle keeps its half of them as they are
  void addSymmetric(Eigen::Index p, Eigen::Index q, const Eigen::Matrix3d& B) override {
    m_K.addNetBlock(p, q, m_scale * B);
  }

 private:
  TangentMatrix& m_K;
  double m_scale;
};
}  // namespace

const Eigen::SparseMatrix<double>& Simulation::tangent(const ControlNet& net, double scale, double shift,
                                                       HessianMode mode, const LoadContext* forces,
                                                       double velocityScale, double forceScale) const {
  if (!m_tangent) {
    std::vector<int> foldStart;
    std::vector<std::pair<Eigen::Index, double>> fold;
    m_space.foldMap(foldStart, fold);
    m_tangent = std::make_unique<TangentMatrix>(m_space, std::move(foldStart), std::move(fold));
  }
  TangentMatrix& K = *m_tangent;
  std::optional<CostTimer> timer(&m_costs.elastic);
  K.setZero();
  bool energyProjected = false;  // whether the projection changed any of the energy's Hessians
  if (m_shell) {
    // periodic in u: the first and last u-blocks fold onto the same unknowns (one thread)
    energyProjected =
        m_shell->elementHessians(net, mode, m_space.periodicU(),
                                 [&K, scale](int e1, int e2, const double* Ke) { K.addElement(e1, e2, Ke, scale); });
  } else {
    // the paper's energy is quadratic: its Hessian is A_II at every state (positive
    // semi-definite, nothing to project)
    if (m_paperStiffness.rows() == 0) m_paperStiffness = m_stencil.movingMatrix();
    K.addScalarMatrix(m_paperStiffness, scale);
  }
  if (shift != 0.0) K.addScalarMatrix(m_mass->matrix(), shift);
  timer.emplace(&m_costs.loads);
  if (forces) {
    TangentSink sink(K, forceScale);
    // Projected where the energy's projection changed nothing (the paper's energy, or no Gauss
    // point clamped): the matrix would be the exact one, so the loads are projected instead
    sink.wantsDefinite =
        mode == HessianMode::Definite || (mode == HessianMode::Projected && !energyProjected);
    for (const auto& f : m_forces)
      if (f->hasJacobian()) f->addJacobian(*forces, velocityScale, sink);
  }
  K.settlePattern();  // self-contact's couplings of points in no common element
  K.applyHeld(m_tangentHeldMask);
  return K.matrix();
}

const Eigen::SparseMatrix<double>& Simulation::shiftTangent(double extra) const {
  assert(m_tangent);
  TangentMatrix& K = *m_tangent;
  const CostTimer timer(&m_costs.elastic);
  K.addScalarMatrix(m_mass->matrix(), extra);
  K.applyHeld(m_tangentHeldMask);
  return K.matrix();
}

void Simulation::shellUpdateBound() {
  m_elasticLambda = m_energy->eigenvalueBound(m_current);
  updateSubSteps();
}

// The minimum of the total potential (or the zero of the residual, for follower loads), load
// increment by load increment, by the Newton solver backward Euler uses (NewtonMinimizer): a
// thin plate's first, purely bending step cannot take the iteration into the membrane's stiff
// valley, since the line search watches the potential. A surface nothing holds keeps a
// multiple of the mass near its free motions and still converges where the loads balance.
StaticResult Simulation::solveStaticShell(double tolerance, int maxIterations, int loadSteps) const {
  bool conservative = true, followers = true;
  for (const auto& f : m_forces) {
    conservative &= (f->dependence() & ~unsigned(kDependsOnTime)) == 0;
    followers &= f->dependence() == kDependsOnNormal;  // pressure: indifferent to rigid motions
  }
  ControlNet net = m_rest;
  ControlNet x = m_space.gatherMoving(net);
  const ControlNet L0 = conservative ? loadAt(net, 0.0) : ControlNet();
  // Nothing holds the surface (free and periodic sides, no pin, no held coordinate): loads
  // with a resultant have no equilibrium (said at once, not after a minute of cut increments),
  // and an equilibrium found is one of a family of rigid motions, brought back to the rest
  // position below.
  const bool heldByNothing = holdsNothing();
  if (heldByNothing) {
    const ControlNet Lrest = loadAt(net, 0.0);
    const Eigen::RowVector3d resultant = Lrest.colwise().sum();
    const double size = Lrest.cwiseAbs().sum();
    if (resultant.norm() > 1e-8 * size) {
      std::ostringstream os;
      os << "static solve: nothing holds the surface (every side FREE or PERIODIC, no pin) and the loads' "
            "resultant at rest, ("
         << numberText(resultant.x()) << ", " << numberText(resultant.y()) << ", " << numberText(resultant.z())
         << "), is not zero: there is no equilibrium; hold the surface (a side, a pin) or run the dynamics";
      throw std::runtime_error(os.str());
    }
  } else if (conservative && sidesHoldNothing()) {
    // held only in some components (supports per component, SYMMETRY, pins holding some, held
    // coordinates): a translation the constraints leave free has no equilibrium if the constant
    // loads do work on it, and a family of them (any slide along it) if not: refused either
    // way (a spring or contact may still hold it: not checked then). Translations only: a
    // rotation that is free to first order may still be held by the geometric nonlinearity (a
    // flat sheet whose y is held everywhere cannot turn about x without stretching); it is
    // named below if Newton then fails
    const std::string free = freeTranslationRefusal(loadAt(net, 0.0));
    if (!free.empty()) throw std::runtime_error("static solve: " + free);
  }
  // the total potential W(x) - L·x at load factor `loadFactor` (its gradient the residual
  // R = dW/dx - L, held coordinates zeroed) when every load is constant; ||R|| otherwise
  // (follower loads have no potential); judged relative to ||L|| + ||dW/dx||
  ControlNet gW, L;
  double loadFactor = 0.0;
  auto evaluate = [&](const ControlNet& xi, NewtonPoint& p) {
    ControlNet xc = xi;
    completeUnknowns(xc, net);
    shellGradient(net, gW);
    L = conservative ? (loadFactor * L0).eval() : (loadFactor * loadAt(net, 0.0)).eval();
    if (m_components) {
      m_components->fold(gW);
      m_components->fold(L);
    }
    p.g = gW - L;
    for (Eigen::Index f = 0; f < p.g.rows(); ++f)
      for (int c = 0; c < 3; ++c)
        if (heldCoordinate(f, c)) p.g(f, c) = 0.0;
    p.norm = p.g.norm();
    p.scale = L.norm() + gW.norm() + 1e-300;
    p.potential = conservative;
    if (conservative) {
      const double elastic = m_shell->energy(net).total();
      p.value = elastic - (L.array() * xi.array()).sum();
      p.valueScale = std::abs(elastic) + (L.array() * xi.array()).abs().sum();
    } else {
      p.value = p.valueScale = 0.0;
    }
  };
  // Newton's method (NewtonMinimizer, the one backward Euler uses): the exact tangent, the
  // loads' Jacobians inside; where it is not positive definite the element Hessians projected,
  // then a multiple of the mass from a small multiple of the stiffness (a surface nothing
  // holds is singular along its rigid motions), lowered again as Levenberg–Marquardt does.
  // Converged when a full step is below newtonTolerance times the surface's size (a length,
  // no rounding floor: thin shells under small loads sit on the relative residual's), or the
  // relative residual below the tolerance.
  const double extent = (m_rest.colwise().maxCoeff() - m_rest.colwise().minCoeff()).norm();
  const double massMean = m_mass->diagonal().mean();
  double diag = 0.0;
  {
    const Eigen::SparseMatrix<double>& K = tangent(net, 1.0, 0.0, HessianMode::Exact);
    for (int c = 0; c < K.outerSize(); ++c)
      for (Eigen::SparseMatrix<double>::InnerIterator it(K, c); it; ++it)
        if (it.row() == it.col()) diag = std::max(diag, std::abs(it.value()));
  }
  // The loads' Jacobians go into the tangent where every load that depends on the state has a
  // potential (springs, contact: the tangent is then the total potential's Hessian). A follower
  // pressure's symmetrised Jacobian is indefinite on a free body and, shifted, slows Newton to a
  // linear rate: without it the tangent is the elastic one, as before.
  bool jacobians = !conservative;
  {
    const LoadContext ctx = loadContext(net, net, m_params.timeStep, 0.0);
    for (const auto& f : m_forces) {
      double value = 0.0;
      if (f->dependence() != kConstant && (f->dependence() & ~unsigned(kDependsOnTime)) != 0 &&
          !f->potential(ctx, value))
        jacobians = false;
    }
  }
  NewtonMinimizer minimizer;
  NewtonMinimizer::Problem problem;
  problem.evaluate = evaluate;
  Eigen::SparseMatrix<double> folded;  // the tangent with the supports per component eliminated
  problem.tangent = [&](HessianMode mode, double shift) -> const Eigen::SparseMatrix<double>& {
    const LoadContext ctx = loadContext(net, net, m_params.timeStep, 0.0);
    const Eigen::SparseMatrix<double>& K =
        jacobians ? tangent(net, 1.0, shift, mode, &ctx, 0.0, loadFactor) : tangent(net, 1.0, shift, mode);
    return unknownsTangent(m_components.get(), K, m_heldMask, folded);
  };
  problem.residualSmall = [&](const NewtonPoint& p) { return p.norm <= tolerance * p.scale; };
  // the update against the displacement so far (whatever the load's size: a thin strip under a
  // small load moves microns), with a floor of 1e-11 of the surface's size (the positions'
  // rounding as the step sees it)
  const ControlNet restUnknowns = x;
  problem.updateTolerance = [&](const ControlNet& xi) {
    return tolerance * (xi - restUnknowns).cwiseAbs().maxCoeff() + 1e-11 * extent;
  };
  NewtonMinimizer::Options options;
  options.firstExtraShift = 1e-8 * diag / massMean;
  // a surface nothing holds keeps that smallest shift in every tangent: unshifted, its singular
  // tangent can still factorise in rounding and a step then moves it 1e7 along a rigid motion
  if (heldByNothing) options.shift = options.firstExtraShift;
  options.shiftAttempts = 60;
  options.rememberShift = true;
  StaticResult result;
  result.method = "Newton (CHOLMOD)";
  int totalIterations = 0;
  NewtonPoint cur;
  // Newton from x at load factor `f`, at most `limit` iterations; x is the last accepted
  // iterate either way
  auto newton = [&](ControlNet& xi, double f, int limit, int& used) {
    loadFactor = f;
    evaluate(xi, cur);
    options.maxIterations = limit;
    const NewtonMinimizer::Outcome outcome = minimizer.minimize(xi, cur, problem, options);
    used = outcome.iterations;
    return outcome.converged;
  };
  // Load increments: the loadSteps equal ones are the equilibria reported; between them the
  // increment is cut by 4 when Newton does not converge within 25 iterations (from the rest of
  // a thin plate, the first pure-bending step must stay near the linear range), and grown
  // again after quick convergence. Each increment starts from the secant prediction of the
  // last two equilibria.
  const int perIncrement = std::min(maxIterations, 25);
  double done = 0.0, delta = 1.0 / loadSteps, lastDelta = 0.0;
  ControlNet previous = x;
  int next = 1;
  while (next <= loadSteps) {
    const double target = double(next) / loadSteps;
    const double factor = std::min(done + delta, target);
    ControlNet xi = x;
    if (lastDelta > 0.0) xi += ((factor - done) / lastDelta) * (x - previous);
    int used = 0;
    const bool ok = newton(xi, factor, perIncrement, used);
    totalIterations += used;
    if (!ok) {
      delta = 0.25 * (factor - done);
      if (delta < 1e-7 / loadSteps || totalIterations > maxIterations * loadSteps * 4) {
        const std::string free = conservative ? freeRigidMotionLoaded(L0, true) : std::string();
        throw std::runtime_error("static solve: Newton's method did not reach the equilibrium of load factor " +
                                 numberText(factor) + " (relative residual " + numberText(cur.norm / cur.scale) + ", tolerance " +
                                 numberText(tolerance) + ", " + std::to_string(totalIterations) +
                                 " iterations in all); " + (free.empty() ? "" : "perhaps because " + free + "; ") +
                                 "run the dynamics with damping to find this equilibrium");
      }
      continue;
    }
    previous = x;
    x = xi;
    lastDelta = factor - done;
    done = factor;
    if (used <= 6) delta = std::min(2.0 * (factor - (done - lastDelta)), 1.0 / loadSteps);
    if (factor == target) {
      StaticResult::Increment inc;
      inc.loadFactor = factor;
      ControlNet xc = x;
      completeUnknowns(xc, net);
      inc.net = net;
      inc.residual = cur.norm / cur.scale;
      inc.iterations = used;
      result.increments.push_back(std::move(inc));
      ++next;
    }
  }
  if (heldByNothing) {
    // the rigid drift the free motions allowed, taken out: the mass-weighted centroid back at
    // rest's, and (loads indifferent to rotations: pressure) the best-fitting rotation about it
    // (Kabsch, weighted by the net masses); the equilibrium is the same up to that motion
    const Eigen::VectorXd& W = m_shellModel->netMass();
    const double total = W.sum();
    for (StaticResult::Increment& inc : result.increments) {
      const Eigen::RowVector3d c = (W.transpose() * inc.net) / total, c0 = (W.transpose() * m_rest) / total;
      Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
      if (followers) {
        const Eigen::Matrix3d H = (inc.net.rowwise() - c).transpose() * W.asDiagonal() * (m_rest.rowwise() - c0);
        Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
        Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
        D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
        R = svd.matrixV() * D * svd.matrixU().transpose();  // rotates the solution onto rest
      }
      inc.net = ((inc.net.rowwise() - c) * R.transpose()).rowwise() + c0;
    }
  }
  result.net = result.increments.back().net;
  result.residual = result.increments.back().residual;
  result.loadIterations = totalIterations;
  return result;
}


StaticResult Simulation::solveStaticArcLength(const ArcLengthOptions& options,
                                              const std::function<void(const StaticResult::Increment&)>& each) const {
  if (!m_shell) throw std::runtime_error("arc length: only the SHELL energy (energy SHELL) traces equilibrium paths");
  for (const auto& f : m_forces)
    if (const char* why = f->backwardEulerOnly()) throw std::runtime_error(std::string("arc length: ") + why);
  if (std::find(m_sideMoved.begin(), m_sideMoved.end(), true) != m_sideMoved.end())
    throw std::runtime_error("arc length: a moved side (motionUMin ...) belongs to a BACKWARD_EULER run; arc length "
                             "holds every side at rest");
  if (holdsNothing())
    throw std::runtime_error("arc length: nothing holds the surface (every side FREE or PERIODIC, no pin): its "
                             "rigid motions leave the tangent singular; hold a side or pin a point");
  bool constantLoads = true;
  for (const auto& f : m_forces) constantLoads &= (f->dependence() & ~unsigned(kDependsOnTime)) == 0;
  if (constantLoads && sidesHoldNothing()) {  // as the static solve (solveStaticShell)
    const std::string free = freeTranslationRefusal(loadAt(m_rest, 0.0));
    if (!free.empty()) throw std::runtime_error("arc length: " + free);
  }
  const Eigen::Index n = m_space.numMoving();
  ControlNet net = m_rest, grad;
  auto toNet = [&](const Eigen::VectorXd& x) {
    ControlNet xc = Eigen::Map<const ControlNet>(x.data(), n, 3);
    completeUnknowns(xc, net);
  };
  auto zeroHeld = [&](Eigen::VectorXd& v) {
    for (Eigen::Index i = 0; i < v.size(); ++i)
      if (m_heldMask[size_t(i)]) v[i] = 0.0;
  };
  ArcLengthProblem problem;
  problem.evaluate = [&](const Eigen::VectorXd& x, Eigen::VectorXd& g, Eigen::VectorXd& F) {
    toNet(x);
    shellGradient(net, grad);
    ControlNet L = loadAt(net, 0.0);
    if (m_components) {
      m_components->fold(grad);
      m_components->fold(L);
    }
    g = Eigen::Map<const Eigen::VectorXd>(grad.data(), grad.size());
    F = Eigen::Map<const Eigen::VectorXd>(L.data(), L.size());
    zeroHeld(g);
    zeroHeld(F);
  };
  problem.tangent = [&](const Eigen::VectorXd& x) {
    toNet(x);
    const Eigen::SparseMatrix<double>& K = tangent(net, 1.0, 0.0, HessianMode::Exact);
    return m_components ? m_components->foldTangent(K, m_heldMask) : Eigen::SparseMatrix<double>(K);
  };
  problem.lowerOnly = !m_components;
  const ControlNet x0 = m_space.gatherMoving(m_rest);
  // a point is converged, as in the static Newton (solveStaticShell), also when a Newton
  // correction is below the tolerance times the displacement from rest, with a floor of 1e-11
  // of the surface's size: the relative residual alone has a rounding floor where the snapped
  // shell's large internal forces cancel near a zero load, and the path would stall there
  const double extent = (m_rest.colwise().maxCoeff() - m_rest.colwise().minCoeff()).norm();
  const Eigen::Map<const Eigen::VectorXd> rest(x0.data(), x0.size());
  problem.updateTolerance = [&](const Eigen::VectorXd& x) {
    return options.tolerance * (x - rest).cwiseAbs().maxCoeff() + 1e-11 * extent;
  };
  StaticResult result;
  result.method = "arc length (Crisfield, SparseLU)";
  int total = 0;
  auto increment = [&](const ArcLengthPoint& p) {
    StaticResult::Increment inc;
    inc.loadFactor = p.loadFactor;
    toNet(p.x);
    inc.net = net;
    inc.residual = p.residual;
    inc.iterations = p.iterations;
    total += p.iterations;
    return inc;
  };
  arcLengthPath(rest, problem, options,
                [&](const ArcLengthPoint& p) {
                  result.increments.push_back(increment(p));
                  if (each) each(result.increments.back());
                });
  if (result.increments.empty()) throw std::runtime_error("arc length: no point found");
  result.net = result.increments.back().net;
  result.residual = result.increments.back().residual;
  result.loadIterations = total;
  return result;
}


bool Simulation::sidesHoldNothing() const {
  const Boundaries& b = m_space.boundaries();
  auto loose = [](Boundary side) { return side == Boundary::Free || side == Boundary::Periodic; };
  return loose(b.uMin) && loose(b.uMax) && loose(b.vMin) && loose(b.vMax);
}

bool Simulation::holdsNothing() const {
  return sidesHoldNothing() && std::none_of(m_heldMask.begin(), m_heldMask.end(), [](char held) { return held != 0; });
}

void Simulation::completeUnknowns(ControlNet& x, ControlNet& net) const {
  if (m_components) m_components->complete(x);
  m_space.scatterMoving(x, net);
  m_space.completeNet(net, &m_rest);
}


// The rigid motions of the unknowns: translations along x, y, z and rotations about the axes
// through the rest centroid. A motion is free when every held coordinate stays and every
// constrained one follows its row (ComponentConstraints::complete of rest + motion gives it
// back); the free ones are the null space of those violations (the eigenvectors of VᵀV with a
// negligible eigenvalue). One on which `load` (on the unknowns; null: any) does work is named.
// Translations alone are judged on the translations' block of V: a free translation is then
// found however the free rotations mix with it.
std::string Simulation::freeRigidMotion(const ControlNet* load, bool rotations) const {
  const ControlNet x0 = m_space.gatherMoving(m_rest);
  const Eigen::RowVector3d c = x0.colwise().mean();
  const double size = (x0.colwise().maxCoeff() - x0.colwise().minCoeff()).norm() + 1e-300;
  std::vector<ControlNet> motions;
  for (int a = 0; a < 3; ++a) {
    ControlNet t = ControlNet::Zero(x0.rows(), 3);
    t.col(a).setOnes();
    motions.push_back(t);
  }
  for (int a = 0; a < 3; ++a) {  // rotation about axis a, scaled to a unit motion at the size
    ControlNet r(x0.rows(), 3);
    const Eigen::Vector3d e = Eigen::Vector3d::Unit(a);
    for (Eigen::Index f = 0; f < x0.rows(); ++f) r.row(f) = e.cross((x0.row(f) - c).transpose()).transpose() / size;
    motions.push_back(r);
  }
  // violations of each motion, one column per motion
  Eigen::MatrixXd V(3 * x0.rows(), 6);
  for (int k = 0; k < 6; ++k) {
    ControlNet moved = x0 + motions[size_t(k)];
    if (m_components) m_components->complete(moved);
    const ControlNet violation = (x0 + motions[size_t(k)]) - moved;  // constrained coordinates
    for (Eigen::Index d = 0; d < V.rows(); ++d) {
      const bool constrained = m_components && m_components->constrained(d);
      V(d, k) = constrained ? violation(d / 3, int(d % 3))
                            : (m_heldMask[size_t(d)] ? motions[size_t(k)](d / 3, int(d % 3)) : 0.0);
    }
  }
  const double loadSize = load ? load->cwiseAbs().sum() + 1e-300 : 0.0;
  auto loaded = [&](const ControlNet& delta) {
    return !load || std::abs((load->array() * delta.array()).sum()) > 1e-8 * loadSize * delta.cwiseAbs().maxCoeff();
  };
  auto translation = [](const Eigen::Vector3d& t) {
    const Eigen::Vector3d dir = t.normalized();
    Eigen::Index axis = 0;
    std::ostringstream os;
    if (dir.cwiseAbs().maxCoeff(&axis) >= 1.0 - 1e-9)
      os << "the translation along " << char('x' + axis);
    else
      os << "the translation along (" << numberText(dir.x()) << ", " << numberText(dir.y()) << ", "
         << numberText(dir.z()) << ")";
    os << " is free (no support, symmetry side or pin holds it)";
    return os.str();
  };
  if (!rotations) {
    const Eigen::Matrix3d VtV = V.leftCols<3>().transpose() * V.leftCols<3>();
    const double largest = std::max(VtV.diagonal().maxCoeff(), 1.0);
    // the coordinate axes first (the constraints act on world components: the free
    // translations are spanned by the axes they leave alone), then any other free direction
    std::vector<Eigen::Vector3d> free;
    for (int a = 0; a < 3; ++a)
      if (VtV(a, a) <= 1e-16 * largest) free.push_back(Eigen::Vector3d::Unit(a));
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(VtV);
    for (int k = 0; k < 3; ++k)
      if (eig.eigenvalues()[k] <= 1e-16 * largest) free.push_back(eig.eigenvectors().col(k));
    for (const Eigen::Vector3d& t : free) {
      const ControlNet delta = t.x() * motions[0] + t.y() * motions[1] + t.z() * motions[2];
      if (loaded(delta)) return translation(t) + (load ? " and the loads do work on it" : "");
    }
    return std::string();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig((V.transpose() * V).eval());
  const double largest = std::max(eig.eigenvalues().maxCoeff(), 1.0);
  for (int k = 0; k < 6; ++k) {
    if (eig.eigenvalues()[k] > 1e-16 * largest) continue;  // blocked
    const Eigen::Matrix<double, 6, 1> alpha = eig.eigenvectors().col(k);
    ControlNet delta = ControlNet::Zero(x0.rows(), 3);
    for (int j = 0; j < 6; ++j) delta += alpha[j] * motions[size_t(j)];
    if (!loaded(delta)) continue;
    const Eigen::Vector3d t = alpha.head<3>(), w = alpha.tail<3>();
    const std::string onIt = load ? " and the loads do work on it" : "";
    if (w.norm() <= 1e-6 * alpha.norm()) return translation(t) + onIt;
    // velocity t + ω × (x − c) with ω = w / size: the axis passes through c + ω × t / |ω|²
    const Eigen::Vector3d omega = w / size;
    Eigen::Index lead = 0;  // the axis said with its largest component positive (either sense turns)
    w.cwiseAbs().maxCoeff(&lead);
    const Eigen::Vector3d axis = w[lead] < 0.0 ? Eigen::Vector3d(-w.normalized()) : w.normalized();
    const Eigen::Vector3d through = c.transpose() + omega.cross(t) / omega.squaredNorm();
    // rounding noise said as 0 (below 1e-9 of a unit direction, of the size for a point)
    auto unit = [](double v) { return std::abs(v) < 1e-9 ? 0.0 : v; };
    auto point = [size](double v) { return std::abs(v) < 1e-9 * size ? 0.0 : v; };
    std::ostringstream os;
    os << "the rotation about the axis (" << numberText(unit(axis.x())) << ", " << numberText(unit(axis.y())) << ", "
       << numberText(unit(axis.z())) << ") through (" << numberText(point(through.x())) << ", "
       << numberText(point(through.y())) << ", " << numberText(point(through.z()))
       << ") is free (no support, symmetry side or pin holds it)" << onIt;
    return os.str();
  }
  return std::string();
}

std::string Simulation::freeRigidMotionLoaded(const ControlNet& load, bool rotations) const {
  return freeRigidMotion(&load, rotations);
}

std::string Simulation::freeTranslationRefusal(const ControlNet& load) const {
  const std::string loaded = freeRigidMotion(&load, false);
  if (!loaded.empty())
    return loaded + ": there is no equilibrium; hold it somewhere (a pin holding that component: pins and holdPins; "
                    "a side's hold components)";
  const std::string free = freeRigidMotion(nullptr, false);
  if (!free.empty())
    return free + ": the loads do no work on it, but any slide along it is an equilibrium as well, so there is no "
                  "unique one; hold it somewhere (a pin holding that component: pins and holdPins; a side's hold "
                  "components)";
  return std::string();
}

}  // namespace bsdeform
