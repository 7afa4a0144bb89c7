// SPDX-License-Identifier: MIT
#pragma once
// The implicit system's test cases, shared by ImplicitSystem_test.cpp and Multigrid_test.cpp:
// one per boundary kind (pins, lumped mass), K as a dense matrix, a simulation-like mass term.
#include <Eigen/Dense>
#include <algorithm>
#include <string>
#include <vector>

#include "bsdeform/spline/SplineSpace.h"
#include "bsdeform/energy/StiffnessStencil.h"

namespace bsdeform::test {

struct Case {
  std::string name;
  Boundaries sides;
  bool lumped;
  std::vector<Eigen::Vector2d> pins;
};

const Boundary C = Boundary::Clamped, F = Boundary::Free, P = Boundary::Periodic;

inline std::vector<Case> cases() {
  return {{"clamped", {C, C, C, C}, false, {}},
          {"curtain (three free sides), lumped", {F, F, F, C}, true, {}},
          {"all free, lumped", {F, F, F, F}, true, {}},
          {"tube (u periodic)", {P, P, C, C}, false, {}},
          {"torus, lumped", {P, P, P, P}, true, {}},
          {"free with pins", {F, F, C, F}, false, {{0.3, 0.6}, {0.9, 0.1}, {0.0, 0.5}}}};
}

// K as the dense matrix the system stands for: D + A_II/4 with pinned rows and columns reduced
// to D.
inline Eigen::MatrixXd denseK(const StiffnessStencil& st, const Eigen::VectorXd& D, const std::vector<Eigen::Index>& pinned) {
  Eigen::MatrixXd K = 0.25 * Eigen::MatrixXd(st.movingMatrix());
  for (Eigen::Index f : pinned) {
    K.row(f).setZero();
    K.col(f).setZero();
  }
  K.diagonal() += D;
  return K;
}

inline std::vector<Eigen::Index> pinnedMoving(const SplineSpace& s, const std::vector<Eigen::Vector2d>& pins) {
  std::vector<Eigen::Index> out;
  for (const Eigen::Vector2d& pin : pins) {
    const int su = s.basisU().span(pin.x()), sv = s.basisV().span(pin.y());
    for (int k1 = su - s.degreeU(); k1 <= su; ++k1)
      for (int k2 = sv - s.degreeV(); k2 <= sv; ++k2) {
        const Eigen::Index m = s.movingIndex(k1, k2);
        if (m >= 0 && std::find(out.begin(), out.end(), m) == out.end()) out.push_back(m);
      }
  }
  return out;
}

// A mass term like the simulation's: nodal (constant) or lumped (rho times the row sums, smaller
// at a free edge), over dt^2, plus damping.
inline Eigen::VectorXd massTerm(const SplineSpace& s, const StiffnessStencil& st, bool lumped, double dt) {
  Eigen::VectorXd D(s.numMoving());
  for (Eigen::Index f = 0; f < s.numMoving(); ++f) {
    const Eigen::Index r = s.movingToNet(f);
    const int i = int(r / s.netCols()), j = int(r % s.netCols());
    const double m = lumped ? st.gramU().rowSum(st.gramU().rowType(i)) * st.gramV().rowSum(st.gramV().rowType(j)) : 1.0;
    D[f] = m / (dt * dt) + 0.3 * m / (2 * dt);
  }
  return D;
}

inline double relativeError(const ControlNet& x, const Eigen::MatrixXd& ref) { return (x - ref).norm() / ref.norm(); }

}  // namespace bsdeform::test
