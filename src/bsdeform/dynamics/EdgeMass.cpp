// SPDX-License-Identifier: MIT
#include "bsdeform/dynamics/EdgeMass.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cassert>

namespace bsdeform {

namespace {
// Rows of the 1-D mass T^T W T over the moving layers, and of its inverse: diagonal W_i except
// on the source layers of a side with derived layers, where the block is
// diag(W_s) + Z^T diag(W_e) Z.
void buildRows(const LayerRange& moving, const std::vector<SplineSpace::DerivedSide>& sides, const std::vector<double>& w,
               std::vector<std::vector<LayerWeight>>& rows, std::vector<std::vector<LayerWeight>>& inverse,
               std::vector<int>& blockOf) {
  rows.assign(w.size(), {});
  inverse.assign(w.size(), {});
  blockOf.assign(w.size(), -1);
  for (int l = moving.first; l < moving.first + moving.count; ++l) {
    rows[size_t(l)] = {{l, w[size_t(l)]}};
    inverse[size_t(l)] = {{l, 1.0 / w[size_t(l)]}};
  }
  for (size_t side = 0; side < sides.size(); ++side) {
    const SplineSpace::DerivedSide& d = sides[side];
    const int ns = int(d.sources.size()), nd = int(d.derived.size());
    for (int a = 0; a < ns; ++a) blockOf[size_t(d.sources[size_t(a)])] = int(side);
    Eigen::MatrixXd block = Eigen::MatrixXd::Zero(ns, ns);
    for (int a = 0; a < ns; ++a) block(a, a) = w[size_t(d.sources[size_t(a)])];
    for (int e = 0; e < nd; ++e) {
      const double we = w[size_t(d.derived[size_t(e)])];
      block += we * d.Z.row(e).transpose() * d.Z.row(e);
    }
    const Eigen::MatrixXd inv = block.llt().solve(Eigen::MatrixXd::Identity(ns, ns));
    for (int a = 0; a < ns; ++a) {
      std::vector<LayerWeight>& r = rows[size_t(d.sources[size_t(a)])];
      std::vector<LayerWeight>& q = inverse[size_t(d.sources[size_t(a)])];
      r.clear();
      q.clear();
      for (int b = 0; b < ns; ++b) {
        r.push_back({d.sources[size_t(b)], block(a, b)});
        q.push_back({d.sources[size_t(b)], inv(a, b)});
      }
    }
  }
}
}  // namespace

EdgeMass::EdgeMass(const SplineSpace& space, const GramRows1D& gu, const GramRows1D& gv, bool lumped, double density)
    : m_space(&space), m_scale(density) {
  m_wu.resize(size_t(space.netRows()));
  m_wv.resize(size_t(space.netCols()));
  for (int i = 0; i < space.netRows(); ++i) m_wu[size_t(i)] = lumped ? gu.rowSum(gu.rowType(i)) : 1.0;
  for (int j = 0; j < space.netCols(); ++j) m_wv[size_t(j)] = lumped ? gv.rowSum(gv.rowType(j)) : 1.0;
  buildRows(space.movingU(), space.derivedU(), m_wu, m_rowU, m_invU, m_blockU);
  buildRows(space.movingV(), space.derivedV(), m_wv, m_rowV, m_invV, m_blockV);
}

std::pair<long long, long long> EdgeMass::groupKey(int i, int j) const {
  // a source block by its number, a layer of its own by -1 - layer
  return {m_blockU[size_t(i)] >= 0 ? m_blockU[size_t(i)] : -1LL - i, m_blockV[size_t(j)] >= 0 ? m_blockV[size_t(j)] : -1LL - j};
}

const EdgeMass::PinnedGroup* EdgeMass::pinnedGroup(int i, int j) const {
  if (m_pinnedGroups.empty()) return nullptr;
  const auto key = groupKey(i, j);
  for (const auto& g : m_pinnedGroups)
    if (g.first == key) return &g.second;
  return nullptr;
}

void EdgeMass::setPinned(const std::vector<Eigen::Index>& pinnedMoving) {
  const SplineSpace& s = *m_space;
  const LayerRange mu = s.movingU(), mv = s.movingV();
  m_pinned.assign(size_t(s.numMoving()), 0);
  m_pinnedGroups.clear();
  for (Eigen::Index f : pinnedMoving) m_pinned[size_t(f)] = 1;
  for (Eigen::Index f : pinnedMoving) {
    const Eigen::Index n = s.movingToNet(f);
    const int i = int(n / s.netCols()), j = int(n % s.netCols());
    const auto key = groupKey(i, j);
    if (m_rowU[size_t(i)].size() == 1 && m_rowV[size_t(j)].size() == 1) continue;  // M is diagonal there
    if (pinnedGroup(i, j)) continue;
    PinnedGroup g;
    for (const LayerWeight& a : m_rowU[size_t(i)])
      for (const LayerWeight& b : m_rowV[size_t(j)]) {
        const Eigen::Index h = Eigen::Index(a.layer - mu.first) * mv.count + (b.layer - mv.first);
        if (!m_pinned[size_t(h)]) g.free.push_back(h);
      }
    const Eigen::Index k = Eigen::Index(g.free.size());
    Eigen::MatrixXd block(k, k);
    for (Eigen::Index a = 0; a < k; ++a) {
      const Eigen::Index na = s.movingToNet(g.free[size_t(a)]);
      const int ia = int(na / s.netCols()), ja = int(na % s.netCols());
      for (Eigen::Index b = 0; b < k; ++b) {
        const Eigen::Index nb = s.movingToNet(g.free[size_t(b)]);
        const int ib = int(nb / s.netCols()), jb = int(nb % s.netCols());
        double mu_ = 0.0, mv_ = 0.0;
        for (const LayerWeight& e : m_rowU[size_t(ia)])
          if (e.layer == ib) mu_ = e.weight;
        for (const LayerWeight& e : m_rowV[size_t(ja)])
          if (e.layer == jb) mv_ = e.weight;
        block(a, b) = m_scale * mu_ * mv_;
      }
    }
    g.inverse = block.llt().solve(Eigen::MatrixXd::Identity(k, k));
    m_pinnedGroups.push_back({key, std::move(g)});
  }
}

double EdgeMass::diagonal(int i, int j) const {
  double du = 0.0, dv = 0.0;
  for (const LayerWeight& e : m_rowU[size_t(i)])
    if (e.layer == i) du = e.weight;
  for (const LayerWeight& e : m_rowV[size_t(j)])
    if (e.layer == j) dv = e.weight;
  return m_scale * du * dv;
}

namespace {
// sum over a Kronecker product of 1-D rows: out(i, j) = scale sum_{i', j'} U(i, i') V(j, j') x(i', j')
Eigen::RowVector3d kroneckerRow(const SplineSpace& s, const std::vector<LayerWeight>& u, const std::vector<LayerWeight>& v,
                                double scale, const ControlNet& x) {
  const LayerRange mu = s.movingU(), mv = s.movingV();
  Eigen::RowVector3d acc = Eigen::RowVector3d::Zero();
  for (const LayerWeight& a : u)
    for (const LayerWeight& b : v)
      acc += (a.weight * b.weight) * x.row(Eigen::Index(a.layer - mu.first) * mv.count + (b.layer - mv.first));
  return scale * acc;
}
}  // namespace

void EdgeMass::apply(const ControlNet& x, ControlNet& out) const {
  const SplineSpace& s = *m_space;
  out.resize(s.numMoving(), 3);
  for (Eigen::Index f = 0; f < s.numMoving(); ++f) {
    const Eigen::Index r = s.movingToNet(f);
    const int i = int(r / s.netCols()), j = int(r % s.netCols());
    out.row(f) = kroneckerRow(s, m_rowU[size_t(i)], m_rowV[size_t(j)], m_scale, x);
  }
}

void EdgeMass::inverseRow(int i, int j, double scale, std::vector<std::pair<Eigen::Index, double>>& out) const {
  const SplineSpace& s = *m_space;
  const LayerRange mu = s.movingU(), mv = s.movingV();
  out.clear();
  if (const PinnedGroup* g = pinnedGroup(i, j)) {
    const Eigen::Index f = Eigen::Index(i - mu.first) * mv.count + (j - mv.first);
    if (m_pinned[size_t(f)]) return;
    const Eigen::Index a = std::find(g->free.begin(), g->free.end(), f) - g->free.begin();
    for (size_t c = 0; c < g->free.size(); ++c) out.emplace_back(g->free[c], scale * g->inverse(a, Eigen::Index(c)));
    return;
  }
  for (const LayerWeight& u : m_invU[size_t(i)])
    for (const LayerWeight& v : m_invV[size_t(j)])
      out.emplace_back(Eigen::Index(u.layer - mu.first) * mv.count + (v.layer - mv.first), scale * u.weight * v.weight / m_scale);
}

void EdgeMass::solve(ControlNet& r) const {
  const SplineSpace& s = *m_space;
  const ControlNet copy = r;
  std::vector<std::pair<Eigen::Index, double>> row;
  for (Eigen::Index f = 0; f < s.numMoving(); ++f) {
    const Eigen::Index n = s.movingToNet(f);
    inverseRow(int(n / s.netCols()), int(n % s.netCols()), 1.0, row);
    Eigen::RowVector3d acc = Eigen::RowVector3d::Zero();
    for (const auto& [g, c] : row) acc += c * copy.row(g);
    r.row(f) = acc;
  }
}

EdgeMass::BandPlan EdgeMass::bandPlan(const std::vector<StiffnessStencil::BandPoint>& band, double scale) const {
  std::vector<int> bandIndex(size_t(m_space->numMoving()), -1);
  for (size_t k = 0; k < band.size(); ++k) bandIndex[size_t(band[k].m)] = int(k);
  BandPlan plan;
  plan.start.push_back(0);
  std::vector<std::pair<Eigen::Index, double>> row;
  for (const StiffnessStencil::BandPoint& b : band) {
    inverseRow(b.i, b.j, scale, row);
    for (const auto& [g, c] : row) {
      const int k = bandIndex[size_t(g)];
      assert(k >= 0 && "the mass couples a band point only with band points (the source layers are)");
      plan.entries.emplace_back(k, c);
    }
    plan.start.push_back(int(plan.entries.size()));
  }
  return plan;
}

std::vector<Eigen::Triplet<double>> EdgeMass::offDiagonal(double scale) const {
  const SplineSpace& s = *m_space;
  const LayerRange mu = s.movingU(), mv = s.movingV();
  std::vector<Eigen::Triplet<double>> t;
  for (Eigen::Index f = 0; f < s.numMoving(); ++f) {
    const Eigen::Index n = s.movingToNet(f);
    const int i = int(n / s.netCols()), j = int(n % s.netCols());
    const auto &ru = m_rowU[size_t(i)], &rv = m_rowV[size_t(j)];
    if (ru.size() == 1 && rv.size() == 1) continue;
    for (const LayerWeight& a : ru)
      for (const LayerWeight& b : rv) {
        const Eigen::Index g = Eigen::Index(a.layer - mu.first) * mv.count + (b.layer - mv.first);
        if (g != f) t.emplace_back(f, g, scale * m_scale * a.weight * b.weight);
      }
  }
  return t;
}

}  // namespace bsdeform
