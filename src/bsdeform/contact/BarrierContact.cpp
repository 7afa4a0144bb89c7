// SPDX-License-Identifier: MIT
#include "bsdeform/contact/BarrierContact.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cassert>
#include <unordered_map>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "bsdeform/base/CostTimer.h"
#include "bsdeform/base/NumberText.h"
#include "bsdeform/base/Parallel.h"
#include "bsdeform/contact/AdditiveCCD.h"
#include "bsdeform/contact/Barrier.h"
#include "bsdeform/contact/BroadPhase.h"
#include "bsdeform/contact/Distance.h"
#include "bsdeform/contact/Friction.h"

namespace bsdeform {

namespace {

using Vector12d = Eigen::Matrix<double, 12, 1>;
using Matrix12d = Eigen::Matrix<double, 12, 12>;

/// The unique undirected edges of a triangle list.
Eigen::MatrixX2i uniqueEdges(const std::vector<Eigen::Vector3i>& triangles) {
  std::vector<std::pair<int, int>> e;
  e.reserve(triangles.size() * 3);
  for (const Eigen::Vector3i& t : triangles)
    for (int c = 0; c < 3; ++c) {
      const int a = t[c], b = t[(c + 1) % 3];
      e.emplace_back(std::min(a, b), std::max(a, b));
    }
  std::sort(e.begin(), e.end());
  e.erase(std::unique(e.begin(), e.end()), e.end());
  Eigen::MatrixX2i out(Eigen::Index(e.size()), 2);
  for (size_t i = 0; i < e.size(); ++i) out.row(Eigen::Index(i)) << e[i].first, e[i].second;
  return out;
}

}  // namespace

ContactMesh staticContactMesh(const TriangleMesh& m) {
  ContactMesh out;
  out.start.resize(Eigen::Index(m.vertices.size()), 3);
  for (size_t v = 0; v < m.vertices.size(); ++v) out.start.row(Eigen::Index(v)) = m.vertices[v].transpose();
  out.end = out.start;
  // degenerate triangles (a cone's apex welded to one vertex) have no distance class: left out,
  // with their edges (a degenerate triangle's nonzero edges belong to its neighbours too)
  std::vector<Eigen::Vector3i> kept;
  kept.reserve(m.triangles.size());
  for (const Eigen::Vector3i& t : m.triangles) {
    const Eigen::Vector3d a = m.vertices[size_t(t[0])], b = m.vertices[size_t(t[1])], c = m.vertices[size_t(t[2])];
    const double area2 = (b - a).cross(c - a).squaredNorm();
    const double scale = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    if (std::isfinite(area2) && area2 > 1e-24 * scale * scale) kept.push_back(t);
  }
  out.triangles.resize(Eigen::Index(kept.size()), 3);
  for (size_t t = 0; t < kept.size(); ++t) out.triangles.row(Eigen::Index(t)) = kept[t].transpose();
  out.edges = uniqueEdges(kept);
  return out;
}

/// What stays between evaluations: the proxy (made at the first call, when the space is known),
/// the obstacles as ContactMeshes, the barrier stiffness and what adapts it.
struct BarrierContactForce::State {
  std::unique_ptr<CollisionProxy> proxy;
  /// The proxy as a ContactMesh: its triangles and edges (set with the proxy) and the vertex
  /// positions in the world of the last evaluation (start = end) or CCD (start to end).
  ContactMesh mesh;
  const SplineSpace* space = nullptr;
  Eigen::MatrixX3d restWorld;  ///< the proxy at the rest net (LoadContext::restShape, else the first state), world frame
  struct Obstacle {
    const TriangleTree* tree = nullptr;
    std::uint64_t version = ~std::uint64_t(0);
    ContactMesh mesh;          ///< start = end: where the obstacle is in the step now
    Eigen::MatrixX3d target;   ///< its pose now (the tree's); mesh.start sweeps toward it
    Eigen::MatrixX3d origin;   ///< where the sweep began: the pose the surface last saw
    double remaining = 0.0;    ///< the fraction of the sweep still to go
    /// Moves it by `t` of what it has left (all of it from 1 on: exactly to its target).
    void sweepBy(double t) {
      if (t >= 1.0) {
        mesh.start = target;
        remaining = 0.0;
      } else {
        mesh.start += t * (target - mesh.start);
        remaining *= 1.0 - t;
      }
      mesh.end = mesh.start;
    }
  };
  /// The start state of the step the obstacles' sweeps began in: a step taken again from it (a
  /// failed attempt, retaken in pieces) sweeps them again from their origins.
  ControlNet sweepStart;
  bool sweepStartPending = false;
  /// Obstacle poses a state put back gives (setAdaptedState()), taken at the next prepare()
  std::vector<Eigen::MatrixX3d> restoredPoses;
  std::vector<Obstacle> obstacles;
  double kappa = 0.0, kappaMax = 0.0;
  double previousMinimum = std::numeric_limits<double>::infinity();
  double minimum = std::numeric_limits<double>::infinity();
  double deviation = 0.0;
  int closestObstacle = -1;      ///< of the closest pair at the last evaluation (obstacles.size(): self)
  Eigen::Index closestVertex = -1;
  ContactWorldSnapshot seen;  ///< for storedEnergy()
  std::vector<FrictionPair> friction;  ///< frozen at the last beginStep()
  Eigen::MatrixX3d previousWorld;      ///< the proxy at ctx.previous (friction's slip)
  Costs costs;
  /// The potential of the terms the last addLoad() summed (their values come with their
  /// gradients), and the nets, step and proxy generation it was at: potential() at the same
  /// answers from it instead of a second pass over the pairs. Forgotten by whatever changes the
  /// terms at the same nets (a step's start: κ and friction; moved obstacles; a state put back).
  struct LoadValue {
    bool valid = false;
    ControlNet current, previous;
    double stepSize = 0.0;
    std::uint64_t generation = 0;
    double kappa = 0.0;
    Eigen::Matrix3d linear;
    Eigen::Vector3d offset;
    double value = 0.0;
  } loadValue;
  struct Block {
    Eigen::Index a, b;
    Eigen::Matrix3d h;
  };
  std::vector<Block> blocks;  ///< addJacobian()'s scratch
  /// addJacobian()'s order of the blocks: (vertex pair a · n + b, place in `blocks`), sorted
  std::vector<std::pair<std::uint64_t, std::uint32_t>> blockOrder;
  std::vector<size_t> blockCount;            ///< blockOrder's counting sorts' positions
  std::vector<std::uint32_t> blockBySecond;  ///< the blocks' places ordered by their second vertex
  /// addJacobian()'s view of each proxy vertex's weights within its element (the knot span whose
  /// control points they lie on, named by its first net point `corner`): `count` weights from
  /// `first` on in `slot` (the point's place among the element's L1 x L2) and `weight`. The
  /// proxy's weights are fixed: made once per proxy (emptied by prepare() when it makes one).
  struct VertexLocals {
    std::vector<Eigen::Index> corner;
    std::vector<int> first, count;
    std::vector<int> slot;
    std::vector<double> weight;
  } locals;
  /// terms()'s scratch with kernel threads: per part of the pairs in visiting order its active
  /// terms and its smallest distance within reach (the first pair in order that has it)
  struct TermPart {
    /// its active terms: each without its Hessian, and for a Jacobian the Hessian's blocks that
    /// addJacobian() reads (between the pair's moving points)
    struct Light {
      std::array<Eigen::Index, 4> vertex;
      double value;
      Eigen::Matrix<double, 12, 1> grad;
    };
    std::vector<Light> light;
    /// a Jacobian's: the k-th active term's 3 x 3 blocks between its moving points (vertex >= 0),
    /// in order, from `blockStart[k]` in `blocks`
    std::vector<size_t> blockStart;
    std::vector<double> blocks;
    std::vector<PairSite> inside;  ///< its pairs within reach (a first call's: Gathered)
    double d = 0.0;
    size_t where = 0;
    std::array<Eigen::Index, 4> vertex{};
    long computed = 0;  ///< pairs whose terms it computed
  };
  std::vector<TermPart> parts;
  /// addJacobian()'s sums per pair of elements (first net points a, b): L x L blocks, row-major
  struct ElementPair {
    Eigen::Index a, b;
    std::vector<double> K;
  };
  std::vector<ElementPair> elementPairs;
  std::unordered_map<std::uint64_t, size_t> elementPairIndex;
  /// addJacobian()'s vertex pairs: the element pair each goes to, its vertices and its block
  /// through the frame; per element pair its vertex pairs (`pairMembers` from `pairStart[p]` to
  /// `pairStart[p + 1]`), and the element pairs in the sink's order
  struct VertexPair {
    size_t pair;
    size_t a, b;
    Eigen::Matrix3d H;
  };
  std::vector<VertexPair> vertexPairs;
  std::vector<size_t> pairStart, pairMembers, pairOrder;
  /// Counts the times the proxy or an obstacle's triangles were made anew (the cache below
  /// belongs to one generation).
  std::uint64_t generation = 0;
  /// Candidate pairs kept across evaluations (a Verlet list): found around the proxy's move
  /// from `refStart` to `refEnd` (a query's start and end: its swept boxes) with the reach
  /// widened by two skins, the obstacles where they were then. While no proxy vertex is more
  /// than a skin from its segment from refStart to refEnd (at both ends of a query) and no
  /// obstacle moved, every pair within the reach now (or within the offset along the step) is
  /// among them (a box within a skin of a swept box lies in it grown by the skin), and
  /// narrowCandidates() picks exactly those the broad phase would find now: the same pairs in
  /// the same order, so nothing computed depends on when they were found.
  struct Candidates {
    bool valid = false;
    std::uint64_t generation = 0;
    Eigen::MatrixX3d refStart, refEnd;
    std::vector<Eigen::MatrixX3d> obstacles;
    std::vector<ContactCandidates> wide, now;
    double skin = 0.0;     ///< how far a vertex may stray from its segment
    int narrowSkinFor = 0;  ///< lists still to find with the narrow skin
    long builds = 0;
  } candidates;
  /// What the last gather() found: the proxy's world positions at `net` and the pairs within
  /// reach there. A Newton iteration's Jacobian comes at the net of the line search's last
  /// accepted load: the same proxy, obstacles and transform give the same positions and pairs,
  /// taken from here instead of a second proxy evaluation and broad phase.
  struct Gathered {
    bool valid = false;
    std::uint64_t generation = 0;
    ControlNet net;
    Eigen::Matrix3d linear;
    Eigen::Vector3d offset;
    std::vector<Eigen::MatrixX3d> obstacleStarts, obstacleEnds;
    Eigen::MatrixX3d positions;
    std::vector<ContactCandidates> pairs;
    /// The pairs of `pairs` within the barrier's reach at these positions (d² - ξ² < ŝ), in the
    /// visiting order, as the first terms() call here found them (`withinValid`). The kept
    /// candidates carry a skin, and most lie beyond the reach, where a term is zero: the later
    /// calls at the same positions (the tangent after the line search's evaluation, the
    /// potential beside the load) visit only these.
    bool withinValid = false;
    std::vector<PairSite> within;
  } gathered;
  /// The self pairs (sharing no vertex) within the reach of each other at rest, in the world
  /// (`rest`, as restWorld was when they were found), sorted: neighbours in the sheet, left out of
  /// the self candidates (docs/math.md §18.2). Found once instead of a distance per candidate.
  struct RestNeighbours {
    Eigen::MatrixX3d rest;
    double reach = 0.0;
    std::vector<std::array<int, 2>> vertexTriangle, edgeEdge;
    /// Where each first index's pairs begin in the lists above (one more entry than vertices,
    /// edges): a candidate is looked up among its own first index's few, not the whole list.
    std::vector<size_t> vertexStart, edgeStart;
  } restNeighbours;
};

BarrierContactForce::BarrierContactForce(std::shared_ptr<const ContactWorld> world, const BarrierContactParameters& p)
    : m_world(std::move(world)), m_params(p), m_state(std::make_shared<State>()) {
  auto positive = [](double x, const char* name) {
    if (!(x > 0.0) || !std::isfinite(x)) {
      std::ostringstream os;
      os << "barrier contact: " << name << " must be positive and finite, got " << numberText(x);
      throw std::invalid_argument(os.str());
    }
  };
  if (!m_world) throw std::invalid_argument("barrier contact: no obstacle world");
  positive(p.offset, "thickness (the offset)");
  positive(p.dhat, "dhat");
  positive(p.mass, "mass");
  positive(p.epsv, "epsv");
  if (!(p.friction >= 0.0) || !std::isfinite(p.friction))
    throw std::invalid_argument("barrier contact: friction must be 0 or more, got " + numberText(p.friction));
  if (p.samplesPerSpan < 1 || p.samplesPerSpan > 16)
    throw std::invalid_argument("barrier contact: proxySamples must be 1..16, got " + std::to_string(p.samplesPerSpan));
}

BarrierContactForce::~BarrierContactForce() = default;

unsigned BarrierContactForce::dependence() const {
  return kDependsOnPosition | (m_params.friction > 0.0 ? kDependsOnVelocity : 0u);
}

double BarrierContactForce::stiffness() const { return m_state->kappa; }

std::vector<double> BarrierContactForce::adaptedState() const {
  const State& st = *m_state;
  if (st.kappa == 0.0) return {};
  std::vector<double> out{st.kappa, st.kappaMax, std::isfinite(st.previousMinimum) ? st.previousMinimum : -1.0};
  // where each obstacle was when the surface last saw it: a resumed run sweeps it from there
  // (a pose put back and not yet taken up counts as where it was seen)
  const size_t count = std::max(st.obstacles.size(), st.restoredPoses.size());
  out.push_back(double(count));
  for (size_t o = 0; o < count; ++o) {
    const bool seen = o < st.obstacles.size() && st.obstacles[o].tree;
    const bool pending = o < st.restoredPoses.size() && st.restoredPoses[o].rows() > 0;
    const Eigen::MatrixX3d* pose = seen ? &st.obstacles[o].mesh.start : pending ? &st.restoredPoses[o] : nullptr;
    out.push_back(pose ? double(pose->rows()) : 0.0);
    for (Eigen::Index v = 0; pose && v < pose->rows(); ++v)
      for (int k = 0; k < 3; ++k) out.push_back((*pose)(v, k));
  }
  return out;
}

void BarrierContactForce::setAdaptedState(const std::vector<double>& state) const {
  State& st = *m_state;
  st.loadValue.valid = false;
  auto refuse = [&](const char* why) {
    std::ostringstream os;
    os << "barrier contact: its adapted state is the stiffness (> 0), its cap (>= it), the last smallest distance "
          "(>= 0 or -1), then the obstacles' last poses (a count, and per obstacle its vertex count and coordinates): "
       << why << " (" << state.size() << " values:";
    for (size_t k = 0; k < std::min<size_t>(state.size(), 6); ++k) os << ' ' << numberText(state[k]);
    os << (state.size() > 6 ? " ...)" : ")");
    throw std::invalid_argument(os.str());
  };
  std::vector<Eigen::MatrixX3d> poses;
  if (!state.empty()) {
    if (state.size() < 3 || !(state[0] > 0.0) || !(state[1] >= state[0]) || !std::isfinite(state[1]) ||
        !(state[2] == -1.0 || state[2] >= 0.0) || !std::isfinite(state[2]))
      refuse("the first three are not that");
    size_t at = 3;
    if (at < state.size()) {
      const double count = state[at++];
      if (!(count >= 0.0) || count != std::floor(count) || count > 1e6) refuse("the obstacle count is not a count");
      for (size_t o = 0; o < size_t(count); ++o) {
        if (at >= state.size()) refuse("it ends before the obstacles do");
        const double n = state[at++];
        if (!(n >= 0.0) || n != std::floor(n) || 3.0 * n > double(state.size() - at)) refuse("a vertex count runs past the end");
        Eigen::MatrixX3d pose(Eigen::Index(n), 3);
        for (Eigen::Index v = 0; v < pose.rows(); ++v)
          for (int k = 0; k < 3; ++k) pose(v, k) = state[at++];
        if (!pose.allFinite()) refuse("a pose is not finite");
        poses.push_back(std::move(pose));
      }
      if (at != state.size()) refuse("values are left after the obstacles");
    }
  }
  // a state put back (reset, the timeline, a file): the obstacles are taken where they are at the
  // next step (swept from the poses the state gives, when it gives them), nothing is lagged
  for (State::Obstacle& ob : st.obstacles) ob.tree = nullptr;
  st.restoredPoses = std::move(poses);
  st.sweepStart.resize(0, 3);
  st.sweepStartPending = false;
  st.friction.clear();
  if (state.empty()) {
    st.kappa = st.kappaMax = 0.0;
    st.previousMinimum = std::numeric_limits<double>::infinity();
    return;
  }
  st.kappa = state[0];
  st.kappaMax = state[1];
  st.previousMinimum = state[2] < 0.0 ? std::numeric_limits<double>::infinity() : state[2];
}

void BarrierContactForce::roundAdaptedState(double (*round)(double)) const {
  State& st = *m_state;
  st.loadValue.valid = false;
  st.kappa = round(st.kappa);
  st.kappaMax = round(st.kappaMax);
  if (std::isfinite(st.previousMinimum)) st.previousMinimum = round(st.previousMinimum);
}

size_t BarrierContactForce::frictionPairCount() const { return m_state->friction.size(); }
double BarrierContactForce::frictionNormalForce() const {
  double sum = 0.0;
  for (const FrictionPair& f : m_state->friction) sum += f.normalForce;
  return sum;
}
double BarrierContactForce::lastMinimumDistance() const { return m_state->minimum; }
double BarrierContactForce::lastDeviationBound() const { return m_state->deviation; }

void BarrierContactForce::prepare(const LoadContext& ctx) const {
  State& st = *m_state;
  const ContactWorld& w = *m_world;
  if (!st.proxy || st.space != &ctx.space) {
    st.proxy = std::make_unique<CollisionProxy>(ctx.space, m_params.samplesPerSpan);
    st.space = &ctx.space;
    st.mesh.triangles = st.proxy->triangles();
    st.mesh.edges = st.proxy->edges();
    proxyWorld(ctx.restShape ? *ctx.restShape : ctx.rest ? *ctx.rest : ctx.current, st.restWorld);
    ++st.generation;
    st.locals.corner.clear();  // addJacobian()'s view of the weights: made again
  }
  if (st.obstacles.size() != w.obstacles.size()) ++st.generation;  // one removed or added: other pairs
  st.obstacles.resize(w.obstacles.size());
  for (size_t o = 0; o < w.obstacles.size(); ++o) {
    State::Obstacle& ob = st.obstacles[o];
    const TriangleTree* tree = w.obstacles[o].tree.get();
    if (!tree) continue;
    if (ob.tree == tree && ob.version == tree->version()) continue;
    ContactMesh fresh = staticContactMesh(tree->mesh());
    ++st.generation;
    // the same triangles at new positions (a Transform or an engine moved it, another surface
    // stepped): swept from where it is toward them by advanceObstacles(); anything else: taken as it is
    const bool moved = ob.tree == tree && ob.mesh.start.rows() == fresh.start.rows() &&
                       ob.mesh.triangles.rows() == fresh.triangles.rows() && ob.mesh.triangles == fresh.triangles;
    ob.tree = tree;
    ob.version = tree->version();
    // a state put back that says where the surface last saw this obstacle: swept from there
    const bool restored = o < st.restoredPoses.size() && st.restoredPoses[o].rows() > 0 &&
                          st.restoredPoses[o].rows() == fresh.start.rows();
    if (restored) {
      ob.target = fresh.start;
      ob.mesh = std::move(fresh);
      ob.origin = ob.mesh.start = ob.mesh.end = st.restoredPoses[o];
      ob.remaining = ob.origin == ob.target ? 0.0 : 1.0;
      if (ob.remaining > 0.0) st.sweepStartPending = true;
      st.restoredPoses[o].resize(0, 3);  // taken
    } else if (moved && ob.mesh.start != fresh.start) {
      ob.origin = ob.mesh.start;
      ob.target = fresh.start;
      ob.remaining = 1.0;
      st.sweepStartPending = true;
    } else {
      ob.mesh = std::move(fresh);
      ob.target = ob.origin = ob.mesh.start;
      ob.remaining = 0.0;
    }
  }
}

void BarrierContactForce::proxyWorld(const ControlNet& net, Eigen::MatrixX3d& out) const {
  const CostTimer timer(&m_state->costs.proxy);
  const ContactWorld& w = *m_world;
  m_state->proxy->positions(net, w.linear, w.offset, out);
}

namespace {
/// Empties the lists, keeping their memory for the next pairs (millions of a sheet's with itself).
void clearCandidates(ContactCandidates& c) {
  c.vertexTriangle.clear();
  c.triangleVertex.clear();
  c.edgeEdge.clear();
}
}  // namespace

const std::vector<ContactCandidates>& BarrierContactForce::candidatesWithin(double inflation) const {
  State& st = *m_state;
  const CostTimer timer(&st.costs.broadPhase);
  State::Candidates& c = st.candidates;
  const double reach = m_params.offset + m_params.dhat;
  // The squared distance of the farthest vertex of x from its segment from refStart to refEnd
  // (infinity: another mesh, or not finite).
  auto farthest2 = [&](const Eigen::MatrixX3d& x) {
    if (x.rows() != c.refStart.rows() || x.rows() == 0) return double(INFINITY);
    double out = 0.0;
    for (Eigen::Index i = 0; i < x.rows(); ++i) {
      const Eigen::RowVector3d a = c.refStart.row(i), d = c.refEnd.row(i) - a, q = x.row(i) - a;
      const double dd = d.squaredNorm(), t = dd > 0.0 ? std::clamp(q.dot(d) / dd, 0.0, 1.0) : 0.0;
      const double r2 = (q - t * d).squaredNorm();
      if (!(r2 <= out)) out = std::isnan(r2) ? double(INFINITY) : r2;
    }
    return out;
  };
  auto obstaclesAsThen = [&] {
    if (c.obstacles.size() != st.obstacles.size()) return false;
    for (size_t o = 0; o < st.obstacles.size(); ++o) {
      const State::Obstacle& ob = st.obstacles[o];
      const Eigen::MatrixX3d& then = c.obstacles[o];
      if (!ob.tree) {
        if (then.rows() != 0) return false;
        continue;
      }
      if (ob.mesh.start.rows() != then.rows() || ob.mesh.end.rows() != then.rows() || ob.mesh.start != then ||
          ob.mesh.end != then)
        return false;
    }
    return true;
  };
  // how far the query strays from the list's segment: kept while every vertex, at both ends of
  // the query, is within the skin (the argument's margin is exactly 0: no rounding's)
  const double stray2 = std::max(farthest2(st.mesh.start), farthest2(st.mesh.end));
  const bool sameMesh = c.valid && c.generation == st.generation;
  if (!(sameMesh && obstaclesAsThen() && stray2 <= (1.0 - 1e-12) * c.skin * c.skin)) {
    // found again around the query's move (a CCD query's from its start to its end: the
    // iterates that follow on that segment, the step's first, cut by CCD, and Newton's near it,
    // then keep the list), the obstacles where they are (a moving obstacle mid-sweep, start and
    // end apart: not kept)
    // The skin: how far the queries that follow may stray from this one's segment and keep the
    // list. Half the reach, unless the surface has self-contact and a query that ended one of the
    // last 8 lists strayed beyond that: no skin this wide would have kept those lists (a sheet
    // turned fast leaves its list at every step), and an eighth of the reach makes the sheet's
    // pairs with itself, most of the list, fewer to narrow. Without self-contact a list is cheap
    // to narrow and finding it again against the obstacles is what costs, so the wide skin stays
    // (both measured in docs/benchmarks.md, "the self-contact broad phase"). The pairs found do
    // not depend on the skin, only how often and among how many they are sought.
    const double stray = sameMesh && m_params.selfContact ? std::sqrt(stray2) : 0.0;
    c.narrowSkinFor = stray > 0.5 * reach ? 8 : std::max(0, c.narrowSkinFor - 1);
    c.skin = (c.narrowSkinFor > 0 ? 0.125 : 0.5) * reach;
    const double skin = c.skin;
    c.refStart = st.mesh.start;
    c.refEnd = st.mesh.end;
    c.generation = st.generation;
    c.valid = true;
    ContactMesh at;
    at.start = c.refStart;
    at.end = c.refEnd;
    at.triangles = st.mesh.triangles;
    at.edges = st.mesh.edges;
    c.wide.resize(st.obstacles.size() + 1);  // each list cleared as it is found again: its memory kept
    c.obstacles.assign(st.obstacles.size(), Eigen::MatrixX3d());
    for (ContactCandidates& list : c.wide) clearCandidates(list);
    for (size_t o = 0; o < st.obstacles.size(); ++o) {
      const State::Obstacle& ob = st.obstacles[o];
      if (!ob.tree) continue;
      c.valid &= ob.mesh.start == ob.mesh.end;
      c.obstacles[o] = ob.mesh.start;
      candidatePairs(at, ob.mesh, reach + 2.0 * skin, c.wide[o]);
    }
    if (m_params.selfContact) {
      selfCandidatesApartAtRest(at, reach + 2.0 * skin, c.wide.back());
    }
    ++c.builds;
  }
  c.now.resize(st.obstacles.size() + 1);
  const bool kept = c.valid;
  for (size_t o = 0; o < st.obstacles.size(); ++o) {
    clearCandidates(c.now[o]);
    if (!st.obstacles[o].tree) continue;
    if (kept)
      narrowCandidates(st.mesh, st.obstacles[o].mesh, inflation, c.wide[o], c.now[o]);
    else  // a step longer than the skin: the broad phase itself
      candidatePairs(st.mesh, st.obstacles[o].mesh, inflation, c.now[o]);
  }
  clearCandidates(c.now.back());
  if (m_params.selfContact) {
    if (kept)
      narrowCandidates(st.mesh, inflation, c.wide.back(), c.now.back());
    else
      selfCandidatesApartAtRest(st.mesh, inflation, c.now.back());
  }
  return c.now;
}

void BarrierContactForce::selfCandidatesApartAtRest(const ContactMesh& mesh, double inflation,
                                                    ContactCandidates& out) const {
  State& st = *m_state;
  State::RestNeighbours& rn = st.restNeighbours;
  const double reach = m_params.offset + m_params.dhat;
  if (rn.reach != reach || rn.rest.rows() != st.restWorld.rows() || rn.rest != st.restWorld ||
      rn.edgeStart.size() != size_t(st.mesh.edges.rows()) + 1) {
    // every pair closer than the reach at rest has boxes within the reach: among these
    const Eigen::MatrixX3d& R = st.restWorld;
    const Eigen::MatrixX3i& T = st.mesh.triangles;
    const Eigen::MatrixX2i& E = st.mesh.edges;
    auto row = [&R](Eigen::Index i) { return Eigen::Vector3d(R.row(i).transpose()); };
    ContactMesh atRest;
    atRest.start = atRest.end = R;
    atRest.triangles = T;
    atRest.edges = E;
    ContactCandidates near;
    candidatePairs(atRest, reach, near);
    const double reach2 = reach * reach;
    rn.vertexTriangle.clear();
    for (const auto& vt : near.vertexTriangle)
      if (pointTriangleDistanceSquared(row(vt[0]), row(T(vt[1], 0)), row(T(vt[1], 1)), row(T(vt[1], 2))) < reach2)
        rn.vertexTriangle.push_back(vt);
    rn.edgeEdge.clear();
    for (const auto& ee : near.edgeEdge)
      if (edgeEdgeDistanceSquared(row(E(ee[0], 0)), row(E(ee[0], 1)), row(E(ee[1], 0)), row(E(ee[1], 1))) < reach2)
        rn.edgeEdge.push_back(ee);
    const auto starts = [](const std::vector<std::array<int, 2>>& pairs, Eigen::Index count,
                           std::vector<size_t>& start) {
      start.assign(size_t(count) + 1, 0);
      for (const auto& p : pairs) ++start[size_t(p[0]) + 1];
      for (size_t k = 1; k < start.size(); ++k) start[k] += start[k - 1];
    };
    starts(rn.vertexTriangle, R.rows(), rn.vertexStart);
    starts(rn.edgeEdge, E.rows(), rn.edgeStart);
    rn.rest = R;
    rn.reach = reach;
  }
  const auto among = [](const std::vector<std::array<int, 2>>& pairs, const std::vector<size_t>& start,
                        const std::array<int, 2>& p) {
    const auto first = pairs.begin() + std::ptrdiff_t(start[size_t(p[0])]);
    const auto last = pairs.begin() + std::ptrdiff_t(start[size_t(p[0]) + 1]);
    return std::binary_search(first, last, p);
  };
  const auto apart = [&](const std::array<int, 2>& vt) { return !among(rn.vertexTriangle, rn.vertexStart, vt); };
  const auto edgesApart = [&](const std::array<int, 2>& ee) { return !among(rn.edgeEdge, rn.edgeStart, ee); };
  candidatePairs(mesh, inflation, out, apart, edgesApart);
}

long BarrierContactForce::candidateSearches() const { return m_state->candidates.builds; }
const BarrierContactForce::Costs& BarrierContactForce::costs() const { return m_state->costs; }
void BarrierContactForce::resetCosts() const { m_state->costs = Costs(); }

const std::vector<ContactCandidates>& BarrierContactForce::gather(const LoadContext& ctx) const {
  prepare(ctx);
  State& st = *m_state;
  const ContactWorld& w = *m_world;
  State::Gathered& g = st.gathered;
  auto obstaclesAsThen = [&] {
    if (g.obstacleStarts.size() != st.obstacles.size()) return false;
    for (size_t o = 0; o < st.obstacles.size(); ++o) {
      const ContactMesh& m = st.obstacles[o].mesh;
      const Eigen::MatrixX3d &s0 = g.obstacleStarts[o], &e0 = g.obstacleEnds[o];
      if (m.start.rows() != s0.rows() || m.end.rows() != e0.rows() || m.start != s0 || m.end != e0) return false;
    }
    return true;
  };
  if (g.valid && g.generation == st.generation && g.net.rows() == ctx.current.rows() && g.net == ctx.current &&
      g.linear == w.linear && g.offset == w.offset && obstaclesAsThen()) {
    const CostTimer timer(&st.costs.broadPhase);
    st.mesh.start = st.mesh.end = g.positions;
    return g.pairs;
  }
  proxyWorld(ctx.current, st.mesh.start);
  st.mesh.end = st.mesh.start;
  const std::vector<ContactCandidates>& pairs = candidatesWithin(m_params.offset + m_params.dhat);
  const CostTimer timer(&st.costs.broadPhase);
  g.valid = true;
  g.generation = st.generation;
  g.net = ctx.current;
  g.linear = w.linear;
  g.offset = w.offset;
  g.obstacleStarts.resize(st.obstacles.size());
  g.obstacleEnds.resize(st.obstacles.size());
  for (size_t o = 0; o < st.obstacles.size(); ++o) {
    g.obstacleStarts[o] = st.obstacles[o].mesh.start;
    g.obstacleEnds[o] = st.obstacles[o].mesh.end;
  }
  g.positions = st.mesh.start;
  g.pairs = pairs;
  g.withinValid = false;
  return g.pairs;
}

struct BarrierContactForce::PairSite {
  enum Kind { VertexTriangle, TriangleVertex, EdgeEdge } kind;
  size_t where;  ///< the obstacle (obstacles.size(): the proxy itself)
  bool self;
  /// The pair's points as a Term names them: proxy vertices, -1 for an obstacle's
  std::array<Eigen::Index, 4> vertex;
  /// The same points as indices into their own meshes (an obstacle's too): a vertex and a
  /// triangle's three (VertexTriangle: proxy vertex, second mesh's triangle; TriangleVertex:
  /// second mesh's vertex, proxy triangle), or two edges' ends (EdgeEdge: proxy, second mesh)
  std::array<Eigen::Index, 4> index;
  /// World positions, in the order of `index`
  Eigen::Vector3d x[4];
  /// EdgeEdge: the mollifier's threshold from the rest positions (edgeEdgeMollifierThreshold)
  double threshold;
};

namespace {
/// fn(a, b) for the 3 x 3 blocks of a pair's 12 x 12 Hessian between its moving points (vertex
/// >= 0; an obstacle's are -1), row by row: the blocks addJacobian() reads.
template <typename Fn>
void forMovingBlocks(const std::array<Eigen::Index, 4>& vertex, Fn&& fn) {
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4 && vertex[size_t(a)] >= 0; ++b)
      if (vertex[size_t(b)] >= 0) fn(a, b);
}
}  // namespace

