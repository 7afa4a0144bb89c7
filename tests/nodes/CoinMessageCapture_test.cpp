// SPDX-License-Identifier: MIT
// Coin's messages collected while a capture lives; nested captures give the handlers back.
#include <Inventor/errors/SoDebugError.h>
#include <Inventor/errors/SoReadError.h>
#include <catch2/catch.hpp>

#include "NodesTestUtil.h"
#include "bsdeform/CoinMessageCapture.h"

TEST_CASE("CoinMessageCapture: collects while it lives, nests, restores the handlers", "[nodes]") {
  testutil::Coin& coin = testutil::Coin::get();  // the test run's own capture, the outer one
  coin.messages.clear();
  SoErrorCB* const outerDebug = SoDebugError::getHandlerCallback();
  void* const outerDebugData = SoDebugError::getHandlerData();
  SoErrorCB* const outerRead = SoReadError::getHandlerCallback();
  void* const outerReadData = SoReadError::getHandlerData();
  {
    bsdeform::CoinMessageCapture all;
    SoDebugError::postWarning("test", "first");
    {
      bsdeform::CoinMessageCapture reads(bsdeform::CoinMessageCapture::ReadErrors);
      SoDebugError::postWarning("test", "second");  // not a read error: the outer capture has it
      SoInput in;
      const char text[] = "#Inventor V2.1 ascii\nSeparator { NoSuchNode { } }\n";
      in.setBuffer(text, sizeof(text) - 1);
      SoSeparator* root = SoDB::readAll(&in);
      CHECK(root == nullptr);
      REQUIRE(reads.messages.size() >= 1);
      CHECK(reads.joined("\n").find("NoSuchNode") != std::string::npos);
    }
    CHECK(SoReadError::getHandlerData() == static_cast<void*>(&all));  // `all`'s handler is back
    REQUIRE(all.messages.size() == 2);
    CHECK(all.messages[0].find("first") != std::string::npos);
    CHECK(all.messages[1].find("second") != std::string::npos);
    CHECK(all.joined("; ").find("; ") != std::string::npos);
  }
  CHECK(SoDebugError::getHandlerCallback() == outerDebug);
  CHECK(SoDebugError::getHandlerData() == outerDebugData);
  CHECK(SoReadError::getHandlerCallback() == outerRead);
  CHECK(SoReadError::getHandlerData() == outerReadData);
  CHECK(coin.messages.empty());  // the inner captures took every message
  SoDebugError::postWarning("test", "third");
  CHECK(coin.messages.size() == 1);
  coin.messages.clear();
}
