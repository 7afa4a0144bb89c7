// SPDX-License-Identifier: MIT
#include "bsdeform/contact/CollisionProxy.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "bsdeform/forces/LoadQuadrature.h"

namespace bsdeform {

namespace {
// Basis values below this are rounding of an exact zero (a vertex on a knot line evaluates the
// function that starts there at tau ~ 1e-16, where it is ~1e-48): leaving them out keeps every
// triangle's vertices on the control points of its own element.
constexpr double kZeroWeight = 1e-14;
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
  m_netWeights.resize(size_t(nu) * nv);
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
          m_netWeights[k].push_back({Eigen::Index(bu.first + a + nu1) * cols + (bv.first + b + nv1), w});
        }
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
  m_edges.resize(Eigen::Index(edges.size()), 2);
  for (size_t e = 0; e < edges.size(); ++e) m_edges.row(Eigen::Index(e)) = edges[e].transpose();
}

void CollisionProxy::positions(const ControlNet& net, Eigen::MatrixX3d& out) const {
  out.resize(numVertices(), 3);
  for (Eigen::Index k = 0; k < numVertices(); ++k) {
    Eigen::RowVector3d x = Eigen::RowVector3d::Zero();
    for (const Weight& w : m_netWeights[size_t(k)]) x += w.weight * net.row(w.index);
    out.row(k) = x;
  }
}

void CollisionProxy::addVertexForces(const Eigen::MatrixX3d& f, ControlNet& load) const {
  for (Eigen::Index k = 0; k < numVertices(); ++k) {
    if (f.row(k).isZero(0.0)) continue;
    for (const Weight& w : m_movingWeights[size_t(k)]) load.row(w.index) += w.weight * f.row(k);
  }
}

double CollisionProxy::deviationBound(const ControlNet& net) const {
  const int rows = m_space.netRows(), cols = m_space.netCols();
  auto P = [&](int i, int j) { return net.row(Eigen::Index(i) * cols + j); };
  double uu = 0.0, uv = 0.0, vv = 0.0;
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      if (i >= 1 && i + 1 < rows) uu = std::max(uu, (P(i + 1, j) - 2.0 * P(i, j) + P(i - 1, j)).norm());
      if (j >= 1 && j + 1 < cols) vv = std::max(vv, (P(i, j + 1) - 2.0 * P(i, j) + P(i, j - 1)).norm());
      if (i + 1 < rows && j + 1 < cols) uv = std::max(uv, (P(i + 1, j + 1) - P(i + 1, j) - P(i, j + 1) + P(i, j)).norm());
    }
  // degree 1 in a direction: the surface is linear along it inside a span, and the proxy's
  // vertices lie on the knots, so that direction's second derivative never enters
  if (m_space.degreeU() < 2) uu = 0.0;
  if (m_space.degreeV() < 2) vv = 0.0;
  return (uu + 2.0 * uv + vv) / (8.0 * m_samples * m_samples);
}

}  // namespace bsdeform
