// SPDX-License-Identifier: MIT
#pragma once
/// @file SplineSpace.h
/// The discretisation of [0,1]^2 (paper §4.2): degree (n1, n2), N1 x N2 inner control points,
/// h_i = 1/(N_i + n_i) (erratum, see docs/math.md), the full control net of
/// (N1 + 2 n1) x (N2 + 2 n2) points indexed by the paper's k = (k1, k2), the boundary condition
/// of each side of the parameter square (which control points move), and surface evaluation
/// (eq. 9) with derivatives.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <utility>
#include <vector>

#include "bsdeform/spline/BSpline.h"

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

/// Condition on one side of the parameter square. The knot grid never depends on it.
enum class Boundary {
  Clamped,          ///< the n outer layers of control points are held (the paper): S and its
                    ///< first n-1 cross derivatives stay at rest (a "super-clamp" for n >= 3)
  Free,             ///< the outer layers move; natural boundary condition (energy over [0,1]^2 only)
  Periodic,         ///< k and k + (N+n) are one control point; must be set on both sides of a direction
  SimplySupported,  ///< the edge curve S(u0, .) stays at rest, the surface turns about it (a hinge)
  BuiltIn,          ///< the edge curve and the cross derivative (S_u on a u side) stay at rest: the
                    ///< tangent plane along the edge is fixed (an engineering clamp); for degree 2
                    ///< this is Clamped, for degree 1 it holds the outer layer and the next one
};

/// The four sides: uMin is u = 0, uMax is u = 1, vMin is v = 0, vMax is v = 1.
struct Boundaries {
  Boundary uMin = Boundary::Clamped, uMax = Boundary::Clamped;
  Boundary vMin = Boundary::Clamped, vMax = Boundary::Clamped;
  bool allClamped() const {
    return uMin == Boundary::Clamped && uMax == Boundary::Clamped && vMin == Boundary::Clamped &&
           vMax == Boundary::Clamped;
  }
};

/// "CLAMPED", "FREE", "PERIODIC", "SIMPLY_SUPPORTED" or "BUILT_IN".
const char* boundaryName(Boundary b);

/// How one side holds the layers next to it (docs/math.md §14), counted from the edge inwards:
/// `held` layers at rest, then `derived` layers that are not unknowns but follow the next
/// `sources` layers (moving) so that the held quantities stay at rest:
///   P_derived = R_derived + Z (P_sources - R_sources)   (R the rest net), Z derived x sources.
/// CLAMPED: held = n. FREE, PERIODIC: nothing. SIMPLY_SUPPORTED holds S at the edge, one linear
/// combination of the n outer layers: the outermost layer is derived from the n-1 next ones
/// (degree 1: the one outer layer is held). BUILT_IN holds S and the cross derivative: the two
/// outermost layers are derived from the n-2 next ones (degree 2: both held, = CLAMPED; degree
/// 1: the outer layer and the first inner one are held, the one-sided derivative inside [0,1]).
struct EdgeLayers {
  int held = 0;
  int derived = 0;
  int sources = 0;
  Eigen::MatrixXd Z;
};
EdgeLayers edgeLayers(Boundary side, int degree);

/// A moving layer and a weight: what a net layer stands for in terms of the unknowns.
struct LayerWeight {
  int layer;
  double weight;
};
/// The moving net layers of one direction: net layers first .. first + count - 1.
///  - both sides clamped: the N inner layers, [n, N+n);
///  - a free side adds its n outer layers ([0, ...) or [..., N+2n));
///  - a SIMPLY_SUPPORTED or BUILT_IN side adds the source layers of EdgeLayers (n-1 or n-2 of
///    them; BUILT_IN of degree 1 removes inner layer k = 0);
///  - periodic: the N+n distinct layers [n, N+2n); layers [0, n) are copies of [N+n, N+2n).
struct LayerRange {
  int first = 0;
  int count = 0;
  bool contains(int layer) const { return layer >= first && layer < first + count; }
};

/// Limits of a model, checked once, here: inner control points per direction and in all.
constexpr int kMaxPerSide = 1 << 16;
/// N1 N2 <= 2048^2: about 100 MB per net of doubles; a running model holds six (docs/reliability.md:
/// bsdeform-run peaks at 633 MB for 2048^2, writing included, as text is streamed).
constexpr long long kMaxInnerPoints = 1LL << 22;