template <typename Visit>
void BarrierContactForce::forEachPair(const std::vector<ContactCandidates>& candidates, Visit&& visit, size_t begin,
                                      size_t end, double beyond) const {
  const State& st = *m_state;
  const Eigen::MatrixX3d& V = st.mesh.start;
  const Eigen::MatrixX3i& T = st.mesh.triangles;
  const Eigen::MatrixX2i& E = st.mesh.edges;
  auto row = [](const Eigen::MatrixX3d& M, Eigen::Index i) { return Eigen::Vector3d(M.row(i).transpose()); };
  PairSite site;
  size_t at = 0;  // the place of the list's first pair in the visiting order
  // the places [lo, hi) of a list of n pairs that fall in [begin, end)
  auto range = [&](size_t n, size_t& lo, size_t& hi) {
    lo = std::min(n, begin > at ? begin - at : size_t(0));
    hi = std::min(n, end > at ? end - at : size_t(0));
    at += n;
  };
  size_t lo = 0, hi = 0;
  // pairs certainly farther than `beyond` left out (Distance.h's lower bounds; none when beyond <= 0)
  const bool skip = beyond > 0.0;
  for (size_t o = 0; o <= st.obstacles.size(); ++o) {
    const ContactCandidates& c = candidates[o];
    const bool self = o == st.obstacles.size();
    const ContactMesh* ob = self ? &st.mesh : &st.obstacles[o].mesh;
    const Eigen::MatrixX3d& R = self ? st.restWorld : ob->start;  // rest positions of the second mesh
    const Eigen::MatrixX3d& W = self ? V : ob->start;
    site.where = o;
    site.self = self;
    site.threshold = 0.0;
    site.kind = PairSite::VertexTriangle;
    range(c.vertexTriangle.size(), lo, hi);
    for (size_t n = lo; n < hi; ++n) {
      const auto& [v, t] = c.vertexTriangle[n];
      const Eigen::Vector3i tri = ob->triangles.row(t).transpose();
      site.vertex = {v, self ? tri[0] : -1, self ? tri[1] : -1, self ? tri[2] : -1};
      site.index = {v, tri[0], tri[1], tri[2]};
      site.x[0] = row(V, v);
      for (int k = 0; k < 3; ++k) site.x[k + 1] = row(W, tri[k]);
      if (skip && pointTriangleFartherThan(site.x[0], site.x[1], site.x[2], site.x[3], beyond)) continue;
      visit(site);
    }
    site.kind = PairSite::TriangleVertex;
    range(c.triangleVertex.size(), lo, hi);
    for (size_t n = lo; n < hi; ++n) {  // an obstacle's vertex and a proxy triangle
      const auto& [t, v] = c.triangleVertex[n];
      const Eigen::Vector3i tri = T.row(t).transpose();
      site.vertex = {-1, tri[0], tri[1], tri[2]};
      site.index = {v, tri[0], tri[1], tri[2]};
      site.x[0] = row(W, v);
      for (int k = 0; k < 3; ++k) site.x[k + 1] = row(V, tri[k]);
      if (skip && pointTriangleFartherThan(site.x[0], site.x[1], site.x[2], site.x[3], beyond)) continue;
      visit(site);
    }
    site.kind = PairSite::EdgeEdge;
    range(c.edgeEdge.size(), lo, hi);
    for (size_t n = lo; n < hi; ++n) {
      const auto& [ea, eb] = c.edgeEdge[n];
      const Eigen::Index a0 = E(ea, 0), a1 = E(ea, 1);
      const Eigen::Index b0 = ob->edges(eb, 0), b1 = ob->edges(eb, 1);
      site.vertex = {a0, a1, self ? b0 : -1, self ? b1 : -1};
      site.index = {a0, a1, b0, b1};
      site.x[0] = row(V, a0);
      site.x[1] = row(V, a1);
      site.x[2] = row(W, b0);
      site.x[3] = row(W, b1);
      if (skip && edgeEdgeFartherThan(site.x[0], site.x[1], site.x[2], site.x[3], beyond)) continue;
      site.threshold =
          edgeEdgeMollifierThreshold(row(st.restWorld, a0), row(st.restWorld, a1), row(R, b0), row(R, b1));
      visit(site);
    }
  }
}

