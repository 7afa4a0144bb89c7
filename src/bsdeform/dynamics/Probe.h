// SPDX-License-Identifier: MIT
#pragma once
/// @file Probe.h
/// A probe: the surface point at a parameter point and its displacement from rest
/// (bsdeform-run --probe, Python Surface.probe()).

#include <Eigen/Core>

#include "bsdeform/spline/SplineSpace.h"

namespace bsdeform {

class Simulation;

struct ProbeSample {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();         ///< S(u, v) of the net
  Eigen::Vector3d displacement = Eigen::Vector3d::Zero();  ///< S(u, v) - S_rest(u, v)
};

/// The probe at (u, v) of `net` against `rest` (both full nets of `space`, eq. 9).
/// @throws std::invalid_argument naming u or v when it is not in [0, 1]
ProbeSample probe(const SplineSpace& space, const ControlNet& net, const ControlNet& rest, double u, double v);
/// The same for `net` (default: the current state) of `sim` against its rest net.
ProbeSample probe(const Simulation& sim, double u, double v);
ProbeSample probe(const Simulation& sim, const ControlNet& net, double u, double v);

}  // namespace bsdeform
