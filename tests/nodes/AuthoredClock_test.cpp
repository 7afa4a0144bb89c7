// SPDX-License-Identifier: MIT
// bsdeform::AuthoredClock: a front end's play state and speed stay out of the written scene.
#include <catch2/catch.hpp>
#include <string>

#include "NodesTestUtil.h"
#include "bsdeform/AuthoredClock.h"
#include "bsdeform/SoBSplineDeformSurface.h"

TEST_CASE("AuthoredClock: a write inside a Scope has the authored on and speed, the run-time values come back", "[nodes]") {
  SoSeparator* root = testutil::read(
      "#Inventor V2.1 ascii\nSeparator { DEF A SoBSplineDeformSurface { numUControlPoints 4 numVControlPoints 4 }\n"
      "DEF B SoBSplineDeformSurface { numUControlPoints 4 numVControlPoints 4 on FALSE speed 2 } }\n");
  REQUIRE(root);
  auto* a = testutil::named<SoBSplineDeformSurface>("A");
  auto* b = testutil::named<SoBSplineDeformSurface>("B");
  bsdeform::AuthoredClock clock(root);
  // a front end pauses everything and runs at its own speed
  a->on = FALSE;
  a->speed = 5.0f;
  b->speed = 5.0f;
  std::string text;
  {
    const bsdeform::AuthoredClock::Scope authored(clock);
    CHECK(a->on.getValue());
    CHECK(a->on.isDefault());  // written as the file had it: not at all
    CHECK(a->speed.isDefault());
    CHECK(b->speed.getValue() == 2.0f);
    text = testutil::write(root);
  }
  CHECK(text.find("on FALSE") == text.rfind("on FALSE"));  // B's only
  CHECK(text.find("speed 2") != std::string::npos);
  CHECK(text.find("speed 5") == std::string::npos);
  // the run-time values are back
  CHECK(!a->on.getValue());
  CHECK(a->speed.getValue() == 5.0f);
  CHECK(!a->on.isDefault());
  // an author's edit becomes the authored value
  b->on = TRUE;
  CHECK(clock.noteEdited(&b->on));
  CHECK(!clock.noteEdited(&a->numUControlPoints));
  CHECK(clock.authoredOn(b));
  {
    const bsdeform::AuthoredClock::Scope authored(clock);
    text = testutil::write(root);
  }
  CHECK(text.find("on FALSE") == std::string::npos);
  root->unref();
}
