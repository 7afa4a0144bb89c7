// SPDX-License-Identifier: MIT
#pragma once
/// @file FixedDifferences.h
/// Central differences of functions of a fixed number N of coordinates (the 6, 9 and 12 of the
/// contact distances and barriers), and the relative error the contact tests compare with.
#include <Eigen/Core>
#include <algorithm>
#include <functional>

namespace bsdeform::test {

template <int N>
using Vec = Eigen::Matrix<double, N, 1>;
template <int N>
using Mat = Eigen::Matrix<double, N, N>;

/// The i-th point of a flat coordinate vector.
template <int N>
Eigen::Vector3d pointOf(const Vec<N>& x, int i) {
  return x.template segment<3>(3 * i);
}

/// ∂f/∂x_i ≈ (f(x + h e_i) - f(x - h e_i)) / 2h.
template <int N>
Vec<N> differenceGradient(const std::function<double(const Vec<N>&)>& f, const Vec<N>& x, double h) {
  Vec<N> g;
  for (int i = 0; i < N; ++i) {
    Vec<N> xp = x, xm = x;
    xp[i] += h;
    xm[i] -= h;
    g[i] = (f(xp) - f(xm)) / (2.0 * h);
  }
  return g;
}

/// Column i: (g(x + h e_i) - g(x - h e_i)) / 2h.
template <int N>
Mat<N> differenceJacobian(const std::function<Vec<N>(const Vec<N>&)>& g, const Vec<N>& x, double h) {
  Mat<N> jac;
  for (int i = 0; i < N; ++i) {
    Vec<N> xp = x, xm = x;
    xp[i] += h;
    xm[i] -= h;
    jac.col(i) = (g(xp) - g(xm)) / (2.0 * h);
  }
  return jac;
}

/// ‖a - b‖ / max(‖b‖, floor): relative, except for a reference smaller than `floor`, where the
/// absolute error is what matters.
template <class A, class B>
double relativeError(const A& a, const B& b, double floor) {
  return (a - b).norm() / std::max(b.norm(), floor);
}

}  // namespace bsdeform::test
