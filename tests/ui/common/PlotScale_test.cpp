// SPDX-License-Identifier: MIT
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "PlotScale.h"

using namespace bsdeform;

namespace {
// step is 1, 2 or 5 times a power of ten, min and max are multiples of it
bool isRound(const AxisTicks& t) {
  const double mantissa = t.step / std::pow(10.0, std::floor(std::log10(t.step)));
  const bool m = std::abs(mantissa - 1) < 1e-9 || std::abs(mantissa - 2) < 1e-9 || std::abs(mantissa - 5) < 1e-9;
  auto multiple = [&](double v) { return std::abs(v / t.step - std::round(v / t.step)) < 1e-6; };
  return m && multiple(t.min) && multiple(t.max) && std::abs(t.min + (t.count - 1) * t.step - t.max) < 1e-9 * std::max(1.0, std::abs(t.max));
}
}  // namespace

TEST_CASE("PlotScale: ticks are round, cover the data and respect the tick budget", "[ui]") {
  const double ranges[][2] = {{0, 1}, {0.0013, 0.0871}, {-3.7, 12.2}, {549, 549.5}, {2.2, 77.3}, {1e-9, 3e-9}, {-5, -1}, {0, 27.4}};
  for (const auto& r : ranges)
    for (int maxTicks : {3, 5, 6, 8}) {
      const AxisTicks t = niceTicks(r[0], r[1], maxTicks);
      INFO(r[0] << " .. " << r[1] << " max " << maxTicks << " -> " << t.min << " .. " << t.max << " step " << t.step);
      CHECK(isRound(t));
      CHECK(t.min <= r[0]);
      CHECK(t.max >= r[1]);
      CHECK(t.count <= maxTicks);
      CHECK(t.count >= 2);
      // not wastefully wide: the data covers more than a third of the axis
      CHECK((r[1] - r[0]) > (t.max - t.min) / 3.0 - 1e-12);
      // the printed decimals tell every tick apart
      CHECK(std::round(t.step * std::pow(10.0, t.decimals)) >= 1.0);
    }
}

TEST_CASE("PlotScale: non-negative quantities never go below zero, one sample gets a real range", "[ui]") {
  AxisTicks t = niceTicks(0.02, 27.0, 6, true);
  CHECK(t.min == 0.0);
  CHECK(t.max >= 27.0);
  t = niceTicks(540.0, 549.0, 6, true);  // far from zero: the axis may start above it
  CHECK(t.min >= 0.0);
  CHECK(t.min <= 540.0);
  t = niceTicks(0.0, 0.0, 6, true);  // after Reset: everything is zero
  CHECK(t.min == 0.0);
  CHECK(t.max == 1.0);
  t = niceTicks(2.2, 2.2, 6);  // a file saved at t = 2.2, one sample: ticks differ
  CHECK(t.min < 2.2);
  CHECK(t.max > 2.2);
  CHECK(t.step >= 0.1);
  CHECK(isRound(t));
  t = niceTicks(3.5, 3.5, 6, true);
  CHECK(t.min == 0.0);
  CHECK(t.max >= 3.5);
  t = niceTicks(NAN, 1.0, 6);
  CHECK(t.min == 0.0);
  CHECK(t.max == 1.0);
}

TEST_CASE("PlotScale: a logarithmic axis when the positive values span decades", "[ui]") {
  CHECK(spansDecades({0, 0.0001, 0.001, 0.01, 0.1, 0.3, 0.5, 1, 2, 5, 7, 10, 25, 50, 75, 100, 150, 200}));
  CHECK_FALSE(spansDecades({1, 2, 5, 10, 25, 50}));
  CHECK_FALSE(spansDecades({0, 0, 0}));
  CHECK_FALSE(spansDecades({}));
  CHECK(spansDecades({1, 1000}, 3.0));
}

TEST_CASE("PlotScale: least squares recovers a line and its correlation", "[ui]") {
  // exact line: r = 1, coefficients recovered
  std::vector<double> x = {0, 0.5, 1, 2, 5, 10, 100}, y;
  for (double v : x) y.push_back(0.4 + 0.038 * v);
  LinearFit f = fitLine(x, y);
  REQUIRE(f.valid);
  CHECK(f.intercept == Approx(0.4).epsilon(1e-12));
  CHECK(f.slope == Approx(0.038).epsilon(1e-12));
  CHECK(f.r == Approx(1.0).epsilon(1e-12));
  CHECK(f.points == 7);
  // decreasing data: negative r; noise makes |r| < 1 and the residuals are orthogonal to 1 and x
  std::vector<double> yn = {5.0, 4.1, 3.9, 3.0, 2.2, 1.1, 0.2}, xs = {0, 1, 2, 3, 4, 5, 6};
  f = fitLine(xs, yn);
  REQUIRE(f.valid);
  CHECK(f.r < -0.95);
  CHECK(f.r > -1.0);
  double sumRes = 0.0, sumResX = 0.0;
  for (size_t i = 0; i < xs.size(); ++i) {
    const double res = yn[i] - (f.intercept + f.slope * xs[i]);
    sumRes += res;
    sumResX += res * xs[i];
  }
  CHECK(std::abs(sumRes) < 1e-12);
  CHECK(std::abs(sumResX) < 1e-11);
  // non-finite pairs are skipped; one distinct x is no line; constant y has r = 0
  f = fitLine({1, NAN, 3}, {2, 5, 6});
  CHECK(f.points == 2);
  CHECK(f.slope == Approx(2.0));
  CHECK_FALSE(fitLine({2, 2, 2}, {1, 2, 3}).valid);
  f = fitLine({1, 2, 3}, {4, 4, 4});
  CHECK(f.valid);
  CHECK(f.r == 0.0);
  CHECK(f.slope == 0.0);
}

TEST_CASE("PlotScale: tick labels tell the ticks apart, also for energies of 1e-16 after a reset", "[ui]") {
  // Issue 37, item 4: the energy axis read "0.000000000000" five times after Reset.
  auto labels = [](const bsdeform::AxisTicks& t) {
    std::vector<std::string> out;
    const std::string format = bsdeform::tickLabelFormat(t);
    for (int i = 0; i < t.count; ++i) {
      char buf[64];
      std::snprintf(buf, sizeof buf, format.c_str(), t.min + i * t.step);
      out.push_back(buf);
    }
    return out;
  };
  for (const auto& range : {std::make_pair(0.0, 3.1e-16), std::make_pair(0.0, 1.2), std::make_pair(0.0, 4.2e9),
                            std::make_pair(2.5e-9, 2.7e-9), std::make_pair(-3.0, 7.0)}) {
    const bsdeform::AxisTicks t = bsdeform::niceTicks(range.first, range.second, 6, range.first >= 0.0);
    const std::vector<std::string> l = labels(t);
    INFO(range.first << ".." << range.second << ": " << bsdeform::tickLabelFormat(t));
    for (size_t i = 1; i < l.size(); ++i) CHECK(l[i] != l[i - 1]);
    for (const std::string& text : l) CHECK(text.size() <= 10);
  }
  CHECK(bsdeform::tickLabelFormat(bsdeform::niceTicks(0.0, 1.2, 6)) == "%.1f");  // ordinary axes as before
}
