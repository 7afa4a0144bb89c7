// SPDX-License-Identifier: MIT
#pragma once
/// @file Diagnostics.h
/// What a run records per history row (Simulation::diagnostics()), in one pass over the nets:
/// the paper's deformation norm (eq. 15), the kinetic energy and the five terms of the strain
/// energy, with no stencil built and no net allocated per call.
///
/// The strain energy of the displacement D = P - P_rest is a sum of five terms
/// \f[ E = \tfrac12 \sum_{(p,q)} c_{pq}\, D^T (G_u^p \otimes G_v^q) D
///       = \tfrac12 \sum_{(p,q)} c_{pq} \sum_{a,b} Z_p(a,b) \cdot Y_q(a,b), \quad
///   Z_p = (G_u^p \otimes I) D,\; Y_q = (I \otimes G_v^q) D \f]
/// (c = w10, w01, 2 w11, w20, w02 for (p,q) = (1,0), (0,1), (1,1), (2,0), (0,2); sums over the
/// moving points, both Gram matrices symmetric on them). Per row of the net the three u
/// combinations Z_p and the three v combinations Y_q are formed point by point from the
/// neighbours (folded, as the explicit kernel does), then the five products summed: about 60
/// flops per coordinate and moving point (as much arithmetic as one explicit sub-step), no
/// stencil built, no net allocated.
///
/// Rounding: the bending terms of a smooth state are small differences of large products.
/// Combining the neighbours point by point before any sum keeps them within 2e-13 of the same
/// sum in long double at 96^2 (tests/core/Diagnostics_test.cpp), closer than the per-term
/// functions (up to 1.4e-12: they round the combined coefficients w G_u G_v first). Summing
/// products of whole rows first and combining the sums after (half the arithmetic) lost 2e-12
/// there, and more on larger nets.
///
/// Threads: the rows are summed in blocks of 32, each block on its own (on kernelThreads(),
/// bsdeform/base/Parallel.h, from explicitParallelMinPoints() moving points on), and the block sums
/// added in block order, so the values are the same bits for any thread count. They differ from a
/// single running sum over all rows in the last bits on nets of more than 32 moving rows
/// (docs/benchmarks.md, "Why the code is as it is").

#include <vector>

#include "bsdeform/energy/StiffnessStencil.h"

namespace bsdeform {

/// Strain energy of the displacement from the rest net, total and per weight term.
struct StrainEnergy {
  double total = 0.0;
  double w10 = 0.0, w01 = 0.0, w11 = 0.0, w20 = 0.0, w02 = 0.0;
};

/// One row of a run's history.
struct Diagnostics {
  double norm = 0.0;     ///< eq. 15: ||P_I - P0_I|| over the moving points
  double kinetic = 0.0;  ///< 1/2 v^T M v, v = (P(t) - P(t - dt_sub)) / dt_sub
  StrainEnergy strain;   ///< 1/2 D^T A_II D per weight term (SHELL: total only)
  double membrane = 0.0;  ///< SHELL: membrane part of the strain energy (0 for the paper's model)
  double bending = 0.0;   ///< SHELL: bending part
};

/// Sums over the moving points of a model, computed in one pass over its nets.
struct DiagnosticSums {
  /// \f$D^T (G_u^p \otimes G_v^q) D\f$ for (p,q) = (1,0), (0,1), (1,1), (2,0), (0,2), unweighted
  double terms[5] = {0.0, 0.0, 0.0, 0.0, 0.0};
  double displacement = 0.0;  ///< sum |D_m|^2
  double velocity = 0.0;      ///< sum mass_m |current_m - previous_m|^2
};

/// diagnosticSums() in blocks of 32 rows that may run on any thread and in any order (each
/// writes its own partial sums), added in block order by sums(): the same bits as
/// diagnosticSums(). Keeps pointers to everything it is given (the nets' storage, the space,
/// the stencil's Gram rows, the masses): they must stay unchanged and alive until the last
/// block has run (DiagnosticsBeside runs the blocks beside the steps, on copies
/// of the current and previous nets).
class DiagnosticPass {
 public:
  /// Arguments as diagnosticSums().
  DiagnosticPass(const SplineSpace& space, const StiffnessStencil& stencil, const ControlNet& current,
                 const ControlNet& rest, const ControlNet& previous, const double* mass);
  int blocks() const;
  /// Block b in [0, blocks()); distinct blocks may run at the same time, on any thread.
  void computeBlock(int b);
  /// The sums, once every block has run.
  DiagnosticSums sums() const;

 private:
  struct BandColumn {
    int j;
    int neighbour[2 * kMaxDegree + 1];  // net column of j + e, or -1
    double g[3][2 * kMaxDegree + 1];    // G_v^q(j, j + e)
  };
  DiagnosticSums blockSums(int rowBegin, int rowEnd) const;

  const SplineSpace* m_space;
  const GramRows1D* m_gu;
  const double *m_current, *m_rest, *m_previous, *m_mass;
  int m_jb = 0, m_je = 0;  ///< interior columns [jb, je): Toeplitz rows of G_v, no periodic wrap
  std::vector<BandColumn> m_bandColumns;  ///< the other moving columns
  double m_gvInterior[3][2 * kMaxDegree + 1] = {}, m_guInterior[3][2 * kMaxDegree + 1] = {};
  struct alignas(64) BlockSums {  // a cache line of its own: blocks on two threads
    DiagnosticSums sums;
  };
  std::vector<BlockSums> m_partial;  ///< per block
};

/// The sums for D = current - rest (full nets, periodic copies in sync, D zero at held points).
/// @param mass per moving point (order of SplineSpace::movingToNet), or null for 1 everywhere
DiagnosticSums diagnosticSums(const SplineSpace& space, const StiffnessStencil& stencil, const ControlNet& current,
                              const ControlNet& rest, const ControlNet& previous, const double* mass);

/// A history row from its sums. `massScale`: the mass per point when uniform (the sums then
/// leave it out), else 1; `dt` the sub-step of the velocity.
Diagnostics diagnosticsFromSums(const DiagnosticSums& sums, const Weights& w, double massScale, double dt);

}  // namespace bsdeform
