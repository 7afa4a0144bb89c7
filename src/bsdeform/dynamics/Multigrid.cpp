// SPDX-License-Identifier: MIT
#include "bsdeform/dynamics/Multigrid.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <stdexcept>
#include <utility>

#include "bsdeform/base/HugePages.h"
#include "bsdeform/dynamics/MultigridOperator.h"
#include "bsdeform/dynamics/MultigridTransfer.h"
#include "bsdeform/base/Multiversion.h"

namespace bsdeform {

using namespace multigrid;

namespace {

// x += y
BSDEFORM_MULTIVERSION
void addTo(const ControlNet& y, ControlNet& x) {
  const double* __restrict py = y.data();
  double* __restrict px = x.data();
  for (Eigen::Index m = 0; m < x.size(); ++m) px[m] += py[m];
}

// The smoothers work on [lambda / ratio, lambda] of diag^-1 K: the B-spline coarse spaces take
// the rest. With degrees 2 to 7 the ratio 3 needs the fewest CG iterations; with degree 1 it
// needs more, so bilinear levels keep 8 (docs/benchmarks.md, "Multigrid, second pass").
constexpr double kSmoothingRatio = 3.0, kSmoothingRatioLinear = 8.0;

constexpr Eigen::Index kCoarsestPoints = 400;

}  // namespace

struct MultigridPreconditioner::Level {
  KroneckerOperator op;  ///< K~ of this level
  int degreeU = 0, degreeV = 0;
  Eigen::VectorXd invDiag;  ///< per point
  double lambda = 1.0;      ///< upper estimate of lambda_max(diag^-1 K~)
  bool coarsest = false;
  bool finest = false;
  Transfer1D toCoarseU, toCoarseV;
  Eigen::LLT<Eigen::MatrixXd> llt;  ///< coarsest level only
  /// right-hand side, solution, residual; y: the smoothing added into x (and power-iteration
  /// scratch); s: the smoother's product
  ControlNet r, x, res, y, s;
  TransferScratch transferScratch;
  int smoothingDegree = 2;  ///< 1: damped Jacobi (no product with K)
  /// The finest level's own operator K (pins and all), when given: used instead of K~.
  MultigridPreconditioner::Operator exact;
  MultigridPreconditioner::SmoothingStep exactStep;

  Eigen::Index points() const { return op.points(); }

  void prepare() {
    op.prepare();
    // diagonal and Gershgorin bound of diag^-1 K~
    Eigen::VectorXd diag, absSum;
    op.diagonalAndRowSums(diag, absSum);
    if (!(diag.minCoeff() > 0.0)) throw std::runtime_error("multigrid: a level's operator has a diagonal entry <= 0");
    invDiag = diag.cwiseInverse();
    const double gershgorin = absSum.cwiseProduct(invDiag).maxCoeff();
    for (ControlNet* m : {&x, &res, &y}) allocateNet(*m, points());
    // the finest level's estimate waits for useExactOperator() (its operator may change); the
    // coarsest level is solved, not smoothed
    lambda = finest || coarsest ? gershgorin : std::min(gershgorin, estimateLambda());
  }

  /// 1.15 times a power-iteration estimate of lambda_max(diag^-1 K) (a lower estimate): the
  /// smoother still reduces every mode up to 4/3 of its upper end.
  double estimateLambda() {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> X(-1.0, 1.0);
    for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] = X(rng);
    double estimate = 0.0;
    for (int it = 0; it < 20; ++it) {
      apply(x, nullptr, y);
      y = invDiag.asDiagonal() * y;
      estimate = std::sqrt(y.squaredNorm() / x.squaredNorm());
      x = y / y.norm();
    }
    return 1.15 * estimate;
  }

  /// out = K x (K~ x), or out = rhs - K x when rhs is given.
  void apply(const ControlNet& xNet, const ControlNet* rhsNet, ControlNet& outNet) {
    if (exact) {
      exact(xNet, rhsNet, outNet);
      return;
    }
    op.apply(xNet, rhsNet, outNet);
  }

