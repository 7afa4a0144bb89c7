// SPDX-License-Identifier: MIT
// TriangleTree on Embree 3 (docs/benchmarks.md, "Closest-point queries: CGAL vs Embree"):
// Embree's BVH culls in single precision with the query radius widened by a few float ulps;
// the distances, the closest point and the feature are computed here in double
// (closestPointOnTriangle), so the answers are those of a brute-force search in double.
#include "bsdeform/contact/TriangleTree.h"

#include <Eigen/Geometry>
#include <embree3/rtcore.h>
#include <fenv.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <tuple>

#include "bsdeform/base/Parallel.h"
#include "bsdeform/contact/ClosestPointOnTriangle.h"

namespace bsdeform {

namespace {

/// Twice the area below this fraction of the squared size of the mesh (diagonal of the box of
/// its vertices) is zero: the cross product of two edges then carries a relative rounding
/// error of 1e-4 or more, and the face normal is no longer meaningful.
constexpr double kDegenerateArea = 1e-12;
/// Embree keeps floats: coordinates beyond this count as non-finite.
constexpr double kMaxCoordinate = 1e30;

/// Finite and within kMaxCoordinate; classifies without arithmetic on inf or NaN (which would
/// trap under feenableexcept).
bool usable(const Eigen::Vector3d& v) {
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(v[k]) || std::abs(v[k]) > kMaxCoordinate) return false;
  return true;
}

/// Embree's SIMD code relies on non-stop IEEE arithmetic: its scene build raises FE_INVALID
/// (seen with 3.13.5), which aborts under feenableexcept (our debug test runner). Holds the
/// floating-point environment for its lifetime and restores it, discarding Embree's flags.
class QuietFloatingPoint {
 public:
  QuietFloatingPoint() { feholdexcept(&m_env); }
  ~QuietFloatingPoint() { fesetenv(&m_env); }
  QuietFloatingPoint(const QuietFloatingPoint&) = delete;
  QuietFloatingPoint& operator=(const QuietFloatingPoint&) = delete;

 private:
  fenv_t m_env;
};

}  // namespace

struct TriangleTree::Impl {
  std::vector<Eigen::Vector3i> input;  // the triangles as given
  TriangleMesh mesh;                   // all vertices, the kept triangles
  std::vector<int> kept;               // index in `input` of each kept triangle
  int dropped = 0;
  std::uint64_t version = 0;  // update() calls so far

