// SPDX-License-Identifier: MIT
#pragma once
/// @file CoinEigen.h
/// The one place that converts between Coin's Sb value types / fields and Eigen (as FreeCAD's
/// src/Gui/Utilities.h does for its own types). Double types convert exactly; the float ones
/// (SbVec3f, SbVec2f) widen exactly on the way in and round to nearest on the way out.

#include <Eigen/Core>
#include <Inventor/SbMatrix.h>
#include <Inventor/SbVec2d.h>
#include <Inventor/SbVec2f.h>
#include <Inventor/SbVec3d.h>
#include <Inventor/SbVec3f.h>
#include <Inventor/fields/SoMFVec3d.h>

namespace bsdeform {

inline Eigen::Vector3d toEigen(const SbVec3d& v) { return Eigen::Vector3d(v[0], v[1], v[2]); }
inline Eigen::Vector3d toEigen(const SbVec3f& v) { return Eigen::Vector3d(v[0], v[1], v[2]); }
inline Eigen::Vector2d toEigen(const SbVec2d& v) { return Eigen::Vector2d(v[0], v[1]); }
inline Eigen::Vector2d toEigen(const SbVec2f& v) { return Eigen::Vector2d(v[0], v[1]); }

inline SbVec3d toSbVec3d(const Eigen::Ref<const Eigen::Vector3d>& v) { return SbVec3d(v.x(), v.y(), v.z()); }
inline SbVec3f toSbVec3f(const Eigen::Ref<const Eigen::Vector3d>& v) {
  return SbVec3f(float(v.x()), float(v.y()), float(v.z()));
}
inline SbVec2d toSbVec2d(const Eigen::Ref<const Eigen::Vector2d>& v) { return SbVec2d(v.x(), v.y()); }
inline SbVec2f toSbVec2f(const Eigen::Ref<const Eigen::Vector2d>& v) { return SbVec2f(float(v.x()), float(v.y())); }

/// The values of an SoMFVec3d as an n x 3 row-major matrix (the layout of bsdeform::ControlNet).
inline Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> toEigen(const SoMFVec3d& f) {
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> m(f.getNum(), 3);
  const SbVec3d* v = f.getValues(0);
  for (int i = 0; i < f.getNum(); ++i) m.row(i) << v[i][0], v[i][1], v[i][2];
  return m;
}

/// Sets an SoMFVec3d to the rows of an n x 3 matrix (one notification).
template <typename Derived>
void setFromEigen(SoMFVec3d& f, const Eigen::MatrixBase<Derived>& m) {
  static_assert(Derived::ColsAtCompileTime == 3, "an n x 3 matrix");
  f.setNum(int(m.rows()));
  SbVec3d* v = f.startEditing();
  for (Eigen::Index i = 0; i < m.rows(); ++i) v[i].setValue(m(i, 0), m(i, 1), m(i, 2));
  f.finishEditing();
}

/// The affine map of a Coin matrix (row vectors, x_world = x m) as x_world = linear x + offset:
/// offset the image of the origin, linear's columns the images of the unit vectors less it (each
/// image through SbMatrix::multVecMatrix, and the difference, in float, as Coin maps points).
inline void affineOf(const SbMatrix& m, Eigen::Matrix3d& linear, Eigen::Vector3d& offset) {
  SbVec3f o, e;
  m.multVecMatrix(SbVec3f(0, 0, 0), o);
  offset = toEigen(o);
  for (int j = 0; j < 3; ++j) {
    SbVec3f unit(0, 0, 0);
    unit[j] = 1.0f;
    m.multVecMatrix(unit, e);
    linear.col(j) = toEigen(e - o);  // the difference in float, as Coin's own vectors
  }
}

}  // namespace bsdeform
