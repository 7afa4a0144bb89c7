// SPDX-License-Identifier: MIT
#include "bsdeform/contact/ClosestPointOnTriangle.h"

namespace bsdeform {

TrianglePoint closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                     const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a;
  // Projections of p - a, p - b, p - c on the two edges from a: they decide the region.
  const Eigen::Vector3d ap = p - a;
  const double abAp = ab.dot(ap), acAp = ac.dot(ap);
  if (abAp <= 0.0 && acAp <= 0.0) return {a, TriangleFeature::VertexA};

  const Eigen::Vector3d bp = p - b;
  const double abBp = ab.dot(bp), acBp = ac.dot(bp);
  if (abBp >= 0.0 && acBp <= abBp) return {b, TriangleFeature::VertexB};

  // Unnormalised barycentric coordinate of c: its sign says which side of ab p projects to.
  const double wc = abAp * acBp - abBp * acAp;
  if (wc <= 0.0 && abAp >= 0.0 && abBp <= 0.0) {
    const double t = abAp / (abAp - abBp);
    return {a + t * ab, TriangleFeature::EdgeAB};
  }

  const Eigen::Vector3d cp = p - c;
  const double abCp = ab.dot(cp), acCp = ac.dot(cp);
  if (acCp >= 0.0 && abCp <= acCp) return {c, TriangleFeature::VertexC};

  const double wb = abCp * acAp - abAp * acCp;
  if (wb <= 0.0 && acAp >= 0.0 && acCp <= 0.0) {
    const double t = acAp / (acAp - acCp);
    return {a + t * ac, TriangleFeature::EdgeCA};
  }

  const double wa = abBp * acCp - abCp * acBp;
  if (wa <= 0.0 && acBp - abBp >= 0.0 && abCp - acCp >= 0.0) {
    const double t = (acBp - abBp) / ((acBp - abBp) + (abCp - acCp));
    return {b + t * (c - b), TriangleFeature::EdgeBC};
  }

  const double inv = 1.0 / (wa + wb + wc);
  return {a + ab * (wb * inv) + ac * (wc * inv), TriangleFeature::Face};
}

}  // namespace bsdeform