  // Pseudo-normals (Baerentzen & Aanaes 2005), recomputed whenever the vertices move.
  std::vector<Eigen::Vector3d> faceNormals;       // per kept triangle
  std::vector<std::array<int, 3>> triangleEdges;  // edge ids of ab, bc, ca per kept triangle
  std::vector<Eigen::Vector3d> edgeNormals;       // per edge: normalised sum of its face normals
  std::vector<Eigen::Vector3d> vertexNormals;     // per vertex: normalised angle-weighted sum
  std::vector<int> canonical;     // per vertex: the first vertex at its position (the topology)
  std::vector<char> referenced;   // per vertex: used by a kept triangle
  double absMax = 0.0;            // largest |coordinate| of a kept vertex

  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  RTCGeometry geometry = nullptr;

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }

  /// Indices into `input` of the triangles to keep for the current vertices.
  std::vector<int> selectTriangles() const {
    const auto& v = mesh.vertices;
    const int n = static_cast<int>(v.size());
    std::vector<char> ok(v.size());
    for (int i = 0; i < n; ++i) ok[i] = usable(v[i]);
    std::vector<int> candidates;
    candidates.reserve(input.size());
    Eigen::Array3d lo = Eigen::Array3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (int t = 0; t < static_cast<int>(input.size()); ++t) {
      const Eigen::Vector3i& f = input[t];
      if ((f.array() < 0).any() || (f.array() >= n).any() || !ok[f[0]] || !ok[f[1]] || !ok[f[2]]) continue;
      candidates.push_back(t);
      for (int k = 0; k < 3; ++k) {
        lo = lo.min(v[f[k]].array());
        hi = hi.max(v[f[k]].array());
      }
    }
    const double threshold = candidates.empty() ? 0.0 : kDegenerateArea * (hi - lo).matrix().squaredNorm();
    std::vector<int> result;
    result.reserve(candidates.size());
    for (int t : candidates) {
      const Eigen::Vector3i& f = input[t];
      if ((v[f[1]] - v[f[0]]).cross(v[f[2]] - v[f[0]]).squaredNorm() > threshold * threshold) result.push_back(t);
    }
    return result;
  }

  /// Vertices at the same position are one vertex for the pseudo-normals: a triangle soup (as
  /// Coin's SoCallbackAction delivers it, three vertices of its own per triangle) then gets the
  /// same edge and vertex normals as the indexed mesh.
  void weldVertices() {
    const auto& v = mesh.vertices;
    std::vector<int> order;
    canonical.resize(v.size());
    for (int i = 0; i < static_cast<int>(v.size()); ++i) {
      canonical[i] = i;
      if (usable(v[i])) order.push_back(i);
    }
    auto less = [&](int a, int b) {
      return std::tie(v[a].x(), v[a].y(), v[a].z(), a) < std::tie(v[b].x(), v[b].y(), v[b].z(), b);
    };
    std::sort(order.begin(), order.end(), less);
    for (size_t i = 1; i < order.size(); ++i)
      if (v[order[i]] == v[order[i - 1]]) canonical[order[i]] = canonical[order[i - 1]];
  }

  /// Edge ids shared by the kept triangles (topology only: done when the kept set changes).
  void connectEdges() {
    const int nt = static_cast<int>(mesh.triangles.size());
    std::vector<std::pair<std::uint64_t, int>> sides;  // (vertex pair, 3 t + k)
    sides.reserve(3 * static_cast<size_t>(nt));
    for (int t = 0; t < nt; ++t)
      for (int k = 0; k < 3; ++k) {
        const std::uint64_t a = static_cast<std::uint32_t>(canonical[mesh.triangles[t][k]]);
        const std::uint64_t b = static_cast<std::uint32_t>(canonical[mesh.triangles[t][(k + 1) % 3]]);
        sides.emplace_back(std::min(a, b) << 32 | std::max(a, b), 3 * t + k);
      }
    std::sort(sides.begin(), sides.end());
    triangleEdges.assign(nt, {0, 0, 0});
    int edges = 0;
    for (size_t i = 0; i < sides.size(); ++i) {
      if (i > 0 && sides[i].first != sides[i - 1].first) ++edges;
      triangleEdges[sides[i].second / 3][sides[i].second % 3] = edges;
    }
    edgeNormals.assign(sides.empty() ? 0 : edges + 1, Eigen::Vector3d::Zero());
  }

  void computeNormals() {
    const auto& v = mesh.vertices;
    const int nt = static_cast<int>(mesh.triangles.size());
    faceNormals.resize(nt);
    std::fill(edgeNormals.begin(), edgeNormals.end(), Eigen::Vector3d::Zero());
    vertexNormals.assign(v.size(), Eigen::Vector3d::Zero());
    absMax = 0.0;
    constexpr double pi = 3.14159265358979323846;
    for (int t = 0; t < nt; ++t) {
      const Eigen::Vector3i& f = mesh.triangles[t];
      const Eigen::Vector3d ab = v[f[1]] - v[f[0]], bc = v[f[2]] - v[f[1]], ca = v[f[0]] - v[f[2]];
      const Eigen::Vector3d cross = ab.cross(-ca);
      const double twiceArea = cross.norm();
      const Eigen::Vector3d n = cross / twiceArea;
      faceNormals[t] = n;
      // Interior angles from atan2(|e x e'|, e . e'), exact near 0 and pi; they sum to pi.
      const double angleA = std::atan2(twiceArea, -ca.dot(ab));
      const double angleB = std::atan2(twiceArea, -ab.dot(bc));
      const double angleC = std::max(0.0, pi - angleA - angleB);
      vertexNormals[canonical[f[0]]] += angleA * n;
      vertexNormals[canonical[f[1]]] += angleB * n;
      vertexNormals[canonical[f[2]]] += angleC * n;
      for (int k = 0; k < 3; ++k) edgeNormals[triangleEdges[t][k]] += n;
    }
    for (size_t i = 0; i < v.size(); ++i)
      if (referenced[i]) absMax = std::max(absMax, v[i].cwiseAbs().maxCoeff());
    // A pseudo-normal that cancels (a fin of two opposite faces, a vertex of an inconsistently
    // wound mesh) stays zero; closest() then falls back to the face normal.
    auto normalise = [](Eigen::Vector3d& n) {
      const double len = n.norm();
      n = len > 0.0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
    };
    for (auto& n : edgeNormals) normalise(n);
    for (auto& n : vertexNormals) normalise(n);
  }

  void checkEmbree(const char* what) const {
    const RTCError e = rtcGetDeviceError(device);
    if (e != RTC_ERROR_NONE) throw std::runtime_error(std::string("TriangleTree: Embree ") + what + " failed (error " +
                                                      std::to_string(static_cast<int>(e)) + ")");
  }

  /// Copies the vertices into Embree's buffer; vertices no kept triangle uses may be anything,
  /// Embree gets 0 for those that are not finite.
  void writeVertices() {
    auto* dst = static_cast<float*>(rtcGetGeometryBufferData(geometry, RTC_BUFFER_TYPE_VERTEX, 0));
    for (size_t i = 0; i < mesh.vertices.size(); ++i) {
      const Eigen::Vector3d& p = mesh.vertices[i];
      const bool ok = usable(p);
      for (int k = 0; k < 3; ++k) dst[3 * i + k] = ok ? static_cast<float>(p[k]) : 0.0f;
    }
  }

  /// (Re)builds everything for the triangles `keep` of `input`.
  void build(std::vector<int> keep) {
    kept = std::move(keep);
    dropped = static_cast<int>(input.size() - kept.size());
    mesh.triangles.clear();
    mesh.triangles.reserve(kept.size());
    referenced.assign(mesh.vertices.size(), 0);
    for (int t : kept) {
      mesh.triangles.push_back(input[t]);
      for (int k = 0; k < 3; ++k) referenced[input[t][k]] = 1;
    }
    weldVertices();
    connectEdges();
    computeNormals();

    if (scene) {
      rtcReleaseScene(scene);
      scene = nullptr;
      geometry = nullptr;
    }
    if (mesh.triangles.empty()) return;
    if (!device) {
      // Embree's TBB tasking caps the whole process's TBB parallelism at its devices' thread
      // count while they live (its task scheduler keeps a tbb::global_control of
      // max_allowed_parallelism), so a device of one thread would hold every runParts() kernel
      // to one thread. The device takes the kernels' thread count when the tree is first built:
      // one build thread by default (no worker pool competing with the simulation), the
      // kernels' threads when they are asked for (a tree built on two answers as one built on
      // one, tests/core/TriangleTree_test.cpp; a later setKernelThreads() keeps this cap).
      const std::string config = "threads=" + std::to_string(kernelThreads());
      device = rtcNewDevice(config.c_str());
      if (!device) throw std::runtime_error("TriangleTree: Embree device creation failed");
    }
    QuietFloatingPoint quiet;
    // A two-level scene whose geometry is built for refitting (RTC_BUILD_QUALITY_REFIT):
    // update() then refits in about a tenth of a rebuild, queries as fast (benchmarks.md).
    scene = rtcNewScene(device);
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_DYNAMIC);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_LOW);
    geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), mesh.triangles.size()));
    rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                            mesh.vertices.size());
    checkEmbree("allocation");
    for (size_t t = 0; t < mesh.triangles.size(); ++t)
      for (int k = 0; k < 3; ++k) idx[3 * t + k] = static_cast<unsigned>(mesh.triangles[t][k]);
    writeVertices();
    rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_REFIT);
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);  // the scene keeps it
    rtcCommitScene(scene);
    checkEmbree("build");
  }

  void refit() {
    computeNormals();
    if (!scene) return;
    QuietFloatingPoint quiet;
    writeVertices();
    rtcUpdateGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0);
    rtcCommitGeometry(geometry);
    rtcCommitScene(scene);
    checkEmbree("refit");
  }

  struct Search {
    const Impl* impl;
    Eigen::Vector3d q;
    double maxSquared;
    double bestSquared;
    float slack;
    double planeSlack;  // rounding allowance of a plane distance
    int triangle;
    TrianglePoint best;
  };

  static bool visit(RTCPointQueryFunctionArguments* args) {
    auto* s = static_cast<Search*>(args->userPtr);
    const int t = static_cast<int>(args->primID);
    const Eigen::Vector3i& f = s->impl->mesh.triangles[t];
    const auto& v = s->impl->mesh.vertices;
    // The distance to the triangle's plane is a lower bound of the distance to the triangle: a
    // triangle whose plane is farther than the best (or the limit) so far is skipped without
    // the closest-point routine. The margins (1e-14 of the coordinates' size, far above the
    // rounding of the dot product, and 1e-9 relative) keep every triangle that could be as
    // close, so the answer is unchanged.
    const double excess = std::abs(s->impl->faceNormals[t].dot(s->q - v[f[0]])) - s->planeSlack;
    if (excess > 0.0 && excess * excess > std::min(s->maxSquared, s->bestSquared) * (1.0 + 1e-9)) return false;
    const TrianglePoint p = closestPointOnTriangle(s->q, v[f[0]], v[f[1]], v[f[2]]);
    const double d2 = (s->q - p.point).squaredNorm();
    if (d2 > s->maxSquared || d2 >= s->bestSquared) return false;
    s->bestSquared = d2;
    s->best = p;
    s->triangle = t;
    const float radius = static_cast<float>(std::sqrt(d2)) + s->slack;
    if (!(radius < args->query->radius)) return false;
    args->query->radius = radius;  // shrinks the search to the best distance so far
    return true;
  }
};

