// SPDX-License-Identifier: MIT
#pragma once
/// @file SimulationPrivate.h
/// Not installed: what Simulation's own sources share (the static solver in SimulationShell.cpp
/// and the shell's implicit stepper in TimeStepper.cpp).

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>

#include "bsdeform/base/Parallel.h"
#include "bsdeform/dynamics/Simulation.h"

namespace bsdeform {

/// The Newton tangent's Cholesky factorisation (CHOLMOD), its symbolic analysis kept.
struct NewtonSolver {
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> llt;
  bool analysed = false;
  NewtonSolver() { llt.cholmod().print = 0; }  // an indefinite tangent is expected, not news
  /// Factorises K (symbolic analysis once: the pattern never changes); false if K is not
  /// positive definite.
  bool factor(const Eigen::SparseMatrix<double>& K) {
    const SerialOpenMp serial;  // CHOLMOD's fixed 4-thread regions cost more than they save here
    if (!analysed) {
      llt.analyzePattern(K);
      analysed = true;
    }
    llt.factorize(K);
    return llt.info() == Eigen::Success;
  }
};

}  // namespace bsdeform
