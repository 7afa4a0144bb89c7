// SPDX-License-Identifier: MIT
#include "bsdeform/spline/SplineSpace.h"

#include "bsdeform/forces/LoadQuadrature.h"
#include "bsdeform/base/ParameterError.h"

#include <Eigen/LU>
#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "bsdeform/base/HugePages.h"

namespace bsdeform {

Eigen::Vector3d SurfacePoint::normal() const {
  Eigen::Vector3d n = du.cross(dv);
  const double len = n.norm();
  return len > 0.0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
}

namespace {
BSplineBasis1D makeBasis(int degree, int numFree, const char* degreeName, const char* countName) {
  requireParameter(degree >= 1 && degree <= kMaxDegree, degreeName,
                   "must be between 1 and " + std::to_string(kMaxDegree) + ", got " + std::to_string(degree));
  requireParameter(numFree >= 1, countName, "(free control points) must be at least 1, got " + std::to_string(numFree));
  requireParameter(numFree <= kMaxPerSide, countName,
                   "must be at most " + std::to_string(kMaxPerSide) + ", got " + std::to_string(numFree));
  return BSplineBasis1D(degree, numFree);
}
}  // namespace

const char* boundaryName(Boundary b) {
  switch (b) {
    case Boundary::Clamped: return "CLAMPED";
    case Boundary::Free: return "FREE";
    case Boundary::Periodic: return "PERIODIC";
    case Boundary::SimplySupported: return "SIMPLY_SUPPORTED";
    case Boundary::BuiltIn: return "BUILT_IN";
  }
  return "?";
}

EdgeLayers edgeLayers(Boundary side, int n) {
  EdgeLayers e;
  switch (side) {
    case Boundary::Free:
    case Boundary::Periodic: return e;
    case Boundary::Clamped: e.held = n; return e;
    case Boundary::SimplySupported:
      if (n == 1) {
        e.held = 1;
        return e;
      }
      e.derived = 1;
      break;
    case Boundary::BuiltIn:
      if (n <= 2) {
        e.held = 2;  // degree 2: both outer layers (= CLAMPED); degree 1: the outer one and k = 0
        return e;
      }
      e.derived = 2;
      break;
  }
  // The side u = 0 in cardinal coordinates x = u/h: outer layer l = 0..n-1 (l = 0 at the edge) is
  // function k = l - n, b^n(x - k); at x = 0 its value is b^n(n - l) and its derivative
  // b^n'(n - l) (continuous there for n >= 2). The side u = 1 is the mirror image (the derivative
  // changes sign, which leaves Z alone).
  const int r = e.derived;
  e.sources = n - r;
  Eigen::MatrixXd C(r, n);
  for (int l = 0; l < n; ++l) {
    C(0, l) = cardinalBSpline(n, n - l);
    if (r == 2) C(1, l) = cardinalBSplineDerivative(n, 1, n - l);
  }
  // eliminate the r outermost layers: C_E P_E + C_S P_S = g  =>  P_E = C_E^-1 (g - C_S P_S)
  e.Z = -C.leftCols(r).fullPivLu().solve(C.rightCols(e.sources));
  return e;
}

namespace {
LayerRange movingLayers(const BSplineBasis1D& basis, Boundary lo, Boundary hi, const char* loName, const char* hiName) {
  if ((lo == Boundary::Periodic) != (hi == Boundary::Periodic))
    throw ParameterError(lo == Boundary::Periodic ? loName : hiName,
                         std::string("is PERIODIC but ") + (lo == Boundary::Periodic ? hiName : loName) + " is " +
                             boundaryName(lo == Boundary::Periodic ? hi : lo) +
                             ": a periodic direction needs PERIODIC on both sides");
  const int n = basis.degree(), N = basis.numFree();
  if (lo == Boundary::Periodic) return {n, N + n};
  const EdgeLayers a = edgeLayers(lo, n), b = edgeLayers(hi, n);
  const int first = a.held + a.derived, last = N + 2 * n - (b.held + b.derived);
  if (last - first < 1)
    throw ParameterError(loName, std::string(boundaryName(lo)) + " and " + hiName + " " + boundaryName(hi) +
                                     " hold every control point of the " + std::to_string(N) +
                                     " inner layers at degree " + std::to_string(n) + ": give more control points");
  return {first, last - first};
}

// Derived layers of the two sides of one direction, and every layer's fold (SplineSpace::foldU).
void buildFold(const BSplineBasis1D& basis, Boundary lo, Boundary hi, const LayerRange& moving,
               std::vector<SplineSpace::DerivedSide>& sides, std::vector<std::vector<LayerWeight>>& fold) {
  const int n = basis.degree(), layers = basis.numTotal();
  fold.assign(size_t(layers), {});
  if (lo == Boundary::Periodic) {
    for (int l = 0; l < layers; ++l) {
      const int target = l < n ? l + moving.count : l;
      fold[size_t(l)].push_back({target, 1.0});
    }
    return;
  }
  for (int l = moving.first; l < moving.first + moving.count; ++l) fold[size_t(l)].push_back({l, 1.0});
  for (int side = 0; side < 2; ++side) {
    const EdgeLayers e = edgeLayers(side == 0 ? lo : hi, n);
    if (e.derived == 0) continue;
    // outer layer l (from the edge) is net layer l on the low side, layers - 1 - l on the high one
    auto net = [&](int l) { return side == 0 ? l : layers - 1 - l; };
    SplineSpace::DerivedSide d;
    d.Z = e.Z;
    for (int r = 0; r < e.derived; ++r) d.derived.push_back(net(e.held + r));
    for (int s = 0; s < e.sources; ++s) d.sources.push_back(net(e.held + e.derived + s));
    for (int r = 0; r < e.derived; ++r)
      for (int s = 0; s < e.sources; ++s)
        if (e.Z(r, s) != 0.0) fold[size_t(d.derived[size_t(r)])].push_back({d.sources[size_t(s)], e.Z(r, s)});
    sides.push_back(std::move(d));
  }
}

int movingLayer(const LayerRange& r, bool periodic, int n, int layer) {
  if (periodic && layer < n) layer += r.count;  // copy layer k = -n..-1 stands for k + (N+n)
  return r.contains(layer) ? layer : -1;
}
}  // namespace

SplineSpace::SplineSpace(int degreeU, int degreeV, int numU, int numV, const Boundaries& b)
    : m_u(makeBasis(degreeU, numU, "degreeU", "numU")),
      m_v(makeBasis(degreeV, numV, "degreeV", "numV")),
      m_boundaries(b),
      m_movingU(movingLayers(m_u, b.uMin, b.uMax, "boundaryUMin", "boundaryUMax")),
      m_movingV(movingLayers(m_v, b.vMin, b.vMax, "boundaryVMin", "boundaryVMax")) {
  buildFold(m_u, b.uMin, b.uMax, m_movingU, m_derivedU, m_foldU);
  buildFold(m_v, b.vMin, b.vMax, m_movingV, m_derivedV, m_foldV);
  m_hasDerived = !m_derivedU.empty() || !m_derivedV.empty();
  const long long points = static_cast<long long>(numU) * numV;
  if (points > kMaxInnerPoints)
    throw ParameterError("numU",
                         "must be at most " + std::to_string(kMaxInnerPoints) +
                             " (2048^2; about 1 GB of memory), got " + std::to_string(points),
                         "numU * numV");
}

void SplineSpace::foldMap(std::vector<int>& start, std::vector<std::pair<Eigen::Index, double>>& entries) const {
  const int cols = netCols();
  start.assign(size_t(netSize()) + 1, 0);
  entries.clear();
  for (int i = 0; i < netRows(); ++i)
    for (int j = 0; j < cols; ++j) {
      for (const LayerWeight& wu : foldU(i))
        for (const LayerWeight& wv : foldV(j))
          entries.emplace_back(Eigen::Index(wu.layer - m_movingU.first) * m_movingV.count + (wv.layer - m_movingV.first),
                               wu.weight * wv.weight);
      start[size_t(i) * cols + j + 1] = int(entries.size());
    }
}

int SplineSpace::movingLayerU(int i) const { return movingLayer(m_movingU, periodicU(), degreeU(), i); }
int SplineSpace::movingLayerV(int j) const { return movingLayer(m_movingV, periodicV(), degreeV(), j); }

Eigen::Index SplineSpace::movingIndex(int k1, int k2) const {
  const int i = movingLayerU(k1 + degreeU()), j = movingLayerV(k2 + degreeV());
  if (i < 0 || j < 0) return -1;
  return Eigen::Index(i - m_movingU.first) * m_movingV.count + (j - m_movingV.first);
}

double SplineSpace::grevilleU(int k1) const { return (k1 + 0.5 * (degreeU() + 1)) * m_u.spacing(); }
double SplineSpace::grevilleV(int k2) const { return (k2 + 0.5 * (degreeV() + 1)) * m_v.spacing(); }

ControlNet SplineSpace::grevillePlane() const {
  ControlNet net;
  allocateNet(net, netSize());
  std::vector<double> gv(static_cast<size_t>(netCols()));
  for (int j = 0; j < netCols(); ++j) gv[size_t(j)] = grevilleV(j - degreeV());
  for (int i = 0; i < netRows(); ++i) {
    const double gu = grevilleU(i - degreeU());
    double* row = net.data() + 3 * (Eigen::Index(i) * netCols());
    for (int j = 0; j < netCols(); ++j) {
      row[3 * j] = gu;
      row[3 * j + 1] = gv[size_t(j)];
      row[3 * j + 2] = 0.0;
    }
  }
  return net;
}

ControlNet SplineSpace::gatherMoving(const ControlNet& net) const {
  ControlNet f(numMoving(), 3);
  // a moving u-layer is one run of movingV().count points in the net
  const Eigen::Index w = m_movingV.count;
  for (int a = 0; a < m_movingU.count; ++a) f.middleRows(a * w, w) = net.middleRows(movingToNet(a * w), w);
  return f;
}

void SplineSpace::scatterMoving(const ControlNet& movingPoints, ControlNet& net) const {
  const Eigen::Index w = m_movingV.count;
  for (int a = 0; a < m_movingU.count; ++a) net.middleRows(movingToNet(a * w), w) = movingPoints.middleRows(a * w, w);
  refreshPeriodicCopies(net);
}

void SplineSpace::refreshPeriodicCopies(ControlNet& net) const {
  const int rows = netRows(), cols = netCols();
  if (periodicU()) {
    const int n = degreeU(), shift = m_movingU.count;
    for (int i = 0; i < n; ++i) net.middleRows(Eigen::Index(i) * cols, cols) = net.middleRows(Eigen::Index(i + shift) * cols, cols);
  }
  if (periodicV()) {
    const int n = degreeV(), shift = m_movingV.count;
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < n; ++j) net.row(Eigen::Index(i) * cols + j) = net.row(Eigen::Index(i) * cols + j + shift);
  }
}

