// SPDX-License-Identifier: MIT
// Embree 3 point queries with a user callback doing the exact point-triangle distance in double.
#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "closest_index.h"

namespace closestbench {
namespace {

class EmbreeIndex final : public ClosestIndex {
 public:
  explicit EmbreeIndex(bool refit) : m_refit(refit), m_device(rtcNewDevice("threads=1")) {
    if (!m_device) throw std::runtime_error("rtcNewDevice failed");
  }
  ~EmbreeIndex() override {
    if (m_scene) rtcReleaseScene(m_scene);
    rtcReleaseDevice(m_device);
  }

  void build(const bsdeform::TriangleMesh& mesh) override {
    if (m_scene) rtcReleaseScene(m_scene);
    m_vertices = mesh.vertices;
    m_triangles = mesh.triangles;
    m_scene = rtcNewScene(m_device);
    if (m_refit) {
      rtcSetSceneFlags(m_scene, RTC_SCENE_FLAG_DYNAMIC);
      rtcSetSceneBuildQuality(m_scene, RTC_BUILD_QUALITY_LOW);
    }
    m_geometry = rtcNewGeometry(m_device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(m_geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), m_triangles.size()));
    for (size_t t = 0; t < m_triangles.size(); ++t)
      for (int k = 0; k < 3; ++k) idx[3 * t + k] = static_cast<unsigned>(m_triangles[t][k]);
    rtcSetNewGeometryBuffer(m_geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                            m_vertices.size());
    writeVertices();
    if (m_refit) rtcSetGeometryBuildQuality(m_geometry, RTC_BUILD_QUALITY_REFIT);
    rtcCommitGeometry(m_geometry);
    rtcAttachGeometry(m_scene, m_geometry);
    rtcReleaseGeometry(m_geometry);  // the scene holds it
    rtcCommitScene(m_scene);
    if (rtcGetDeviceError(m_device) != RTC_ERROR_NONE) throw std::runtime_error("embree build failed");
  }

  void update(const std::vector<Eigen::Vector3d>& vertices) override {
    m_vertices = vertices;
    writeVertices();
    rtcUpdateGeometryBuffer(m_geometry, RTC_BUFFER_TYPE_VERTEX, 0);
    rtcCommitGeometry(m_geometry);
    rtcCommitScene(m_scene);
  }

  bool closest(const Eigen::Vector3d& q, double maxDistance, Hit& hit) const override {
    Search s{this, q, maxDistance * maxDistance, std::numeric_limits<double>::infinity(), -1, {}};
    // Embree culls with float boxes around float vertices: widen its radius by a few float ulps
    // of the coordinates so no triangle within maxDistance (in double) is culled.
    s.slack = 8.0f * std::numeric_limits<float>::epsilon() * float(std::max(m_absMax, q.cwiseAbs().maxCoeff()));
    RTCPointQuery query;
    query.x = float(q.x());
    query.y = float(q.y());
    query.z = float(q.z());
    query.time = 0.0f;
    query.radius = float(maxDistance) + s.slack;
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    rtcPointQuery(m_scene, &query, &context, &EmbreeIndex::visit, &s);
    if (s.triangle < 0) return false;
    hit.point = s.best.point;
    hit.feature = s.best.feature;
    hit.distance = std::sqrt(s.bestSq);
    hit.triangle = s.triangle;
    return true;
  }

 private:
  struct Search {
    const EmbreeIndex* index;
    Eigen::Vector3d q;
    double maxSq;
    double bestSq;
    int triangle;
    bsdeform::TrianglePoint best;
    float slack = 0.0f;
  };

  static bool visit(RTCPointQueryFunctionArguments* args) {
    auto* s = static_cast<Search*>(args->userPtr);
    const Eigen::Vector3i& t = s->index->m_triangles[args->primID];
    const auto& v = s->index->m_vertices;
    const bsdeform::TrianglePoint p = bsdeform::closestPointOnTriangle(s->q, v[t[0]], v[t[1]], v[t[2]]);
    const double d2 = (s->q - p.point).squaredNorm();
    if (d2 > s->maxSq || d2 >= s->bestSq) return false;
    s->bestSq = d2;
    s->best = p;
    s->triangle = int(args->primID);
    const float r = float(std::sqrt(d2)) + s->slack;
    if (r >= args->query->radius) return false;
    args->query->radius = r;
    return true;
  }

  void writeVertices() {
    auto* dst = static_cast<float*>(rtcGetGeometryBufferData(m_geometry, RTC_BUFFER_TYPE_VERTEX, 0));
    m_absMax = 0.0;
    for (size_t i = 0; i < m_vertices.size(); ++i) {
      for (int k = 0; k < 3; ++k) dst[3 * i + k] = float(m_vertices[i][k]);
      m_absMax = std::max(m_absMax, m_vertices[i].cwiseAbs().maxCoeff());
    }
  }

  bool m_refit;
  RTCDevice m_device;
  RTCScene m_scene = nullptr;
  RTCGeometry m_geometry = nullptr;
  std::vector<Eigen::Vector3d> m_vertices;
  std::vector<Eigen::Vector3i> m_triangles;
  double m_absMax = 0.0;
};

}  // namespace

std::unique_ptr<ClosestIndex> makeEmbreeIndex(bool refit) { return std::make_unique<EmbreeIndex>(refit); }

}  // namespace closestbench
