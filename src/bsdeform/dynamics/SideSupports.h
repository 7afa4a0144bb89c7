// SPDX-License-Identifier: MIT
#pragma once
/// @file SideSupports.h
/// Supports that hold chosen world components of a side (issue 36; docs/math.md §16, "Supports
/// per component"), exact, by elimination as the SIMPLY_SUPPORTED sides are (no penalty):
///  - Hinge (`SIMPLY_SUPPORTED` with `holdUMin (X | Z)`, a rigid diaphragm): each held
///    component c of the edge curve stays at rest. The edge curve is Σ_a N_a(edge) P_a over the
///    n outer layers, so coordinate c of the outermost layer is derived from coordinate c of the
///    n - 1 next ones with SIMPLY_SUPPORTED's weights Z (EdgeLayers): P₀c = R₀c + Σ Z_s (P_sc − R_sc);
///    the other components move freely (degree 1: coordinate c of the outer layer is held).
///  - Clamp (`BUILT_IN` with `holdUMin ...`): the same for the edge curve and its cross
///    derivative, with BUILT_IN's layers (EdgeLayers: the two outer layers' coordinate c derived
///    from the n - 2 next ones; degree 2 and 1 hold their layers' coordinate c).
///  - Symmetry (`SYMMETRY`): the rest surface is mirror-symmetric about a coordinate plane
///    x_a = x0 through the edge, and so is the solution. On a uniform knot grid the B-spline of
///    net layer i mirrors that of layer n - 1 - i about the edge, so the outer layers
///    i < (n - 1)/2 are the mirror images of their partners (coordinate a: 2 x0 − P, the others
///    equal; in rest-relative form with weights -1 and +1), and for odd n the middle layer
///    i = (n - 1)/2 lies on the plane (coordinate a held). The surface then meets the plane at a
///    right angle and its mirror image continues it smoothly, exactly.
/// The side is FREE in the spline space (its layers are unknowns); the constraints act on the
/// unknowns' coordinates (3 f + c), u sides first, then v sides, a corner following both (as
/// the space's derived layers do). Columns (rows) where a derived point or its partners are not
/// unknowns (held or derived by a neighbouring side of the space) are left to that side.

#include <Eigen/SparseCore>
#include <array>
#include <string>
#include <vector>

#include "bsdeform/spline/SplineSpace.h"

namespace bsdeform {

/// What one side holds beyond what the spline space's boundary does.
struct SideSupport {
  enum class Kind {
    None,      ///< nothing here (the space's boundary kind alone)
    Hinge,     ///< the edge curve's `components` held (a diaphragm, a roller)
    Clamp,     ///< the edge curve's and the cross derivative's `components` held (BUILT_IN's)
    Symmetry,  ///< a symmetry plane through the edge
  };
  Kind kind = Kind::None;
  unsigned components = 7;  ///< Hinge, Clamp: bit 0 x, bit 1 y, bit 2 z
};

/// The four sides in the order uMin, uMax, vMin, vMax.
using SideSupports = std::array<SideSupport, 4>;

class ComponentConstraints {
 public:
  /// Builds the constraints of `supports` on `space` (each side with a support must be FREE in
  /// the space) for the rest net `rest` (full net).
  /// @throws std::invalid_argument naming the side: a support on a side that is not FREE in the
  ///         space, a Hinge holding no component, a SYMMETRY side whose rest net is not
  ///         mirror-symmetric about a coordinate plane through its edge
  ComponentConstraints(const SplineSpace& space, const ControlNet& rest, const SideSupports& supports);

  bool empty() const { return m_derived.empty(); }
  /// Whether coordinate dof = 3 f + c of the unknowns is not an unknown (derived or held here).
  bool constrained(Eigen::Index dof) const { return m_isDerived[size_t(dof)] != 0; }
  /// Sets the constrained coordinates of the unknowns x (numMoving x 3) from the others.
  void complete(ControlNet& x) const;
  /// g ← Tᵀ g: a gradient (or load) on the unknowns folded onto the free coordinates, the
  /// constrained ones zero.
  void fold(ControlNet& g) const;
  /// Tᵀ K T for the unknowns' tangent K (lower triangle, as TangentMatrix gives it, with the
  /// constrained coordinates' rows still in it): the full symmetric matrix, where `held` (per
  /// dof, the constrained ones among them) with a unit diagonal and nothing else.
  Eigen::SparseMatrix<double> foldTangent(const Eigen::SparseMatrix<double>& lowerK,
                                          const std::vector<char>& held) const;
  /// The plane of a SYMMETRY side (axis 0..2 and its coordinate), for messages and tests.
  struct Plane {
    int axis = -1;
    double value = 0.0;
  };
  const std::array<Plane, 4>& planes() const { return m_planes; }

 private:
  Eigen::Index m_n = 0;             ///< 3 numMoving
  ControlNet m_restUnknowns;
  std::vector<char> m_isDerived;    ///< per dof
  std::vector<Eigen::Index> m_derived;  ///< the constrained dofs
  Eigen::SparseMatrix<double> m_T;  ///< unknowns = T free + offset (derived rows: their weights)
  std::array<Plane, 4> m_planes;
};

/// "umin", "umax", "vmin", "vmax" (side 0..3), for messages.
const char* sideName(int side);

/// The tangent K over the free coordinates: K itself without supports per component
/// (`components` null), else components->foldTangent(K, held) made in `folded`.
const Eigen::SparseMatrix<double>& unknownsTangent(const ComponentConstraints* components,
                                                   const Eigen::SparseMatrix<double>& K, const std::vector<char>& held,
                                                   Eigen::SparseMatrix<double>& folded);

}  // namespace bsdeform