void SplineSpace::refreshDerived(ControlNet& net, const ControlNet* rest) const {
  if (!m_hasDerived) return;
  const int rows = netRows(), cols = netCols();
  // u sides: whole net rows
  for (const DerivedSide& d : m_derivedU)
    for (size_t r = 0; r < d.derived.size(); ++r) {
      double* dst = net.data() + 3L * d.derived[r] * cols;
      const double* rd = rest ? rest->data() + 3L * d.derived[r] * cols : nullptr;
      for (long m = 0; m < 3L * cols; ++m) dst[m] = rd ? rd[m] : 0.0;
      for (size_t s = 0; s < d.sources.size(); ++s) {
        const double z = d.Z(Eigen::Index(r), Eigen::Index(s));
        const double* src = net.data() + 3L * d.sources[s] * cols;
        const double* rs = rest ? rest->data() + 3L * d.sources[s] * cols : nullptr;
        if (rs)
          for (long m = 0; m < 3L * cols; ++m) dst[m] += z * (src[m] - rs[m]);
        else
          for (long m = 0; m < 3L * cols; ++m) dst[m] += z * src[m];
      }
    }
  // v sides: every row, derived rows of the u sides included (a corner follows both)
  for (const DerivedSide& d : m_derivedV)
    for (int i = 0; i < rows; ++i)
      for (size_t r = 0; r < d.derived.size(); ++r) {
        const Eigen::Index e = Eigen::Index(i) * cols + d.derived[r];
        Eigen::RowVector3d p = rest ? Eigen::RowVector3d(rest->row(e)) : Eigen::RowVector3d::Zero();
        for (size_t s = 0; s < d.sources.size(); ++s) {
          const Eigen::Index src = Eigen::Index(i) * cols + d.sources[s];
          const double z = d.Z(Eigen::Index(r), Eigen::Index(s));
          p += z * (rest ? Eigen::RowVector3d(net.row(src) - rest->row(src)) : Eigen::RowVector3d(net.row(src)));
        }
        net.row(e) = p;
      }
}