class SplineSpace {
 public:
  /// @throws std::invalid_argument naming the parameter for degrees outside 1..7, N < 1,
  ///         N > kMaxPerSide, N1 N2 > kMaxInnerPoints, PERIODIC on only one side of a direction
  ///         (facing any other kind), or sides that leave no moving layer
  SplineSpace(int degreeU, int degreeV, int numU, int numV, const Boundaries& boundaries = Boundaries());

  const BSplineBasis1D& basisU() const { return m_u; }
  const BSplineBasis1D& basisV() const { return m_v; }
  int degreeU() const { return m_u.degree(); }
  int degreeV() const { return m_v.degree(); }
  /// N1, N2: the inner control points (the paper's free points, whose B-splines lie inside).
  int numU() const { return m_u.numFree(); }
  int numV() const { return m_v.numFree(); }
  /// Net rows (u direction): N1 + 2 n1; columns (v direction): N2 + 2 n2.
  int netRows() const { return m_u.numTotal(); }
  int netCols() const { return m_v.numTotal(); }
  Eigen::Index netSize() const { return Eigen::Index(netRows()) * netCols(); }

  const Boundaries& boundaries() const { return m_boundaries; }
  bool periodicU() const { return m_boundaries.uMin == Boundary::Periodic; }
  bool periodicV() const { return m_boundaries.vMin == Boundary::Periodic; }
  /// Moving layers of each direction (see LayerRange).
  const LayerRange& movingU() const { return m_movingU; }
  const LayerRange& movingV() const { return m_movingV; }
  /// What net layer i (0-based) stands for in terms of the moving layers: {(i, 1)} for a
  /// moving layer, {(i + N + n, 1)} for a periodic copy, the weights of Z for a derived layer
  /// (EdgeLayers), nothing for a held layer. A displacement of the moving layers moves layer i
  /// by the sum of weight x displacement of each entry's layer.
  const std::vector<LayerWeight>& foldU(int i) const { return m_foldU[size_t(i)]; }
  const std::vector<LayerWeight>& foldV(int j) const { return m_foldV[size_t(j)]; }
  /// T as a sparse map: net point p is the sum over entries [start[p], start[p+1]) of weight x
  /// unknown (moving-point number; held points have none). Products of foldU() and foldV().
  void foldMap(std::vector<int>& start, std::vector<std::pair<Eigen::Index, double>>& entries) const;
  /// Whether net point (i, j) is derived (next to a SIMPLY_SUPPORTED or BUILT_IN side): not an
  /// unknown, not held, not a periodic copy, but moving with the unknowns it folds onto.
  bool isDerived(int i, int j) const {
    auto copy = [](const LayerRange& r, int moving, int layer) { return moving >= 0 && !r.contains(layer); };
    return !foldU(i).empty() && !foldV(j).empty() && !isMoving(i, j) && !copy(m_movingU, movingLayerU(i), i) &&
           !copy(m_movingV, movingLayerV(j), j);
  }
  /// Whether some side has derived layers (SIMPLY_SUPPORTED, or BUILT_IN of degree >= 3).
  bool hasDerived() const { return m_hasDerived; }
  /// Number of moving control points (the unknowns): movingU().count * movingV().count.
  /// All sides clamped: N1 N2, the paper's free points.
  Eigen::Index numMoving() const { return Eigen::Index(m_movingU.count) * m_movingV.count; }

  /// Row of the control point with paper index (k1, k2), k in -n .. N+n-1.
  Eigen::Index netIndex(int k1, int k2) const {
    return Eigen::Index(k1 + degreeU()) * netCols() + (k2 + degreeV());
  }
  /// Whether net point (i, j) (0-based net layers) is a moving point (not held by a side, not
  /// derived, not a periodic copy). Pins are not known here: see Simulation.
  bool isMoving(int i, int j) const { return m_movingU.contains(i) && m_movingV.contains(j); }
  /// Row in the full net of moving point number f (f = a * movingV().count + b, a along u);
  /// with all sides clamped this is the paper's order of the free points.
  Eigen::Index movingToNet(Eigen::Index f) const {
    const Eigen::Index w = m_movingV.count;
    return Eigen::Index(m_movingU.first + f / w) * netCols() + (m_movingV.first + f % w);
  }
  /// Moving-point number of B-spline (k1, k2) (its own control point, or the one it is a
  /// periodic copy of), or -1 if that control point is held or derived.
  Eigen::Index movingIndex(int k1, int k2) const;
  /// The moving net layer that net layer i (0-based) stands for: itself, or for a periodic copy
  /// layer the layer it copies; -1 if layer i is held or derived (see foldU()).
  int movingLayerU(int i) const;
  int movingLayerV(int j) const;