void BarrierContactForce::terms(const LoadContext& ctx, int order, const std::function<void(const Term&)>& fn,
                                bool withFriction, bool projected) const {
  State& st = *m_state;
  const std::vector<ContactCandidates>& candidates = gather(ctx);
  std::optional<CostTimer> timer(&st.costs.pairs);
  BarrierParameters bp;
  bp.offset = m_params.offset;
  bp.dhat = m_params.dhat;
  bp.stiffness = st.kappa;
  const Eigen::MatrixX3d& V = st.mesh.start;
  const BarrierHessian mode = projected ? BarrierHessian::ProjectedPsd : BarrierHessian::Exact;
  // One pair's term (value, and derivatives up to `order`) into t; its squared distance.
  // Against an obstacle only the proxy's points move: the pair's Hessian in them (a 3 x 3, 9 x 9
  // or 6 x 6 block of the 12 x 12) is what Newton needs, and where asked (`projected`) that block
  // is projected to PSD, not the whole (exact Newton where the block is PSD; a 3 x 3 eigenproblem
  // instead of a 12 x 12 for the common point–face pair). `first`, `n`: the moving coordinates;
  // n = 12: self-contact.
  // Reads nothing it writes: the pairs may be computed on any threads.
  auto compute = [&bp, order, mode](const PairSite& p, Term& t) {
    Vector12d* grad = order >= 1 ? &t.grad : nullptr;
    Matrix12d* hess = order >= 2 ? &t.hess : nullptr;
    t.vertex = p.vertex;
    t.friction = false;
    int first = 0, n = 12;
    double d2 = 0.0;
    switch (p.kind) {
      case PairSite::VertexTriangle:
        if (!p.self) {  // a proxy vertex and an obstacle's triangle: the point's 3 x 3 in closed form
          Eigen::Vector3d g;
          Eigen::Matrix3d h;
          t.value = pointStaticTriangleBarrier(p.x[0], p.x[1], p.x[2], p.x[3], bp, grad ? &g : nullptr,
                                               hess ? &h : nullptr, mode, &d2);
          if (grad) {
            grad->setZero();
            grad->head<3>() = g;
          }
          if (hess) {
            hess->setZero();
            hess->topLeftCorner<3, 3>() = h;
          }
          return d2;
        }
        [[fallthrough]];
      case PairSite::TriangleVertex:
        first = p.kind == PairSite::TriangleVertex ? 3 : 0;
        n = p.kind == PairSite::TriangleVertex ? 9 : (p.self ? 12 : 3);
        t.value = pointTriangleBarrier(p.x[0], p.x[1], p.x[2], p.x[3], bp, grad, hess, BarrierHessian::Exact, &d2);
        break;
      case PairSite::EdgeEdge:
        n = p.self ? 12 : 6;
        t.value = edgeEdgeBarrier(p.x[0], p.x[1], p.x[2], p.x[3], p.threshold, bp, grad, hess, BarrierHessian::Exact,
                                  &d2);
        break;
    }
    if (hess && mode == BarrierHessian::ProjectedPsd) projectBlockToPsd(t.hess, first, n);
    return d2;
  };
  // A term counts where any of what is asked of it is not zero: an edge–edge pair of exactly
  // parallel edges within reach has no value (its mollifier is 0) and no gradient, but a Hessian
  auto active = [order](const Term& t) {
    return t.value != 0.0 || (order >= 1 && !t.grad.isZero(0.0)) || (order >= 2 && !t.hess.isZero(0.0));
  };
  // Beyond the reach (s >= ŝ, the barrier's own test) a pair's value, gradient and Hessian are
  // exact zeros: the first call at these positions keeps the pairs within it (State::Gathered),
  // the later ones visit only those. The same terms in the same order, the same bits.
  State::Gathered& g = st.gathered;
  const bool reuse = g.withinValid;
  const double offsetSquared = bp.offset * bp.offset, sHat = barrierSquaredActivation(bp);
  auto withinReach = [&](double d2, const Term& t) { return d2 - offsetSquared < sHat || active(t); };
  // a first call leaves out the pairs a lower bound puts beyond the reach (d² - ξ² < ŝ: d below
  // √(ŝ + ξ²)), with a relative margin of 10⁻⁶ for the bounds' rounding: their terms are zeros
  // and they are not within it, so nothing computed changes (most of a draped cloth's
  // candidates: docs/benchmarks.md)
  const double beyond = (1.0 + 1e-6) * std::sqrt(sHat + offsetSquared);
  double minimum = std::numeric_limits<double>::infinity();
  // the smallest distance of a pair within reach (the first pair in the visiting order that has
  // it) and where it is
  auto closest = [&](double d, size_t where, const std::array<Eigen::Index, 4>& vertex) {
    if (d < minimum) {
      minimum = d;
      st.closestObstacle = int(where);
      st.closestVertex = *std::max_element(vertex.begin(), vertex.end());
    }
  };
  Term term;
  const int threads = kernelThreads();

  if (threads <= 1) {
    auto visit = [&](const PairSite& p) {
      const double d2 = compute(p, term);
      ++st.costs.pairsComputed;
      if (reuse || withinReach(d2, term)) {
        if (!reuse) g.within.push_back(p);
        closest(std::sqrt(std::max(d2, 0.0)), p.where, p.vertex);
      }
      if (active(term)) fn(term);
    };
    if (reuse) {
      for (const PairSite& p : g.within) visit(p);
    } else {
      g.within.clear();
      forEachPair(candidates, visit, 0, std::numeric_limits<size_t>::max(), beyond);
    }
  } else {
    // With kernel threads (BSDEFORM_THREADS) the pairs are computed in parts of the visiting
    // order, each part keeping its active terms, its pairs within reach and its smallest
    // distance, and handed to fn in that order: the same calls with the same bits for any thread
    // count. (A first call's parts walk the candidate lists themselves.)
    size_t count = g.within.size();
    if (!reuse) {
      count = 0;
      for (const ContactCandidates& c : candidates)
        count += c.vertexTriangle.size() + c.triangleVertex.size() + c.edgeEdge.size();
    }
    const int parts = int(std::min<size_t>(size_t(8 * threads), (count + 63) / 64));
    std::vector<State::TermPart>& out = st.parts;
    out.resize(size_t(std::max(parts, 0)));
    runParts(parts, [&](int k) {
      State::TermPart& part = out[size_t(k)];
      part.light.clear();
      part.blockStart.clear();
      part.blocks.clear();
      part.inside.clear();
      part.d = std::numeric_limits<double>::infinity();
      part.computed = 0;
      const size_t begin = count * size_t(k) / size_t(parts), end = count * size_t(k + 1) / size_t(parts);
      Term t;
      auto visit = [&](const PairSite& p) {
        const double d2 = compute(p, t);
        ++part.computed;
        if (reuse || withinReach(d2, t)) {
          if (!reuse) part.inside.push_back(p);
          const double d = std::sqrt(std::max(d2, 0.0));
          if (d < part.d) {
            part.d = d;
            part.where = p.where;
            part.vertex = p.vertex;
          }
        }
        if (!active(t)) return;
        part.light.push_back({t.vertex, t.value, order >= 1 ? t.grad : Vector12d::Zero().eval()});
        if (order < 2) return;
        part.blockStart.push_back(part.blocks.size());
        forMovingBlocks(t.vertex, [&](int a, int b) {
          for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) part.blocks.push_back(t.hess(3 * a + r, 3 * b + c));
        });
      };
      if (reuse) {
        for (size_t i = begin; i < end; ++i) visit(g.within[i]);
      } else {
        forEachPair(candidates, visit, begin, end, beyond);
      }
    });
    for (const State::TermPart& part : out) st.costs.pairsComputed += part.computed;
    for (int k = 0; k < parts; ++k) {
      const State::TermPart& part = out[size_t(k)];
      if (std::isfinite(part.d)) closest(part.d, part.where, part.vertex);
      for (size_t i = 0; i < part.light.size(); ++i) {
        const State::TermPart::Light& l = part.light[i];
        term.vertex = l.vertex;
        term.friction = false;  // a barrier pair's (friction's come below)
        term.value = l.value;
        term.grad = l.grad;
        if (order >= 2) {
          const double* h = part.blocks.data() + part.blockStart[i];
          forMovingBlocks(l.vertex, [&](int a, int b) {
            for (int r = 0; r < 3; ++r)
              for (int c = 0; c < 3; ++c) term.hess(3 * a + r, 3 * b + c) = *h++;
          });
        }
        fn(term);
      }
    }
    if (!reuse) {
      g.within.clear();
      for (int k = 0; k < parts; ++k)
        g.within.insert(g.within.end(), out[size_t(k)].inside.begin(), out[size_t(k)].inside.end());
    }
  }
  g.withinValid = g.valid;
  st.minimum = minimum;
  if (!withFriction || st.friction.empty()) return;
  // friction: each frozen pair's slip r = Σ c_k (x_k - x_k(previous)) over its moving points
  auto row = [](const Eigen::MatrixX3d& M, Eigen::Index i) { return Eigen::Vector3d(M.row(i).transpose()); };
  Vector12d* grad = order >= 1 ? &term.grad : nullptr;
  Matrix12d* hess = order >= 2 ? &term.hess : nullptr;
  timer.reset();
  proxyWorld(ctx.previous, st.previousWorld);
  timer.emplace(&st.costs.pairs);
  const double epsilon = m_params.epsv * ctx.stepSize;
  Eigen::Vector3d gr;
  Eigen::Matrix3d hr;
  for (const FrictionPair& f : st.friction) {
    Eigen::Vector3d r = f.slip;
    for (size_t k = 0; k < 4; ++k)
      if (f.vertex[k] >= 0) r += f.coefficient[k] * (row(V, f.vertex[k]) - row(st.previousWorld, f.vertex[k]));
    term.vertex = f.vertex;
    term.friction = true;
    term.value = frictionPotential(f, r, m_params.friction, epsilon, grad ? &gr : nullptr, hess ? &hr : nullptr);
    for (int k = 0; k < 4 && grad; ++k) term.grad.segment<3>(3 * k) = f.coefficient[size_t(k)] * gr;
    for (int k = 0; k < 4 && hess; ++k)
      for (int l = 0; l < 4; ++l)
        term.hess.block<3, 3>(3 * k, 3 * l) = (f.coefficient[size_t(k)] * f.coefficient[size_t(l)]) * hr;
    fn(term);
  }
}

