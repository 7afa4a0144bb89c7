// SPDX-License-Identifier: MIT
#include "bsdeform/forces/Force.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "bsdeform/spline/GaussLegendre.h"
#include "bsdeform/forces/LoadQuadrature.h"

namespace bsdeform {

namespace {
void checkParam(double x, const char* name) {
  if (!std::isfinite(x) || x < 0.0 || x > 1.0)
    throw std::invalid_argument(std::string(name) + " must be a parameter in [0,1], got " + std::to_string(x));
}
void checkVector(const Eigen::Vector3d& f, const char* name) {
  if (!f.allFinite())
    throw std::invalid_argument(std::string(name) + " must be finite, got (" + std::to_string(f.x()) + ", " +
                                std::to_string(f.y()) + ", " + std::to_string(f.z()) + ")");
}
void checkStiffness(double k) {
  if (!std::isfinite(k) || k < 0.0)
    throw std::invalid_argument("force stiffness bound must be finite and >= 0, got " + std::to_string(k));
}

}  // namespace

SurfaceSample sampleFromBases(const LoadContext& ctx, const LocalBasis& bu, const LocalBasis& bv, double u, double v,
                              unsigned dep) {
  SurfaceSample smp;
  smp.u = u;
  smp.v = v;
  smp.t = ctx.time;
  smp.stepSize = ctx.stepSize;
  if (!(dep & (kDependsOnPosition | kDependsOnVelocity | kDependsOnNormal))) return smp;
  const int order = (dep & kDependsOnNormal) ? 1 : 0;
  const SurfacePoint now = ctx.space.evaluate(ctx.current, bu, bv, order);
  smp.position = now.position;
  if (dep & kDependsOnVelocity)
    smp.velocity = (now.position - ctx.space.evaluate(ctx.previous, bu, bv, 0).position) / ctx.stepSize;
  if (dep & kDependsOnNormal) {
    smp.normal = now.normal();
    smp.areaElement = now.du.cross(now.dv).norm();
  }
  return smp;
}

std::vector<Node1D> splitQuadrature(const BSplineBasis1D& basis, double lo, double hi, int points) {
  std::vector<Node1D> out;
  if (!(hi > lo)) return out;
  const QuadratureRule& rule = gaussLegendre(points);
  const int spans = basis.numSpans();
  const int s0 = basis.span(lo);
  for (int s = s0; s < spans; ++s) {
    const double a = std::max(lo, double(s) / spans);
    const double b = std::min(hi, double(s + 1) / spans);
    if (b <= a) {
      if (double(s) / spans >= hi) break;
      continue;
    }
    for (size_t q = 0; q < rule.nodes.size(); ++q) out.push_back({a + (b - a) * rule.nodes[q], (b - a) * rule.weights[q], s});
  }
  return out;
}

SurfaceSample sampleSurface(const LoadContext& ctx, double u, double v, unsigned dependence) {
  LocalBasis bu, bv;
  ctx.space.basisU().evaluate(u, 1, bu);
  ctx.space.basisV().evaluate(v, 1, bv);
  return sampleFromBases(ctx, bu, bv, u, v, dependence);
}

PointForce::PointForce(double u0, double v0, const Eigen::Vector3d& force)
    : m_u(u0), m_v(v0), m_dependence(kConstant), m_stiffness(0.0) {
  checkParam(u0, "point force u");
  checkParam(v0, "point force v");
  checkVector(force, "point force");
  m_force = [force](const SurfaceSample&) { return force; };
}

PointForce::PointForce(double u0, double v0, ForceFunction force, unsigned dependence, double stiffness)
    : m_u(u0), m_v(v0), m_force(std::move(force)), m_dependence(dependence), m_stiffness(stiffness) {
  checkParam(u0, "point force u");
  checkParam(v0, "point force v");
  checkStiffness(stiffness);
  if (!m_force) throw std::invalid_argument("point force callable is empty");
}

void PointForce::addLoad(const LoadContext& ctx, ControlNet& load) const {
  LocalBasis bu, bv;
  ctx.space.basisU().evaluate(m_u, 1, bu);
  ctx.space.basisV().evaluate(m_v, 1, bv);
  const Eigen::Vector3d f = m_force(sampleFromBases(ctx, bu, bv, m_u, m_v, m_dependence));
  scatter(ctx.space, bu, bv, f, load);
}

double PointForce::eigenvalueBound(const MassContext& ctx) const {
  if (m_stiffness == 0.0) return 0.0;
  const SplineSpace& s = ctx.space;
  LocalBasis bu, bv;
  s.basisU().evaluate(m_u, 0, bu);
  s.basisV().evaluate(m_v, 0, bv);
  // beta per control point that moves (net layers i, j): periodic copies of one point add up;
  // a derived point (SIMPLY_SUPPORTED, BUILT_IN) counts with its own mass, which bounds the
  // Rayleigh quotient of the mass T^T W T of the unknowns alike (EdgeMass.h)
  std::vector<std::pair<std::pair<int, int>, double>> beta;
  for (int a = 0; a < bu.count; ++a)
    for (int b = 0; b < bv.count; ++b) {
      const int li = bu.first + a + s.degreeU(), lj = bv.first + b + s.degreeV();
      if (s.foldU(li).empty() || s.foldV(lj).empty()) continue;  // held
      const int mi = s.movingLayerU(li), mj = s.movingLayerV(lj);
      const std::pair<int, int> key(mi >= 0 ? mi : li, mj >= 0 ? mj : lj);
      auto it = std::find_if(beta.begin(), beta.end(), [&](const auto& e) { return e.first == key; });
      if (it == beta.end()) it = beta.insert(beta.end(), {key, 0.0});
      it->second += bu.d[0][a] * bv.d[0][b];
    }
  double sum = 0.0;
  for (const auto& e : beta) sum += e.second * e.second / ctx.massAt(e.first.first, e.first.second);
  return m_stiffness * sum;
}

struct DistributedForce::GaussPlan {
  /// What the rule was made for: the space's shape, the bases' derivative order, the area element
  struct Key {
    int degreeU, degreeV, freeU, freeV, rows, cols, order;
    bool periodicU, periodicV, restArea;
    Key(const SplineSpace& s, int order, bool restArea)
        : degreeU(s.degreeU()), degreeV(s.degreeV()), freeU(s.basisU().numFree()), freeV(s.basisV().numFree()),
          rows(s.netRows()), cols(s.netCols()), order(order), periodicU(s.periodicU()), periodicV(s.periodicV()),
          restArea(restArea) {}
    bool operator==(const Key& o) const {
      return std::tie(degreeU, degreeV, freeU, freeV, rows, cols, order, periodicU, periodicV, restArea) ==
             std::tie(o.degreeU, o.degreeV, o.freeU, o.freeV, o.rows, o.cols, o.order, o.periodicU, o.periodicV,
                      o.restArea);
    }
  };
  explicit GaussPlan(const Key& k) : key(k) {}
  Key key;
  ControlNet rest;  ///< the rest net of the area element (key.restArea)
  // the rule
  std::vector<Node1D> qu, qv;
  std::vector<LocalBasis> bu, bv;
  std::vector<double> w;  ///< per point (i, j) at i qv.size() + j: Gauss weights, times J0 (restArea)
};

struct DistributedForce::PlanCache {
  std::mutex mutex;
  std::shared_ptr<const GaussPlan> plan;
};

DistributedForce::DistributedForce(const Eigen::Vector3d& density, Rect rect)
    : m_isConstant(true), m_constantDensity(density), m_dependence(kConstant), m_rect(rect), m_extraPoints(0),
      m_stiffness(0.0), m_plans(std::make_shared<PlanCache>()) {
  checkVector(density, "force density");
  m_density = [density](const SurfaceSample&) { return density; };
  checkParam(rect.u0, "region u0");
  checkParam(rect.u1, "region u1");
  checkParam(rect.v0, "region v0");
  checkParam(rect.v1, "region v1");
  if (rect.u1 < rect.u0 || rect.v1 < rect.v0)
    throw std::invalid_argument("region must have u0 <= u1 and v0 <= v1, got [" + std::to_string(rect.u0) + ", " +
                                std::to_string(rect.u1) + "] x [" + std::to_string(rect.v0) + ", " +
                                std::to_string(rect.v1) + "]");
}

DistributedForce::DistributedForce(ForceFunction density, unsigned dependence, Rect rect, int extraPoints,
                                   double stiffness)
    : DistributedForce(Eigen::Vector3d::Zero(), rect) {
  if (!density) throw std::invalid_argument("force density callable is empty");
  if (extraPoints < 0 || extraPoints > 16)
    throw std::invalid_argument("extra Gauss points must be between 0 and 16, got " + std::to_string(extraPoints));
  checkStiffness(stiffness);
  m_isConstant = false;
  m_density = std::move(density);
  m_dependence = dependence;
  m_extraPoints = extraPoints;
  m_stiffness = stiffness;
}

namespace {
// l(layer) = integral over [lo, hi] of the B-spline of each moving layer of one direction (a
// periodic copy adds to the layer it repeats, a derived layer to its sources with their
// weights; held layers are left out), with the n+1-point rule on every span split at lo and
// hi: exact. Indexed by moving layer - first moving layer.
std::vector<double> layerIntegrals(const BSplineBasis1D& basis, const LayerRange& moving,
                                   const std::vector<LayerWeight>& (SplineSpace::*fold)(int) const,
                                   const SplineSpace& s, double lo, double hi) {
  std::vector<double> l(size_t(moving.count), 0.0);
  LocalBasis b;
  for (const Node1D& q : splitQuadrature(basis, lo, hi, basis.degree() + 1)) {
    basis.evaluateInSpan(q.span, q.x, 0, b);
    for (int a = 0; a < b.count; ++a)
      for (const LayerWeight& w : (s.*fold)(b.first + a + basis.degree()))
        l[size_t(w.layer - moving.first)] += w.weight * q.w * b.d[0][a];
  }
  return l;
}
}  // namespace

void DistributedForce::addLoad(const LoadContext& ctx, ControlNet& load) const {
  if (isLine()) {
    addLineLoad(ctx, load);
    return;
  }
  if (!m_isConstant || ctx.rest) {
    addLoadByQuadrature(ctx, load);
    return;
  }
  const SplineSpace& s = ctx.space;
  const LayerRange mu = s.movingU(), mv = s.movingV();
  const std::vector<double> lu = layerIntegrals(s.basisU(), mu, &SplineSpace::foldU, s, m_rect.u0, m_rect.u1);
  const std::vector<double> lv = layerIntegrals(s.basisV(), mv, &SplineSpace::foldV, s, m_rect.v0, m_rect.v1);
  // only the B-splines that meet the rectangle: a small region loads few rows
  int b0 = 0, b1 = mv.count;
  while (b0 < b1 && lv[size_t(b0)] == 0.0) ++b0;
  while (b1 > b0 && lv[size_t(b1 - 1)] == 0.0) --b1;
  const double fx = m_constantDensity.x(), fy = m_constantDensity.y(), fz = m_constantDensity.z();
  for (int a = 0; a < mu.count; ++a) {
    const double la = lu[size_t(a)];
    if (la == 0.0) continue;
    double* row = load.data() + 3 * (Eigen::Index(a) * mv.count);
    for (int b = b0; b < b1; ++b) {
      const double w = la * lv[size_t(b)];
      row[3 * b] += w * fx;
      row[3 * b + 1] += w * fy;
      row[3 * b + 2] += w * fz;
    }
  }
}

std::shared_ptr<const DistributedForce::GaussPlan> DistributedForce::gaussPlan(const LoadContext& ctx, int order,
                                                                               bool restArea) const {
  const SplineSpace& s = ctx.space;
  const GaussPlan::Key key(s, order, restArea);
  {
    const std::lock_guard<std::mutex> lock(m_plans->mutex);
    const GaussPlan* p = m_plans->plan.get();
    if (p && p->key == key && (!restArea || (p->rest.rows() == ctx.rest->rows() && p->rest == *ctx.rest)))
      return m_plans->plan;
  }
  auto plan = std::make_shared<GaussPlan>(key);
  if (restArea) plan->rest = *ctx.rest;
  // n+1 points integrate f * B exactly for constant f (B is degree n per span).
  plan->qu = splitQuadrature(s.basisU(), m_rect.u0, m_rect.u1, s.degreeU() + 1 + m_extraPoints);
  plan->qv = splitQuadrature(s.basisV(), m_rect.v0, m_rect.v1, s.degreeV() + 1 + m_extraPoints);
  plan->bu.resize(plan->qu.size());
  plan->bv.resize(plan->qv.size());
  for (size_t i = 0; i < plan->qu.size(); ++i) s.basisU().evaluateInSpan(plan->qu[i].span, plan->qu[i].x, order, plan->bu[i]);
  for (size_t j = 0; j < plan->qv.size(); ++j) s.basisV().evaluateInSpan(plan->qv[j].span, plan->qv[j].x, order, plan->bv[j]);
  plan->w.resize(plan->qu.size() * plan->qv.size());
  for (size_t i = 0; i < plan->qu.size(); ++i)
    for (size_t j = 0; j < plan->qv.size(); ++j) {
      double w = plan->qu[i].w * plan->qv[j].w;
      if (restArea) {
        const SurfacePoint r = s.evaluate(*ctx.rest, plan->bu[i], plan->bv[j], 1);
        w *= r.du.cross(r.dv).norm();
      }
      plan->w[i * plan->qv.size() + j] = w;
    }
  const std::lock_guard<std::mutex> lock(m_plans->mutex);
  m_plans->plan = plan;
  return plan;
}

void DistributedForce::forEachGaussPoint(
    const LoadContext& ctx, unsigned dependence,
    const std::function<void(const SurfaceSample&, double, const LocalBasis&, const LocalBasis&)>& fn) const {
  // physical units: the rest area element J0, or the current one for a follower load
  const bool restArea = ctx.rest && !m_perCurrentArea, currentArea = ctx.rest && m_perCurrentArea;
  dependence |= currentArea ? unsigned(kDependsOnNormal) : 0u;
  const int order = (dependence & kDependsOnNormal) || restArea ? 1 : 0;
  const std::shared_ptr<const GaussPlan> plan = gaussPlan(ctx, order, restArea);
  const size_t nv = plan->qv.size();
  for (size_t i = 0; i < plan->qu.size(); ++i)
    for (size_t j = 0; j < nv; ++j) {
      const SurfaceSample smp = sampleFromBases(ctx, plan->bu[i], plan->bv[j], plan->qu[i].x, plan->qv[j].x, dependence);
      double w = plan->w[i * nv + j];
      if (currentArea) w *= smp.areaElement;
      fn(smp, w, plan->bu[i], plan->bv[j]);
    }
}

void DistributedForce::addLoadByQuadrature(const LoadContext& ctx, ControlNet& load) const {
  forEachGaussPoint(ctx, m_dependence, [&](const SurfaceSample& smp, double w, const LocalBasis& bu, const LocalBasis& bv) {
    scatter(ctx.space, bu, bv, w * m_density(smp), load);
  });
}

static void addBasisBlocks(const SplineSpace& s, const LocalBasis& bu, const LocalBasis& bv, const Eigen::Matrix3d& K,
                    JacobianSink& sink) {
  const int cols = s.netCols();
  for (int a = 0; a < bu.count; ++a)
    for (int b = 0; b < bv.count; ++b) {
      const double Bp = bu.d[0][a] * bv.d[0][b];
      if (Bp == 0.0) continue;
      const Eigen::Index p = Eigen::Index(bu.first + a + s.degreeU()) * cols + bv.first + b + s.degreeV();
      for (int c = 0; c < bu.count; ++c)
        for (int d = 0; d < bv.count; ++d) {
          const double Bq = bu.d[0][c] * bv.d[0][d];
          if (Bq == 0.0) continue;
          const Eigen::Index q = Eigen::Index(bu.first + c + s.degreeU()) * cols + bv.first + d + s.degreeV();
          sink.add(p, q, (Bp * Bq) * K);
        }
    }
}

void DistributedForce::addJacobian(const LoadContext& ctx, double velocityScale, JacobianSink& sink) const {
  if (!m_hasDensityDerivatives || isLine()) return;
  forEachGaussPoint(ctx, m_dependence, [&](const SurfaceSample& smp, double w, const LocalBasis& bu, const LocalBasis& bv) {
    Eigen::Matrix3d Kx, Kv;
    double phi;
    densityDerivatives(smp, Kx, Kv, phi);
    const Eigen::Matrix3d K = w * (Kx + velocityScale * Kv);
    if (!K.isZero(0.0)) addBasisBlocks(ctx.space, bu, bv, K, sink);
  });
}

bool DistributedForce::potential(const LoadContext& ctx, double& value) const {
  value = 0.0;
  if (!m_hasDensityDerivatives || isLine()) return false;
  forEachGaussPoint(ctx, m_dependence, [&](const SurfaceSample& smp, double w, const LocalBasis&, const LocalBasis&) {
    Eigen::Matrix3d Kx, Kv;
    double phi;
    densityDerivatives(smp, Kx, Kv, phi);
    value += w * phi;
  });
  return true;
}

void PointForce::addJacobian(const LoadContext& ctx, double velocityScale, JacobianSink& sink) const {
  if (!m_hasPointDerivatives) return;
  LocalBasis bu, bv;
  ctx.space.basisU().evaluate(m_u, 1, bu);
  ctx.space.basisV().evaluate(m_v, 1, bv);
  Eigen::Matrix3d Kx, Kv;
  double phi;
  pointDerivatives(sampleFromBases(ctx, bu, bv, m_u, m_v, m_dependence), Kx, Kv, phi);
  addBasisBlocks(ctx.space, bu, bv, Kx + velocityScale * Kv, sink);
}

bool PointForce::potential(const LoadContext& ctx, double& value) const {
  value = 0.0;
  if (!m_hasPointDerivatives) return false;
  LocalBasis bu, bv;
  ctx.space.basisU().evaluate(m_u, 1, bu);
  ctx.space.basisV().evaluate(m_v, 1, bv);
  Eigen::Matrix3d Kx, Kv;
  pointDerivatives(sampleFromBases(ctx, bu, bv, m_u, m_v, m_dependence), Kx, Kv, value);
  return true;
}

void DistributedForce::addLineLoad(const LoadContext& ctx, ControlNet& load) const {
  const SplineSpace& s = ctx.space;
  const bool alongV = m_rect.u0 == m_rect.u1;  // the line u = u0, v in [v0, v1]
  const bool point = alongV && m_rect.v0 == m_rect.v1;
  const BSplineBasis1D& basis = alongV ? s.basisV() : s.basisU();
  const double lo = alongV ? m_rect.v0 : m_rect.u0, hi = alongV ? m_rect.v1 : m_rect.u1;
  std::vector<Node1D> nodes =
      point ? std::vector<Node1D>{{m_rect.v0, 1.0, 0}}
            : splitQuadrature(basis, lo, hi, basis.degree() + 1 + (m_isConstant ? 0 : m_extraPoints) + (ctx.rest ? 2 : 0));
  const unsigned dependence = m_dependence | (ctx.rest && m_perCurrentArea ? unsigned(kDependsOnNormal) : 0u);
  LocalBasis bu, bv;
  for (const Node1D& q : nodes) {
    const double u = alongV ? m_rect.u0 : q.x, v = alongV ? q.x : m_rect.v0;
    s.basisU().evaluate(u, 1, bu);
    s.basisV().evaluate(v, 1, bv);
    const SurfaceSample smp = sampleFromBases(ctx, bu, bv, u, v, dependence);
    double w = q.w;
    if (ctx.rest && !point) {
      // length element of the line on the rest surface, or on the current one (follower)
      const SurfacePoint p = s.evaluate(m_perCurrentArea ? ctx.current : *ctx.rest, bu, bv, 1);
      w *= (alongV ? p.dv : p.du).norm();
    }
    scatter(s, bu, bv, w * m_density(smp), load);
  }
}

}  // namespace bsdeform
