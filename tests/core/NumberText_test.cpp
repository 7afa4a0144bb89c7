// SPDX-License-Identifier: MIT
// The numbers in the core's messages: the shortest text that reads back to the same double.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "bsdeform/base/NumberText.h"

using bsdeform::numberText;

TEST_CASE("NumberText: a number as a person wrote it, and the exact double when it reads back", "[core]") {
  CHECK(numberText(0.7) == "0.7");
  CHECK(numberText(-0.001) == "-0.001");
  CHECK(numberText(0.243) == "0.243");
  CHECK(numberText(821000.0) == "821000");
  CHECK(numberText(0.1 + 0.2) == "0.30000000000000004");  // not 0.3: that is another double
  CHECK(numberText(std::numeric_limits<double>::quiet_NaN()) == "nan");
  CHECK(numberText(-std::numeric_limits<double>::infinity()) == "-inf");
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> X(-1e6, 1e6);
  for (int k = 0; k < 1000; ++k) {
    const double x = X(rng) * std::pow(10.0, double(k % 40) - 20.0);
    CHECK(std::stod(numberText(x)) == x);
  }
}

TEST_CASE("NumberText: a computed quantity in a message has four significant digits", "[core]") {
  using bsdeform::measuredText;
  CHECK(measuredText(0.004083512107596866) == "0.004084");
  CHECK(measuredText(0.0065000000000000006) == "0.0065");
  CHECK(measuredText(1.23456e-5) == "1.235e-05");
  CHECK(measuredText(0.5) == "0.5");
  CHECK(measuredText(12345.6) == "1.235e+04");
  CHECK(measuredText(-0.30000000000000004) == "-0.3");
  CHECK(measuredText(std::numeric_limits<double>::infinity()) == "inf");
}