void BarrierContactForce::freezeFriction(const LoadContext& ctx) const {
  State& st = *m_state;
  st.loadValue.valid = false;
  st.friction.clear();
  if (!(m_params.friction > 0.0)) return;
  const std::vector<ContactCandidates>& candidates = gather(ctx);
  BarrierParameters bp;
  bp.offset = m_params.offset;
  bp.dhat = m_params.dhat;
  const double sHat = barrierSquaredActivation(bp), xi2 = m_params.offset * m_params.offset;
  // λ = -κ b'(s) ∂s/∂d = -2 d κ b'(d² - ξ²) (ipc-toolkit's normal force magnitude), times the
  // mollifier for edge–edge pairs (their barrier's force is scaled by it; ipc-toolkit leaves it out)
  auto normalForce = [&](double d2) { return -2.0 * std::sqrt(d2) * st.kappa * barrierFirstDerivative(d2 - xi2, sHat); };
  auto row = [](const Eigen::MatrixX3d& M, Eigen::Index i) { return Eigen::Vector3d(M.row(i).transpose()); };
  // a moving obstacle's points move over the step by its sweep (§18.4): friction acts on the slip
  // relative to them
  size_t sweepOf = st.obstacles.size();  // the obstacle `sweep` is of (none yet)
  Eigen::MatrixX3d sweep;
  auto moved = [&](const PairSite& p, Eigen::Index i) {
    if (p.self || !(st.obstacles[p.where].remaining > 0.0)) return Eigen::Vector3d::Zero().eval();
    if (sweepOf != p.where) {
      sweep = st.obstacles[p.where].target - st.obstacles[p.where].mesh.start;
      sweepOf = p.where;
    }
    return row(sweep, i);
  };
  FrictionPair f;
  auto visit = [&](const PairSite& p) {
    const std::array<Eigen::Index, 4>& i = p.index;
    switch (p.kind) {
      case PairSite::VertexTriangle:
      case PairSite::TriangleVertex: {
        const double d2 = pointTriangleDistanceSquared(p.x[0], p.x[1], p.x[2], p.x[3]);
        if (!(d2 - xi2 < sHat)) return;
        f.vertex = p.vertex;
        f.normalForce = normalForce(d2);
        pointTriangleFrame(p.x[0], p.x[1], p.x[2], p.x[3], f);
        // the second mesh's points: the triangle's (vertex–triangle) or the vertex (triangle–vertex)
        if (p.kind == PairSite::TriangleVertex)
          f.slip = f.coefficient[0] * moved(p, i[0]);
        else
          f.slip = p.self ? Eigen::Vector3d::Zero().eval()
                          : Eigen::Vector3d(f.coefficient[1] * moved(p, i[1]) + f.coefficient[2] * moved(p, i[2]) +
                                            f.coefficient[3] * moved(p, i[3]));
        break;
      }
      case PairSite::EdgeEdge: {
        const double d2 = edgeEdgeDistanceSquared(p.x[0], p.x[1], p.x[2], p.x[3]);
        if (!(d2 - xi2 < sHat)) return;
        const double m = edgeEdgeMollifier((p.x[1] - p.x[0]).cross(p.x[3] - p.x[2]).squaredNorm(), p.threshold);
        if (!(m > 0.0)) return;
        f.vertex = p.vertex;
        f.normalForce = m * normalForce(d2);
        edgeEdgeFrame(p.x[0], p.x[1], p.x[2], p.x[3], f);
        f.slip = p.self ? Eigen::Vector3d::Zero().eval()
                        : Eigen::Vector3d(f.coefficient[2] * moved(p, i[2]) + f.coefficient[3] * moved(p, i[3]));
        break;
      }
    }
    st.friction.push_back(f);
  };
  // beginStep()'s evaluation at this net kept the pairs within reach, in the visiting order: the
  // only ones that can have friction (the same distances, the same test below)
  if (st.gathered.withinValid) {
    for (const PairSite& p : st.gathered.within) visit(p);
  } else {
    forEachPair(candidates, visit);
  }
}

