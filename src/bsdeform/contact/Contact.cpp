// SPDX-License-Identifier: MIT
#include "bsdeform/contact/Contact.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <stdexcept>
#include <tuple>
#include <unordered_map>

#include "bsdeform/forces/LoadQuadrature.h"
#include "bsdeform/base/NumberText.h"

namespace bsdeform {

namespace {
// Share of rho / dt the damping and friction may reach: with the sub-step sized to
// dt^2 lambda <= 4 s^2 (s = 0.9), a backward-difference damping rate nu keeps the scheme stable
// while dt nu <= 2 (1 - s^2) = 0.38 (DragForce).
constexpr double kRateCap = 0.3;
// Obstacles are searched within this many thicknesses.
constexpr double kSearch = 3.0;

// What CollisionForce asks of the closest-point queries at one quadrature point: a radius of
// its own (at least the law's search), one hint per obstacle, and in return how far the point
// may move before any obstacle can act on it (-inf: unknown).
struct PointQuery {
  double radius = 0.0;
  int* hints = nullptr;  // one per obstacle, or null
  double free = std::numeric_limits<double>::infinity();
};

Eigen::Vector3d densityAt(const ContactWorld& world, const ContactParameters& p, const Eigen::Vector3d& x,
                          const Eigen::Vector3d& v, double dt, const Eigen::Matrix3d& frame, double scale,
                          double* depthOut, PointQuery* query);
// The distance of x (moving with v) from an obstacle's closest point `hit`, signed for closed
// obstacles, and in n the unit direction away from the obstacle.
double separation(const ContactWorld::Obstacle& o, const ClosestHit& hit, const Eigen::Vector3d& x,
                  const Eigen::Vector3d& v, Eigen::Vector3d& n) {
  const double s = o.closed ? hit.signedDistance : hit.distance;
  n = hit.normal;
  if (hit.distance > 1e-12 * (1.0 + x.norm())) {
    n = (x - hit.point) / hit.distance;
    if (o.closed && s < 0.0) n = -n;
  } else if (!o.closed && v.dot(n) > 0.0) {
    n = -n;  // on an open shell: push back to the side it came from
  }
  return s;
}

double checked(double x, const char* name, bool positive) {
  if (!std::isfinite(x) || x < 0.0 || (positive && x == 0.0))
    throw std::invalid_argument(std::string("collision ") + name + (positive ? " must be finite and > 0" : " must be finite and >= 0") +
                                ", got " + numberText(x));
  return x;
}
// s^2 when A = s R (R orthogonal, a similarity: every area scales alike), else 0.
double frameAreaScale(const Eigen::Matrix3d& A) {
  const Eigen::Matrix3d g = A.transpose() * A;
  const double s2 = g.trace() / 3.0;
  return (g - s2 * Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= 1e-12 * s2 ? s2 : 0.0;
}

// The frame's quantities one load needs.
struct Frame {
  Eigen::Matrix3d cofactor;  // cof(A) = det(A) A^-T, (A u) x (A v) = cof(A) (u x v); defined for singular A
  double similarity;         // frameAreaScale(A)
  explicit Frame(const Eigen::Matrix3d& A) : similarity(frameAreaScale(A)) {
    cofactor.col(0) = A.col(1).cross(A.col(2));
    cofactor.col(1) = A.col(2).cross(A.col(0));
    cofactor.col(2) = A.col(0).cross(A.col(1));
  }
};

// The density per unit parameter area at a sample (position, velocity, and the normal unless the
// frame is a similarity): a gamma A^T f_world, the law per unit world area with its caps in the
// surface's own terms.
Eigen::Vector3d localDensity(const ContactWorld& w, const ContactParameters& p, const Frame& fr, const SurfaceSample& s,
                             PointQuery& query) {
  const double gamma = fr.similarity > 0.0 ? fr.similarity : (fr.cofactor * s.normal).norm();
  if (!(gamma > 0.0)) {  // a degenerate point of the surface: nothing learnt about the distance
    query.free = -std::numeric_limits<double>::infinity();
    return Eigen::Vector3d::Zero();
  }
  const double scale = p.areaScale * gamma;
  const Eigen::Vector3d f =
      densityAt(w, p, w.linear * s.position + w.offset, w.linear * s.velocity, s.stepSize, w.linear, scale, nullptr,
                &query);
  if (f.isZero(0.0)) return f;
  return scale * (w.linear.transpose() * f);
}
}  // namespace

bool isClosedMesh(const TriangleMesh& mesh) {
  if (mesh.triangles.empty()) return false;
  std::map<std::pair<int, int>, int> directed;  // each directed edge once
  for (const Eigen::Vector3i& t : mesh.triangles)
    for (int e = 0; e < 3; ++e)
      if (++directed[{t[e], t[(e + 1) % 3]}] > 1) return false;
  for (const auto& d : directed)
    if (!directed.count({d.first.second, d.first.first})) return false;
  return true;
}

TriangleMesh weldVertices(const TriangleMesh& mesh, double tolerance) {
  if (tolerance < 0.0) {
    double largest = 0.0;
    for (const Eigen::Vector3d& p : mesh.vertices)
      if (p.allFinite()) largest = std::max(largest, p.cwiseAbs().maxCoeff());
    tolerance = kWeldUlps * double(std::numeric_limits<float>::epsilon()) * largest;
  }
  TriangleMesh out;
  std::vector<int> map(mesh.vertices.size(), -1);
  // Cells four tolerances wide: a vertex within the tolerance (per coordinate) of a kept one lies
  // in its cell or, along an axis where it is within the tolerance of the cell's side, in the
  // neighbour there (usually no neighbour needs looking at). Exact equality when it is 0.
  const double cell = 4.0 * tolerance;
  struct KeyHash {
    std::size_t operator()(const Eigen::Matrix<std::int64_t, 3, 1>& k) const {
      return std::size_t(k.x() * 73856093LL ^ k.y() * 19349663LL ^ k.z() * 83492791LL);
    }
  };
  std::unordered_map<Eigen::Matrix<std::int64_t, 3, 1>, std::vector<int>, KeyHash> grid;
  std::map<std::tuple<double, double, double>, int> exact;  // no tolerance, non-finite or beyond the grid's range
  const double range = 0x1p60;
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Eigen::Vector3d& p = mesh.vertices[i];
    const Eigen::Vector3d q = tolerance > 0.0 ? Eigen::Vector3d(p / cell) : Eigen::Vector3d::Constant(NAN);
    if (!q.allFinite() || q.cwiseAbs().maxCoeff() > range) {
      auto it = exact.emplace(std::make_tuple(p.x(), p.y(), p.z()), int(out.vertices.size()));
      if (it.second) out.vertices.push_back(p);
      map[i] = it.first->second;
      continue;
    }
    const Eigen::Vector3d fl = q.array().floor();
    const Eigen::Matrix<std::int64_t, 3, 1> k = fl.cast<std::int64_t>();
    // per axis: 0, or -1 / +1 when within a quarter cell (one tolerance) of that side
    Eigen::Vector3i side = Eigen::Vector3i::Zero();
    for (int a = 0; a < 3; ++a) {
      const double f = q[a] - fl[a];
      side[a] = f <= 0.25 ? -1 : (f >= 0.75 ? 1 : 0);
    }
    int found = -1;
    for (int dx = 0; dx <= std::abs(side.x()) && found < 0; ++dx)
      for (int dy = 0; dy <= std::abs(side.y()) && found < 0; ++dy)
        for (int dz = 0; dz <= std::abs(side.z()) && found < 0; ++dz) {
          const Eigen::Matrix<std::int64_t, 3, 1> c = k + Eigen::Matrix<std::int64_t, 3, 1>(dx * side.x(), dy * side.y(), dz * side.z());
          auto it = grid.find(c);
          if (it == grid.end()) continue;
          for (int j : it->second)
            if ((out.vertices[std::size_t(j)] - p).cwiseAbs().maxCoeff() <= tolerance) {
              found = j;
              break;
            }
        }
    if (found < 0) {
      found = int(out.vertices.size());
      out.vertices.push_back(p);
      grid[k].push_back(found);
    }
    map[i] = found;
  }
  out.triangles.reserve(mesh.triangles.size());
  for (const Eigen::Vector3i& t : mesh.triangles) {
    bool ok = true;
    for (int k = 0; k < 3; ++k) ok &= t[k] >= 0 && std::size_t(t[k]) < map.size();
    out.triangles.push_back(ok ? Eigen::Vector3i(map[std::size_t(t[0])], map[std::size_t(t[1])], map[std::size_t(t[2])]) : t);
  }
  return out;
}

Eigen::Vector3d contactDensity(const ContactWorld& world, const ContactParameters& p, const Eigen::Vector3d& x,
                               const Eigen::Vector3d& v, double dt, double* depthOut) {
  return contactDensity(world, p, x, v, dt, Eigen::Matrix3d::Identity(), 1.0, depthOut);
}

Eigen::Vector3d contactDensity(const ContactWorld& world, const ContactParameters& p, const Eigen::Vector3d& x,
                               const Eigen::Vector3d& v, double dt, const Eigen::Matrix3d& frame, double scale,
                               double* depthOut) {
  return densityAt(world, p, x, v, dt, frame, scale, depthOut, nullptr);
}

namespace {
Eigen::Vector3d densityAt(const ContactWorld& world, const ContactParameters& p, const Eigen::Vector3d& x,
                          const Eigen::Vector3d& v, double dt, const Eigen::Matrix3d& frame, double scale,
                          double* depthOut, PointQuery* query) {
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  double deepest = 0.0;
  // rho / dt share per unit of the surface's own rate (see the declaration)
  const double rateCap = dt > 0.0 && scale > 0.0 ? kRateCap * p.massDensity / (dt * scale) : 0.0;
  for (std::size_t k = 0; k < world.obstacles.size(); ++k) {
    const ContactWorld::Obstacle& o = world.obstacles[k];
    if (!o.tree) continue;
    ClosestHit hit;
    int none = -1;
    const double search = kSearch * p.thickness;
    if (!query) {
      if (!o.tree->closest(x, search, hit)) continue;
    } else {
      // The law acts within the thickness outside and, inside a closed obstacle, within the
      // search; to get there a point crosses the remaining distance (outside it cannot change
      // sides before it reaches the surface).
      const bool found = o.tree->closest(x, query->radius, hit, query->hints ? query->hints[k] : none);
      if (!found) {
        query->free = std::min(query->free, query->radius - search);
        continue;
      }
      const bool inside = o.closed && hit.signedDistance < 0.0;
      query->free = std::min(query->free, hit.distance - (inside ? search : p.thickness));
      if (hit.distance > search) continue;  // the law looks no farther than the search
    }
    Eigen::Vector3d n;
    const double depth = p.thickness - separation(o, hit, x, v, n);
    if (!(depth > 0.0)) continue;
    deepest = std::max(deepest, depth);
    // the frame's gain along the normal and, at most, in the tangent plane: |A^T n|^2 and the
    // largest eigenvalue of A^T P_t A (that of the 2 x 2 matrix B^T B, B = A^T [t1 t2])
    const Eigen::Vector3d an = frame.transpose() * n;
    const Eigen::Vector3d t1 = n.unitOrthogonal(), t2 = n.cross(t1);
    const Eigen::Vector3d b1 = frame.transpose() * t1, b2 = frame.transpose() * t2;
    const double g11 = b1.squaredNorm(), g22 = b2.squaredNorm(), g12 = b1.dot(b2);
    const double tangentGain = 0.5 * (g11 + g22) + std::sqrt(0.25 * (g11 - g22) * (g11 - g22) + g12 * g12);
    const double damping = std::min(p.damping, rateCap / std::max(an.squaredNorm(), 1e-300));
    const double vn = v.dot(n);
    const double fn = std::max(0.0, p.stiffness * depth - damping * vn);
    f += fn * n;
    const Eigen::Vector3d vt = v - vn * n;
    const double speed = vt.norm();
    if (p.friction > 0.0 && speed > 0.0 && fn > 0.0)
      f -= std::min(p.friction * fn, rateCap / std::max(tangentGain, 1e-300) * speed) / speed * vt;
  }
  if (depthOut) *depthOut = deepest;
  return f;
}
}  // namespace

namespace {
// -d f_world / dx - s d f_world / dv at x (world) for the law of densityAt: per obstacle in
// contact, the normal penalty's k n nᵀ (exact where the closest point lies inside a face, its
// Gauss–Newton part at an edge or vertex, where n turns with x) and the normal damping's
// c' n nᵀ times s while the normal force is positive, and friction's derivative with respect to
// the tangential velocity times s.
Eigen::Matrix3d jacobianAt(const ContactWorld& world, const ContactParameters& p, const Eigen::Vector3d& x,
                           const Eigen::Vector3d& v, double dt, const Eigen::Matrix3d& frame, double scale,
                           double velocityScale) {
  Eigen::Matrix3d K = Eigen::Matrix3d::Zero();
  const double rateCap = dt > 0.0 && scale > 0.0 ? kRateCap * p.massDensity / (dt * scale) : 0.0;
  const double search = kSearch * p.thickness;
  for (const ContactWorld::Obstacle& o : world.obstacles) {
    if (!o.tree) continue;
    ClosestHit hit;
    if (!o.tree->closest(x, search, hit)) continue;
    Eigen::Vector3d n;
    const double depth = p.thickness - separation(o, hit, x, v, n);
    if (!(depth > 0.0)) continue;
    const Eigen::Vector3d an = frame.transpose() * n;
    const double damping = std::min(p.damping, rateCap / std::max(an.squaredNorm(), 1e-300));
    const double vn = v.dot(n);
    const double fn = p.stiffness * depth - damping * vn;
    if (!(fn > 0.0)) continue;
    const Eigen::Matrix3d nn = n * n.transpose();
    K += (p.stiffness + velocityScale * damping) * nn;
    // friction's dependence on the tangential velocity (its dependence on fn, through the
    // depth, is left out: it is not symmetric): viscous at the rate cap, else Coulomb's
    // mu fn (I - n nᵀ - t tᵀ) / |v_t|; both positive semidefinite
    const Eigen::Vector3d vt = v - vn * n;
    const double speed = vt.norm();
    if (p.friction > 0.0 && speed > 0.0) {
      const Eigen::Vector3d t1 = n.unitOrthogonal(), t2 = n.cross(t1);
      const Eigen::Vector3d b1 = frame.transpose() * t1, b2 = frame.transpose() * t2;
      const double g11 = b1.squaredNorm(), g22 = b2.squaredNorm(), g12 = b1.dot(b2);
      const double tangentGain = 0.5 * (g11 + g22) + std::sqrt(0.25 * (g11 - g22) * (g11 - g22) + g12 * g12);
      const double viscous = rateCap / std::max(tangentGain, 1e-300);
      const Eigen::Matrix3d tangential = Eigen::Matrix3d::Identity() - nn;
      if (p.friction * fn >= viscous * speed) {
        K += velocityScale * viscous * tangential;
      } else {
        const Eigen::Vector3d t = vt / speed;
        K += velocityScale * (p.friction * fn / speed) * (tangential - t * t.transpose());
      }
    }
  }
  return K;
}
}  // namespace

struct CollisionForce::Cache {
  // The quadrature, which depends on the space only.
  int degreeU = -1, degreeV = -1, spansU = -1, spansV = -1;
  std::vector<Node1D> qu, qv;
  std::vector<LocalBasis> bu, bv;
  std::vector<int> uBegin, vBegin;  // per span: its first node (spans + 1 entries)
  // The reference net and what the clearances were measured against.
  bool valid = false;
  std::vector<std::pair<const TriangleTree*, std::uint64_t>> trees;
  Eigen::Matrix3d linear = Eigen::Matrix3d::Zero();
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  ControlNet reference;
  double skin = 0.0;
  double normA = 0.0;
  std::vector<double> clearance;  // per element (su * spansV + sv)
  // Per quadrature point (i * qv.size() + j): a clearance like the elements' (no obstacle can
  // act on the point while the net has moved less than it since the reference; -inf: unknown),
  // and per point and obstacle the triangle found last (-1: none), the next query's hint.
  std::vector<float> pointClearance;
  std::vector<int> hints;
  Counters counters;