TriangleTree::TriangleTree(TriangleMesh mesh) : m(std::make_unique<Impl>()) {
  m->input = std::move(mesh.triangles);
  m->mesh.vertices = std::move(mesh.vertices);
  m->build(m->selectTriangles());
}

TriangleTree::~TriangleTree() = default;

void TriangleTree::update(const std::vector<Eigen::Vector3d>& vertices) {
  if (vertices.size() != m->mesh.vertices.size())
    throw std::invalid_argument("TriangleTree::update: " + std::to_string(vertices.size()) +
                                " vertices, the mesh has " + std::to_string(m->mesh.vertices.size()));
  m->mesh.vertices = vertices;
  ++m->version;
  std::vector<int> keep = m->selectTriangles();
  if (keep == m->kept)
    m->refit();
  else
    m->build(std::move(keep));  // a triangle became degenerate or non-finite (or valid again)
}

bool TriangleTree::closest(const Eigen::Vector3d& query, double maxDistance, ClosestHit& hit) const {
  int none = -1;
  return closest(query, maxDistance, hit, none);
}

bool TriangleTree::closest(const Eigen::Vector3d& query, double maxDistance, ClosestHit& hit, int& hint) const {
  const int guess = hint;
  hint = -1;
  if (!m->scene || !usable(query) || std::isnan(maxDistance) || maxDistance < 0.0) return false;
  double radius = maxDistance;  // of the culling; the answer is still checked against maxDistance
  if (guess >= 0 && guess < static_cast<int>(m->mesh.triangles.size())) {
    // Any kept triangle's distance is at least the closest one's: cull no farther.
    const Eigen::Vector3i& f = m->mesh.triangles[guess];
    const auto& v = m->mesh.vertices;
    radius = std::min(radius, (query - closestPointOnTriangle(query, v[f[0]], v[f[1]], v[f[2]]).point).norm());
  }
  Impl::Search s;
  s.impl = m.get();
  s.q = query;
  s.maxSquared = maxDistance * maxDistance;
  s.bestSquared = std::numeric_limits<double>::infinity();
  s.triangle = -1;
  // Embree culls with float boxes of float vertices around a float query point: widening its
  // radius by 8 float ulps of the largest coordinate keeps every triangle within maxDistance
  // (in double) in the search.
  const double scale = std::max(m->absMax, query.cwiseAbs().maxCoeff());
  s.slack = 8.0f * std::numeric_limits<float>::epsilon() * static_cast<float>(std::min(scale, kMaxCoordinate));
  s.planeSlack = 1e-14 * scale;
  RTCPointQuery q;
  q.x = static_cast<float>(query.x());
  q.y = static_cast<float>(query.y());
  q.z = static_cast<float>(query.z());
  q.time = 0.0f;
  q.radius = static_cast<float>(std::min(radius, kMaxCoordinate)) + s.slack;
  if (std::isinf(radius)) q.radius = std::numeric_limits<float>::infinity();
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(m->scene, &q, &context, &Impl::visit, &s);
  if (s.triangle < 0) return false;

  const int t = s.triangle;
  const Eigen::Vector3i& f = m->mesh.triangles[t];
  const Eigen::Vector3d* pseudo = nullptr;
  switch (s.best.feature) {
    case TriangleFeature::Face: break;
    case TriangleFeature::EdgeAB: pseudo = &m->edgeNormals[m->triangleEdges[t][0]]; break;
    case TriangleFeature::EdgeBC: pseudo = &m->edgeNormals[m->triangleEdges[t][1]]; break;
    case TriangleFeature::EdgeCA: pseudo = &m->edgeNormals[m->triangleEdges[t][2]]; break;
    case TriangleFeature::VertexA: pseudo = &m->vertexNormals[m->canonical[f[0]]]; break;
    case TriangleFeature::VertexB: pseudo = &m->vertexNormals[m->canonical[f[1]]]; break;
    case TriangleFeature::VertexC: pseudo = &m->vertexNormals[m->canonical[f[2]]]; break;
  }
  hit.point = s.best.point;
  hit.normal = pseudo && !pseudo->isZero(0.0) ? *pseudo : m->faceNormals[t];
  hit.distance = std::sqrt(s.bestSquared);
  hit.signedDistance = (query - hit.point).dot(hit.normal) < 0.0 ? -hit.distance : hit.distance;
  hit.triangle = t;
  hint = t;
  return true;
}

const TriangleMesh& TriangleTree::mesh() const { return m->mesh; }
std::uint64_t TriangleTree::version() const { return m->version; }

int TriangleTree::droppedTriangles() const { return m->dropped; }
int TriangleTree::triangleCount() const { return static_cast<int>(m->mesh.triangles.size()); }

}  // namespace bsdeform
