// SPDX-License-Identifier: MIT
#pragma once
/// @file CollisionProxy.h
/// The triangle mesh that stands for a spline surface in barrier contact (docs/math.md §18.1):
/// samples of the surface on a (u, v) grid, `samplesPerSpan` intervals per knot span in each
/// direction, each cell split into two triangles. Every vertex is a fixed linear combination of
/// control points (the B-splines at its parameters), so a Newton update of the net moves the
/// vertices on straight lines and linear CCD on the proxy is exact for the step; forces on the
/// vertices go back to the control points through the same weights.

#include <Eigen/Core>
#include <utility>
#include <vector>

#include "bsdeform/spline/SplineSpace.h"

namespace bsdeform {

class CollisionProxy {
 public:
  /// A net point (full-net row) or an unknown (moving-point row) and its weight.
  struct Weight {
    Eigen::Index index;
    double weight;
  };

  /// @throws std::invalid_argument when samplesPerSpan is outside 1..16
  CollisionProxy(const SplineSpace& space, int samplesPerSpan);

  /// A vertex's weights: a range over the proxy's flat list.
  struct Weights {
    const Weight* first;
    const Weight* last;
    const Weight* begin() const { return first; }
    const Weight* end() const { return last; }
    size_t size() const { return size_t(last - first); }
  };

  int samplesPerSpan() const { return m_samples; }
  Eigen::Index numVertices() const { return Eigen::Index(m_netStart.size()) - 1; }
  const Eigen::MatrixX3i& triangles() const { return m_triangles; }
  const Eigen::MatrixX2i& edges() const { return m_edges; }
  /// The (u, v) of vertex k.
  Eigen::Vector2d parameters(Eigen::Index k) const { return m_params[size_t(k)]; }
  /// The knot span (element) each triangle lies in: every vertex of a triangle depends only on
  /// the control points of that element (vertices on a knot line have zero weight on the rest).
  std::pair<int, int> triangleElement(Eigen::Index t) const { return m_triangleElement[size_t(t)]; }

  /// The vertices of the surface of the full net `net`: row k = Σ weight × net row.
  void positions(const ControlNet& net, Eigen::MatrixX3d& out) const;
  /// The same vertices mapped by x ↦ linear x + offset (a surface's world frame), in one pass.
  /// The sums are taken in the order of positions() and of Eigen's
  /// general product of the n x 3 positions by linearᵀ (each coordinate from zero, the three
  /// columns in order, the product added to a zeroed destination: hence 0 + t), so the values
  /// equal `(positions * linearᵀ).rowwise() + offsetᵀ` bit for bit in this build (the core
  /// compiled without fused multiply–adds; a build that lets Eigen fuse them rounds its product
  /// differently).
  void positions(const ControlNet& net, const Eigen::Matrix3d& linear, const Eigen::Vector3d& offset,
                 Eigen::MatrixX3d& out) const;
  /// Net rows and weights of vertex k (zero weights left out).
  Weights netWeights(Eigen::Index k) const {
    return {m_netWeights.data() + m_netStart[size_t(k)], m_netWeights.data() + m_netStart[size_t(k) + 1]};
  }
  /// Adds Σ_k weight × f_k to the load of the moving points (numMoving x 3, order of
  /// SplineSpace::movingToNet): periodic copies load the point they repeat, derived points their
  /// sources (SplineSpace::foldU()); held points nothing.
  void addVertexForces(const Eigen::MatrixX3d& f, ControlNet& load) const;

  /// An upper bound of the distance between the surface of `net` and the proxy, at every (u, v):
  /// the largest over the knot spans of (1 / (8 r²)) (max |Δ²_u| + 2 max |Δ_u Δ_v| + max |Δ²_v|),
  /// r = samplesPerSpan, the maxima taken over the Bézier coefficients of the span's differenced
  /// net (h² S_uu, h_u h_v S_uv, h² S_vv on the span; docs/math.md §18.1).
  double deviationBound(const ControlNet& net) const;

 private:
  const SplineSpace& m_space;
  int m_samples;
  std::vector<Eigen::Vector2d> m_params;
  /// Every vertex's net weights, one after the other: vertex k's from m_netStart[k] to
  /// m_netStart[k + 1] (one flat list: the positions' pass reads it in order)
  std::vector<Weight> m_netWeights;
  std::vector<size_t> m_netStart;
  std::vector<std::vector<Weight>> m_movingWeights;
  Eigen::MatrixX3i m_triangles;
  Eigen::MatrixX2i m_edges;
  std::vector<std::pair<int, int>> m_triangleElement;
  /// B-spline to Bézier coefficients on one span of a uniform spline, degree p at index p:
  /// Bézier = m_bezier[p] · (the span's p + 1 B-spline coefficients).
  std::vector<Eigen::MatrixXd> m_bezier;
};

}  // namespace bsdeform