  /// The quadrature of `s` (the cache starts over when the space is another).
  void fitQuadrature(const SplineSpace& s) {
    if (degreeU == s.degreeU() && degreeV == s.degreeV() && spansU == s.basisU().numSpans() &&
        spansV == s.basisV().numSpans())
      return;
    *this = Cache{};
    degreeU = s.degreeU();
    degreeV = s.degreeV();
    spansU = s.basisU().numSpans();
    spansV = s.basisV().numSpans();
    // the points DistributedForce uses: n + 1 for the basis, two more for the density
    qu = splitQuadrature(s.basisU(), 0.0, 1.0, s.degreeU() + 3);
    qv = splitQuadrature(s.basisV(), 0.0, 1.0, s.degreeV() + 3);
    bu.resize(qu.size());
    bv.resize(qv.size());
    for (std::size_t i = 0; i < qu.size(); ++i) s.basisU().evaluateInSpan(qu[i].span, qu[i].x, 1, bu[i]);
    for (std::size_t j = 0; j < qv.size(); ++j) s.basisV().evaluateInSpan(qv[j].span, qv[j].x, 1, bv[j]);
    auto begins = [](const std::vector<Node1D>& q, int spans) {
      std::vector<int> b(std::size_t(spans) + 1, int(q.size()));
      for (int i = int(q.size()) - 1; i >= 0; --i) b[std::size_t(q[std::size_t(i)].span)] = i;
      for (int k = spans - 1; k >= 0; --k) b[std::size_t(k)] = std::min(b[std::size_t(k)], b[std::size_t(k) + 1]);
      return b;
    };
    uBegin = begins(qu, spansU);
    vBegin = begins(qv, spansV);
  }