double SplineSpace::derivedMismatch(const ControlNet& net, const ControlNet& rest) const {
  if (!m_hasDerived) return 0.0;
  ControlNet fixed = net;
  refreshDerived(fixed, &rest);
  double worst = 0.0;
  for (Eigen::Index r = 0; r < net.rows(); ++r)
    worst = std::max(worst, (fixed.row(r) - net.row(r)).cwiseAbs().maxCoeff() / (1.0 + rest.row(r).cwiseAbs().maxCoeff()));
  return worst;
}

double SplineSpace::closePeriodic(ControlNet& net) const {
  const int rows = netRows(), cols = netCols();
  double diff = 0.0;
  if (periodicU()) {
    const int n = degreeU(), shift = m_movingU.count;
    for (int i = 0; i < n; ++i) {
      auto first = net.middleRows(Eigen::Index(i) * cols, cols);
      auto last = net.middleRows(Eigen::Index(i + shift) * cols, cols);
      diff = std::max(diff, (first - last).cwiseAbs().maxCoeff());
      last = first;
    }
  }
  if (periodicV()) {
    const int n = degreeV(), shift = m_movingV.count;
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < n; ++j) {
        const Eigen::Index a = Eigen::Index(i) * cols + j;
        diff = std::max(diff, (net.row(a) - net.row(a + shift)).cwiseAbs().maxCoeff());
        net.row(a + shift) = net.row(a);
      }
  }
  return diff;
}