  /// Greville abscissa of function k: xi_k = (k + (n+1)/2) h.
  double grevilleU(int k1) const;
  double grevilleV(int k2) const;
  /// The net with every point at its Greville abscissae: S(u,v) = (u, v, 0) exactly.
  ControlNet grevillePlane() const;

  /// Moving points of a full net, as a numMoving() x 3 matrix (order of movingToNet).
  ControlNet gatherMoving(const ControlNet& net) const;
  /// Writes moving points back into a full net and refreshes its periodic copies.
  void scatterMoving(const ControlNet& movingPoints, ControlNet& net) const;
  /// Periodic directions: sets the copy layers [0, n) from the layers they repeat, [N+n, N+2n).
  void refreshPeriodicCopies(ControlNet& net) const;
  /// Sets the derived layers (EdgeLayers) from their source layers: net = rest + Z (net - rest)
  /// there; with rest null, the homogeneous form net = Z net (a displacement or a direction).
  /// u sides first, then v sides over every row, so a corner follows both. Nothing to do
  /// unless hasDerived().
  void refreshDerived(ControlNet& net, const ControlNet* rest) const;
  /// refreshDerived() then refreshPeriodicCopies(): a net whose moving points were written.
  void completeNet(ControlNet& net, const ControlNet* rest) const {
    refreshDerived(net, rest);
    refreshPeriodicCopies(net);
  }
  /// Largest difference, relative to 1 + |rest|, between the derived layers of `net` and what
  /// refreshDerived() would put there (a net read from a file must already agree).
  double derivedMismatch(const ControlNet& net, const ControlNet& rest) const;
  /// Derived layers of each direction, each with its source layers and Z (net layers).
  struct DerivedSide {
    std::vector<int> derived, sources;
    Eigen::MatrixXd Z;
  };
  const std::vector<DerivedSide>& derivedU() const { return m_derivedU; }
  const std::vector<DerivedSide>& derivedV() const { return m_derivedV; }
  /// Periodic directions, for nets read from outside (where the first n layers win): sets the
  /// last n layers from the first n. Returns the largest coordinate difference found before.
  double closePeriodic(ControlNet& net) const;

  /// S(u,v) (eq. 9) and derivatives up to `order` (0, 1 or 2) from a full net.
  SurfacePoint evaluate(const ControlNet& net, double u, double v, int order = 1) const;
  /// Same, with the 1-D bases at (u, v) already evaluated (to at least `order`), e.g. shared
  /// by many quadrature points.
  SurfacePoint evaluate(const ControlNet& net, const LocalBasis& bu, const LocalBasis& bv, int order) const;

 private:
  BSplineBasis1D m_u;
  BSplineBasis1D m_v;
  Boundaries m_boundaries;
  LayerRange m_movingU, m_movingV;
  std::vector<DerivedSide> m_derivedU, m_derivedV;
  std::vector<std::vector<LayerWeight>> m_foldU, m_foldV;
  bool m_hasDerived = false;
};

/// Area of the surface of `net` over [0,1]^2: the integral of |S_u x S_v| by Gauss–Legendre with
/// degree + 3 points per knot span and direction.
double surfaceArea(const SplineSpace& space, const ControlNet& net);

/// Whether the surface of `net` is closed: it has no boundary curve of positive length. Each
/// direction is periodic, or both of its edges collapse to a point (the poles of a sphere or
/// an ellipsoid: S(u, 0) and S(u, 1) each the same point for every u, to 1e-9 of the net's
/// size), and at least one direction is periodic.
bool isClosedSurface(const SplineSpace& space, const ControlNet& net);

}  // namespace bsdeform
