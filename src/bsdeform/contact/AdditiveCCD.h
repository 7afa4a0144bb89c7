// SPDX-License-Identifier: MIT
#pragma once
/// @file AdditiveCCD.h
/// Continuous collision detection of the primitive pairs of barrier contact: additive CCD
/// (Li, Kaufman, Jiang, "Codimensional Incremental Potential Contact", 2021, §4; as in C-IPC and
/// ipc-sim/ipc-toolkit's ccd/additive_ccd.cpp). Vertices move on straight lines over a step,
/// x(t) = x0 + t (x1 - x0), t in [0, 1].
///
/// The method: after the mean displacement of the pair's vertices is subtracted (a common
/// translation leaves distances unchanged), the distance d(t) of the pair can fall no faster than
/// l = (largest displacement of one primitive's vertices) + (largest of the other's), because the
/// closest point of a primitive is a convex combination of its vertices. So from a time t_k with
/// distance d_k the pair stays farther than ξ for Δt < (d_k - ξ) / l; additive CCD advances by
/// Δt = s (d_k - ξ) / l (s = conservativeRescaling) until the distance left above ξ would fall
/// below the gap g = (1 - s)(d_0 - ξ).
///
/// Guarantee (exact arithmetic; rounding is covered by the gaps), with d_0 the start distance:
/// - returned true with toi > 0: d(toi) - ξ ≥ (1 - s)(d_0 - ξ), and on [0, toi] the distance
///   stays at least ξ + (1 - s)²(d_0 - ξ) (every sub-step keeps a fraction 1 - s of the gap it
///   started from, and every sub-step after the first starts at least g above ξ);
/// - returned false (toi = tMax): the same bound holds on the whole of [0, tMax];
/// - toi = 0 and true when the pair starts within ξ (d_0 ≤ ξ) or so close to it
///   (d_0 - ξ ≤ 1e-10 (d_0 + ξ)) that the gap is lost in rounding.
/// It is conservative, not exact: toi can be earlier than the first time the distance reaches ξ
/// (by a fraction s of the gap at least, more when the pair slides past each other instead of
/// approaching; the tests measure how much on random pairs).
///
/// A pair whose distance hovers just above g for long takes many sub-steps; after
/// kAdditiveCCDMaxIterations the current, safe time is returned with true.

#include <Eigen/Core>

#include "bsdeform/contact/BroadPhase.h"

namespace bsdeform {

/// The number of sub-steps after which additive CCD gives up and returns its current time of
/// impact (safe, but possibly earlier than needed).
inline constexpr int kAdditiveCCDMaxIterations = 1000000;

/// C-IPC's rescaling s: each pair keeps 10 % of its gap above ξ at least.
inline constexpr double kAdditiveCCDRescaling = 0.9;

/// Point p against triangle (t0, t1, t2), from the positions at t = 0 (…0) to those at t = 1 (…1).
/// true and toi in [0, tMax]: the pair may come within ξ = offset at or after toi, and stays
/// farther than ξ on [0, toi] (see the file's guarantee); false and toi = tMax: it cannot come
/// within ξ before tMax. @pre offset ≥ 0, 0 < conservativeRescaling < 1, the triangle is not
/// degenerate over the step.
bool pointTriangleCCD(const Eigen::Vector3d& p0, const Eigen::Vector3d& t00, const Eigen::Vector3d& t10,
                      const Eigen::Vector3d& t20, const Eigen::Vector3d& p1, const Eigen::Vector3d& t01,
                      const Eigen::Vector3d& t11, const Eigen::Vector3d& t21, double offset, double tMax,
                      double& toi, double conservativeRescaling = kAdditiveCCDRescaling);

/// Segment (a0, a1) against segment (b0, b1), positions at t = 0 (a00, …) and t = 1 (a01, …); the
/// same contract as pointTriangleCCD. @pre neither segment is degenerate over the step.
bool edgeEdgeCCD(const Eigen::Vector3d& a00, const Eigen::Vector3d& a10, const Eigen::Vector3d& b00,
                 const Eigen::Vector3d& b10, const Eigen::Vector3d& a01, const Eigen::Vector3d& a11,
                 const Eigen::Vector3d& b01, const Eigen::Vector3d& b11, double offset, double tMax, double& toi,
                 double conservativeRescaling = kAdditiveCCDRescaling);

/// The largest fraction t ≤ 1 of the step from start to end over which no candidate pair of
/// candidatePairs(a, b, offset) comes within `offset`: the minimum of the pairs' additive CCD times
/// of impact, 1 when none. Positions start + τ (end - start), τ in [0, t],
/// then keep every vertex–triangle and edge–edge pair farther than `offset` (the file's
/// guarantee). Each pair is searched only up to the fraction found so far (tMax), which skips the
/// sub-steps of far pairs; a pair may then return "no impact before tMax" where with tMax = 1 it
/// would have stopped a little earlier, so the result can depend on the pairs' order by the
/// conservativeness of CCD (never past a safe time).
/// `conservativeRescaling` is the pairs' s: each keeps (1 - s) of its gap above ξ at least.
double collisionFreeFraction(const ContactMesh& a, const ContactMesh& b, double offset,
                             double conservativeRescaling = kAdditiveCCDRescaling);
/// A mesh against itself (pairs sharing a vertex left out).
double collisionFreeFraction(const ContactMesh& a, double offset, double conservativeRescaling = kAdditiveCCDRescaling);
/// The same over the pairs `candidates` (what candidatePairs() would give, found beforehand).
double collisionFreeFraction(const ContactMesh& a, const ContactMesh& b, const ContactCandidates& candidates,
                             double offset, double conservativeRescaling = kAdditiveCCDRescaling);
double collisionFreeFraction(const ContactMesh& a, const ContactCandidates& candidates, double offset,
                             double conservativeRescaling = kAdditiveCCDRescaling);

}  // namespace bsdeform