SurfacePoint SplineSpace::evaluate(const ControlNet& net, double u, double v, int order) const {
  LocalBasis bu, bv;
  m_u.evaluate(u, order, bu);
  m_v.evaluate(v, order, bv);
  return evaluate(net, bu, bv, order);
}

SurfacePoint SplineSpace::evaluate(const ControlNet& net, const LocalBasis& bu, const LocalBasis& bv, int order) const {
  SurfacePoint p;
  const int nu = degreeU(), nv = degreeV();
  for (int a = 0; a < bu.count; ++a) {
    Eigen::Vector3d c0 = Eigen::Vector3d::Zero(), c1 = Eigen::Vector3d::Zero(), c2 = Eigen::Vector3d::Zero();
    const Eigen::Index rowBase = Eigen::Index(bu.first + a + nu) * netCols() + (bv.first + nv);
    for (int b = 0; b < bv.count; ++b) {
      const Eigen::Vector3d P = net.row(rowBase + b).transpose();
      c0 += bv.d[0][b] * P;
      if (order >= 1) c1 += bv.d[1][b] * P;
      if (order >= 2) c2 += bv.d[2][b] * P;
    }
    p.position += bu.d[0][a] * c0;
    if (order >= 1) {
      p.du += bu.d[1][a] * c0;
      p.dv += bu.d[0][a] * c1;
    }
    if (order >= 2) {
      p.duu += bu.d[2][a] * c0;
      p.duv += bu.d[1][a] * c1;
      p.dvv += bu.d[0][a] * c2;
    }
  }
  return p;
}

namespace {
// Whether the edge where `param` (u when alongU, else v) is `at` is one point.
bool edgeCollapses(const SplineSpace& space, const ControlNet& net, bool alongU, double at, double tolerance) {
  constexpr int kSamples = 9;
  Eigen::Vector3d first;
  for (int k = 0; k < kSamples; ++k) {
    const double s = double(k) / (kSamples - 1);
    const Eigen::Vector3d p = alongU ? space.evaluate(net, s, at, 0).position : space.evaluate(net, at, s, 0).position;
    if (k == 0) first = p;
    else if ((p - first).norm() > tolerance) return false;
  }
  return true;
}
}  // namespace

bool isClosedSurface(const SplineSpace& space, const ControlNet& net) {
  if (!space.periodicU() && !space.periodicV()) return false;
  const double tolerance = 1e-9 * (1.0 + (net.rows() ? net.cwiseAbs().maxCoeff() : 0.0));
  auto closedAcross = [&](bool periodic, bool alongU) {
    return periodic || (edgeCollapses(space, net, alongU, 0.0, tolerance) && edgeCollapses(space, net, alongU, 1.0, tolerance));
  };
  // the v edges run along u (v = 0, v = 1); the u edges along v
  return closedAcross(space.periodicV(), true) && closedAcross(space.periodicU(), false);
}

double surfaceArea(const SplineSpace& space, const ControlNet& net) {
  const std::vector<Node1D> qu = splitQuadrature(space.basisU(), 0.0, 1.0, space.degreeU() + 3);
  const std::vector<Node1D> qv = splitQuadrature(space.basisV(), 0.0, 1.0, space.degreeV() + 3);
  std::vector<LocalBasis> bv(qv.size());
  for (std::size_t j = 0; j < qv.size(); ++j) space.basisV().evaluateInSpan(qv[j].span, qv[j].x, 1, bv[j]);
  double area = 0.0;
  LocalBasis bu;
  for (const Node1D& nu : qu) {
    space.basisU().evaluateInSpan(nu.span, nu.x, 1, bu);
    for (std::size_t j = 0; j < qv.size(); ++j) {
      const SurfacePoint p = space.evaluate(net, bu, bv[j], 1);
      area += nu.w * qv[j].w * p.du.cross(p.dv).norm();
    }
  }
  return area;
}

}  // namespace bsdeform
