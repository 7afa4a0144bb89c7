// SPDX-License-Identifier: MIT
#include "bsdeform/contact/AdditiveCCD.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>

#include "bsdeform/contact/Distance.h"

namespace bsdeform {

namespace {

using Positions = std::array<Eigen::Vector3d, 4>;

/// The additive CCD loop on four vertices x (start) moving by dx (mean already subtracted);
/// `distanceSquared` of four positions, `speed` the bound l of the header.
template <class DistanceSquared>
bool additiveCCD(const Positions& x, const Positions& dx, DistanceSquared distanceSquared, double speed,
                 double offset, double tMax, double s, double& toi) {
  assert(offset >= 0.0 && s > 0.0 && s < 1.0);
  const double offsetSq = offset * offset;
  double dSq = distanceSquared(x);
  double d = std::sqrt(dSq);
  // d - ξ as (d² - ξ²) / (d + ξ): no cancellation between d and ξ when ξ ≫ d - ξ.
  double dAbove = dSq > offsetSq ? (dSq - offsetSq) / (d + offset) : 0.0;
  if (dAbove <= 1e-10 * (d + offset)) {
    toi = 0.0;
    return true;
  }
  if (speed <= 0.0 || tMax <= 0.0) {  // the pair moves rigidly together: its distance is constant
    toi = std::max(tMax, 0.0);
    return false;
  }
  const double gap = (1.0 - s) * dAbove;
  double t = 0.0;
  Positions xt;
  for (int iteration = 0; iteration < kAdditiveCCDMaxIterations; ++iteration) {
    const double dt = s * dAbove / speed;
    if (t + dt >= tMax) {  // [t, tMax] lies within this safe sub-step
      toi = tMax;
      return false;
    }
    // From the start positions each time, not accumulated: no drift over many sub-steps.
    const double tNext = t + dt;
    for (int i = 0; i < 4; ++i) xt[i] = x[i] + tNext * dx[i];
    dSq = distanceSquared(xt);
    d = std::sqrt(dSq);
    const double nextAbove = dSq > offsetSq ? (dSq - offsetSq) / (d + offset) : 0.0;
    // The first sub-step keeps (1 - s)(d_0 - ξ) = gap by the bound: it is accepted unless rounding
    // made it touch ξ; a later one that ends below the gap stops the search before it.
    if (nextAbove <= 0.0 || (iteration > 0 && nextAbove < gap)) {
      toi = t;
      return true;
    }
    t = tNext;
    dAbove = nextAbove;
  }
  toi = t;
  return true;
}

/// Subtracts the mean of the displacements from each.
void subtractMean(Positions& dx) {
  const Eigen::Vector3d mean = (dx[0] + dx[1] + dx[2] + dx[3]) / 4.0;
  for (Eigen::Vector3d& v : dx) v -= mean;
}

}  // namespace

bool pointTriangleCCD(const Eigen::Vector3d& p0, const Eigen::Vector3d& t00, const Eigen::Vector3d& t10,
                      const Eigen::Vector3d& t20, const Eigen::Vector3d& p1, const Eigen::Vector3d& t01,
                      const Eigen::Vector3d& t11, const Eigen::Vector3d& t21, double offset, double tMax,
                      double& toi, double conservativeRescaling) {
  const Positions x{p0, t00, t10, t20};
  Positions dx{p1 - p0, t01 - t00, t11 - t10, t21 - t20};
  subtractMean(dx);
  const double speed =
      dx[0].norm() + std::sqrt(std::max({dx[1].squaredNorm(), dx[2].squaredNorm(), dx[3].squaredNorm()}));
  // a pair farther at the start than the loop's first sub-step could close (d - ξ >= l tMax / s)
  // ends there, before any distance: a cheap lower bound decides (a relative margin of 10⁻⁶ for
  // its rounding), with the same answer
  if (speed > 0.0 && tMax > 0.0 &&
      pointTriangleFartherThan(p0, t00, t10, t20, (1.0 + 1e-6) * (offset + speed * tMax / conservativeRescaling))) {
    toi = tMax;
    return false;
  }
  const auto distanceSquared = [](const Positions& y) { return pointTriangleDistanceSquared(y[0], y[1], y[2], y[3]); };
  return additiveCCD(x, dx, distanceSquared, speed, offset, tMax, conservativeRescaling, toi);
}

bool edgeEdgeCCD(const Eigen::Vector3d& a00, const Eigen::Vector3d& a10, const Eigen::Vector3d& b00,
                 const Eigen::Vector3d& b10, const Eigen::Vector3d& a01, const Eigen::Vector3d& a11,
                 const Eigen::Vector3d& b01, const Eigen::Vector3d& b11, double offset, double tMax, double& toi,
                 double conservativeRescaling) {
  const Positions x{a00, a10, b00, b10};
  Positions dx{a01 - a00, a11 - a10, b01 - b00, b11 - b10};
  subtractMean(dx);
  const double speed = std::sqrt(std::max(dx[0].squaredNorm(), dx[1].squaredNorm())) +
                       std::sqrt(std::max(dx[2].squaredNorm(), dx[3].squaredNorm()));
  // Distance.h's segment distance is the true one for near-parallel segments too (it takes an
  // endpoint class there), so C-IPC's fallback to endpoint distances is not needed.
  if (speed > 0.0 && tMax > 0.0 &&
      edgeEdgeFartherThan(a00, a10, b00, b10, (1.0 + 1e-6) * (offset + speed * tMax / conservativeRescaling))) {
    toi = tMax;  // as in pointTriangleCCD: farther than the first sub-step closes
    return false;
  }
  const auto distanceSquared = [](const Positions& y) { return edgeEdgeDistanceSquared(y[0], y[1], y[2], y[3]); };
  return additiveCCD(x, dx, distanceSquared, speed, offset, tMax, conservativeRescaling, toi);
}

namespace {

Eigen::Vector3d startOf(const ContactMesh& mesh, int v) { return mesh.start.row(v).transpose(); }
Eigen::Vector3d endOf(const ContactMesh& mesh, int v) { return mesh.end.row(v).transpose(); }

/// Lowers t to the time of impact of point v of `pm` against triangle f of `tm`.
void lowerByPointTriangle(const ContactMesh& pm, int v, const ContactMesh& tm, int f, double offset, double s,
                          double& t) {
  const int i = tm.triangles(f, 0), j = tm.triangles(f, 1), k = tm.triangles(f, 2);
  double toi = t;
  // tMax = the current fraction: a pair cannot lower it past what it would need to reach.
  if (pointTriangleCCD(startOf(pm, v), startOf(tm, i), startOf(tm, j), startOf(tm, k), endOf(pm, v), endOf(tm, i),
                       endOf(tm, j), endOf(tm, k), offset, t, toi, s))
    t = std::min(t, toi);
}

void lowerByEdgeEdge(const ContactMesh& am, int e, const ContactMesh& bm, int g, double offset, double s,
                     double& t) {
  const int a0 = am.edges(e, 0), a1 = am.edges(e, 1), b0 = bm.edges(g, 0), b1 = bm.edges(g, 1);
  double toi = t;
  if (edgeEdgeCCD(startOf(am, a0), startOf(am, a1), startOf(bm, b0), startOf(bm, b1), endOf(am, a0), endOf(am, a1),
                  endOf(bm, b0), endOf(bm, b1), offset, t, toi, s))
    t = std::min(t, toi);
}

}  // namespace

double collisionFreeFraction(const ContactMesh& a, const ContactMesh& b, double offset, double s) {
  ContactCandidates candidates;
  candidatePairs(a, b, offset, candidates);
  return collisionFreeFraction(a, b, candidates, offset, s);
}

double collisionFreeFraction(const ContactMesh& a, const ContactMesh& b, const ContactCandidates& candidates,
                             double offset, double s) {
  double t = 1.0;
  for (const auto& [v, f] : candidates.vertexTriangle) lowerByPointTriangle(a, v, b, f, offset, s, t);
  for (const auto& [f, v] : candidates.triangleVertex) lowerByPointTriangle(b, v, a, f, offset, s, t);
  for (const auto& [e, g] : candidates.edgeEdge) lowerByEdgeEdge(a, e, b, g, offset, s, t);
  return t;
}

double collisionFreeFraction(const ContactMesh& a, double offset, double s) {
  ContactCandidates candidates;
  candidatePairs(a, offset, candidates);
  return collisionFreeFraction(a, candidates, offset, s);
}

double collisionFreeFraction(const ContactMesh& a, const ContactCandidates& candidates, double offset, double s) {
  double t = 1.0;
  for (const auto& [v, f] : candidates.vertexTriangle) lowerByPointTriangle(a, v, a, f, offset, s, t);
  for (const auto& [e, g] : candidates.edgeEdge) lowerByEdgeEdge(a, e, a, g, offset, s, t);
  return t;
}

}  // namespace bsdeform
