// SPDX-License-Identifier: MIT
// The "frames due" rule of bsdeform-run --video and the viewer's Record (ui/common/FrameClock).
#include <catch2/catch.hpp>

#include "FrameClock.h"

using bsdeform::FrameClock;

TEST_CASE("FrameClock: a frame at the start and one per 1/fps crossed", "[ui]") {
  FrameClock clock(10.0, 0.0);
  CHECK(clock.due(0.0) == 1);   // the first picture, at the start time
  CHECK(clock.due(0.0) == 0);   // asked again: nothing new
  CHECK(clock.due(0.05) == 0);  // a step that crosses no frame time
  CHECK(clock.due(0.1) == 1);   // one that reaches one exactly
  CHECK(clock.due(0.35) == 2);  // one that crosses two (0.2, 0.3): the picture repeats
  CHECK(clock.due(1.0) == 7);   // several (0.4 ... 1.0)
  CHECK(clock.frames() == 11);
  CHECK(clock.nextTime() == Approx(1.1));
}

TEST_CASE("FrameClock: frame times do not drift and allow rounding of the simulated time", "[ui]") {
  FrameClock clock(30.0, 2.0);
  REQUIRE(clock.due(2.0) == 1);
  // 3000 steps of 1/300 s summed up: the time falls a little below or above each frame time
  double t = 2.0;
  long frames = 1;
  for (int i = 0; i < 3000; ++i) {
    t += 1.0 / 300.0;
    frames += clock.due(t);
  }
  CHECK(frames == 301);  // 10 s at 30 frames per second, and the start
  CHECK(clock.nextTime() == Approx(2.0 + 301.0 / 30.0));
  // just below a frame time (a rounding error) counts as reaching it, clearly below does not
  FrameClock c2(10.0, 0.0);
  c2.due(0.0);
  CHECK(c2.due(0.1 - 1e-12) == 1);
  CHECK(c2.due(0.2 - 1e-6) == 0);
}

TEST_CASE("FrameClock: a reset starts over at the new time", "[ui]") {
  FrameClock clock(10.0, 0.0);
  REQUIRE(clock.due(0.0) == 1);
  REQUIRE(clock.due(0.5) == 5);
  CHECK(clock.due(0.0) == 1);  // time went back: a frame at once
  CHECK(clock.due(0.05) == 0);
  CHECK(clock.due(0.1) == 1);
  CHECK(clock.due(0.22) == 1);
  CHECK(clock.frames() == 9);  // frames count on over the reset
  // a reset to a time between frame times: frame times from there on
  CHECK(clock.due(0.15) == 1);
  CHECK(clock.due(0.2) == 0);
  CHECK(clock.due(0.25) == 1);
}

TEST_CASE("FrameClock: a long jump gives at most the cap and skips ahead", "[ui]") {
  FrameClock clock(10.0, 0.0);
  REQUIRE(clock.due(0.0) == 1);
  CHECK(clock.due(100.0, 250) == 250);
  CHECK(clock.nextTime() == Approx(100.1));  // not the 749 frames left behind
  CHECK(clock.due(100.05, 250) == 0);
  CHECK(clock.due(100.1, 250) == 1);
  CHECK(clock.due(100.3, 250) == 2);
  CHECK(clock.frames() == 254);
}