bool BarrierContactForce::potential(const LoadContext& ctx, double& value) const {
  prepare(ctx);
  const State::LoadValue& kept = m_state->loadValue;
  const ContactWorld& w = *m_world;
  if (kept.valid && kept.generation == m_state->generation && kept.stepSize == ctx.stepSize &&
      kept.kappa == m_state->kappa && kept.linear == w.linear && kept.offset == w.offset &&
      kept.current.rows() == ctx.current.rows() && kept.previous.rows() == ctx.previous.rows() &&
      kept.current == ctx.current && kept.previous == ctx.previous) {
    value = kept.value;  // the same terms summed in the same order: the same bits
    return true;
  }
  value = 0.0;
  terms(ctx, 0, [&](const Term& t) { value += t.value; });
  return true;
}

bool BarrierContactForce::storedEnergy(const LoadContext& ctx, double& value) const {
  value = 0.0;
  if (!m_state->seen.unchangedSinceFirst(*m_world)) return false;  // a moving obstacle does work on the surface
  terms(ctx, 0, [&](const Term& t) { value += t.value; }, false);
  return true;
}

void BarrierContactForce::addLoad(const LoadContext& ctx, ControlNet& load) const {
  const ContactWorld& w = *m_world;
  Eigen::MatrixX3d f;
  bool any = false;
  State::LoadValue& kept = m_state->loadValue;
  kept.valid = false;
  double value = 0.0;  // the terms at order 1 are those at order 0 and some of value 0
  terms(ctx, 1, [&](const Term& t) {
    value += t.value;
    if (!any) {
      f = Eigen::MatrixX3d::Zero(m_state->proxy->numVertices(), 3);
      any = true;
    }
    for (int k = 0; k < 4; ++k)
      if (t.vertex[size_t(k)] >= 0)
        f.row(t.vertex[size_t(k)]) -= (w.linear.transpose() * t.grad.segment<3>(3 * k)).transpose();
  });
  if (any) m_state->proxy->addVertexForces(f, load);
  kept.current = ctx.current;
  kept.previous = ctx.previous;
  kept.stepSize = ctx.stepSize;
  kept.generation = m_state->generation;
  kept.kappa = m_state->kappa;
  kept.linear = w.linear;
  kept.offset = w.offset;
  kept.value = value;
  kept.valid = true;
}

