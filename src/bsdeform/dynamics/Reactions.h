// SPDX-License-Identifier: MIT
#pragma once
/// @file Reactions.h
/// What the supports of an equilibrium carry (docs/math.md, "Probes and reactions"): the force
/// resultant of every held side and pin, and the sum of the applied loads, which they balance.
///
/// Per control point k of the FULL net (held, derived and periodic-copy points included, nothing
/// folded) \f$f_k = \partial W/\partial P_k - L_k\f$: W the elastic energy as a function of
/// every point of the full net, L the loads on the full net (\f$L_k = \int f B_k\f$ over every
/// B-spline k). A supported side's *band* is its outer layers: the n layers whose B-splines do
/// not vanish on the edge (n the degree across it) and any further layer the side holds (BUILT_IN
/// of degree 1 also holds layer k = 0). The reaction of a side is \f$\sum f_k\f$ over its band,
/// component by component: component c of \f$f_k\f$ goes to the sides whose band holds k and
/// which hold c (every component for CLAMPED, SIMPLY_SUPPORTED and BUILT_IN, the chosen ones
/// for a support per component, the plane's normal for SYMMETRY), split equally among them at a
/// corner; a point no side holds in c adds it to `elsewhere`. Pinned points are left out of the
/// bands in the components the pins hold (ModelParameters::pinComponents) and make up their pin's
/// reaction there (a point two pins hold, split equally).
///
/// Sign: a reaction is the force the support exerts ON the surface. At a held point the elastic
/// force \f$-\partial W/\partial P_k\f$, the load \f$L_k\f$ and the support's force \f$R_k\f$
/// balance, so \f$R_k = f_k\f$, and a plate under gravity (applied z < 0) has reactions of
/// z > 0.
///
/// Why they balance: W does not change when the whole net is translated (its terms measure
/// derivatives of S, and the B-splines sum to 1 on [0,1]), so \f$\sum_k \partial W/\partial
/// P_k = 0\f$ and \f$\sum_k f_k = -\sum_k L_k\f$. At equilibrium the residual of every unknown
/// vanishes; an unknown outside the bands and pins gathers only its own f and its periodic
/// copies' (derived points and their sources lie in the bands), so those points sum to zero and
/// \f$\sum \text{reactions} + \text{applied} = 0\f$ to the solver's tolerance. What the points
/// outside bands and pins do sum to is reported too (`elsewhere`): the equilibrium's residual
/// there, plus the reactions of ModelParameters::heldCoordinates, which are not supports of the
/// file format.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "bsdeform/dynamics/Simulation.h"

namespace bsdeform {

/// Whether a side of the spline space holds anything, and so has a reaction: CLAMPED,
/// SIMPLY_SUPPORTED, BUILT_IN (a FREE side with a support per component or SYMMETRY has one too).
bool sideHoldsSomething(Boundary side);

/// The reactions of an equilibrium (see the file comment for the definition and the sign).
struct SupportReactions {
  struct Side {
    std::string name;  ///< "umin", "umax", "vmin" or "vmax"
    Eigen::Vector3d force = Eigen::Vector3d::Zero();
  };
  /// Every side that holds something (sideHoldsSomething(), or a support per component or
  /// SYMMETRY in ModelParameters::sideSupports), in the order umin, umax, vmin, vmax.
  std::vector<Side> sides;
  /// One per ModelParameters::pins entry, in that order (zero for a pin whose points are all
  /// held by a side: its share is the side's).
  std::vector<Eigen::Vector3d> pins;
  /// Sum of the applied loads, \f$\sum_k L_k\f$ (the load factor included).
  Eigen::Vector3d applied = Eigen::Vector3d::Zero();
  /// Sum of f_k over the points neither in a band nor pinned (see the file comment).
  Eigen::Vector3d elsewhere = Eigen::Vector3d::Zero();
  /// applied + the sides' and pins' reactions: zero at an equilibrium, to the solver's tolerance.
  Eigen::Vector3d imbalance() const;
};

/// The reactions of `net` (a full net, derived layers and periodic copies in sync: an
/// equilibrium of Simulation::solveStatic(), e.g. one of its increments) under the loads of
/// `sim`'s forces evaluated on `net` at rest (zero velocity) at `time`, times `loadFactor`: what
/// solveStatic() balanced for that increment.
/// @throws std::invalid_argument for a net of the wrong size
SupportReactions supportReactions(const Simulation& sim, const ControlNet& net, double loadFactor = 1.0,
                                  double time = 0.0);

/// \f$\partial W/\partial P_k\f$ for every point k of the full net (netSize x 3): SHELL,
/// ShellEnergy::gradient(); the paper's model, \f$A (P - P_{rest})\f$ (Rest reference) or
/// \f$A P\f$ (Absolute) with A the energy's operator over [0,1]^2 on every B-spline of the full
/// net. Folded onto the unknowns it is Simulation::energy().gradient() (tested).
ControlNet fullNetEnergyGradient(const Simulation& sim, const ControlNet& net);

/// The loads of `sim`'s forces on every point of the full net (netSize x 3) for `net` at rest
/// (zero velocity) at `time`; folded onto the unknowns they are Simulation::loadVector() (tested).
ControlNet fullNetLoad(const Simulation& sim, const ControlNet& net, double time = 0.0);

}  // namespace bsdeform
