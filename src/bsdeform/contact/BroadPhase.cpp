// SPDX-License-Identifier: MIT
#include "bsdeform/contact/BroadPhase.h"

#include <algorithm>
#include <cmath>

namespace bsdeform {

namespace detail {

/// One box for the sweep: its interval on the sweep axis and on the two others, inflated.
struct SweepItem {
  double lo, hi, lo1, hi1, lo2, hi2;
  int index;
};

/// Sweep and prune on the axis along which the box centres spread most; `b` null for one set
/// against itself. Faster than a uniform grid (cells of the median box size, keyed by sorting) on
/// a cloth draped over a box and on the cloth against itself (docs/benchmarks.md, issue 35).
void sweepPairs(const std::vector<Box>& a, const std::vector<Box>* b, double inflation,
                std::vector<std::pair<int, int>>& out) {
  out.clear();
  Eigen::Vector3d cmin = Eigen::Vector3d::Constant(INFINITY), cmax = -cmin;
  const auto extend = [&](const std::vector<Box>& set) {
    for (const Box& box : set) {
      const Eigen::Vector3d c = 0.5 * (box.lo + box.hi);
      cmin = cmin.cwiseMin(c);
      cmax = cmax.cwiseMax(c);
    }
  };
  extend(a);
  if (b) extend(*b);
  if (!(cmin.array() <= cmax.array()).all()) return;  // empty
  int axis = 0;
  (cmax - cmin).maxCoeff(&axis);
  const int axis1 = (axis + 1) % 3, axis2 = (axis + 2) % 3;
  const auto sorted = [&](const std::vector<Box>& set) {
    std::vector<SweepItem> items;
    items.reserve(set.size());
    for (int i = 0; i < int(set.size()); ++i) {
      const Box& box = set[i];
      items.push_back({box.lo[axis] - inflation, box.hi[axis] + inflation, box.lo[axis1] - inflation,
                       box.hi[axis1] + inflation, box.lo[axis2] - inflation, box.hi[axis2] + inflation, i});
    }
    std::sort(items.begin(), items.end(), [](const SweepItem& x, const SweepItem& y) { return x.lo < y.lo; });
    return items;
  };
  const auto overlapOthers = [](const SweepItem& x, const SweepItem& y) {
    return x.lo1 <= y.hi1 && y.lo1 <= x.hi1 && x.lo2 <= y.hi2 && y.lo2 <= x.hi2;
  };
  if (!b) {
    const std::vector<SweepItem> items = sorted(a);
    const int n = int(items.size());
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n && items[j].lo <= items[i].hi; ++j)
        if (overlapOthers(items[i], items[j]))
          out.emplace_back(std::min(items[i].index, items[j].index), std::max(items[i].index, items[j].index));
    return;
  }
  // Two sorted lists: each item scans only the other list, from the first item starting at or
  // after its own start (ties: the first list's item scans), so a pair is found once.
  const std::vector<SweepItem> x = sorted(a), y = sorted(*b);
  const int nx = int(x.size()), ny = int(y.size());
  int jx = 0, jy = 0;
  while (jx < nx || jy < ny) {
    if (jy == ny || (jx < nx && x[jx].lo <= y[jy].lo)) {
      const SweepItem& item = x[jx++];
      for (int k = jy; k < ny && y[k].lo <= item.hi; ++k)
        if (overlapOthers(item, y[k])) out.emplace_back(item.index, y[k].index);
    } else {
      const SweepItem& item = y[jy++];
      for (int k = jx; k < nx && x[k].lo <= item.hi; ++k)
        if (overlapOthers(item, x[k])) out.emplace_back(x[k].index, item.index);
    }
  }
}

}  // namespace detail

void overlappingPairs(const std::vector<Box>& a, const std::vector<Box>& b, double inflation,
                      std::vector<std::pair<int, int>>& out) {
  detail::sweepPairs(a, &b, inflation, out);
}

void selfOverlappingPairs(const std::vector<Box>& a, double inflation, std::vector<std::pair<int, int>>& out) {
  detail::sweepPairs(a, nullptr, inflation, out);
}

