// SPDX-License-Identifier: MIT
#pragma once
// The comparison of an assembled Newton tangent with an energy's Hessian product, shared by the
// SHELL and the paper's tangent tests.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "bsdeform/dynamics/TangentMatrix.h"

namespace bsdeform::test {

/// The largest |(K d) - Hd| over the unknowns' coordinates: K is indexed 3 f + c, the row-major
/// layout of a numMoving x 3 net, so d is its vector as it lies in memory.
inline double tangentProductError(const TangentMatrix& K, const ControlNet& d, const ControlNet& Hd) {
  const Eigen::VectorXd Kd = K.multiply(Eigen::Map<const Eigen::VectorXd>(d.data(), d.size()));
  double err = 0.0;
  for (Eigen::Index f = 0; f < d.rows(); ++f)
    for (int c = 0; c < 3; ++c) err = std::max(err, std::abs(Kd[3 * f + c] - Hd(f, c)));
  return err;
}

}  // namespace bsdeform::test
