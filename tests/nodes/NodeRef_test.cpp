// SPDX-License-Identifier: MIT
// bsdeform::NodeRef: one reference, given back on scope exit, passed on by a move.
#include <Inventor/nodes/SoCube.h>
#include <Inventor/sensors/SoNodeSensor.h>

#include <catch2/catch.hpp>
#include <utility>

#include "NodesTestUtil.h"
#include "bsdeform/NodeRef.h"

namespace {

/// Notes when Coin destroys the watched node.
struct Watch {
  SoNodeSensor sensor;
  bool destroyed = false;
  explicit Watch(SoNode* node) {
    sensor.setDeleteCallback([](void* self, SoSensor*) { static_cast<Watch*>(self)->destroyed = true; }, this);
    sensor.attach(node);
  }
};

}  // namespace

TEST_CASE("NodeRef: the node is freed when its holder leaves the scope, also by an early return", "[nodes]") {
  testutil::Coin::get();
  auto* cube = new SoCube;
  Watch watch(cube);
  auto holdAndReturn = [](SoCube* node, bool early) {
    const bsdeform::NodeRef<SoCube> held(node);
    if (early) return node->getRefCount();
    return node->getRefCount() + 100;
  };
  cube->ref();  // the test's own reference keeps the node while the holder comes and goes
  CHECK(holdAndReturn(cube, true) == 2);
  CHECK(cube->getRefCount() == 1);
  CHECK(holdAndReturn(cube, false) == 102);
  CHECK(cube->getRefCount() == 1);
  cube->unrefNoDelete();
  CHECK(!watch.destroyed);
  {
    const bsdeform::NodeRef<SoCube> held(cube);
    CHECK(held.get() == cube);
    CHECK(cube->getRefCount() == 1);
  }
  CHECK(watch.destroyed);
}

TEST_CASE("NodeRef: a move passes the one reference on, reset and assignment give the old node back", "[nodes]") {
  testutil::Coin::get();
  auto* a = new SoCube;
  auto* b = new SoCube;
  Watch watchA(a), watchB(b);
  bsdeform::NodeRef<SoCube> first(a);
  bsdeform::NodeRef<SoCube> second(std::move(first));
  CHECK(!first);
  CHECK(second.get() == a);
  CHECK(a->getRefCount() == 1);
  {
    bsdeform::NodeRef<SoCube> third(b);
    third = std::move(second);  // b's holder takes a: b is given back and freed
    CHECK(watchB.destroyed);
    CHECK(!second);
    CHECK(third.get() == a);
    CHECK(a->getRefCount() == 1);
    third.reset(a);  // the same node again: kept
    CHECK(!watchA.destroyed);
    CHECK(a->getRefCount() == 1);
  }
  CHECK(watchA.destroyed);  // the last holder left the scope
}