  /// out = p(diag^-1 K) diag^-1 b from zero (out += that when `accumulate`): the Chebyshev
  /// polynomial of smoothingDegree (1 or 2) on [lambda / ratio, lambda], which amplifies no mode
  /// of (0, (1 + 1 / ratio) lambda); degree 2 takes one product with K (`s` is its scratch).
  void smooth(const ControlNet& b, ControlNet& out, bool accumulate = false) {
    const double ratio = std::min(degreeU, degreeV) >= 2 ? kSmoothingRatio : kSmoothingRatioLinear;
    const double hi = lambda, lo = lambda / ratio;
    const double theta = 0.5 * (hi + lo), delta = 0.5 * (hi - lo);
    const double sigma = theta / delta, rho0 = 1.0 / sigma, rho1 = 1.0 / (2.0 * sigma - rho0);
    if (smoothingDegree >= 2 && exactStep) {
      exactStep(b, 1.0 / theta, 1.0 + rho1 * rho0, 2.0 * rho1 / delta, invDiag, accumulate, out);
      return;
    }
    ControlNet& target = accumulate ? y : out;
    target = invDiag.asDiagonal() * b / theta;
    if (smoothingDegree >= 2) {
      allocateNet(s, points());
      apply(target, &b, s);
      target = (1.0 + rho1 * rho0) * target + (2.0 * rho1 / delta) * (invDiag.asDiagonal() * s);
    }
    if (accumulate) addTo(y, out);
  }
};

MultigridPreconditioner::MultigridPreconditioner(const SplineSpace& space, const StiffnessStencil& stencil,
                                                 const Weights& weights, const Eigen::VectorXd& massTerm) {
  auto fine = std::make_unique<Level>();
  Level& L = *fine;
  KroneckerOperator& K = L.op;
  K.mu = space.movingU().count;
  K.mv = space.movingV().count;
  L.degreeU = space.degreeU();
  L.degreeV = space.degreeV();
  if (massTerm.size() != L.points()) throw std::invalid_argument("multigrid: the mass term needs one entry per moving point");
  const Boundaries& sides = space.boundaries();
  K.u.periodic = space.periodicU();
  K.v.periodic = space.periodicV();
  // SIMPLY_SUPPORTED and BUILT_IN sides keep some outer layers moving: their coarse functions
  // are cut at the edge like a FREE side's (the transfer only has to be a good one)
  auto allHeld = [](Boundary side, int n) { return side != Boundary::Periodic && edgeLayers(side, n).held >= n; };
  K.u.clampedMin = allHeld(sides.uMin, L.degreeU);
  K.u.clampedMax = allHeld(sides.uMax, L.degreeU);
  K.v.clampedMin = allHeld(sides.vMin, L.degreeV);
  K.v.clampedMax = allHeld(sides.vMax, L.degreeV);

  // separable fit of the mass term: D_ab ~ du(a) dv(b) / mean(D)
  const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> D(massTerm.data(), K.mu, K.mv);
  const Eigen::VectorXd du = D.rowwise().mean(), dv = D.colwise().mean().transpose();
  // periodic like the direction, so that its Galerkin products wrap instead of widening
  K.u.matrices.push_back(diagonalMatrix(du, K.u.periodic));
  K.v.matrices.push_back(diagonalMatrix(dv, K.v.periodic));
  K.terms.push_back({1.0 / D.mean(), 0, 0});
  // the five energy terms, c G_u^p (x) G_v^q / 4; index p + 1 in each direction's list
  for (int p = 0; p <= 2; ++p) {
    K.u.matrices.push_back(gramMatrix(stencil.gramU(), space.movingU(), space.netRows(), K.u.periodic, p,
                                      &SplineSpace::foldU, space));
    K.v.matrices.push_back(gramMatrix(stencil.gramV(), space.movingV(), space.netCols(), K.v.periodic, p,
                                      &SplineSpace::foldV, space));
  }
  const struct {
    double w;
    int p, q;
  } energy[] = {{weights.w10, 1, 0}, {weights.w01, 0, 1}, {2.0 * weights.w11, 1, 1}, {weights.w20, 2, 0}, {weights.w02, 0, 2}};
  for (const auto& e : energy)
    if (e.w > 0.0 && e.p <= L.degreeU && e.q <= L.degreeV) K.terms.push_back({0.25 * e.w, e.p + 1, e.q + 1});
  m_levels.push_back(std::move(fine));

  // coarser levels: Galerkin products, until small or neither direction coarsens
  for (;;) {
    Level& f = *m_levels.back();
    const bool cu = subdivisionTransfer(f.op.u, f.degreeU, f.toCoarseU);
    const bool cv = subdivisionTransfer(f.op.v, f.degreeV, f.toCoarseV);
    if (f.points() <= kCoarsestPoints || (!cu && !cv)) {
      f.coarsest = true;
      break;
    }
    if (!cu) f.toCoarseU = identityTransfer(f.op.mu);
    if (!cv) f.toCoarseV = identityTransfer(f.op.mv);
    auto c = std::make_unique<Level>();
    c->op.u = f.op.u;
    c->op.v = f.op.v;
    c->degreeU = f.degreeU;
    c->degreeV = f.degreeV;
    c->op.terms = f.op.terms;
    for (BandMatrix& B : c->op.u.matrices) B = galerkin(B, f.toCoarseU);
    for (BandMatrix& B : c->op.v.matrices) B = galerkin(B, f.toCoarseV);
    c->op.mu = f.toCoarseU.coarseSize();
    c->op.mv = f.toCoarseV.coarseSize();
    m_levels.push_back(std::move(c));
  }
  // degree 2 on the finest level, 1 (damped Jacobi) below: measured fastest (docs/benchmarks.md)
  for (size_t l = 1; l < m_levels.size(); ++l) m_levels[l]->smoothingDegree = 1;
  m_levels.front()->finest = true;
  for (auto& level : m_levels) level->prepare();

  // the coarsest level: K~ assembled densely and factorised
  Level& c = *m_levels.back();
  c.llt.compute(c.op.dense());
  if (c.llt.info() != Eigen::Success) throw std::runtime_error("multigrid: the coarsest level is not positive definite");
}

