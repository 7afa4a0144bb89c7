// SPDX-License-Identifier: MIT
#include "bsdeform/contact/CollisionProxy.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/LU>

#include "bsdeform/forces/LoadQuadrature.h"

namespace bsdeform {

namespace {
// Basis values below this are rounding of an exact zero (a vertex on a knot line evaluates the
// function that starts there at tau ~ 1e-16, where it is ~1e-48): leaving them out keeps every
// triangle's vertices on the control points of its own element.
constexpr double kZeroWeight = 1e-14;
Eigen::MatrixXd bsplineToBezier(int p);
}  // namespace

CollisionProxy::CollisionProxy(const SplineSpace& space, int samplesPerSpan)
    : m_space(space), m_samples(samplesPerSpan) {
  if (samplesPerSpan < 1 || samplesPerSpan > 16)
    throw std::invalid_argument("collision proxy samples per knot span must be 1..16, got " +
                                std::to_string(samplesPerSpan));
  const int su = space.basisU().numSpans(), sv = space.basisV().numSpans();
  const bool pu = space.periodicU(), pv = space.periodicV();
  const int cellsU = su * samplesPerSpan, cellsV = sv * samplesPerSpan;
  const int nu = pu ? cellsU : cellsU + 1, nv = pv ? cellsV : cellsV + 1;
  const int nu1 = space.degreeU(), nv1 = space.degreeV(), cols = space.netCols();
  const int firstU = space.movingU().first, firstV = space.movingV().first, width = space.movingV().count;
  m_params.reserve(size_t(nu) * nv);
  m_netStart.reserve(size_t(nu) * nv + 1);
  m_netStart.push_back(0);
  m_movingWeights.resize(size_t(nu) * nv);
  LocalBasis bu, bv;
  for (int i = 0; i < nu; ++i) {
    const double u = double(i) / cellsU;
    space.basisU().evaluate(u, 0, bu);
    for (int j = 0; j < nv; ++j) {
      const double v = double(j) / cellsV;
      space.basisV().evaluate(v, 0, bv);
      const size_t k = size_t(i) * nv + j;
      m_params.emplace_back(u, v);
      for (int a = 0; a < bu.count; ++a)
        for (int b = 0; b < bv.count; ++b) {
          const double w = bu.d[0][a] * bv.d[0][b];
          if (std::abs(w) < kZeroWeight) continue;
          m_netWeights.push_back({Eigen::Index(bu.first + a + nu1) * cols + (bv.first + b + nv1), w});
        }
      m_netStart.push_back(m_netWeights.size());  // vertices come in the order of k
      std::vector<Weight>& mw = m_movingWeights[k];
      forEachMovingBasis(space, bu, bv, [&](int li, int lj, double w) {
        if (std::abs(w) < kZeroWeight) return;
        const Eigen::Index row = Eigen::Index(li - firstU) * width + (lj - firstV);
        auto it = std::find_if(mw.begin(), mw.end(), [&](const Weight& e) { return e.index == row; });
        if (it == mw.end())
          mw.push_back({row, w});
        else
          it->weight += w;
      });
    }
  }
  auto vertex = [&](int i, int j) { return int((i % nu) * nv + (j % nv)); };
  m_triangles.resize(Eigen::Index(2) * cellsU * cellsV, 3);
  m_triangleElement.reserve(size_t(2) * cellsU * cellsV);
  Eigen::Index t = 0;
  for (int i = 0; i < cellsU; ++i)
    for (int j = 0; j < cellsV; ++j) {
      const int a = vertex(i, j), b = vertex(i + 1, j), c = vertex(i + 1, j + 1), d = vertex(i, j + 1);
      // counter-clockwise in (u, v): the normals point along S_u x S_v
      m_triangles.row(t++) << a, b, c;
      m_triangles.row(t++) << a, c, d;
      const std::pair<int, int> element(i / samplesPerSpan, j / samplesPerSpan);
      m_triangleElement.push_back(element);
      m_triangleElement.push_back(element);
    }
  // each undirected edge once: along u, along v, and the cells' diagonals
  std::vector<Eigen::Vector2i> edges;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      if (i + 1 < nu || pu) edges.emplace_back(vertex(i, j), vertex(i + 1, j));
      if (j + 1 < nv || pv) edges.emplace_back(vertex(i, j), vertex(i, j + 1));
      if ((i + 1 < nu || pu) && (j + 1 < nv || pv)) edges.emplace_back(vertex(i, j), vertex(i + 1, j + 1));
    }
  for (int p = 0; p <= std::max(space.degreeU(), space.degreeV()); ++p) m_bezier.push_back(bsplineToBezier(p));
  m_edges.resize(Eigen::Index(edges.size()), 2);
  for (size_t e = 0; e < edges.size(); ++e) m_edges.row(Eigen::Index(e)) = edges[e].transpose();
}

void CollisionProxy::positions(const ControlNet& net, Eigen::MatrixX3d& out) const {
  out.resize(numVertices(), 3);
  for (Eigen::Index k = 0; k < numVertices(); ++k) {
    Eigen::RowVector3d x = Eigen::RowVector3d::Zero();
    for (const Weight& w : netWeights(k)) x += w.weight * net.row(w.index);
    out.row(k) = x;
  }
}

