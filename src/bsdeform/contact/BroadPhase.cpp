// SPDX-License-Identifier: MIT
#include "bsdeform/contact/BroadPhase.h"

#include "bsdeform/base/Parallel.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <optional>

namespace bsdeform {

namespace detail {

/// One box for the sweep: its interval on the sweep axis and on the two others, inflated.
struct SweepItem {
  double lo, hi, lo1, hi1, lo2, hi2;
  int index;
};

/// A list's items by slab (an item in every slab its interval across overlaps), each slab in the
/// order of the items' starts along the axis: items[start[s] .. start[s + 1]).
struct Slabbed {
  std::vector<SweepItem> items;
  std::vector<size_t> start;
};

/// A T kept on each thread with its memory from one search to the next (a sheet's lists are
/// megabytes: fresh pages each time otherwise), lent to one user at a time: while a search holds
/// it, a search that starts on the same thread (TBB may run another's task on a thread that waits
/// for its parts) gets a T of its own.
template <typename T>
class ThreadKept {
 public:
  ThreadKept() : m_nested(inUse()) { inUse() = true; }
  ~ThreadKept() {
    if (!m_nested) inUse() = false;
  }
  ThreadKept(const ThreadKept&) = delete;
  ThreadKept& operator=(const ThreadKept&) = delete;
  T& get() { return m_nested ? m_own : kept(); }