MultigridPreconditioner::~MultigridPreconditioner() = default;

int MultigridPreconditioner::levels() const { return int(m_levels.size()); }

Eigen::Index MultigridPreconditioner::levelPoints(int level) const { return m_levels[size_t(level)]->points(); }

void MultigridPreconditioner::useExactOperator(Operator op, SmoothingStep step, const Eigen::VectorXd& diagonal,
                                               double lambdaBound) {
  Level& L = *m_levels.front();
  if (L.coarsest) return;  // a one-level hierarchy solves K~ directly
  L.exact = std::move(op);
  L.exactStep = std::move(step);
  L.invDiag = diagonal.cwiseInverse();
  L.lambda = std::min(lambdaBound, L.estimateLambda());
}

void MultigridPreconditioner::applyOperator(const ControlNet& x, ControlNet& y) {
  Level& L = *m_levels.front();
  allocateNet(y, L.points());
  L.apply(x, nullptr, y);
}

void MultigridPreconditioner::cycle(int level, const ControlNet& r, ControlNet& x) {
  Level& L = *m_levels[size_t(level)];
  if (L.coarsest) {
    x = L.llt.solve(r);
    return;
  }
  Level& C = *m_levels[size_t(level) + 1];
  allocateNet(x, L.points());
  L.smooth(r, x);
  L.apply(x, &r, L.res);
  restrictTo(L.res, L.toCoarseU, L.toCoarseV, L.transferScratch, C.r);
  cycle(level + 1, C.r, C.x);
  prolongAdd(C.x, L.toCoarseU, L.toCoarseV, L.transferScratch, x);
  L.apply(x, &r, L.res);
  L.smooth(L.res, x, true);
}

void MultigridPreconditioner::apply(const ControlNet& r, ControlNet& z) { cycle(0, r, z); }

}  // namespace bsdeform