void BarrierContactForce::addJacobian(const LoadContext& ctx, double velocityScale, JacobianSink& sink) const {
  const ContactWorld& w = *m_world;
  // friction is a function of the slip x - x(previous) = h v alone: its K = -s ∂L/∂v = s h ∂²D/∂x²
  const double frictionScale = velocityScale * ctx.stepSize;
  // The pairs' 3 x 3 blocks between proxy vertices, summed per vertex pair first (a vertex is in
  // several pairs: against neighbouring triangles and edges, barrier and friction), then each
  // pushed once through the weights: 16 x 16 control-point blocks per vertex pair, not per pair.
  using Block = State::Block;
  std::vector<Block>& blocks = m_state->blocks;
  blocks.clear();
  terms(ctx, 2, [&](const Term& t) {
    const double scale = t.friction ? frictionScale : 1.0;
    // every block between the pair's moving points, those coupling the two primitives of a
    // self-contact pair too (points of no common element: the tangent's pattern takes them in,
    // TangentMatrix::settlePattern)
    forMovingBlocks(t.vertex, [&](int a, int b) {
      blocks.push_back({t.vertex[size_t(a)], t.vertex[size_t(b)], scale * t.hess.block<3, 3>(3 * a, 3 * b)});
    });
  }, /*withFriction=*/true, /*projected=*/m_params.projectHessian && sink.wantsDefinite);
  if (blocks.empty()) return;
  State& st = *m_state;
  const CostTimer timer(&st.costs.push);
  // summed per vertex pair in the order the terms came (a stable order: keys, then places)
  const std::uint64_t vertices = std::uint64_t(m_state->proxy->numVertices());
  std::vector<std::pair<std::uint64_t, std::uint32_t>>& order = st.blockOrder;
  order.resize(blocks.size());
  assert(blocks.size() <= size_t(std::numeric_limits<std::uint32_t>::max()));
  // as std::sort of (key, place) would order them: two counting sorts, by the second vertex and
  // then by the first, each keeping the order it is given (a comparison sort of all of them was
  // 9 % of the 32² twist's run once its folds touched)
  std::vector<size_t>& count = st.blockCount;
  std::vector<std::uint32_t>& bySecond = st.blockBySecond;
  bySecond.resize(blocks.size());
  const auto countingSort = [&](auto vertexOf, auto placeOf, auto put) {
    count.assign(size_t(vertices) + 1, 0);
    for (size_t k = 0; k < blocks.size(); ++k) ++count[size_t(vertexOf(placeOf(k))) + 1];
    for (size_t v = 0; v < size_t(vertices); ++v) count[v + 1] += count[v];
    for (size_t k = 0; k < blocks.size(); ++k) {
      const std::uint32_t place = placeOf(k);
      put(count[size_t(vertexOf(place))]++, place);
    }
  };
  countingSort([&](std::uint32_t k) { return blocks[k].b; }, [](size_t k) { return std::uint32_t(k); },
               [&](size_t at, std::uint32_t k) { bySecond[at] = k; });
  countingSort([&](std::uint32_t k) { return blocks[k].a; }, [&](size_t k) { return bySecond[k]; },
               [&](size_t at, std::uint32_t k) {
                 order[at] = {std::uint64_t(blocks[k].a) * vertices + std::uint64_t(blocks[k].b), k};
               });
  // Then per pair of elements (the knot span whose control points a vertex's weights lie in,
  // named by its first net point): Σ over the pair's vertex pairs of (w_a w_bᵀ) ⊗ H_ab, dense,
  // and each control-point block of that to the sink once, as a block of a symmetric Jacobian
  // (barrier and lagged friction are Hessians): a vertex pair no longer costs 16 x 16 sink calls,
  // which had been a fifth of cloth_on_cube's run (docs/benchmarks.md, issue 35).
  const CollisionProxy& proxy = *st.proxy;
  const SplineSpace& space = ctx.space;
  const int cols = space.netCols(), L1 = space.degreeU() + 1, L2 = space.degreeV() + 1, L = L1 * L2;
  State::VertexLocals& loc = st.locals;
  if (loc.corner.size() != size_t(vertices)) {
    loc.corner.resize(size_t(vertices));
    loc.first.resize(size_t(vertices));
    loc.count.resize(size_t(vertices));
    loc.slot.clear();
    loc.weight.clear();
    for (Eigen::Index v = 0; v < Eigen::Index(vertices); ++v) {
      const CollisionProxy::Weights ws = proxy.netWeights(v);
      Eigen::Index i0 = std::numeric_limits<Eigen::Index>::max(), j0 = i0;
      for (const auto& e : ws) {
        i0 = std::min(i0, e.index / cols);
        j0 = std::min(j0, e.index % cols);
      }
      loc.corner[size_t(v)] = i0 * cols + j0;
      loc.first[size_t(v)] = int(loc.slot.size());
      loc.count[size_t(v)] = int(ws.size());
      assert(int(ws.size()) <= L);
      for (const auto& e : ws) {
        const Eigen::Index di = e.index / cols - i0, dj = e.index % cols - j0;
        assert(di < L1 && dj < L2);
        loc.slot.push_back(int(di * L2 + dj));
        loc.weight.push_back(e.weight);
      }
    }
  }
  // Each vertex pair's summed block through the frame, and the element pair it goes to
  std::vector<State::ElementPair>& pairs = st.elementPairs;  // the first `used` in use
  std::unordered_map<std::uint64_t, size_t>& pairIndex = st.elementPairIndex;
  std::vector<State::VertexPair>& vps = st.vertexPairs;
  pairIndex.clear();
  vps.clear();
  size_t used = 0;
  const std::uint64_t netSize = std::uint64_t(space.netSize());
  std::uint64_t lastKey = std::numeric_limits<std::uint64_t>::max();
  size_t lastPair = 0;
  for (size_t i = 0; i < order.size();) {
    const Block& first = blocks[order[i].second];
    Eigen::Matrix3d sum = first.h;
    size_t j = i + 1;
    for (; j < order.size() && order[j].first == order[i].first; ++j) sum += blocks[order[j].second].h;
    const size_t a = size_t(first.a), b = size_t(first.b);
    const std::uint64_t key = std::uint64_t(loc.corner[a]) * netSize + std::uint64_t(loc.corner[b]);
    if (key != lastKey) {
      auto [it, fresh] = pairIndex.emplace(key, used);
      if (fresh) {
        if (used == pairs.size()) pairs.emplace_back();
        pairs[used].a = loc.corner[a];
        pairs[used].b = loc.corner[b];
        ++used;
      }
      lastKey = key;
      lastPair = it->second;
    }
    vps.push_back({lastPair, a, b, w.linear.transpose() * sum * w.linear});
    i = j;
  }
  // per element pair, its vertex pairs in the order above (a counting sort: stable)
  std::vector<size_t>& start = st.pairStart;
  std::vector<size_t>& members = st.pairMembers;
  start.assign(used + 1, 0);
  for (const State::VertexPair& vp : vps) ++start[vp.pair + 1];
  for (size_t p = 0; p < used; ++p) start[p + 1] += start[p];
  members.resize(vps.size());
  {
    std::vector<size_t> next(start.begin(), start.end() - 1);
    for (size_t k = 0; k < vps.size(); ++k) members[next[vps[k].pair]++] = k;
  }
  // Σ (w_a w_bᵀ) ⊗ H_ab per element pair on the kernel threads: each pair's sums are its own,
  // their terms added in the order above (the same bits for any thread count)
  const size_t entries = size_t(L) * size_t(L) * 9;
  auto accumulate = [&](size_t p) {
    std::vector<double>& Kp = pairs[p].K;
    Kp.assign(entries, 0.0);
    double* K = Kp.data();
    for (size_t m = start[p]; m < start[p + 1]; ++m) {
      const State::VertexPair& vp = vps[members[m]];
      const Eigen::Matrix3d& H = vp.H;
      const int* sa = &loc.slot[size_t(loc.first[vp.a])];
      const int* sb = &loc.slot[size_t(loc.first[vp.b])];
      const double* wa = &loc.weight[size_t(loc.first[vp.a])];
      const double* wb = &loc.weight[size_t(loc.first[vp.b])];
      const int na = loc.count[vp.a], nb = loc.count[vp.b];
      for (int x = 0; x < na; ++x)
        for (int y = 0; y < nb; ++y) {
          double* k = K + (size_t(sa[x]) * L + size_t(sb[y])) * 9;
          const double ww = wa[x] * wb[y];
          for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) k[3 * r + c] += ww * H(r, c);
        }
    }
  };
  const int parts = int(std::min<size_t>(size_t(4 * kernelThreads()), used));
  if (parts <= 1) {
    for (size_t p = 0; p < used; ++p) accumulate(p);
  } else {
    runParts(parts, [&](int k) {
      for (size_t p = used * size_t(k) / size_t(parts); p < used * size_t(k + 1) / size_t(parts); ++p) accumulate(p);
    });
  }
  // to the sink in the order of the element pairs' first net points
  std::vector<size_t>& sorted = st.pairOrder;
  sorted.resize(used);
  for (size_t p = 0; p < used; ++p) sorted[p] = p;
  std::sort(sorted.begin(), sorted.end(), [&](size_t x, size_t y) {
    return pairs[x].a != pairs[y].a ? pairs[x].a < pairs[y].a : pairs[x].b < pairs[y].b;
  });
  for (const size_t p : sorted) {
    const State::ElementPair& pair = pairs[p];
    for (int x = 0; x < L; ++x)
      for (int y = 0; y < L; ++y) {
        const double* k = pair.K.data() + (size_t(x) * L + size_t(y)) * 9;
        bool any = false;
        for (int e = 0; e < 9; ++e) any |= k[e] != 0.0;
        if (!any) continue;
        const Eigen::Matrix3d B = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(k);
        sink.addSymmetric(pair.a + (x / L2) * cols + x % L2, pair.b + (y / L2) * cols + y % L2, B);
      }
  }
}

