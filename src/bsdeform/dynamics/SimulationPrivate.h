// SPDX-License-Identifier: MIT
#pragma once
/// @file SimulationPrivate.h
/// Not installed: what Simulation's own sources share (the static solver in SimulationShell.cpp
/// and the shell's implicit stepper in TimeStepper.cpp).

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>
#include <algorithm>
#include <vector>

#include "bsdeform/base/Parallel.h"
#include "bsdeform/dynamics/Simulation.h"

namespace bsdeform {

/// The Newton tangent's Cholesky factorisation (CHOLMOD), its symbolic analysis kept.
struct NewtonSolver {
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> llt;
  /// The pattern the symbolic analysis was made for (empty: none yet).
  std::vector<int> outer, inner;
  NewtonSolver() { llt.cholmod().print = 0; }  // an indefinite tangent is expected, not news
  /// Factorises K (the symbolic analysis again only when K's pattern is not the last one's: the
  /// elements' pattern stays, self-contact's couplings come and go); false if K is not positive
  /// definite.
  bool factor(const Eigen::SparseMatrix<double>& K) {
    const SerialOpenMp serial;  // CHOLMOD's fixed 4-thread regions cost more than they save here
    const int* o = K.outerIndexPtr();
    const int* i = K.innerIndexPtr();
    const size_t columns = size_t(K.outerSize()) + 1, nnz = size_t(K.nonZeros());
    if (outer.size() != columns || inner.size() != nnz || !std::equal(outer.begin(), outer.end(), o) ||
        !std::equal(inner.begin(), inner.end(), i)) {
      llt.analyzePattern(K);
      outer.assign(o, o + columns);
      inner.assign(i, i + nnz);
    }
    llt.factorize(K);
    return llt.info() == Eigen::Success;
  }
};

}  // namespace bsdeform