void CollisionProxy::positions(const ControlNet& net, const Eigen::Matrix3d& linear, const Eigen::Vector3d& offset,
                               Eigen::MatrixX3d& out) const {
  const Eigen::Index n = numVertices();
  assert(net.rows() == m_space.netSize() && "CollisionProxy::positions: the net of the proxy's spline space");
  out.resize(n, 3);
  const double* X = net.data();  // row-major: point r at X[3 r .. 3 r + 2]
  double* o0 = out.col(0).data();
  double* o1 = out.col(1).data();
  double* o2 = out.col(2).data();
  for (Eigen::Index k = 0; k < n; ++k) {
    double x = 0.0, y = 0.0, z = 0.0;
    for (const Weight& e : netWeights(k)) {
      const double* p = X + 3 * size_t(e.index);
      x += e.weight * p[0];
      y += e.weight * p[1];
      z += e.weight * p[2];
    }
    double* o[3] = {o0, o1, o2};
    for (int c = 0; c < 3; ++c) {
      double t = 0.0;
      t += x * linear(c, 0);
      t += y * linear(c, 1);
      t += z * linear(c, 2);
      o[c][k] = (0.0 + t) + offset(c);
    }
  }
}

void CollisionProxy::addVertexForces(const Eigen::MatrixX3d& f, ControlNet& load) const {
  for (Eigen::Index k = 0; k < numVertices(); ++k) {
    if (f.row(k).isZero(0.0)) continue;
    for (const Weight& w : m_movingWeights[size_t(k)]) load.row(w.index) += w.weight * f.row(k);
  }
}

namespace {
/// Bézier coefficients of the p + 1 uniform B-splines of one span: b_i = Σ_j M(j, i) B_j^p, so the
/// Bézier coefficients of Σ_i c_i b_i are M c. Found by interpolation at p + 1 points of the span.
Eigen::MatrixXd bsplineToBezier(int p) {
  if (p == 0) return Eigen::MatrixXd::Identity(1, 1);
  const BSplineBasis1D basis(p, p + 1);  // any span of a uniform spline has the same functions
  const int span = p;
  Eigen::MatrixXd B(p + 1, p + 1), V(p + 1, p + 1);
  LocalBasis lb;
  for (int k = 0; k <= p; ++k) {
    const double t = (k + 0.5) / (p + 1);
    basis.evaluateInSpan(span, (span + t) * basis.spacing(), 0, lb);
    for (int i = 0; i <= p; ++i) V(k, i) = lb.d[0][i];
    double binom = 1.0;
    for (int j = 0; j <= p; ++j) {
      B(k, j) = binom * std::pow(t, j) * std::pow(1.0 - t, p - j);
      binom = binom * (p - j) / (j + 1);
    }
  }
  return B.partialPivLu().solve(V);
}

/// The largest norm of the Bézier coefficients of Σ c_ab β_a(u) γ_b(v) over one span, given the
/// coefficients c (rows × cols of 3-vectors, row-major) and the two directions' matrices.
double bezierMaxNorm(const std::vector<Eigen::Vector3d>& c, int rows, int cols, const Eigen::MatrixXd& Mu,
                     const Eigen::MatrixXd& Mv) {
  double worst = 0.0;
  for (int a = 0; a < rows; ++a)
    for (int b = 0; b < cols; ++b) {
      Eigen::Vector3d x = Eigen::Vector3d::Zero();
      for (int i = 0; i < rows; ++i)
        for (int j = 0; j < cols; ++j) x += Mu(a, i) * Mv(b, j) * c[size_t(i * cols + j)];
      worst = std::max(worst, x.norm());
    }
  return worst;
}
}  // namespace

double CollisionProxy::deviationBound(const ControlNet& net) const {
  const int nu = m_space.degreeU(), nv = m_space.degreeV(), cols = m_space.netCols();
  const int spansU = m_space.basisU().numSpans(), spansV = m_space.basisV().numSpans();
  auto M = [&](int p) -> const Eigen::MatrixXd& { return m_bezier[size_t(p)]; };
  double worst = 0.0;
  std::vector<Eigen::Vector3d> c;
  for (int e1 = 0; e1 < spansU; ++e1)
    for (int e2 = 0; e2 < spansV; ++e2) {
      // the span's control points are net layers e1 .. e1 + nu, e2 .. e2 + nv
      auto P = [&](int i, int j) { return Eigen::Vector3d(net.row(Eigen::Index(e1 + i) * cols + (e2 + j)).transpose()); };
      double uu = 0.0, uv = 0.0, vv = 0.0;
      if (nu >= 2) {  // h² S_uu: second differences along u, degree (nu - 2, nv)
        c.clear();
        for (int i = 0; i + 2 <= nu; ++i)
          for (int j = 0; j <= nv; ++j) c.push_back(P(i + 2, j) - 2.0 * P(i + 1, j) + P(i, j));
        uu = bezierMaxNorm(c, nu - 1, nv + 1, M(nu - 2), M(nv));
      }
      if (nv >= 2) {
        c.clear();
        for (int i = 0; i <= nu; ++i)
          for (int j = 0; j + 2 <= nv; ++j) c.push_back(P(i, j + 2) - 2.0 * P(i, j + 1) + P(i, j));
        vv = bezierMaxNorm(c, nu + 1, nv - 1, M(nu), M(nv - 2));
      }
      c.clear();  // h_u h_v S_uv: mixed differences, degree (nu - 1, nv - 1)
      for (int i = 0; i + 1 <= nu; ++i)
        for (int j = 0; j + 1 <= nv; ++j) c.push_back(P(i + 1, j + 1) - P(i + 1, j) - P(i, j + 1) + P(i, j));
      uv = bezierMaxNorm(c, nu, nv, M(nu - 1), M(nv - 1));
      worst = std::max(worst, uu + 2.0 * uv + vv);
    }
  return worst / (8.0 * m_samples * m_samples);
}

}  // namespace bsdeform