namespace {
/// The line search's CCD keeps 40 % of every pair's gap above the offset (additive CCD's
/// rescaling 0.6, where C-IPC's 0.9 keeps 10 %): with 0.9 an impact's iterates crowded a pair to
/// within nanometres of the offset, where the barrier's curvature lets Newton take only steps of
/// about that size (docs/math.md §18.2; the rescalings measured in docs/benchmarks.md, "The line
/// search's CCD").
constexpr double kLineSearchRescaling = 0.6;
}  // namespace

double BarrierContactForce::admissibleFraction(const LoadContext& ctx, const ControlNet& to) const {
  prepare(ctx);
  State& st = *m_state;
  proxyWorld(ctx.current, st.mesh.start);
  proxyWorld(to, st.mesh.end);
  const std::vector<ContactCandidates>& candidates = candidatesWithin(m_params.offset);
  const CostTimer timer(&st.costs.ccd);
  double t = 1.0;
  for (size_t o = 0; o < st.obstacles.size(); ++o)
    if (st.obstacles[o].tree)
      t = std::min(t, collisionFreeFraction(st.mesh, st.obstacles[o].mesh, candidates[o], m_params.offset,
                                            kLineSearchRescaling));
  if (m_params.selfContact)
    t = std::min(t, collisionFreeFraction(st.mesh, candidates.back(), m_params.offset, kLineSearchRescaling));
  return t;
}

