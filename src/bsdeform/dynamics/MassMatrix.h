// SPDX-License-Identifier: MIT
#pragma once
/// @file MassMatrix.h
/// Not installed. The mass of a model's unknowns (the moving control points, order of
/// SplineSpace::movingToNet), built once per model and shared by every scheme that needs more
/// than the explicit step's fused kernel (SOFA's Mass beside its ForceField; G+Smo's mass
/// matrix beside gsThinShellAssembler's tangent):
///  - the paper's NODAL mass, m I, and its LUMPED mass, rho h1 h2 I (smaller next to FREE
///    sides): diagonal;
///  - the SHELL's \f$T^T W T\f$ for the lumped net masses W = rho t ∫ B_k J0 folded through T
///    (periodic copies, derived layers): diagonal unless some side has derived layers;
///  - the paper's mass next to derived layers (EdgeMass's \f$T^T W T\f$, which stays the
///    explicit kernel's fast path).
/// It is one scalar matrix shared by x, y and z. Pinned unknowns keep their rows in the matrix
/// (the energy sees their mass) and are left out of solve(), which gives the accelerations of the
/// others with the pinned ones at zero, \f$M_{ff}^{-1} r_f\f$.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <utility>
#include <vector>

#include "bsdeform/spline/SplineSpace.h"

namespace bsdeform {

class MassMatrix {
 public:
  /// A diagonal mass, one value per unknown (> 0). `pinned[f]` non-zero: unknown f is held.
  MassMatrix(Eigen::VectorXd diagonal, std::vector<char> pinned);
  /// A symmetric positive definite sparse mass (both triangles stored); factorised once without
  /// the pinned rows and columns (when not diagonal). @throws std::runtime_error if singular.
  MassMatrix(Eigen::SparseMatrix<double> matrix, std::vector<char> pinned);
  ~MassMatrix();
  MassMatrix(const MassMatrix&) = delete;
  MassMatrix& operator=(const MassMatrix&) = delete;

  /// \f$T^T W T\f$ for net masses W and the map T of SplineSpace::foldMap().
  static std::unique_ptr<MassMatrix> folded(const SplineSpace& space, const Eigen::VectorXd& netMass,
                                            std::vector<char> pinned);

  Eigen::Index size() const { return m_matrix.rows(); }
  /// Whether M is diagonal (apply and solve are then a scaling).
  bool isDiagonal() const { return m_diagonalOnly; }
  /// The matrix, both triangles (for a Newton tangent's shift, TangentMatrix::addScalarMatrix).
  const Eigen::SparseMatrix<double>& matrix() const { return m_matrix; }
  /// Its diagonal.
  const Eigen::VectorXd& diagonal() const { return m_diagonal; }
  /// M a (size() x 3).
  ControlNet apply(const ControlNet& a) const;
  /// a := M_ff^-1 a_f, pinned rows zero.
  void solve(ControlNet& a) const;
  /// ½ vᵀ M v summed over x, y and z.
  double kineticEnergy(const ControlNet& v) const;

 private:
  void factorise();

  Eigen::SparseMatrix<double> m_matrix;
  Eigen::VectorXd m_diagonal;
  std::vector<char> m_pinned;
  bool m_diagonalOnly = true;
  struct Factor;
  std::unique_ptr<Factor> m_factor;  ///< not diagonal: LDLᵀ of the free rows and columns
};

}  // namespace bsdeform
