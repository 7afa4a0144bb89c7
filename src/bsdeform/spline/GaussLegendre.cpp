// SPDX-License-Identifier: MIT
#include "bsdeform/spline/GaussLegendre.h"

#include <array>
#include <cmath>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>

namespace bsdeform {

namespace {
constexpr int kMaxPoints = 64;

QuadratureRule computeRule(int q) {
  QuadratureRule rule;
  rule.nodes.resize(q);
  rule.weights.resize(q);
  const double pi = 3.14159265358979323846;
  for (int i = 0; i < (q + 1) / 2; ++i) {
    // Chebyshev-like initial guess for the i-th root of P_q on [-1,1], then Newton.
    double x = std::cos(pi * (i + 0.75) / (q + 0.5));
    double dp = 1.0;
    for (int iter = 0; iter < 100; ++iter) {
      double p0 = 1.0, p1 = x;
      for (int k = 2; k <= q; ++k) {
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = q * (x * p1 - p0) / (x * x - 1.0);
      const double dx = p1 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    // recompute derivative at the converged root
    double p0 = 1.0, p1 = x;
    for (int k = 2; k <= q; ++k) {
      const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
      p0 = p1;
      p1 = p2;
    }
    dp = q * (x * p1 - p0) / (x * x - 1.0);
    const double w = 2.0 / ((1.0 - x * x) * dp * dp);
    // map [-1,1] -> [0,1]
    rule.nodes[i] = 0.5 * (1.0 - x);
    rule.nodes[q - 1 - i] = 0.5 * (1.0 + x);
    rule.weights[i] = 0.5 * w;
    rule.weights[q - 1 - i] = 0.5 * w;
  }
  if (q % 2 == 1) rule.nodes[q / 2] = 0.5;
  return rule;
}
}  // namespace

const QuadratureRule& gaussLegendre(int points) {
  if (points < 1 || points > kMaxPoints)
    throw std::invalid_argument("Gauss-Legendre points must be between 1 and 64, got " + std::to_string(points));
  static std::array<std::unique_ptr<QuadratureRule>, kMaxPoints + 1> cache;
  static std::mutex mutex;
  std::lock_guard<std::mutex> lock(mutex);
  if (!cache[points]) cache[points] = std::make_unique<QuadratureRule>(computeRule(points));
  return *cache[points];
}

}  // namespace bsdeform
