// SPDX-License-Identifier: MIT
#pragma once
/// @file MultigridTransfer.h
/// The multigrid transfers (Multigrid.h): prolongation P by dyadic knot insertion, a Kronecker
/// product of 1-D subdivision matrices; restriction \f$P^T\f$; and the Galerkin product
/// \f$P^T B P\f$ of a level's 1-D matrices. A coarse B-spline of degree n is
/// \f$2^{-n} \sum_{k=0}^{n+1} \binom{n+1}{k}\f$ times the fine ones 2j .. 2j+n+1.
/// Private to the core (Multigrid.cpp and the tests): not installed.

#include <utility>
#include <vector>

#include "bsdeform/dynamics/MultigridOperator.h"

namespace bsdeform::multigrid {

/// 1-D transfer between a fine and a coarse index set: coarse function j is the sum of
/// w * fine function f over children[j]; parents[f] lists the same pairs by fine index.
/// The same as a filter: coarse function i sits at fine position stride i + first and its
/// children are the fine functions at that position + k with weight taps[k], dropped outside
/// [0, fineSize) or, when periodic, wrapped.
struct Transfer1D {
  std::vector<std::vector<std::pair<int, double>>> children, parents;
  std::vector<double> taps;
  int stride = 1, first = 0, fineSize = 0;
  bool periodic = false;
  int coarseSize() const { return int(children.size()); }
};

/// Row buffers of the transfers.
struct TransferScratch {
  std::vector<double> row, pad, filtered;
};

/// The identity on n points (a direction that does not coarsen while the other does).
Transfer1D identityTransfer(int n);

/// Dyadic knot insertion for uniform B-splines of degree n on the fine index set of `dir`.
/// Returns false (and leaves `t` alone) when the direction is too small to coarsen.
bool subdivisionTransfer(const MultigridDirection& dir, int degree, Transfer1D& t);

/// P^T B P for the transfer P.
BandMatrix galerkin(const BandMatrix& B, const Transfer1D& t);

/// out (coarse) = (Pu (x) Pv)^T in (fine), one fine row at a time: the row restricted in v is
/// added to each of its coarse parent rows, so no restricted copy of the whole level is
/// written and read back.
void restrictTo(const ControlNet& in, const Transfer1D& tu, const Transfer1D& tv, TransferScratch& scratch,
                ControlNet& out);

/// out (fine) += (Pu (x) Pv) in (coarse), one fine row at a time.
void prolongAdd(const ControlNet& in, const Transfer1D& tu, const Transfer1D& tv, TransferScratch& scratch,
                ControlNet& out);

}  // namespace bsdeform::multigrid
