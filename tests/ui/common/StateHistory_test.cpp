// SPDX-License-Identifier: MIT
#include <catch2/catch.hpp>

#include "StateHistory.h"

using namespace bsdeform;

namespace {
// A frame of one surface whose 100-point nets hold `time` (so frames can be told apart).
StateFrame frameAt(double time) {
  SimulationState s;
  s.current = ControlNet::Constant(100, 3, time);
  s.previous = s.current;
  s.time = time;
  s.steps = long(time * 10);
  return frameOf({s});
}
}  // namespace

TEST_CASE("StateHistory: memory stays within the budget, the first and the newest states stay, older ones are thinned",
          "[ui]") {
  const std::size_t frameBytes = bytesOf(frameAt(0.0));
  StateHistory h(50 * frameBytes);
  for (int k = 0; k <= 2000; ++k) {
    h.append(frameAt(k * 0.1));
    REQUIRE(h.bytes() <= h.budget());
  }
  CHECK(h.size() <= 50);
  CHECK(h.size() >= 25);  // a thinning drops about a quarter: the budget is used, not wasted
  CHECK(h.thinnings() > 0);
  CHECK(h[0].time == 0.0);                  // the whole run stays reachable
  CHECK(h.back().time == 2000 * 0.1);       // the newest state is kept
  CHECK(h.back().surfaces[0].current(0, 0) == 2000 * 0.1);
  // the recent past finely, the older coarsely: the spacing never shrinks going back in time
  for (int i = 1; i + 1 < h.size(); ++i) CHECK(h[i].time - h[i - 1].time >= h[i + 1].time - h[i].time - 1e-9);
  CHECK(h[h.size() - 1].time - h[h.size() - 2].time == Approx(0.1));  // the newest at full resolution
  CHECK(h[1].time - h[0].time > 1.0);
  // the bytes counted are the bytes held
  std::size_t sum = 0;
  for (int i = 0; i < h.size(); ++i) sum += bytesOf(h[i]);
  CHECK(h.bytes() == sum);
  // a smaller budget thins at once
  h.setBudget(10 * frameBytes);
  CHECK(h.bytes() <= 10 * frameBytes);
  CHECK(h[0].time == 0.0);
  CHECK(h.back().time == 2000 * 0.1);
}

TEST_CASE("StateHistory: a branch taken off and put back, an earlier time replaces the later frames", "[ui]") {
  StateHistory h;
  for (int k = 0; k < 10; ++k) h.append(frameAt(k));
  CHECK(h.indexAt(4.5) == 4);
  CHECK(h.indexAt(-1.0) == -1);
  const std::size_t before = h.bytes();
  std::vector<StateFrame> later = h.takeAfter(4);
  REQUIRE(later.size() == 5);
  CHECK(later.front().time == 5.0);
  CHECK(h.size() == 5);
  CHECK(h.bytes() + 5 * bytesOf(frameAt(0)) == before);
  h.appendAll(std::move(later));
  CHECK(h.size() == 10);
  CHECK(h.bytes() == before);
  h.append(frameAt(3.0));  // a state at an earlier time: the frames from 3 on are replaced
  CHECK(h.size() == 4);
  CHECK(h.back().time == 3.0);
  h.clear();
  CHECK(h.isEmpty());
  CHECK(h.bytes() == 0);
}
