// SPDX-License-Identifier: MIT
#include "bsdeform/dynamics/SideSupports.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "bsdeform/base/NumberText.h"

namespace bsdeform {

const char* sideName(int side) {
  static const char* names[4] = {"umin", "umax", "vmin", "vmax"};
  return side >= 0 && side < 4 ? names[side] : "?";
}

namespace {
const char* fieldOf(int side) {
  static const char* names[4] = {"boundaryUMin", "boundaryUMax", "boundaryVMin", "boundaryVMax"};
  return names[side];
}
Boundary boundaryOf(const Boundaries& b, int side) {
  return side == 0 ? b.uMin : side == 1 ? b.uMax : side == 2 ? b.vMin : b.vMax;
}
}  // namespace

ComponentConstraints::ComponentConstraints(const SplineSpace& space, const ControlNet& rest,
                                           const SideSupports& supports) {
  const Eigen::Index moving = space.numMoving();
  m_n = 3 * moving;
  m_restUnknowns = space.gatherMoving(rest);
  m_isDerived.assign(size_t(m_n), 0);
  // rows[d]: coordinate d of the unknowns as a combination of the others (identity until derived)
  std::vector<std::map<Eigen::Index, double>> rows(static_cast<size_t>(m_n));
  for (Eigen::Index k = 0; k < m_n; ++k) rows[size_t(k)][k] = 1.0;
  const int R = space.netRows(), C = space.netCols();
  const double size = 1.0 + (rest.colwise().maxCoeff() - rest.colwise().minCoeff()).norm();
  // the unknown (moving index) of net point (i, j), -1 if the space holds or derives it
  auto unknownAt = [&](int i, int j) -> Eigen::Index {
    if (!space.isMoving(i, j)) return -1;
    return space.movingIndex(i - space.degreeU(), j - space.degreeV());
  };
  // `derive(side-layer l, line t, component c, sources)`: coordinate c of the point of layer l
  // (counted from the edge) on line t becomes R + Σ w (P_s - R_s) over (layer, weight) sources
  for (int side = 0; side < 4; ++side) {
    const SideSupport& s = supports[size_t(side)];
    if (s.kind == SideSupport::Kind::None) continue;
    if (boundaryOf(space.boundaries(), side) != Boundary::Free)
      throw std::invalid_argument(std::string(fieldOf(side)) +
                                  ": SYMMETRY or a SIMPLY_SUPPORTED side holding chosen components needs a side the "
                                  "rest shape leaves open (restShape made it " +
                                  boundaryName(boundaryOf(space.boundaries(), side)) + ")");
    const bool uSide = side < 2;
    const int n = uSide ? space.degreeU() : space.degreeV();
    const int lines = uSide ? C : R;
    auto point = [&](int layer, int line) {
      const int across = uSide ? (side == 0 ? layer : R - 1 - layer) : (side == 2 ? layer : C - 1 - layer);
      return uSide ? std::make_pair(across, line) : std::make_pair(line, across);
    };
    auto derive = [&](int layer, int line, int c, const std::vector<std::pair<int, double>>& sources) {
      const auto [i, j] = point(layer, line);
      const Eigen::Index f = unknownAt(i, j);
      if (f < 0) return;  // held or derived by a neighbouring side of the space: left to it
      std::vector<std::pair<Eigen::Index, double>> src;
      for (const auto& [l, w] : sources) {
        const auto [si, sj] = point(l, line);
        const Eigen::Index g = unknownAt(si, sj);
        if (g < 0) return;
        src.emplace_back(3 * g + c, w);
      }
      std::map<Eigen::Index, double> row;
      for (const auto& [dof, w] : src)
        for (const auto& [k, v] : rows[size_t(dof)]) row[k] += w * v;
      const Eigen::Index d = 3 * f + c;
      rows[size_t(d)] = std::move(row);
      if (!m_isDerived[size_t(d)]) m_derived.push_back(d);
      m_isDerived[size_t(d)] = 1;
    };
    if (s.kind == SideSupport::Kind::Hinge || s.kind == SideSupport::Kind::Clamp) {
      const bool clamp = s.kind == SideSupport::Kind::Clamp;
      if ((s.components & 7u) == 0)
        throw std::invalid_argument(std::string(fieldOf(side)) + ": " + (clamp ? "BUILT_IN" : "SIMPLY_SUPPORTED") +
                                    " holding no component (hold " + sideName(side) + " is empty): use FREE");
      // the space's own layers for the side kind: `held` outer layers at rest, then `derived`
      // layers from the next `sources` ones with weights Z
      const EdgeLayers el = edgeLayers(clamp ? Boundary::BuiltIn : Boundary::SimplySupported, n);
      for (int t = 0; t < lines; ++t)
        for (int c = 0; c < 3; ++c) {
          if (!(s.components & (1u << c))) continue;
          for (int l = 0; l < el.held; ++l) derive(l, t, c, {});
          for (int d = 0; d < el.derived; ++d) {
            std::vector<std::pair<int, double>> sources;
            for (int k = 0; k < el.sources; ++k) sources.emplace_back(el.held + el.derived + k, el.Z(d, k));
            derive(el.held + d, t, c, sources);
          }
        }
      continue;
    }
    // SYMMETRY: find the plane from the rest net (pairs of layers mirror images, the middle
    // layer of an odd degree on it)
    const int pairs = n / 2;          // layers 0 .. pairs-1 mirror layers n-1 .. n-pairs
    const bool middle = (n % 2) == 1;  // layer (n - 1)/2 on the plane
    Plane found;
    for (int a = 0; a < 3 && found.axis < 0; ++a) {
      double sum = 0.0;
      int count = 0;
      for (int t = 0; t < lines; ++t) {
        for (int l = 0; l < pairs; ++l) {
          const auto [i, j] = point(l, t);
          const auto [pi, pj] = point(n - 1 - l, t);
          sum += 0.5 * (rest(Eigen::Index(i) * C + j, a) + rest(Eigen::Index(pi) * C + pj, a));
          ++count;
        }
        if (middle) {
          const auto [i, j] = point((n - 1) / 2, t);
          sum += rest(Eigen::Index(i) * C + j, a);
          ++count;
        }
      }
      const double x0 = sum / count;
      bool ok = true;
      for (int t = 0; t < lines && ok; ++t) {
        for (int l = 0; l < pairs && ok; ++l) {
          const auto [i, j] = point(l, t);
          const auto [pi, pj] = point(n - 1 - l, t);
          const Eigen::RowVector3d p = rest.row(Eigen::Index(i) * C + j), q = rest.row(Eigen::Index(pi) * C + pj);
          for (int b = 0; b < 3; ++b)
            ok &= std::abs(b == a ? p[b] + q[b] - 2.0 * x0 : p[b] - q[b]) <= 1e-9 * size;
        }
        if (middle) {
          const auto [i, j] = point((n - 1) / 2, t);
          ok &= std::abs(rest(Eigen::Index(i) * C + j, a) - x0) <= 1e-9 * size;
        }
      }
      if (ok) found = Plane{a, x0};
    }
    if (found.axis < 0)
      throw std::invalid_argument(std::string(fieldOf(side)) + " SYMMETRY: the rest net is not mirror-symmetric about "
                                  "a coordinate plane (x, y or z constant) through its edge " + sideName(side) +
                                  ": the " + std::to_string(n / 2 + n % 2) +
                                  " outer control layers must mirror the next ones (and for an odd degree the "
                                  "middle layer lie on the plane)");
    m_planes[size_t(side)] = found;
    for (int t = 0; t < lines; ++t)
      for (int c = 0; c < 3; ++c) {
        for (int l = 0; l < pairs; ++l) derive(l, t, c, {{n - 1 - l, c == found.axis ? -1.0 : 1.0}});
        if (middle && c == found.axis) derive((n - 1) / 2, t, c, {});
      }
  }
  // every constrained row in terms of free coordinates only (u sides first, then v sides, a
  // corner following both: see the header)
  std::vector<Eigen::Triplet<double>> t;
  for (Eigen::Index k = 0; k < m_n; ++k)
    for (const auto& [col, w] : rows[size_t(k)]) {
      if (m_isDerived[size_t(col)])
        throw std::invalid_argument(std::string("supports per component: the corner where ") +
                                    "two supported sides meet constrains a coordinate twice in a way this model "
                                    "cannot eliminate (coordinate " + std::to_string(col % 3) + " of unknown " +
                                    std::to_string(col / 3) + ")");
      if (w != 0.0) t.emplace_back(k, col, w);
    }
  m_T.resize(m_n, m_n);
  m_T.setFromTriplets(t.begin(), t.end());
  std::sort(m_derived.begin(), m_derived.end());
}

void ComponentConstraints::complete(ControlNet& x) const {
  if (m_derived.empty()) return;
  Eigen::Map<Eigen::VectorXd> v(x.data(), x.size());
  Eigen::Map<const Eigen::VectorXd> r(m_restUnknowns.data(), m_restUnknowns.size());
  // the free coordinates are T's identity rows; a constrained one is R + its row of T (x - R)
  const Eigen::VectorXd full = m_T * (v - r);
  for (Eigen::Index dof : m_derived) v[dof] = r[dof] + full[dof];
}

void ComponentConstraints::fold(ControlNet& g) const {
  if (m_derived.empty()) return;
  Eigen::Map<Eigen::VectorXd> v(g.data(), g.size());
  const Eigen::VectorXd folded = m_T.transpose() * v;
  v = folded;
  for (Eigen::Index dof : m_derived) v[dof] = 0.0;
}

const Eigen::SparseMatrix<double>& unknownsTangent(const ComponentConstraints* components,
                                                   const Eigen::SparseMatrix<double>& K, const std::vector<char>& held,
                                                   Eigen::SparseMatrix<double>& folded) {
  if (!components) return K;
  folded = components->foldTangent(K, held);
  return folded;
}

Eigen::SparseMatrix<double> ComponentConstraints::foldTangent(const Eigen::SparseMatrix<double>& lowerK,
                                                              const std::vector<char>& held) const {
  Eigen::SparseMatrix<double> upper = lowerK.transpose();
  upper.diagonal().setZero();
  Eigen::SparseMatrix<double> K = lowerK + upper;
  if (!m_derived.empty()) K = Eigen::SparseMatrix<double>(m_T.transpose()) * K * m_T;
  // held rows and columns out (a held source took a constrained point's couplings), a unit
  // diagonal in: the same structure at every call (CHOLMOD's analysis is kept)
  K.prune([&held](Eigen::Index i, Eigen::Index j, double) { return i == j || !(held[size_t(i)] || held[size_t(j)]); });
  for (Eigen::Index d = 0; d < K.rows(); ++d)
    if (held[size_t(d)]) K.coeffRef(d, d) = 1.0;
  K.makeCompressed();
  return K;
}

}  // namespace bsdeform