 private:
  static T& kept() {
    thread_local T value;
    return value;
  }
  static bool& inUse() {
    thread_local bool value = false;
    return value;
  }
  bool m_nested;
  T m_own;
};

/// sweepWith's lists (ThreadKept: page faults had been 2 % of a contact run).
struct SweepBuffers {
  std::vector<SweepItem> sorted;
  std::vector<size_t> next;
  Slabbed x, y;
};

/// Sweep and prune along one axis; `b` null for one set against itself. The axis is the one whose
/// sweep scans fewest pairs, estimated from histograms of the intervals' starts (two sheets lying
/// one above the other: along the sheets every box overlaps a whole strip of the other sheet,
/// across them none). Faster than a uniform grid (cells of the median box size, keyed by sorting)
/// on a cloth draped over a box and on the cloth against itself (docs/benchmarks.md, issue 35).
///
/// The sweep runs in slabs across one of the two other axes, the one that holds more slabs twice
/// the boxes' mean extent wide (at most 64): a box in every slab it overlaps, a pair reported only in
/// the slab where their overlap along that axis begins, so once. Within a slab a box scans the
/// boxes of its slab only: across a sheet a sweep scans a whole strip of it otherwise (the 32²
/// twisted ribbon's pairs with itself: 20 boxes scanned for each one found). The slabs' sweeps
/// are cut into units that run on `parts` kernel threads (runParts); each pair goes to
/// emit(part, i, j) (i into `a`, j into `b`; one set: i < j) as it is found, from the part that
/// found it, so that a caller that keeps only some of them stores no others. The set of pairs
/// does not depend on `parts`, their order does.
template <typename Emit>
void sweepWith(const std::vector<Box>& a, const std::vector<Box>* b, double inflation, int parts, Emit&& emit) {
  if (a.empty() || (b && b->empty())) return;
  // Along each axis, the inflated boxes' range and their extents' sum (both lists).
  struct Spread {
    double lo = INFINITY, hi = -INFINITY, extent = 0.0;
  };
  std::array<Spread, 3> spread;
  for (const std::vector<Box>* set : {&a, b}) {
    if (!set) continue;
    for (const Box& box : *set)
      for (int k = 0; k < 3; ++k) {
        Spread& s = spread[size_t(k)];
        s.lo = std::min(s.lo, box.lo[k] - inflation);
        s.hi = std::max(s.hi, box.hi[k] + inflation);
        s.extent += box.hi[k] - box.lo[k] + 2.0 * inflation;
      }
  }
  // The pairs a sweep along `axis` scans, about: for each box, the boxes of the other list (or
  // the same) whose start lies within its interval, counted in 1024 bins of the starts.
  const auto estimate = [&](int axis) {
    constexpr int kBins = 1024;
    const double lo = spread[size_t(axis)].lo, hi = spread[size_t(axis)].hi;
    if (!std::isfinite(hi - lo)) return double(INFINITY);  // not finite: the last choice
    // all at one coordinate: every interval overlaps every other along this axis
    if (!(hi > lo)) return double(a.size()) * double(b ? b->size() : a.size());
    const double scale = kBins / (hi - lo);
    const auto bin = [&](double v) {
      const double t = (v - lo) * scale;
      return t >= 0.0 ? (t < kBins ? int(t) : kBins - 1) : 0;  // NaN to bin 0
    };
    const auto starts = [&](const std::vector<Box>& set) {
      std::vector<double> prefix(kBins + 1, 0.0);  // prefix[k]: starts in bins below k
      for (const Box& box : set) prefix[size_t(bin(box.lo[axis] - inflation)) + 1] += 1.0;
      for (int k = 0; k < kBins; ++k) prefix[size_t(k) + 1] += prefix[size_t(k)];
      return prefix;
    };
    const auto scanned = [&](const std::vector<Box>& set, const std::vector<double>& other) {
      double count = 0.0;
      for (const Box& box : set)
        count += std::max(0.0, other[size_t(bin(box.hi[axis] + inflation)) + 1] -
                                   other[size_t(bin(box.lo[axis] - inflation))]);  // ≥ 0 with a NaN end
      return count;
    };
    const std::vector<double> startsA = starts(a);
    if (!b) return scanned(a, startsA);
    return scanned(a, starts(*b)) + scanned(*b, startsA);
  };
  int axis = 0;
  double best = INFINITY;
  for (int k = 0; k < 3; ++k)
    if (const double e = estimate(k); e < best) {
      best = e;
      axis = k;
    }
  const int axis1 = (axis + 1) % 3, axis2 = (axis + 2) % 3;
  // The slabs: across axis1 or axis2, whichever holds more slabs twice the boxes' mean extent wide.
  int across = 1, slabs = 1;
  double origin = 0.0, width = 1.0;
  for (const int k : {axis1, axis2}) {
    const double lo = spread[size_t(k)].lo, hi = spread[size_t(k)].hi;
    const double w = 2.0 * spread[size_t(k)].extent / double(a.size() + (b ? b->size() : 0));
    if (!(std::isfinite(hi - lo) && w > 0.0 && std::isfinite(w))) continue;
    const int n = int(std::min(64.0, std::floor((hi - lo) / w)));
    if (n > slabs) {
      slabs = n;
      across = k == axis1 ? 1 : 2;
      origin = lo;
      width = (hi - lo) / n;
    }
  }
  const auto slabOf = [&](double v) {
    const double t = (v - origin) / width;
    return t >= 0.0 ? (t < slabs ? int(t) : slabs - 1) : 0;  // NaN to slab 0
  };
  // Each list's items, by slab (Slabbed).
  ThreadKept<SweepBuffers> lent;
  SweepBuffers& buffers = lent.get();
  const auto slabbed = [&](const std::vector<Box>& set, Slabbed& out) {
    std::vector<SweepItem>& sorted = buffers.sorted;
    sorted.clear();
    sorted.reserve(set.size());
    for (int i = 0; i < int(set.size()); ++i) {
      const Box& box = set[i];
      sorted.push_back({box.lo[axis] - inflation, box.hi[axis] + inflation, box.lo[axis1] - inflation,
                        box.hi[axis1] + inflation, box.lo[axis2] - inflation, box.hi[axis2] + inflation, i});
    }
    std::sort(sorted.begin(), sorted.end(), [](const SweepItem& x, const SweepItem& y) { return x.lo < y.lo; });
    out.start.assign(size_t(slabs) + 1, 0);
    const auto span = [&](const SweepItem& item) {
      return across == 1 ? std::pair(slabOf(item.lo1), slabOf(item.hi1))
                         : std::pair(slabOf(item.lo2), slabOf(item.hi2));
    };
    for (const SweepItem& item : sorted) {
      const auto [first, last] = span(item);
      for (int k = first; k <= last; ++k) ++out.start[size_t(k) + 1];
    }
    for (size_t k = 1; k < out.start.size(); ++k) out.start[k] += out.start[k - 1];
    out.items.resize(out.start.back());
    std::vector<size_t>& next = buffers.next;
    next.assign(out.start.begin(), out.start.end() - 1);
    for (const SweepItem& item : sorted) {
      const auto [first, last] = span(item);
      for (int k = first; k <= last; ++k) out.items[next[size_t(k)]++] = item;
    }
  };
  Slabbed& x = buffers.x;
  Slabbed& y = buffers.y;
  slabbed(a, x);
  if (b) slabbed(*b, y);  // else y is not read
  const auto overlapOthers = [](const SweepItem& p, const SweepItem& q) {
    return p.lo1 <= q.hi1 && q.lo1 <= p.hi1 && p.lo2 <= q.hi2 && q.lo2 <= p.hi2;
  };
  // the slab in which a pair that overlaps across is reported: where its overlap begins
  const auto reportedIn = [&](const SweepItem& p, const SweepItem& q) {
    return across == 1 ? slabOf(std::max(p.lo1, q.lo1)) : slabOf(std::max(p.lo2, q.lo2));
  };
  // Units of work: a slab's items from `begin` to `end` scanning forward in their own list
  // (one set), or the other list from the first item starting at or after their own start
  // (pass 0: the first list's items scan the second; pass 1: the second's scan the first, from
  // the first item starting strictly after theirs: ties go to the first list, so a pair is
  // found once).
  struct Unit {
    int slab, pass;
    size_t begin, end;
  };
  constexpr size_t kUnit = 2048;
  std::vector<Unit> units;
  for (int s = 0; s < slabs; ++s)
    for (int pass = 0; pass < (b ? 2 : 1); ++pass) {
      const Slabbed& own = pass == 0 ? x : y;
      for (size_t k = own.start[size_t(s)]; k < own.start[size_t(s) + 1]; k += kUnit)
        units.push_back({s, pass, k, std::min(k + kUnit, own.start[size_t(s) + 1])});
    }
  const auto run = [&](int part, const Unit& u) {
    if (!b) {
      const size_t end = x.start[size_t(u.slab) + 1];
      for (size_t i = u.begin; i < u.end; ++i) {
        const SweepItem& p = x.items[i];
        for (size_t j = i + 1; j < end && x.items[j].lo <= p.hi; ++j) {
          const SweepItem& q = x.items[j];
          if (overlapOthers(p, q) && reportedIn(p, q) == u.slab)
            emit(part, std::min(p.index, q.index), std::max(p.index, q.index));
        }
      }
      return;
    }
    const Slabbed& own = u.pass == 0 ? x : y;
    const Slabbed& other = u.pass == 0 ? y : x;
    const auto first = other.items.begin() + std::ptrdiff_t(other.start[size_t(u.slab)]);
    const auto last = other.items.begin() + std::ptrdiff_t(other.start[size_t(u.slab) + 1]);
    for (size_t i = u.begin; i < u.end; ++i) {
      const SweepItem& p = own.items[i];
      auto k = u.pass == 0 ? std::lower_bound(first, last, p.lo, [](const SweepItem& q, double v) { return q.lo < v; })
                           : std::upper_bound(first, last, p.lo, [](double v, const SweepItem& q) { return v < q.lo; });
      for (; k != last && k->lo <= p.hi; ++k)
        if (overlapOthers(p, *k) && reportedIn(p, *k) == u.slab) {
          if (u.pass == 0)
            emit(part, p.index, k->index);
          else
            emit(part, k->index, p.index);
        }
    }
  };
  parts = std::max(1, std::min(parts, int(units.size())));
  if (parts == 1) {
    for (const Unit& u : units) run(0, u);
    return;
  }
  runParts(parts, [&](int part) {
    for (size_t k = size_t(part); k < units.size(); k += size_t(parts)) run(part, units[k]);
  });
}

/// Every pair sweepWith finds, into `out`.
void sweepPairs(const std::vector<Box>& a, const std::vector<Box>* b, double inflation,
                std::vector<std::pair<int, int>>& out) {
  out.clear();
  sweepWith(a, b, inflation, 1, [&out](int, int i, int j) { out.emplace_back(i, j); });
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

/// The swept boxes of a mesh's vertices (each vertex from its start to its end).
std::vector<Box> vertexBoxes(const ContactMesh& mesh) {
  const Eigen::Index n = mesh.start.rows();
  std::vector<Box> out(static_cast<size_t>(n));
  for (int k = 0; k < 3; ++k) {
    const double* a = mesh.start.col(k).data();
    const double* b = mesh.end.col(k).data();
    for (Eigen::Index v = 0; v < n; ++v) {
      out[size_t(v)].lo[k] = std::min(a[v], b[v]);
      out[size_t(v)].hi[k] = std::max(a[v], b[v]);
    }
  }
  return out;
}

/// The box of an element (its vertices `element`): the union of their swept boxes (min and max
/// are exact, so the same box as from the positions themselves).
template <size_t N>
Box unionOf(const std::vector<Box>& vertex, const std::array<int, N>& element) {
  Box box = vertex[size_t(element[0])];
  for (size_t k = 1; k < N; ++k) {
    const Box& b = vertex[size_t(element[k])];
    box.lo = box.lo.cwiseMin(b.lo);
    box.hi = box.hi.cwiseMax(b.hi);
  }
  return box;
}

Box triangleBox(const ContactMesh& mesh, const std::vector<Box>& vertex, int f) {
  return unionOf<3>(vertex, {mesh.triangles(f, 0), mesh.triangles(f, 1), mesh.triangles(f, 2)});
}

Box edgeBox(const ContactMesh& mesh, const std::vector<Box>& vertex, int e) {
  return unionOf<2>(vertex, {mesh.edges(e, 0), mesh.edges(e, 1)});
}

/// The swept boxes of a mesh's vertices, triangles and edges.
struct SweptBoxes {
  std::vector<Box> vertices, triangles, edges;
  explicit SweptBoxes(const ContactMesh& mesh) : vertices(vertexBoxes(mesh)) {
    triangles.resize(size_t(mesh.triangles.rows()));
    for (int f = 0; f < int(mesh.triangles.rows()); ++f) triangles[size_t(f)] = triangleBox(mesh, vertices, f);
    edges.resize(size_t(mesh.edges.rows()));
    for (int e = 0; e < int(mesh.edges.rows()); ++e) edges[size_t(e)] = edgeBox(mesh, vertices, e);
  }
};

/// In index order: the pairs a sum over them visits come in an order that does not depend on
/// how the boxes were found (a cache's wider boxes find more, never the same ones differently).
/// Sorted as std::sort sorts them (by the first index, then the second), by buckets of the first
/// index and a sort of each bucket: a crumpled sheet's self pairs number hundreds of thousands
/// per search, and a comparison sort of them cost more than finding them.
void sortPairs(std::vector<std::array<int, 2>>& pairs) {
  if (pairs.size() < 256) {
    std::sort(pairs.begin(), pairs.end());
    return;
  }
  int largest = 0;
  for (const auto& p : pairs) {
    assert(p[0] >= 0);  // indices of vertices, triangles, edges
    largest = std::max(largest, p[0]);
  }
  // the buffers kept from the last call on this thread (the sorted list leaves in `pairs`, the
  // one given comes back as the next call's): tens of megabytes, fresh pages each time otherwise
  thread_local std::vector<std::array<int, 2>> sorted;
  thread_local std::vector<size_t> start, next;
  start.assign(size_t(largest) + 2, 0);
  for (const auto& p : pairs) ++start[size_t(p[0]) + 1];
  for (size_t k = 1; k < start.size(); ++k) start[k] += start[k - 1];
  sorted.resize(pairs.size());
  next.assign(start.begin(), start.end() - 1);
  for (const auto& p : pairs) sorted[next[size_t(p[0])]++] = p;
  for (size_t k = 0; k + 1 < start.size(); ++k)
    if (start[k + 1] - start[k] > 1)
      std::sort(sorted.begin() + std::ptrdiff_t(start[k]), sorted.begin() + std::ptrdiff_t(start[k + 1]));
  pairs.swap(sorted);
}

void sortCandidates(ContactCandidates& c) {
  sortPairs(c.vertexTriangle);
  sortPairs(c.triangleVertex);
  sortPairs(c.edgeEdge);
}

/// Runs a sweep (sweep(parts, emit)) on the kernel threads and gathers the pairs that
/// keep(pair) accepts into `out`, in no particular order: on one thread straight into `out`,
/// on more into a list per part (kept on the calling thread from one search to the next, with
/// its memory) joined afterwards.
template <typename Sweep, typename Keep>
void gatherPairs(std::vector<std::array<int, 2>>& out, Sweep&& sweep, Keep&& keep) {
  out.clear();
  const int parts = effectiveKernelThreads();
  if (parts <= 1) {
    sweep(1, [&](int, int i, int j) {
      if (keep(i, j)) out.push_back({i, j});
    });
    return;
  }
  // The caller's lists (the parts name them from their own threads), kept on its thread.
  detail::ThreadKept<std::vector<std::vector<std::array<int, 2>>>> lent;
  auto& lists = lent.get();
  lists.resize(size_t(parts));
  for (auto& list : lists) list.clear();
  sweep(parts, [&](int part, int i, int j) {
    if (keep(i, j)) lists[size_t(part)].push_back({i, j});
  });
  size_t total = 0;
  for (size_t k = 0; k < size_t(parts); ++k) total += lists[k].size();
  out.reserve(total);
  for (size_t k = 0; k < size_t(parts); ++k) out.insert(out.end(), lists[k].begin(), lists[k].end());
}

}  // namespace

void candidatePairs(const ContactMesh& a, const ContactMesh& b, double inflation, ContactCandidates& out) {
  // Boxes within `inflation` of each other: each inflated by half of it.
  const double half = 0.5 * inflation;
  const SweptBoxes boxesA(a), boxesB(b);
  const auto between = [half](const std::vector<Box>& x, const std::vector<Box>& y) {
    return [&x, &y, half](int parts, auto&& emit) { detail::sweepWith(x, &y, half, parts, emit); };
  };
  const auto all = [](int, int) { return true; };
  gatherPairs(out.vertexTriangle, between(boxesA.vertices, boxesB.triangles), all);
  gatherPairs(out.triangleVertex, between(boxesA.triangles, boxesB.vertices), all);
  gatherPairs(out.edgeEdge, between(boxesA.edges, boxesB.edges), all);
  sortCandidates(out);
}

void candidatePairs(const ContactMesh& a, double inflation, ContactCandidates& out,
                    const std::function<bool(const std::array<int, 2>&)>& keepVertexTriangle,
                    const std::function<bool(const std::array<int, 2>&)>& keepEdgeEdge) {
  const double half = 0.5 * inflation;
  const SweptBoxes boxes(a);
  gatherPairs(
      out.vertexTriangle,
      [&](int parts, auto&& emit) { detail::sweepWith(boxes.vertices, &boxes.triangles, half, parts, emit); },
      [&](int v, int f) {
        return a.triangles(f, 0) != v && a.triangles(f, 1) != v && a.triangles(f, 2) != v &&
               (!keepVertexTriangle || keepVertexTriangle({v, f}));
      });
  out.triangleVertex.clear();
  gatherPairs(
      out.edgeEdge, [&](int parts, auto&& emit) { detail::sweepWith(boxes.edges, nullptr, half, parts, emit); },
      [&](int e, int g) {
        const int e0 = a.edges(e, 0), e1 = a.edges(e, 1), g0 = a.edges(g, 0), g1 = a.edges(g, 1);
        return e0 != g0 && e0 != g1 && e1 != g0 && e1 != g1 && (!keepEdgeEdge || keepEdgeEdge({e, g}));
      });
  sortCandidates(out);
}

void candidatePairs(const ContactMesh& a, double inflation, ContactCandidates& out) {
  candidatePairs(a, inflation, out, nullptr, nullptr);
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

/// A mesh's element boxes for narrowWith: all of them made at once when the kept list names its
/// elements more often than it has elements (a sheet's pairs with itself: millions of pairs, tens of
/// thousands of elements), else each made as a pair asks for it (a kept list names a few of a large
/// obstacle's elements, and each a few times). The same boxes either way.
class ElementBoxes {
 public:
  ElementBoxes(const ContactMesh& mesh, const std::vector<Box>& vertex, size_t asked)
      : m_mesh(mesh), m_vertex(vertex) {
    if (asked <= size_t(mesh.triangles.rows() + mesh.edges.rows())) return;
    m_triangles.resize(size_t(mesh.triangles.rows()));
    for (int f = 0; f < int(mesh.triangles.rows()); ++f) m_triangles[size_t(f)] = triangleBox(mesh, vertex, f);
    m_edges.resize(size_t(mesh.edges.rows()));
    for (int e = 0; e < int(mesh.edges.rows()); ++e) m_edges[size_t(e)] = edgeBox(mesh, vertex, e);
  }
  Box triangle(int f) const { return m_triangles.empty() ? triangleBox(m_mesh, m_vertex, f) : m_triangles[size_t(f)]; }
  Box edge(int e) const { return m_edges.empty() ? edgeBox(m_mesh, m_vertex, e) : m_edges[size_t(e)]; }

 private:
  const ContactMesh& m_mesh;
  const std::vector<Box>& m_vertex;
  std::vector<Box> m_triangles, m_edges;
};

/// The candidates of `wide` whose boxes meet now. For one mesh against itself, `b` is `a`.
void narrowWith(const ContactMesh& a, const std::vector<Box>& va, const ContactMesh& b, const std::vector<Box>& vb,
                double half, const ContactCandidates& wide, ContactCandidates& out) {
  out.vertexTriangle.clear();
  out.triangleVertex.clear();
  out.edgeEdge.clear();
  const size_t asked = wide.vertexTriangle.size() + wide.triangleVertex.size() + 2 * wide.edgeEdge.size();
  const ElementBoxes boxesA(a, va, &a == &b ? asked : wide.triangleVertex.size() + wide.edgeEdge.size());
  const std::optional<ElementBoxes> ownB =
      &a == &b ? std::nullopt
               : std::optional<ElementBoxes>(std::in_place, b, vb, wide.vertexTriangle.size() + wide.edgeEdge.size());
  const ElementBoxes& boxesB = ownB ? *ownB : boxesA;
  for (const auto& [v, f] : wide.vertexTriangle)
    if (boxesMeet(va[size_t(v)], boxesB.triangle(f), half)) out.vertexTriangle.push_back({v, f});
  for (const auto& [f, v] : wide.triangleVertex)
    if (boxesMeet(boxesA.triangle(f), vb[size_t(v)], half)) out.triangleVertex.push_back({f, v});
  for (const auto& [e, g] : wide.edgeEdge)
    if (boxesMeet(boxesA.edge(e), boxesB.edge(g), half)) out.edgeEdge.push_back({e, g});
}
}  // namespace

void narrowCandidates(const ContactMesh& a, const ContactMesh& b, double inflation, const ContactCandidates& wide,
                      ContactCandidates& out) {
  narrowWith(a, vertexBoxes(a), b, vertexBoxes(b), 0.5 * inflation, wide, out);
}

void narrowCandidates(const ContactMesh& a, double inflation, const ContactCandidates& wide, ContactCandidates& out) {
  const std::vector<Box> boxes = vertexBoxes(a);
  narrowWith(a, boxes, a, boxes, 0.5 * inflation, wide, out);
}

}  // namespace bsdeform
