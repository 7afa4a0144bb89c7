// SPDX-License-Identifier: MIT
#pragma once
/// @file SplineSpace.h
/// The discretisation of [0,1]^2 (paper §4.2): degree (n1, n2), N1 x N2 free control points,
/// h_i = 1/(N_i + n_i) (erratum, see docs/math.md), the full control net of
/// (N1 + 2 n1) x (N2 + 2 n2) points indexed by the paper's k = (k1, k2), and surface evaluation
/// (eq. 9) with derivatives.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "bsdeform/BSpline.h"

namespace bsdeform {

/// A full control net: one row (x, y, z) per control point, row = i * cols + j with
/// i = k1 + n1 (u direction) and j = k2 + n2 (v direction). Row-major so that a net row is one
/// contiguous run of 3 * cols doubles (what the stencil kernel streams).
using ControlNet = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// Position and first/second partial derivatives of S at one (u, v).
struct SurfacePoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d du = Eigen::Vector3d::Zero();
  Eigen::Vector3d dv = Eigen::Vector3d::Zero();
  Eigen::Vector3d duu = Eigen::Vector3d::Zero();
  Eigen::Vector3d duv = Eigen::Vector3d::Zero();
  Eigen::Vector3d dvv = Eigen::Vector3d::Zero();
  /// Unit normal du x dv (zero if degenerate).
  Eigen::Vector3d normal() const;
};

class SplineSpace {
 public:
  /// @throws std::invalid_argument naming the parameter for degrees outside 1..7 or N < 1
  SplineSpace(int degreeU, int degreeV, int numFreeU, int numFreeV);

  const BSplineBasis1D& basisU() const { return m_u; }
  const BSplineBasis1D& basisV() const { return m_v; }
  int degreeU() const { return m_u.degree(); }
  int degreeV() const { return m_v.degree(); }
  int numFreeU() const { return m_u.numFree(); }
  int numFreeV() const { return m_v.numFree(); }
  /// Net rows (u direction): N1 + 2 n1; columns (v direction): N2 + 2 n2.
  int netRows() const { return m_u.numTotal(); }
  int netCols() const { return m_v.numTotal(); }
  Eigen::Index netSize() const { return Eigen::Index(netRows()) * netCols(); }
  Eigen::Index numFree() const { return Eigen::Index(numFreeU()) * numFreeV(); }

  /// Row of the control point with paper index (k1, k2), k in -n .. N+n-1.
  Eigen::Index netIndex(int k1, int k2) const {
    return Eigen::Index(k1 + degreeU()) * netCols() + (k2 + degreeV());
  }
  /// Whether net point (i, j) (0-based net coordinates) is one of the N1 x N2 free points.
  bool isFree(int i, int j) const {
    return i >= degreeU() && i < degreeU() + numFreeU() && j >= degreeV() && j < degreeV() + numFreeV();
  }
  /// Row of free point number f (f = a * N2 + b, a along u) in the full net.
  Eigen::Index freeToNet(Eigen::Index f) const {
    return netIndex(int(f / numFreeV()), int(f % numFreeV()));
  }

  /// Greville abscissa of function k: xi_k = (k + (n+1)/2) h.
  double grevilleU(int k1) const;
  double grevilleV(int k2) const;
  /// The net with every point at its Greville abscissae: S(u,v) = (u, v, 0) exactly.
  ControlNet grevillePlane() const;

  /// Free points of a full net, as an N1*N2 x 3 matrix (free order f = a * N2 + b).
  ControlNet gatherFree(const ControlNet& net) const;
  /// Writes free points back into a full net.
  void scatterFree(const ControlNet& freePoints, ControlNet& net) const;

  /// S(u,v) (eq. 9) and derivatives up to `order` (0, 1 or 2) from a full net.
  SurfacePoint evaluate(const ControlNet& net, double u, double v, int order = 1) const;
  /// Same, with the 1-D bases at (u, v) already evaluated (to at least `order`), e.g. shared
  /// by many quadrature points.
  SurfacePoint evaluate(const ControlNet& net, const LocalBasis& bu, const LocalBasis& bv, int order) const;

 private:
  BSplineBasis1D m_u;
  BSplineBasis1D m_v;
};

}  // namespace bsdeform