  /// Whether the reference is still the one the clearances belong to (same obstacles, frame and
  /// net size, and `current` within the skin of it); `moved` receives the largest control-point
  /// displacement since the reference, world units (when the rest matches).
  bool sameReference(const ContactWorld& w, const ControlNet& current, double& moved) const {
    moved = 0.0;
    bool same = valid && linear == w.linear && offset == w.offset && trees.size() == w.obstacles.size() &&
                reference.rows() == current.rows();
    for (std::size_t k = 0; same && k < w.obstacles.size(); ++k) {
      const TriangleTree* t = w.obstacles[k].tree.get();
      same = trees[k].first == t && (!t || trees[k].second == t->version());
    }
    if (!same) return false;
    moved = normA * std::sqrt((current - reference).rowwise().squaredNorm().maxCoeff());
    return moved < skin;
  }
};

bool ContactWorldSnapshot::unchangedSinceFirst(const ContactWorld& w) {
  std::vector<std::uint64_t> versions;
  for (const ContactWorld::Obstacle& o : w.obstacles) versions.push_back(o.tree ? o.tree->version() : 0);
  if (!m_taken) {
    m_taken = true;
    m_versions = std::move(versions);
    m_linear = w.linear;
    m_offset = w.offset;
    return true;
  }
  return m_versions == versions && m_linear == w.linear && m_offset == w.offset;
}

CollisionForce::CollisionForce(std::shared_ptr<const ContactWorld> world, const ContactParameters& p)
    : m_world(std::move(world)),
      m_params(p),
      m_cache(std::make_shared<Cache>()),
      m_seen(std::make_shared<ContactWorldSnapshot>()) {
  if (!m_world) throw std::invalid_argument("collision: no obstacle world");
  checked(p.thickness, "thickness", true);
  checked(p.stiffness, "stiffness", false);
  checked(p.damping, "damping", false);
  checked(p.friction, "friction", false);
  checked(p.massDensity, "mass density", true);
  checked(p.areaScale, "area scale", true);
  if (!m_world->linear.allFinite() || !m_world->offset.allFinite())
    throw std::invalid_argument("collision: the surface's transform is not finite");
}

ContactParameters CollisionForce::parametersFor(const LoadContext& ctx) const {
  ContactParameters p = m_params;
  if (p.modelMass) {
    p.massDensity = ctx.massPerArea;
    p.areaScale = ctx.restArea;
  }
  return p;
}

double CollisionForce::eigenvalueBound(const MassContext& ctx) const {
  // ||A||^2 through the frame, and sigma_1 sigma_2 the largest world area per local area
  const Eigen::Vector3d sv = m_world->linear.jacobiSvd().singularValues();
  const double areaScale = m_params.modelMass ? ctx.restArea : m_params.areaScale;
  return areaScale * sv(0) * sv(1) * m_params.stiffness * sv(0) * sv(0) * ctx.space.basisU().spacing() *
         ctx.space.basisV().spacing() / ctx.interiorMass;
}

const CollisionForce::Counters& CollisionForce::counters() const { return m_cache->counters; }

void CollisionForce::addLoad(const LoadContext& ctx, ControlNet& load) const {
  const ContactParameters law = parametersFor(ctx);
  Cache& c = *m_cache;
  Counters& n = c.counters;
  ++n.loads;
  n.activeElements = 0;
  const SplineSpace& s = ctx.space;
  c.fitQuadrature(s);
  n.elements = c.spansU * c.spansV;
  const ContactWorld& w = *m_world;
  if (w.obstacles.empty()) return;
  const double search = kSearch * law.thickness;

  double moved = 0.0;  // largest control-point displacement since the reference, world units
  bool same = c.sameReference(w, ctx.current, moved);
  // Box of an element's control points (local coordinates): centre and half diagonal.
  auto box = [&](int su, int sv, Eigen::Vector3d& centre, double& half) {
    const int r0 = c.bu[std::size_t(c.uBegin[std::size_t(su)])].first + s.degreeU();
    const int c0 = c.bv[std::size_t(c.vBegin[std::size_t(sv)])].first + s.degreeV();
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector3d hi = -lo;
    for (int i = r0; i <= r0 + s.degreeU(); ++i)
      for (int j = c0; j <= c0 + s.degreeV(); ++j) {
        const Eigen::Vector3d x = ctx.current.row(Eigen::Index(i) * s.netCols() + j).transpose();
        lo = lo.cwiseMin(x);
        hi = hi.cwiseMax(x);
      }
    centre = 0.5 * (lo + hi);
    half = 0.5 * (hi - lo).norm();
  };
  if (!same) {
    ++n.references;
    c.valid = true;
    c.linear = w.linear;
    c.offset = w.offset;
    c.trees.clear();
    for (const ContactWorld::Obstacle& o : w.obstacles)
      c.trees.emplace_back(o.tree.get(), o.tree ? o.tree->version() : 0);
    c.reference = ctx.current;
    c.normA = w.linear.jacobiSvd().singularValues()(0);
    c.clearance.assign(std::size_t(n.elements), 0.0);
    std::vector<double> halves(std::size_t(n.elements));
    std::vector<Eigen::Vector3d> centres(std::size_t(n.elements));
    double sumHalf = 0.0;
    for (int su = 0; su < c.spansU; ++su)
      for (int sv = 0; sv < c.spansV; ++sv) {
        const std::size_t e = std::size_t(su) * std::size_t(c.spansV) + std::size_t(sv);
        box(su, sv, centres[e], halves[e]);
        halves[e] *= c.normA;
        centres[e] = w.linear * centres[e] + w.offset;
        sumHalf += halves[e];
      }
    // The skin: how far the net may move before the clearances are measured again.
    c.skin = search + sumHalf / std::max(1, n.elements);
    for (std::size_t e = 0; e < halves.size(); ++e) {
      double g = c.skin;  // nothing within the query radius: inactive until the next reference
      const double radius = halves[e] + search + c.skin;
      for (const ContactWorld::Obstacle& o : w.obstacles) {
        if (!o.tree) continue;
        ClosestHit hit;
        ++n.elementQueries;
        if (o.tree->closest(centres[e], radius, hit)) {
          // rounding margin: the skip must never drop a point the query would find
          const double margin = 1e-9 * (1.0 + centres[e].cwiseAbs().maxCoeff() + halves[e] + search);
          g = std::min(g, hit.distance - halves[e] - search - margin);
        }
      }
      c.clearance[e] = g;
    }
    c.pointClearance.assign(c.qu.size() * c.qv.size(), -std::numeric_limits<float>::infinity());
    moved = 0.0;
  }

  const std::size_t nObstacles = w.obstacles.size();
  if (c.hints.size() != c.qu.size() * c.qv.size() * nObstacles) c.hints.assign(c.qu.size() * c.qv.size() * nObstacles, -1);
  const Frame frame(w.linear);
  const unsigned needs = kDependsOnPosition | kDependsOnVelocity | (frame.similarity > 0.0 ? 0u : unsigned(kDependsOnNormal));
  for (int su = 0; su < c.spansU; ++su)
    for (int sv = 0; sv < c.spansV; ++sv) {
      if (c.clearance[std::size_t(su) * std::size_t(c.spansV) + std::size_t(sv)] > moved) continue;
      ++n.activeElements;
      for (int i = c.uBegin[std::size_t(su)]; i < c.uBegin[std::size_t(su) + 1]; ++i)
        for (int j = c.vBegin[std::size_t(sv)]; j < c.vBegin[std::size_t(sv) + 1]; ++j) {
          const LocalBasis& bu = c.bu[std::size_t(i)];
          const LocalBasis& bv = c.bv[std::size_t(j)];
          const std::size_t point = std::size_t(i) * c.qv.size() + std::size_t(j);
          if (c.pointClearance[point] > moved) {
            ++n.pointsSkipped;
            continue;
          }
          const SurfaceSample smp = sampleFromBases(ctx, bu, bv, c.qu[std::size_t(i)].x, c.qv[std::size_t(j)].x, needs);
          ++n.pointQueries;
          // A point no obstacle can act on skips the queries of the steps to come while the net
          // moves less than the distance it has left (PointQuery::free) from where it is now:
          // |S - S_ref| <= the largest control point motion, as the basis functions are >= 0
          // and sum to 1. Searching as far as the skin makes that distance useful for points
          // far from every obstacle.
          PointQuery query;
          query.radius = search + c.skin;
          query.hints = c.hints.data() + point * nObstacles;
          const Eigen::Vector3d f = localDensity(w, law, frame, smp, query);
          const double margin = 1e-9 * (1.0 + smp.position.cwiseAbs().maxCoeff() * c.normA +
                                        w.offset.cwiseAbs().maxCoeff() + search + c.skin);
          const double clear = std::min(query.free - moved - margin, 1e30);
          // rounded down to float: never more than the distance allows (NaN and -inf: query again)
          c.pointClearance[point] =
              clear > -1e30 ? std::nextafter(static_cast<float>(clear), -std::numeric_limits<float>::infinity())
                            : -std::numeric_limits<float>::infinity();
          if (f.isZero(0.0)) continue;
          scatter(s, bu, bv, (c.qu[std::size_t(i)].w * c.qv[std::size_t(j)].w) * f, load);
        }
    }
}

void CollisionForce::addJacobian(const LoadContext& ctx, double velocityScale, JacobianSink& sink) const {
  const ContactParameters law = parametersFor(ctx);
  const ContactWorld& w = *m_world;
  if (w.obstacles.empty()) return;
  const SplineSpace& s = ctx.space;
  Cache& c = *m_cache;
  // the quadrature of the load; its clearances (when they belong to this net's neighbourhood)
  // skip the elements and points no obstacle can reach, as addLoad() does
  c.fitQuadrature(s);
  const std::vector<Node1D>& qu = c.qu;
  const std::vector<Node1D>& qv = c.qv;
  double moved = 0.0;
  const bool useClearance = c.sameReference(w, ctx.current, moved);
  const Frame frame(w.linear);
  const unsigned needs = kDependsOnPosition | kDependsOnVelocity | (frame.similarity > 0.0 ? 0u : unsigned(kDependsOnNormal));
  const int cols = s.netCols();
  const int Lu = s.degreeU() + 1, Lv = s.degreeV() + 1, L = Lu * Lv;
  // per element: Σ over its points of w B_p B_q K, then one block per pair of its points
  std::vector<Eigen::Matrix3d> local(std::size_t(L) * L);
  for (int su = 0; su < c.spansU; ++su)
    for (int sv = 0; sv < c.spansV; ++sv) {
      if (useClearance && c.clearance[std::size_t(su) * std::size_t(c.spansV) + std::size_t(sv)] > moved) continue;
      bool any = false;
      for (int i = c.uBegin[std::size_t(su)]; i < c.uBegin[std::size_t(su) + 1]; ++i)
        for (int j = c.vBegin[std::size_t(sv)]; j < c.vBegin[std::size_t(sv) + 1]; ++j) {
          if (useClearance && c.pointClearance[std::size_t(i) * qv.size() + std::size_t(j)] > moved) continue;
          const LocalBasis& bu = c.bu[std::size_t(i)];
          const LocalBasis& bv = c.bv[std::size_t(j)];
          const SurfaceSample smp = sampleFromBases(ctx, bu, bv, qu[std::size_t(i)].x, qv[std::size_t(j)].x, needs);
          const double gamma = frame.similarity > 0.0 ? frame.similarity : (frame.cofactor * smp.normal).norm();
          if (!(gamma > 0.0)) continue;
          const double scale = law.areaScale * gamma;
          const Eigen::Matrix3d Kw = jacobianAt(w, law, w.linear * smp.position + w.offset,
                                                w.linear * smp.velocity, smp.stepSize, w.linear, scale, velocityScale);
          if (Kw.isZero(0.0)) continue;
          if (!any) {
            for (Eigen::Matrix3d& m : local) m.setZero();
            any = true;
          }
          const Eigen::Matrix3d K =
              (qu[std::size_t(i)].w * qv[std::size_t(j)].w * scale) * (w.linear.transpose() * Kw * w.linear);
          for (int p = 0; p < L; ++p) {
            const double Bp = bu.d[0][p / Lv] * bv.d[0][p % Lv];
            if (Bp == 0.0) continue;
            for (int q = 0; q < L; ++q) local[std::size_t(p) * L + q] += (Bp * (bu.d[0][q / Lv] * bv.d[0][q % Lv])) * K;
          }
        }
      if (!any) continue;
      // the element's points: net rows su + a, columns sv + b (its B-splines' first index plus n)
      const int firstU = c.bu[std::size_t(c.uBegin[std::size_t(su)])].first + s.degreeU();
      const int firstV = c.bv[std::size_t(c.vBegin[std::size_t(sv)])].first + s.degreeV();
      for (int p = 0; p < L; ++p) {
        const Eigen::Index rp = Eigen::Index(firstU + p / Lv) * cols + firstV + p % Lv;
        for (int q = 0; q < L; ++q) {
          const Eigen::Index rq = Eigen::Index(firstU + q / Lv) * cols + firstV + q % Lv;
          sink.add(rp, rq, local[std::size_t(p) * L + q]);
        }
      }
    }
}

bool CollisionForce::storedEnergy(const LoadContext& ctx, double& value) const {
  const ContactParameters law = parametersFor(ctx);
  value = 0.0;
  const ContactWorld& w = *m_world;
  if (!m_seen->unchangedSinceFirst(w)) return false;
  if (w.obstacles.empty()) return true;
  Cache& c = *m_cache;
  c.fitQuadrature(ctx.space);
  const Frame frame(w.linear);
  const unsigned needs = kDependsOnPosition | (frame.similarity > 0.0 ? 0u : unsigned(kDependsOnNormal));
  for (std::size_t i = 0; i < c.qu.size(); ++i) {
    const Node1D& nu = c.qu[i];
    for (std::size_t j = 0; j < c.qv.size(); ++j) {
      const Node1D& nv = c.qv[j];
      const SurfaceSample smp = sampleFromBases(ctx, c.bu[i], c.bv[j], nu.x, nv.x, needs);
      const double gamma = frame.similarity > 0.0 ? frame.similarity : (frame.cofactor * smp.normal).norm();
      double depth = 0.0;
      densityAt(w, law, w.linear * smp.position + w.offset, Eigen::Vector3d::Zero(), 0.0, w.linear, 1.0, &depth,
                nullptr);
      value += nu.w * nv.w * law.areaScale * gamma * 0.5 * law.stiffness * depth * depth;
    }
  }
  return true;
}

}  // namespace bsdeform
