// SPDX-License-Identifier: MIT
#include "bsdeform/Contact.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <tuple>

#include "bsdeform/NumberText.h"

namespace bsdeform {

namespace {
// Share of rho / dt the damping and friction may reach: with the sub-step sized to
// dt^2 lambda <= 4 s^2 (s = 0.9), a backward-difference damping rate nu keeps the scheme stable
// while dt nu <= 2 (1 - s^2) = 0.38 (DragForce).
constexpr double kRateCap = 0.3;
// Obstacles are searched within this many thicknesses.
constexpr double kSearch = 3.0;

double checked(double x, const char* name, bool positive) {
  if (!std::isfinite(x) || x < 0.0 || (positive && x == 0.0))
    throw std::invalid_argument(std::string("collision ") + name + (positive ? " must be finite and > 0" : " must be finite and >= 0") +
                                ", got " + numberText(x));
  return x;
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

TriangleMesh weldVertices(const TriangleMesh& mesh) {
  TriangleMesh out;
  std::map<std::tuple<double, double, double>, int> index;
  std::vector<int> map(mesh.vertices.size(), -1);
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Eigen::Vector3d& p = mesh.vertices[i];
    auto it = index.emplace(std::make_tuple(p.x(), p.y(), p.z()), int(out.vertices.size()));
    if (it.second) out.vertices.push_back(p);
    map[i] = it.first->second;
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
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  double deepest = 0.0;
  const double rateCap = dt > 0.0 ? kRateCap * p.massDensity / dt : 0.0;
  const double damping = std::min(p.damping, rateCap);
  for (const ContactWorld::Obstacle& o : world.obstacles) {
    if (!o.tree) continue;
    ClosestHit hit;
    if (!o.tree->closest(x, kSearch * p.thickness, hit)) continue;
    // s: distance from the obstacle, signed for closed obstacles; n: away from the obstacle
    double s = hit.distance;
    Eigen::Vector3d n = hit.normal;
    if (o.closed) s = hit.signedDistance;
    if (hit.distance > 1e-12 * (1.0 + x.norm())) {
      n = (x - hit.point) / hit.distance;
      if (o.closed && s < 0.0) n = -n;
    } else if (!o.closed && v.dot(n) > 0.0) {
      n = -n;  // on an open shell: push back to the side it came from
    }
    const double depth = p.thickness - s;
    if (!(depth > 0.0)) continue;
    deepest = std::max(deepest, depth);
    const double vn = v.dot(n);
    const double fn = std::max(0.0, p.stiffness * depth - damping * vn);
    f += fn * n;
    const Eigen::Vector3d vt = v - vn * n;
    const double speed = vt.norm();
    if (p.friction > 0.0 && speed > 0.0 && fn > 0.0) f -= std::min(p.friction * fn, rateCap * speed) / speed * vt;
  }
  if (depthOut) *depthOut = deepest;
  return f;
}

CollisionForce::CollisionForce(std::shared_ptr<const ContactWorld> world, const ContactParameters& p)
    : DistributedForce(
          [w = world.get(), p](const SurfaceSample& s) {
            const Eigen::Vector3d xw = w->linear * s.position + w->offset;
            const Eigen::Vector3d vw = w->linear * s.velocity;
            return Eigen::Vector3d(w->linear.transpose() * contactDensity(*w, p, xw, vw, s.stepSize));
          },
          kDependsOnPosition | kDependsOnVelocity, ParamRect{}, 2, 0.0),
      m_world(std::move(world)),
      m_params(p) {
  if (!m_world) throw std::invalid_argument("collision: no obstacle world");
  checked(p.thickness, "thickness", true);
  checked(p.stiffness, "stiffness", false);
  checked(p.damping, "damping", false);
  checked(p.friction, "friction", false);
  checked(p.massDensity, "mass density", true);
  if (!m_world->linear.allFinite() || !m_world->offset.allFinite())
    throw std::invalid_argument("collision: the surface's transform is not finite");
}

double CollisionForce::eigenvalueBound(const MassContext& ctx) const {
  const double a = m_world->linear.jacobiSvd().singularValues()(0);
  return m_params.stiffness * a * a * ctx.space.basisU().spacing() * ctx.space.basisV().spacing() / ctx.interiorMass;
}

}  // namespace bsdeform
