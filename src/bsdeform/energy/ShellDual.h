// SPDX-License-Identifier: MIT
#pragma once
/// @file ShellDual.h
/// Dual numbers a + b ε (ε² = 0) for the shell's kernels (Shell.cpp, ShellKinematics.h,
/// ShellLaws.h): a kernel written once for `double` and `Dual` and evaluated at y + εẏ returns
/// its exact directional derivative in the ε part. Private to the core (not installed).

#include <cmath>

namespace bsdeform::shell {

struct Dual {
  double a = 0.0, b = 0.0;
  Dual() = default;
  Dual(double x) : a(x) {}  // NOLINT: constants promote
  Dual(double x, double dx) : a(x), b(dx) {}
};
inline Dual operator+(Dual x, Dual y) { return {x.a + y.a, x.b + y.b}; }
inline Dual operator-(Dual x, Dual y) { return {x.a - y.a, x.b - y.b}; }
inline Dual operator-(Dual x) { return {-x.a, -x.b}; }
inline Dual operator*(Dual x, Dual y) { return {x.a * y.a, x.a * y.b + x.b * y.a}; }
inline Dual operator/(Dual x, Dual y) { return {x.a / y.a, (x.b * y.a - x.a * y.b) / (y.a * y.a)}; }
inline Dual& operator+=(Dual& x, Dual y) { return x = x + y; }
inline Dual sqrt(Dual x) {
  const double s = std::sqrt(x.a);
  return {s, x.b / (2.0 * s)};
}
inline Dual log1p(Dual x) { return {std::log1p(x.a), x.b / (1.0 + x.a)}; }
inline Dual expm1(Dual x) { return {std::expm1(x.a), x.b * std::exp(x.a)}; }
inline double value(double x) { return x; }
inline double value(Dual x) { return x.a; }
using std::expm1;
using std::log1p;
using std::sqrt;

template <typename T>
inline T dot3(const T* x, const T* y) {
  return x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
}
template <typename T>
inline void cross3(const T* x, const T* y, T* out) {
  out[0] = x[1] * y[2] - x[2] * y[1];
  out[1] = x[2] * y[0] - x[0] * y[2];
  out[2] = x[0] * y[1] - x[1] * y[0];
}

}  // namespace bsdeform::shell
