// SPDX-License-Identifier: MIT
#include "PlotScale.h"

#include <algorithm>
#include <cmath>

namespace bsdeform {

namespace {
// The smallest step of 1, 2 or 5 times a power of ten that is at least `raw`.
double niceStep(double raw) {
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * power >= raw * (1.0 - 1e-12)) return m * power;
  return 10.0 * power;
}
}  // namespace

AxisTicks niceTicks(double lo, double hi, int maxTicks, bool nonNegative) {
  AxisTicks t;
  if (!std::isfinite(lo) || !std::isfinite(hi)) return t;
  if (lo > hi) std::swap(lo, hi);
  maxTicks = std::max(2, maxTicks);
  if (nonNegative) {
    lo = std::max(0.0, lo);
    hi = std::max(0.0, hi);
    if (lo < hi - lo) lo = 0.0;  // closer to 0 than the spread: show 0
  }
  if (hi - lo <= 1e-12 * std::max(std::abs(lo), std::abs(hi))) {
    // one value: a range around it (from 0 for a non-negative one) instead of a degenerate axis
    const double v = lo;
    if (v == 0.0) {
      lo = 0.0;
      hi = 1.0;
    } else if (nonNegative) {
      lo = 0.0;
      hi = v;
    } else {
      lo = v - 0.5 * std::abs(v);
      hi = v + 0.5 * std::abs(v);
    }
  }
  // the step that lets [lo, hi] be covered by at most maxTicks - 1 intervals
  double step = niceStep((hi - lo) / (maxTicks - 1));
  double a = std::floor(lo / step) * step, b = std::ceil(hi / step) * step;
  while (std::lround((b - a) / step) > maxTicks - 1) {
    step = niceStep(step * 1.0001);
    a = std::floor(lo / step) * step;
    b = std::ceil(hi / step) * step;
  }
  if (nonNegative) a = std::max(0.0, a);
  t.min = a;
  t.max = b;
  t.step = step;
  t.count = int(std::lround((b - a) / step)) + 1;
  t.decimals = std::max(0, -int(std::floor(std::log10(step) + 1e-9)));
  return t;
}

std::string tickLabelFormat(const AxisTicks& t) {
  const double biggest = std::max(std::abs(t.min), std::abs(t.max));
  if (t.decimals <= 6 && biggest < 1e7) return "%." + std::to_string(t.decimals) + "f";
  if (!(t.step > 0.0) || !std::isfinite(biggest)) return "%g";
  const int digits = int(std::floor(std::log10(std::max(biggest, t.step)) + 1e-9)) - int(std::floor(std::log10(t.step) + 1e-9)) + 1;
  return "%." + std::to_string(std::clamp(digits, 1, 15)) + "g";
}

bool spansDecades(const std::vector<double>& values, double decades) {
  double lo = INFINITY, hi = 0.0;
  for (double v : values)
    if (std::isfinite(v) && v > 0.0) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  return hi > 0.0 && std::log10(hi / lo) >= decades;
}

LinearFit fitLine(const std::vector<double>& x, const std::vector<double>& y) {
  LinearFit fit;
  const size_t n = std::min(x.size(), y.size());
  double mx = 0.0, my = 0.0;
  for (size_t i = 0; i < n; ++i)
    if (std::isfinite(x[i]) && std::isfinite(y[i])) {
      mx += x[i];
      my += y[i];
      ++fit.points;
    }
  if (fit.points < 2) return fit;
  mx /= fit.points;
  my /= fit.points;
  double sxx = 0.0, sxy = 0.0, syy = 0.0;  // about the means: no cancellation for large values
  for (size_t i = 0; i < n; ++i)
    if (std::isfinite(x[i]) && std::isfinite(y[i])) {
      sxx += (x[i] - mx) * (x[i] - mx);
      sxy += (x[i] - mx) * (y[i] - my);
      syy += (y[i] - my) * (y[i] - my);
    }
  if (!(sxx > 0.0)) return fit;
  fit.slope = sxy / sxx;
  fit.intercept = my - fit.slope * mx;
  fit.r = syy > 0.0 ? sxy / std::sqrt(sxx * syy) : 0.0;
  fit.valid = true;
  return fit;
}

}  // namespace bsdeform
