// SPDX-License-Identifier: MIT
#pragma once
/// @file ExactPredicates.h
/// Exact signs of orientation determinants of double-precision points, for tests that must not
/// be fooled by rounding (is there a crossing or not). Expansion arithmetic after Shewchuk,
/// "Adaptive precision floating-point arithmetic and fast robust geometric predicates" (1997):
/// a number is a sum of doubles of increasing magnitude that do not overlap, so the sign of the
/// largest is the sign of the sum. No filter: slow, and plenty fast for tests.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <vector>

namespace bsdeform::test {

/// An exact sum of doubles, nonoverlapping, in increasing magnitude.
using Expansion = std::vector<double>;

/// a + b = x + y exactly, x = fl(a + b).
inline void twoSum(double a, double b, double& x, double& y) {
  x = a + b;
  const double bv = x - a, av = x - bv;
  y = (a - av) + (b - bv);
}

/// e + b (Shewchuk's Grow-Expansion, zero components dropped).
inline Expansion grow(const Expansion& e, double b) {
  Expansion h;
  h.reserve(e.size() + 1);
  double q = b;
  for (double ei : e) {
    double sum, err;
    twoSum(q, ei, sum, err);
    if (err != 0.0) h.push_back(err);
    q = sum;
  }
  if (q != 0.0 || h.empty()) h.push_back(q);
  return h;
}

inline Expansion operator+(Expansion e, const Expansion& f) {
  for (double fj : f) e = grow(e, fj);
  return e;
}

inline Expansion operator-(const Expansion& e) {
  Expansion n(e);
  for (double& x : n) x = -x;
  return n;
}

inline Expansion operator-(const Expansion& e, const Expansion& f) { return e + (-f); }

inline Expansion operator*(const Expansion& e, const Expansion& f) {
  Expansion result;
  for (double fj : f)
    for (double ei : e) {
      const double p = ei * fj, err = std::fma(ei, fj, -p);  // ei fj = p + err exactly
      result = grow(grow(result, err), p);
    }
  return result;
}

/// The sign (-1, 0, 1) of the sum.
inline int sign(const Expansion& e) {
  for (auto it = e.rbegin(); it != e.rend(); ++it)
    if (*it != 0.0) return *it > 0.0 ? 1 : -1;
  return 0;
}

/// a - b exactly.
inline Expansion difference(double a, double b) {
  double x, y;
  twoSum(a, -b, x, y);
  return y != 0.0 ? Expansion{y, x} : Expansion{x};
}

/// The exact sign of det[a - d; b - d; c - d]: positive when d lies below the plane through a, b,
/// c oriented counterclockwise seen from above.
inline int orient3d(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                    const Eigen::Vector3d& d) {
  const Expansion ax = difference(a.x(), d.x()), ay = difference(a.y(), d.y()), az = difference(a.z(), d.z());
  const Expansion bx = difference(b.x(), d.x()), by = difference(b.y(), d.y()), bz = difference(b.z(), d.z());
  const Expansion cx = difference(c.x(), d.x()), cy = difference(c.y(), d.y()), cz = difference(c.z(), d.z());
  return sign(ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx));
}

/// The exact sign of det[a - c; b - c] of 2D points: positive when a, b, c turn counterclockwise.
inline int orient2d(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  return sign(difference(a.x(), c.x()) * difference(b.y(), c.y()) - difference(a.y(), c.y()) * difference(b.x(), c.x()));
}

/// Whether the closed 2D segments pq and rs meet (exactly, collinear overlaps included).
inline bool segmentsMeet2d(const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& r,
                           const Eigen::Vector2d& s) {
  const int o1 = orient2d(p, q, r), o2 = orient2d(p, q, s), o3 = orient2d(r, s, p), o4 = orient2d(r, s, q);
  if (o1 == 0 && o2 == 0) {  // collinear: the intervals overlap along an axis that separates them
    const int k = p.x() != q.x() || r.x() != s.x() ? 0 : 1;
    return std::max(std::min(p[k], q[k]), std::min(r[k], s[k])) <= std::min(std::max(p[k], q[k]), std::max(r[k], s[k]));
  }
  return o1 * o2 <= 0 && o3 * o4 <= 0;
}

/// Whether the closed segment pq meets the closed triangle abc, exactly; a segment in the
/// triangle's plane is tested in that plane (projected along the axis the triangle faces most:
/// an affine bijection of the plane, so meeting is preserved).
inline bool segmentMeetsTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& a,
                                 const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const int op = orient3d(a, b, c, p), oq = orient3d(a, b, c, q);
  if (op * oq > 0) return false;  // both strictly on one side
  if (op == 0 && oq == 0) {
    Eigen::Index drop = 0;
    (b - a).cross(c - a).cwiseAbs().maxCoeff(&drop);
    const int i = drop == 0 ? 1 : 0, j = drop == 2 ? 1 : 2;
    auto flat = [i, j](const Eigen::Vector3d& x) { return Eigen::Vector2d(x[i], x[j]); };
    const Eigen::Vector2d P = flat(p), Q = flat(q), A = flat(a), B = flat(b), C = flat(c);
    const int s1 = orient2d(A, B, P), s2 = orient2d(B, C, P), s3 = orient2d(C, A, P);
    if ((s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0)) return true;  // p inside
    return segmentsMeet2d(P, Q, A, B) || segmentsMeet2d(P, Q, B, C) || segmentsMeet2d(P, Q, C, A);
  }
  const int s1 = orient3d(p, q, a, b), s2 = orient3d(p, q, b, c), s3 = orient3d(p, q, c, a);
  return (s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0);
}

/// Whether two closed triangles meet: for triangles not in one plane, the ends of their common
/// segment lie on edges, so some edge of one meets the other.
inline bool trianglesMeet(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& a2,
                          const Eigen::Vector3d& b0, const Eigen::Vector3d& b1, const Eigen::Vector3d& b2) {
  return segmentMeetsTriangle(a0, a1, b0, b1, b2) || segmentMeetsTriangle(a1, a2, b0, b1, b2) ||
         segmentMeetsTriangle(a2, a0, b0, b1, b2) || segmentMeetsTriangle(b0, b1, a0, a1, a2) ||
         segmentMeetsTriangle(b1, b2, a0, a1, a2) || segmentMeetsTriangle(b2, b0, a0, a1, a2);
}

}  // namespace bsdeform::test