double BarrierContactForce::advanceObstacles(const LoadContext& ctx) const {
  prepare(ctx);
  State& st = *m_state;
  st.loadValue.valid = false;
  double remaining = 0.0;
  bool any = false;
  for (State::Obstacle& ob : st.obstacles) {
    if (!ob.tree || ob.remaining == 0.0) continue;
    if (!any) {
      proxyWorld(ctx.current, st.mesh.start);
      st.mesh.end = st.mesh.start;
      any = true;
    }
    ContactMesh sweep = ob.mesh;
    sweep.end = ob.target;
    const CostTimer timer(&st.costs.ccd);
    ob.sweepBy(collisionFreeFraction(st.mesh, sweep, m_params.offset));
    remaining = std::max(remaining, ob.remaining);
  }
  return remaining;
}

double BarrierContactForce::jointAdvanceFraction(const LoadContext& ctx, const ControlNet& to,
                                                 double obstacleFraction) const {
  prepare(ctx);
  State& st = *m_state;
  proxyWorld(ctx.current, st.mesh.start);
  proxyWorld(to, st.mesh.end);
  const double f = std::clamp(obstacleFraction, 0.0, 1.0);
  for (State::Obstacle& ob : st.obstacles)
    if (ob.tree && ob.remaining > 0.0) ob.mesh.end = ob.mesh.start + f * (ob.target - ob.mesh.start);
  // the surface and the obstacles both move: the line search's rescaling (each pair keeps 40 %
  // of its gap), found against the swept obstacles (not kept: their start and end differ)
  const std::vector<ContactCandidates>& candidates = candidatesWithin(m_params.offset);
  double t = 1.0;
  {
    const CostTimer timer(&st.costs.ccd);
    for (size_t o = 0; o < st.obstacles.size(); ++o)
      if (st.obstacles[o].tree)
        t = std::min(t, collisionFreeFraction(st.mesh, st.obstacles[o].mesh, candidates[o], m_params.offset,
                                              kLineSearchRescaling));
    if (m_params.selfContact)
      t = std::min(t, collisionFreeFraction(st.mesh, candidates.back(), m_params.offset, kLineSearchRescaling));
  }
  for (State::Obstacle& ob : st.obstacles)
    if (ob.tree) ob.mesh.end = ob.mesh.start;
  return t;
}

double BarrierContactForce::advanceObstaclesBy(const LoadContext& ctx, double fraction) const {
  prepare(ctx);
  State& st = *m_state;
  st.loadValue.valid = false;
  const double f = std::clamp(fraction, 0.0, 1.0);
  double remaining = 0.0;
  for (State::Obstacle& ob : st.obstacles) {
    if (!ob.tree || ob.remaining == 0.0) continue;
    ob.sweepBy(f);
    remaining = std::max(remaining, ob.remaining);
  }
  return remaining;
}

std::string BarrierContactForce::beginStep(const LoadContext& ctx) const {
  prepare(ctx);
  State& st = *m_state;
  st.loadValue.valid = false;
  const bool retaken = !st.sweepStartPending && st.sweepStart.rows() == ctx.current.rows() && st.sweepStart == ctx.current;
  if (retaken) {
    // the step taken again from the same start (a failed attempt, retaken in pieces): every
    // obstacle from where it was when the step began
    for (State::Obstacle& ob : st.obstacles)
      if (ob.tree && ob.origin.rows() == ob.mesh.start.rows() && ob.origin != ob.mesh.start) {
        ob.mesh.start = ob.mesh.end = ob.origin;
        ob.remaining = ob.origin == ob.target ? 0.0 : 1.0;
      }
  } else {
    // a new step: where each obstacle is now is where the surface last saw it
    st.sweepStart = ctx.current;
    st.sweepStartPending = false;
    for (State::Obstacle& ob : st.obstacles) ob.origin = ob.mesh.start;
  }
  const ContactWorld& w = *m_world;
  // the spline lies within `deviation` of its proxy (docs/math.md §18.1): the offset must exceed
  // it, or the spline could reach an obstacle while its proxy keeps the offset
  // (through the frame: its largest singular value bounds how far a distance can stretch)
  const double stretch = Eigen::JacobiSVD<Eigen::Matrix3d>(w.linear).singularValues()(0);
  st.deviation = st.proxy->deviationBound(ctx.current) * stretch;
  std::ostringstream os;
  if (!(st.deviation < m_params.offset)) {
    os << "the surface has curved so much that it may lie " << measuredText(st.deviation)
       << " m from its collision proxy, as much as the contact offset thickness " << numberText(m_params.offset)
       << " m; raise proxySamples (now " << m_params.samplesPerSpan << ") or thickness";
    return os.str();
  }
  const double diagonal = (st.restWorld.colwise().maxCoeff() - st.restWorld.colwise().minCoeff()).norm();
  if (st.kappa == 0.0) {
    // IPC's potential is h² times ours (its inertia ½|x - x̂|²_M against our ½|x - x̂|²_M / h²):
    // its κ over h² here. The gradients are not balanced (κ_min, IPC's choice without them).
    const double mass = m_params.modelMass ? ctx.massPerArea * ctx.restArea : m_params.mass;
    const double averageMass = mass / double(st.proxy->numVertices());
    const Eigen::VectorXd none = Eigen::VectorXd::Zero(1);
    const double h2 = ctx.stepSize * ctx.stepSize;
    st.kappa = initialBarrierStiffness(diagonal, m_params.dhat, averageMass, none, none, st.kappaMax, 1e11,
                                       m_params.offset) / h2;
    st.kappaMax /= h2;
  }
  terms(ctx, 0, [](const Term&) {}, false);  // finds the smallest distance
  if (!(st.minimum > m_params.offset)) {
    const Eigen::Vector2d uv = st.proxy->parameters(std::max<Eigen::Index>(st.closestVertex, 0));
    os << "the surface is within the contact offset thickness " << numberText(m_params.offset) << " m of ";
    if (st.closestObstacle == int(st.obstacles.size()))
      os << "itself";
    else
      os << "obstacle " << st.closestObstacle + 1;
    if (st.closestObstacle >= 0 && size_t(st.closestObstacle) < w.obstacles.size() &&
        !w.obstacles[size_t(st.closestObstacle)].name.empty())
      os << " (" << w.obstacles[size_t(st.closestObstacle)].name << ")";
    os << " near (u, v) = (" << measuredText(uv.x()) << ", " << measuredText(uv.y()) << "): distance " << measuredText(st.minimum)
       << " m; start it clear of obstacles and of itself";
    return os.str();
  }
  updateBarrierStiffness(st.previousMinimum - m_params.offset, st.minimum - m_params.offset, st.kappaMax, st.kappa,
                         diagonal);
  st.previousMinimum = st.minimum;
  freezeFriction(ctx);
  return std::string();
}

}  // namespace bsdeform