namespace {

/// The box of the vertices of `element` of a mesh, at the start and the end of the step.
template <class Rows>
Box sweptBox(const ContactMesh& mesh, const Rows& element) {
  Box box{Eigen::Vector3d::Constant(INFINITY), Eigen::Vector3d::Constant(-INFINITY)};
  for (int k = 0; k < int(element.size()); ++k) {
    const int v = element[k];
    box.lo = box.lo.cwiseMin(mesh.start.row(v).transpose()).cwiseMin(mesh.end.row(v).transpose());
    box.hi = box.hi.cwiseMax(mesh.start.row(v).transpose()).cwiseMax(mesh.end.row(v).transpose());
  }
  return box;
}

/// The swept boxes of a mesh's vertices, triangles and edges.
struct SweptBoxes {
  std::vector<Box> vertices, triangles, edges;
  explicit SweptBoxes(const ContactMesh& mesh) {
    vertices.resize(mesh.start.rows());
    for (int v = 0; v < int(mesh.start.rows()); ++v) vertices[v] = sweptBox(mesh, std::array<int, 1>{v});
    triangles.resize(mesh.triangles.rows());
    for (int f = 0; f < int(mesh.triangles.rows()); ++f)
      triangles[f] = sweptBox(mesh, std::array<int, 3>{mesh.triangles(f, 0), mesh.triangles(f, 1), mesh.triangles(f, 2)});
    edges.resize(mesh.edges.rows());
    for (int e = 0; e < int(mesh.edges.rows()); ++e)
      edges[e] = sweptBox(mesh, std::array<int, 2>{mesh.edges(e, 0), mesh.edges(e, 1)});
  }
};

/// In index order: the pairs a sum over them visits come in an order that does not depend on
/// how the boxes were found (a cache's wider boxes find more, never the same ones differently).
void sortCandidates(ContactCandidates& c) {
  std::sort(c.vertexTriangle.begin(), c.vertexTriangle.end());
  std::sort(c.triangleVertex.begin(), c.triangleVertex.end());
  std::sort(c.edgeEdge.begin(), c.edgeEdge.end());
}

void toArrays(const std::vector<std::pair<int, int>>& pairs, std::vector<std::array<int, 2>>& out) {
  out.clear();
  out.reserve(pairs.size());
  for (const auto& [i, j] : pairs) out.push_back({i, j});
}

}  // namespace

void candidatePairs(const ContactMesh& a, const ContactMesh& b, double inflation, ContactCandidates& out) {
  // Boxes within `inflation` of each other: each inflated by half of it.
  const double half = 0.5 * inflation;
  const SweptBoxes boxesA(a), boxesB(b);
  std::vector<std::pair<int, int>> pairs;
  overlappingPairs(boxesA.vertices, boxesB.triangles, half, pairs);
  toArrays(pairs, out.vertexTriangle);
  overlappingPairs(boxesA.triangles, boxesB.vertices, half, pairs);
  toArrays(pairs, out.triangleVertex);
  overlappingPairs(boxesA.edges, boxesB.edges, half, pairs);
  toArrays(pairs, out.edgeEdge);
  sortCandidates(out);
}

void candidatePairs(const ContactMesh& a, double inflation, ContactCandidates& out) {
  const double half = 0.5 * inflation;
  const SweptBoxes boxes(a);
  std::vector<std::pair<int, int>> pairs;
  overlappingPairs(boxes.vertices, boxes.triangles, half, pairs);
  out.vertexTriangle.clear();
  for (const auto& [v, f] : pairs)
    if (a.triangles(f, 0) != v && a.triangles(f, 1) != v && a.triangles(f, 2) != v) out.vertexTriangle.push_back({v, f});
  out.triangleVertex.clear();
  selfOverlappingPairs(boxes.edges, half, pairs);
  out.edgeEdge.clear();
  for (const auto& [e, g] : pairs) {
    const int e0 = a.edges(e, 0), e1 = a.edges(e, 1), g0 = a.edges(g, 0), g1 = a.edges(g, 1);
    if (e0 != g0 && e0 != g1 && e1 != g0 && e1 != g1) out.edgeEdge.push_back({e, g});
  }
  sortCandidates(out);
}

}  // namespace bsdeform

namespace bsdeform {

namespace {
/// Whether two swept boxes overlap once each is inflated by `half`: the test the sweep makes
/// (the same bounds, the same comparisons).
bool boxesMeet(const Box& x, const Box& y, double half) {
  for (int k = 0; k < 3; ++k)
    if (!(x.lo[k] - half <= y.hi[k] + half && y.lo[k] - half <= x.hi[k] + half)) return false;
  return true;
}

void narrowWith(const SweptBoxes& a, const SweptBoxes& b, double half, const ContactCandidates& wide,
                ContactCandidates& out) {
  out.vertexTriangle.clear();
  out.triangleVertex.clear();
  out.edgeEdge.clear();
  for (const auto& [v, f] : wide.vertexTriangle)
    if (boxesMeet(a.vertices[size_t(v)], b.triangles[size_t(f)], half)) out.vertexTriangle.push_back({v, f});
  for (const auto& [f, v] : wide.triangleVertex)
    if (boxesMeet(a.triangles[size_t(f)], b.vertices[size_t(v)], half)) out.triangleVertex.push_back({f, v});
  for (const auto& [e, g] : wide.edgeEdge)
    if (boxesMeet(a.edges[size_t(e)], b.edges[size_t(g)], half)) out.edgeEdge.push_back({e, g});
}
}  // namespace

void narrowCandidates(const ContactMesh& a, const ContactMesh& b, double inflation, const ContactCandidates& wide,
                      ContactCandidates& out) {
  narrowWith(SweptBoxes(a), SweptBoxes(b), 0.5 * inflation, wide, out);
}

void narrowCandidates(const ContactMesh& a, double inflation, const ContactCandidates& wide, ContactCandidates& out) {
  const SweptBoxes boxes(a);
  narrowWith(boxes, boxes, 0.5 * inflation, wide, out);
}

}  // namespace bsdeform
