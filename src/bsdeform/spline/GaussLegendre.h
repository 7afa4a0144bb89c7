// SPDX-License-Identifier: MIT
#pragma once
/// @file GaussLegendre.h
/// Gauss–Legendre rules on [0,1]; q points integrate polynomials of degree 2q-1 exactly.

#include <vector>

namespace bsdeform {

struct QuadratureRule {
  std::vector<double> nodes;    ///< in (0,1), increasing
  std::vector<double> weights;  ///< sum to 1
};

/// Gauss–Legendre rule with `points` nodes (1..64) on [0,1], nodes by Newton's method on P_q.
/// @throws std::invalid_argument outside 1..64
const QuadratureRule& gaussLegendre(int points);

}  // namespace bsdeform
