// SPDX-License-Identifier: MIT
#pragma once
/// @file LoadQuadrature.h
/// The pieces every force integrated over the surface is built from (DistributedForce,
/// CollisionForce): Gauss points per knot span, surface samples from precomputed 1-D bases, and
/// the scatter of a weighted density into the load of the moving control points.

#include <Eigen/Core>
#include <vector>

#include "bsdeform/spline/BSpline.h"
#include "bsdeform/forces/Force.h"
#include "bsdeform/spline/SplineSpace.h"

namespace bsdeform {

/// One Gauss point of a 1-D quadrature: parameter, weight, and the knot span it lies in.
struct Node1D {
  double x, w;
  int span;
};

/// Gauss points (`points` per span) of [lo, hi] split at the knots of `basis`, span by span in
/// increasing order (the points of one span are contiguous).
std::vector<Node1D> splitQuadrature(const BSplineBasis1D& basis, double lo, double hi, int points);

/// Surface quantities at (u, v) from precomputed 1-D bases (values, and first derivatives when
/// `dependence` asks for the normal); only what `dependence` asks for is filled in.
SurfaceSample sampleFromBases(const LoadContext& ctx, const LocalBasis& bu, const LocalBasis& bv, double u, double v,
                              unsigned dependence);

/// Calls fn(i, j, B_k(u, v)) for every B-spline k non-zero at (u, v), given the 1-D bases, with
/// (i, j) the net layers of the moving point it loads (a periodic copy loads the point it
/// repeats, a derived point the sources it follows, with its weights: SplineSpace::foldU());
/// held points are skipped. One point may come more than once.
template <typename Fn>
inline void forEachMovingBasis(const SplineSpace& s, const LocalBasis& bu, const LocalBasis& bv, Fn&& fn) {
  for (int a = 0; a < bu.count; ++a) {
    const std::vector<LayerWeight>& fu = s.foldU(bu.first + a + s.degreeU());
    for (const LayerWeight& wu : fu)
      for (int b = 0; b < bv.count; ++b)
        for (const LayerWeight& wv : s.foldV(bv.first + b + s.degreeV()))
          fn(wu.layer, wv.layer, wu.weight * wv.weight * bu.d[0][a] * bv.d[0][b]);
  }
}

/// Adds w * f * B_k(u, v) to the load of the moving point of every B-spline k non-zero at (u, v).
inline void scatter(const SplineSpace& s, const LocalBasis& bu, const LocalBasis& bv, const Eigen::Vector3d& wf,
                    ControlNet& load) {
  const int firstU = s.movingU().first, firstV = s.movingV().first, width = s.movingV().count;
  forEachMovingBasis(s, bu, bv, [&](int i, int j, double B) {
    load.row(Eigen::Index(i - firstU) * width + (j - firstV)) += B * wf.transpose();
  });
}


}  // namespace bsdeform
