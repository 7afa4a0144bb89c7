// SPDX-License-Identifier: MIT
#pragma once
/// @file RestShape.h
/// Ready-made rest nets for closed and second-order shapes (the paper's future work, §8:
/// "cones, ellipsoids, spheres"): the control net of a uniform B-spline surface of the model's
/// space that approximates the exact shape, with the boundary conditions the shape needs.
///
/// Parametrisations (u around, v along; all centred at the origin, axis z):
///  - PLANE      S = (u, v, 0): the Greville net, exact (linear precision);
///  - CYLINDER   (R cos 2pi u, R sin 2pi u, H (v - 1/2)), u PERIODIC;
///  - CONE       (R (1-v) cos 2pi u, R (1-v) sin 2pi u, H (v - 1/2)), u PERIODIC, apex v = 1
///               CLAMPED (its n layers collapsed onto the apex);
///  - SPHERE     R (sin pi v cos 2pi u, sin pi v sin 2pi u, -cos pi v), u PERIODIC, both v
///               sides CLAMPED with their layers collapsed onto the poles;
///  - ELLIPSOID  the sphere of radius 1 scaled by the radii (a, b, c);
///  - TORUS      ((R + r cos 2pi v) cos 2pi u, (R + r cos 2pi v) sin 2pi u, r sin 2pi v), both
///               directions PERIODIC.
/// A periodic circle is the periodic B-spline whose control points lie on a regular polygon
/// scaled so that the curve passes through the circle at every Greville parameter; a linear
/// profile uses the Greville abscissae (exact); the sphere's half-circle profile is the least-
/// squares fit of the inner layers with the pole layers held.

#include "bsdeform/spline/SplineSpace.h"

namespace bsdeform {

enum class ShapeKind { Plane, Cylinder, Cone, Sphere, Ellipsoid, Torus };

/// "PLANE", "CYLINDER", "CONE", "SPHERE", "ELLIPSOID" or "TORUS".
const char* shapeName(ShapeKind kind);

/// Sizes of the shapes (the ones a shape does not use are ignored).
struct ShapeSize {
  double radius = 0.5;                                   ///< R: cylinder, cone base, sphere, torus
  double height = 1.0;                                   ///< H: cylinder, cone
  double minorRadius = 0.2;                              ///< r: torus tube
  Eigen::Vector3d radii = Eigen::Vector3d(0.6, 0.45, 0.35);  ///< (a, b, c): ellipsoid
};

/// Boundaries the shape imposes on top of `requested`: the directions it closes become
/// PERIODIC, the sides with a pole or apex CLAMPED; the others keep their requested condition.
Boundaries shapeBoundaries(ShapeKind kind, const Boundaries& requested);

/// The exact point of the shape at (u, v).
Eigen::Vector3d exactShapePoint(ShapeKind kind, const ShapeSize& size, double u, double v);

/// The rest net of `kind` in `space`, whose boundaries must be shapeBoundaries(kind, ...).
/// @throws std::invalid_argument for a size that is not finite and > 0 (names it), or a
///         space whose boundaries do not match the shape
ControlNet shapeRestNet(ShapeKind kind, const ShapeSize& size, const SplineSpace& space);

/// Distance from point p to the shape: exact for the plane, cylinder (lateral surface),
/// cone (lateral surface), sphere and torus; for the ellipsoid the first-order estimate
/// |g| / |grad g| of g = (x/a)^2 + (y/b)^2 + (z/c)^2 - 1 (exact to second order in the distance).
double shapeDistance(ShapeKind kind, const ShapeSize& size, const Eigen::Vector3d& p);

/// Largest shapeDistance() of S(u, v) of `net` over `samples` x `samples` parameter points:
/// the geometric error of the generated surface.
double shapeGeometricError(ShapeKind kind, const ShapeSize& size, const SplineSpace& space, const ControlNet& net,
                           int samples = 101);

}  // namespace bsdeform
