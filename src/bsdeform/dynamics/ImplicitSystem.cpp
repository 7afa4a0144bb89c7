// SPDX-License-Identifier: MIT
#include "bsdeform/dynamics/ImplicitSystem.h"
#include "bsdeform/base/Parallel.h"

#include "bsdeform/base/HugePages.h"
#include "bsdeform/dynamics/Multigrid.h"
#include "bsdeform/dynamics/SparseCholesky.h"

#include <Eigen/Sparse>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <stdexcept>

namespace bsdeform {

ImplicitSystem::ImplicitSystem(const SplineSpace& space, const StiffnessStencil& stencil,
                               const Eigen::VectorXd& massTerm, const std::vector<Eigen::Index>& pinned,
                               LinearSolver kind, double tolerance, int maxIterations,
                               std::vector<Eigen::Triplet<double>> coupling, double kappaEstimate)
    : m_space(space),
      m_stencil(stencil),
      m_mass(massTerm),
      m_pinned(pinned),
      m_method(kind),
      m_tolerance(tolerance),
      m_maxIterations(maxIterations) {
  const Eigen::Index n = space.numMoving();
  if (m_mass.size() != n || !(m_mass.minCoeff() > 0.0))
    throw std::invalid_argument("implicit system: the mass term must be > 0 for every moving point");
  std::sort(m_pinned.begin(), m_pinned.end());
  for (Eigen::Index f : m_pinned) m_pinnedNet.push_back(space.movingToNet(f));
  if (!coupling.empty()) {
    std::vector<char> isPinned(size_t(n), 0);
    for (Eigen::Index f : m_pinned) isPinned[size_t(f)] = 1;
    for (const auto& t : coupling)
      if (!isPinned[size_t(t.row())] && !isPinned[size_t(t.col())]) m_coupling.push_back(t);
  }

  // kappa(K) <= (max D + lambda_max(A)/4) / min D: A_act is positive semi-definite and its
  // largest eigenvalue is at most A_II's (a principal submatrix), which the symbol bounds.
  m_kappa = kappaEstimate > 0.0 ? kappaEstimate
                                : (m_mass.maxCoeff() + 0.25 * stencil.eigenvalueBound()) / m_mass.minCoeff();
  if (m_method == LinearSolver::Automatic) {
    const double iterations = predictedIterations();
    if (n <= kAutomaticDirectPoints || (iterations > kAutomaticIterationLimit && n <= kAutomaticFactorPoints))
      m_method = LinearSolver::Direct;
    else if (iterations > kAutomaticMultigridIterations)
      m_method = LinearSolver::Multigrid;
    else
      m_method = LinearSolver::ConjugateGradient;
  }

  if (m_method == LinearSolver::Direct) {
    // Lower triangle of K: A_II without pinned rows and columns, / 4, plus D.
    Eigen::SparseMatrix<double> K = stencil.movingMatrix();
    std::vector<char> isPinned(size_t(n), 0);
    for (Eigen::Index f : m_pinned) isPinned[size_t(f)] = 1;
    K.prune([&](Eigen::Index r, Eigen::Index c, double) { return r >= c && !isPinned[size_t(r)] && !isPinned[size_t(c)]; });
    K *= 0.25;
    Eigen::SparseMatrix<double> Dm(n, n);
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(size_t(n));
    for (Eigen::Index f = 0; f < n; ++f) t.emplace_back(f, f, m_mass[f]);
    for (const auto& c : m_coupling)
      if (c.row() > c.col()) t.push_back(c);
    Dm.setFromTriplets(t.begin(), t.end());
    K += Dm;
    K.makeCompressed();
    m_factor = std::make_unique<SparseCholesky>();
    if (!m_factor->factor(K))
      throw std::runtime_error("implicit integrator: Cholesky factorisation of the system matrix failed");
    m_factorNonZeros = m_factor->factorNonZeros();
    return;
  }

  ensureNet();
  const Eigen::VectorXd diag = diagonal();
  if (m_method == LinearSolver::Multigrid) {
    try {
      m_multigrid = std::make_unique<MultigridPreconditioner>(space, stencil, stencil.weights(), m_mass);
    } catch (const std::exception&) {
      // e.g. a periodic direction too short to coarsen: an explicit request reports it,
      // Automatic falls back to Jacobi-CG
      if (kind != LinearSolver::Automatic) throw;
      m_method = LinearSolver::ConjugateGradient;
    }
  }
  if (m_multigrid) {
    // the finest level smooths with K itself (the stencil, pins included); lambda_max(diag^-1 K)
    // <= max_f (D_f + lambda_max(A)/4) / diag_f, as x'Kx <= sum_f (D_f + lambda_max(A)/4) x_f^2
    // (a mass coupling adds at most its absolute row sums: Gershgorin)
    Eigen::VectorXd massRow = m_mass;
    for (const auto& t : m_coupling) massRow[t.row()] += std::abs(t.value());
    const double lambdaBound =
        ((massRow.array() + 0.25 * stencil.eigenvalueBound()) / diag.array()).maxCoeff();
    m_multigrid->useExactOperator(
        [this](const ControlNet& x, const ControlNet* b, ControlNet& y) { b ? residual(x, *b, y) : apply(x, y); },
        [this](const ControlNet& b, double scale, double alpha, double beta, const Eigen::VectorXd& inv,
               bool accumulate, ControlNet& out) { smoothingStep(b, scale, alpha, beta, inv, accumulate, out); },
        diag, lambdaBound);
    return;
  }
  // Jacobi scaling: diag(K) = D + diag(A)/4 off the pins. Where it is one constant (all sides
  // clamped, nodal mass) it changes nothing and is skipped.
  if (diag.maxCoeff() != diag.minCoeff()) m_inverseDiag = diag.cwiseInverse();
}

Eigen::VectorXd ImplicitSystem::diagonal() const {
  Eigen::VectorXd diag = m_mass + 0.25 * m_stencil.movingDiagonal();
  for (Eigen::Index f : m_pinned) diag[f] = m_mass[f];
  return diag;
}

ImplicitSystem::~ImplicitSystem() = default;

namespace {
/// dot[c] = sum_f a(f, c) b(f, c), in one pass over both (a column dot is a strided pass each).
void dotPerCoordinate(const ControlNet& a, const ControlNet& b, double dot[3]) {
  const double* pa = a.data();
  const double* pb = b.data();
  double s0 = 0.0, s1 = 0.0, s2 = 0.0;
  for (Eigen::Index f = 0; f < a.rows(); ++f) {
    s0 += pa[3 * f] * pb[3 * f];
    s1 += pa[3 * f + 1] * pb[3 * f + 1];
    s2 += pa[3 * f + 2] * pb[3 * f + 2];
  }
  dot[0] = s0;
  dot[1] = s1;
  dot[2] = s2;
}
}  // namespace

double ImplicitSystem::predictedIterations() const {
  return 0.5 * std::sqrt(m_kappa) * std::log(2.0 / m_tolerance);
}

void ImplicitSystem::ensureNet() {
  if (m_net.rows() != m_space.netSize()) {
    allocateNet(m_net, m_space.netSize());
    m_net.setZero();
  }
}

void ImplicitSystem::scatterDirection(const ControlNet& x) {
  ensureNet();
  // Held points of m_net are zero and stay so; pinned points are zeroed after the scatter so
  // that A sees x with its pinned rows and columns removed.
  m_space.scatterMoving(x, m_net);  // refreshes the periodic copies
  if (!m_pinnedNet.empty() || m_space.hasDerived()) zeroPinnedInNet();
}

void ImplicitSystem::zeroPinnedInNet() {
  for (Eigen::Index r : m_pinnedNet) m_net.row(r).setZero();
  m_space.completeNet(m_net, nullptr);  // derived layers follow x (homogeneous)
}

template <typename XAt, typename EntryFunction>
void ImplicitSystem::forEachProductEntry(XAt&& xAt, ControlNet& y, EntryFunction&& fn) const {
  for (Eigen::Index f : m_pinned) y.row(f).setZero();
  // the mass coupling goes into y, which is scaled by 1/4 below
  for (const auto& t : m_coupling)
    for (int c = 0; c < 3; ++c) y.data()[3 * t.row() + c] += 4.0 * t.value() * xAt(t.col(), 3 * t.col() + c);
  const Eigen::Index n = y.rows();
  const double* py = y.data();
  const double* d = m_mass.data();
  for (Eigen::Index f = 0; f < n; ++f) {
    const double m = d[f];
    for (int c = 0; c < 3; ++c) {
      const Eigen::Index k = 3 * f + c;
      fn(f, c, k, 0.25 * py[k] + m * xAt(f, k));
    }
  }
}

void ImplicitSystem::finishApply(const ControlNet& x, ControlNet& y, double dot[3]) const {
  // y = K x and dot = x . y per coordinate, in one pass
  const double* px = x.data();
  double* py = y.data();
  double s[3] = {0.0, 0.0, 0.0};
  forEachProductEntry([px](Eigen::Index, Eigen::Index k) { return px[k]; }, y,
                      [&](Eigen::Index, int c, Eigen::Index k, double Kx) {
    py[k] = Kx;
    s[c] += px[k] * Kx;
  });
  for (int c = 0; c < 3; ++c) dot[c] = s[c];
}

void ImplicitSystem::residual(const ControlNet& x, const ControlNet& b, ControlNet& out) {
  scatterDirection(x);
  m_stencil.applyMoving(m_net, out);
  const double* px = x.data();
  const double* pb = b.data();
  double* po = out.data();
  forEachProductEntry([px](Eigen::Index, Eigen::Index k) { return px[k]; }, out,
                      [&](Eigen::Index, int, Eigen::Index k, double Kx) { po[k] = pb[k] - Kx; });
}

void ImplicitSystem::smoothingStep(const ControlNet& b, double scale, double alpha, double beta,
                                   const Eigen::VectorXd& invDiag, bool accumulate, ControlNet& out) {
  assert(b.rows() == m_space.numMoving() && invDiag.size() == b.rows());
  assert(!accumulate || out.rows() == b.rows());
  // x0 = scale diag(invDiag) b goes straight into the stencil's net (never stored as a vector),
  // pinned points zeroed as in scatterDirection()
  ensureNet();
  const double* pb = b.data();
  const double* inv = invDiag.data();
  const Eigen::Index w = m_space.movingV().count;
  for (int a = 0; a < m_space.movingU().count; ++a) {
    const Eigen::Index f0 = Eigen::Index(a) * w;
    double* dst = m_net.data() + 3 * m_space.movingToNet(f0);
    for (Eigen::Index j = 0; j < w; ++j) {
      const double s = scale * inv[f0 + j];
      for (int c = 0; c < 3; ++c) dst[3 * j + c] = s * pb[3 * (f0 + j) + c];
    }
  }
  zeroPinnedInNet();
  m_stencil.applyMoving(m_net, m_smooth);
  if (!accumulate) allocateNet(out, b.rows());
  double* po = out.data();
  const auto x0 = [&](Eigen::Index f, Eigen::Index k) { return scale * inv[f] * pb[k]; };
  if (accumulate)
    forEachProductEntry(x0, m_smooth, [&](Eigen::Index f, int, Eigen::Index k, double Kx) {
      po[k] += alpha * x0(f, k) + beta * inv[f] * (pb[k] - Kx);
    });
  else
    forEachProductEntry(x0, m_smooth, [&](Eigen::Index f, int, Eigen::Index k, double Kx) {
      po[k] = alpha * x0(f, k) + beta * inv[f] * (pb[k] - Kx);
    });
}

void ImplicitSystem::apply(const ControlNet& x, ControlNet& y) {
  scatterDirection(x);
  m_stencil.applyMoving(m_net, y);
  double dot[3];
  finishApply(x, y, dot);
}

bool ImplicitSystem::solve(const ControlNet& b, ControlNet& x) {
  if (m_method == LinearSolver::Direct) {
    x = m_factor->solve(Eigen::MatrixXd(b));
    m_lastIterations = 0;
    m_lastResidual = 0.0;
    return true;
  }
  // Conjugate gradients for each coordinate (three independent recurrences sharing the passes
  // over memory): p = z + beta p (written into the stencil's net too), q = K p, then x, r and
  // z = r / diag(K) with the dot products; or z = B r, one V-cycle.
  const Eigen::Index n = b.rows();
  const bool jacobi = m_inverseDiag.size() > 0;
  const bool multigrid = m_multigrid != nullptr;
  double bb[3], goal[3];
  for (int c = 0; c < 3; ++c) {
    bb[c] = b.col(c).squaredNorm();
    goal[c] = m_tolerance * m_tolerance * bb[c];
    if (bb[c] == 0.0) x.col(c).setZero();  // the exact solution; no relative residual to reach
  }
  apply(x, m_q);
  m_r = b - m_q;
  if (jacobi) m_z = m_inverseDiag.asDiagonal() * m_r;
  if (multigrid) m_multigrid->apply(m_r, m_z);
  const ControlNet& z = jacobi || multigrid ? m_z : m_r;
  double rr[3], rz[3];
  dotPerCoordinate(m_r, m_r, rr);
  dotPerCoordinate(m_r, z, rz);
  allocateNet(m_p, n);
  m_p.setZero();
  double beta[3] = {0.0, 0.0, 0.0};
  bool active[3];
  int it = 0;
  for (;; ++it) {
    bool any = false;
    for (int c = 0; c < 3; ++c) any |= active[c] = rr[c] > goal[c];
    if (!any || it == m_maxIterations) break;
    m_p = z + m_p * Eigen::Vector3d(beta[0], beta[1], beta[2]).asDiagonal();
    scatterDirection(m_p);
    m_stencil.applyMoving(m_net, m_q);
    double pq[3], a[3];
    finishApply(m_p, m_q, pq);
    for (int c = 0; c < 3; ++c) a[c] = active[c] ? rz[c] / pq[c] : 0.0;
    double* px = x.data();
    double* pr = m_r.data();
    double* pz = jacobi ? m_z.data() : nullptr;
    const double* pp = m_p.data();
    const double* pqv = m_q.data();
    const double* inv = jacobi ? m_inverseDiag.data() : nullptr;
    double s[6] = {0, 0, 0, 0, 0, 0};
    for (Eigen::Index f = 0; f < n; ++f)
      for (int c = 0; c < 3; ++c) {
        const Eigen::Index k = 3 * f + c;
        px[k] += a[c] * pp[k];
        const double r = pr[k] - a[c] * pqv[k];
        pr[k] = r;
        const double zk = jacobi ? inv[f] * r : r;
        if (jacobi) pz[k] = zk;
        s[c] += r * r;
        s[3 + c] += r * zk;
      }
    if (multigrid) {
      m_multigrid->apply(m_r, m_z);
      dotPerCoordinate(m_r, m_z, s + 3);
    }
    for (int c = 0; c < 3; ++c) {
      rr[c] = s[c];
      beta[c] = active[c] ? s[3 + c] / rz[c] : 0.0;
      rz[c] = s[3 + c];
    }
  }
  m_lastIterations = it;
  m_lastResidual = 0.0;
  bool converged = true;
  for (int c = 0; c < 3; ++c) {
    if (bb[c] > 0.0) m_lastResidual = std::max(m_lastResidual, std::sqrt(rr[c] / bb[c]));
    converged &= !(rr[c] > goal[c]);
  }
  return x.allFinite() && converged;
}

}  // namespace bsdeform
