// SPDX-License-Identifier: MIT
#include <Inventor/SoDB.h>
#include <Inventor/SoInput.h>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <random>

#include "NodesTestUtil.h"
#include "bsdeform/SceneText.h"

using namespace bsdeform;

namespace {
double readWithCoin(const std::string& text) {
  SoInput in;
  in.setBuffer(text.c_str(), text.size());
  double d = NAN;
  REQUIRE(in.read(d));
  return d;
}
}  // namespace

TEST_CASE("SceneText: the emulated reader computes what Coin's reader computes", "[nodes]") {
  testutil::Coin::get();
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> mant(1.0, 10.0);
  std::uniform_int_distribution<int> ex(-20, 8);
  int mismatches = 0, inexact = 0;
  for (int i = 0; i < 4000; ++i) {
    const double x = (i % 2 ? -1 : 1) * mant(rng) * std::pow(10.0, ex(rng));
    char buf[40];
    std::snprintf(buf, sizeof buf, i % 3 ? "%.15g" : "%.16g", x);
    double emulated = 0.0;
    REQUIRE(coinReadReal(buf, emulated));
    const double coin = readWithCoin(buf);
    mismatches += emulated != coin;
    inexact += coin != std::strtod(buf, nullptr);
  }
  CHECK(mismatches == 0);
  CHECK(inexact > 100);  // Coin's reader really is inexact, so the check above means something
}

TEST_CASE("SceneText: every double written is read back by Coin to its 15-digit value", "[nodes]") {
  testutil::Coin::get();
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> mant(1.0, 10.0);
  std::uniform_int_distribution<int> ex(-25, 12);
  const double hard[] = {0.000983542385712959, 0.05, 0.3, 1e-5, 123456.789, 0.0, -0.0625};
  auto check = [](double x) {
    const std::string text = coinDoubleText(x);
    INFO(x << " written as " << text);
    CHECK(snap15(readWithCoin(text)) == snap15(x));
  };
  for (double x : hard) check(x);
  for (int i = 0; i < 4000; ++i) check(mant(rng) * std::pow(10.0, ex(rng)));
  // readable where possible: short decimals stay as they are
  CHECK(coinDoubleText(0.1) == "0.1");
  CHECK(coinDoubleText(2.5) == "2.5");
  CHECK(coinDoubleText(0.000983542385712959) == "983542385712959e-18");
}

TEST_CASE("SceneText: a scene streams in pieces of at most a megabyte, and a failing sink stops it", "[nodes]") {
  SoSeparator* root = testutil::read("#Inventor V2.1 ascii\nSeparator { SoBSplineDeformSurface { on FALSE "
                                     "numUControlPoints 160 numVControlPoints 160 "
                                     "forces SoForceField { type UNIFORM force 0 0 5 } } }");
  REQUIRE(root);
  testutil::find<SoBSplineDeformSurface>(root)->stepSimulation(2);
  std::vector<std::size_t> pieces;
  std::string streamed;
  CHECK(writeSceneText(root, [&](const char* data, std::size_t size) {
    pieces.push_back(size);
    streamed.append(data, size);
    return true;
  }));
  CHECK(streamed.size() > 3u << 20);  // three nets of 166^2 points
  CHECK(pieces.size() >= 3);
  CHECK(*std::max_element(pieces.begin(), pieces.end()) <= std::size_t(1) << 20);
  CHECK(streamed == testutil::write(root));
  // the sink fails on the second piece: writing stops there and says so
  int calls = 0;
  CHECK_FALSE(writeSceneText(root, [&](const char*, std::size_t) { return ++calls < 2; }));
  CHECK(calls == 2);
  root->unref();
}
