// SPDX-License-Identifier: MIT
#pragma once
/// @file PlotScale.h
/// The arithmetic of the front ends' plots, kept apart from Qt so that it can be tested: axis
/// ranges with round ticks, the choice of a logarithmic axis, and the least-squares line of a
/// parameter sweep (the paper's Figs. 8 and 11 print n = a + b omega with its coefficient r).

#include <string>
#include <vector>

namespace bsdeform {

/// An axis from `min` to `max` with `count` ticks `step` apart (min and max are multiples of
/// step, so every tick is a round number).
struct AxisTicks {
  double min = 0.0, max = 1.0, step = 0.25;
  int count = 5;
  /// Digits after the decimal point that show every tick exactly (0 for integer steps).
  int decimals = 2;
};

/// Round ticks covering [lo, hi] with at most `maxTicks` ticks (>= 2), steps of 1, 2 or 5 times
/// a power of ten. With `nonNegative` (a norm, an energy) the axis never goes below 0, and starts
/// at 0 when lo is closer to 0 than the data's spread. An empty range (one sample, all samples
/// equal) gets a range around the value; NaN or infinite bounds give [0, 1].
AxisTicks niceTicks(double lo, double hi, int maxTicks = 6, bool nonNegative = false);

/// The printf format of the axis' tick labels: fixed with `decimals` digits for ordinary axes
/// ("%.2f"), and "%.Ng" with the N significant digits that tell the ticks apart when a fixed
/// format would need more than six decimals or the numbers are large (an energy of 1e-16 after a
/// reset: "5e-17", "1e-16", not five times "0.000000000000").
std::string tickLabelFormat(const AxisTicks& ticks);

/// Whether a plot of `values` should use a logarithmic axis: the positive values span at least
/// `decades` powers of ten (the sweep 0, 0.0001, ..., 200 spans six).
bool spansDecades(const std::vector<double>& values, double decades = 2.0);

/// Least-squares line y = intercept + slope x over the finite pairs (x[i], y[i]) and the
/// correlation coefficient r (Pearson). `valid` is false with fewer than two distinct x; r is
/// 0 when every y is the same.
struct LinearFit {
  double intercept = 0.0, slope = 0.0, r = 0.0;
  int points = 0;
  bool valid = false;
};
LinearFit fitLine(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace bsdeform
