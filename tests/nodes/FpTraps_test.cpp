// SPDX-License-Identifier: MIT
// Floating-point traps in the nodes tests: on around our numerics (an FpTrapScope), off while
// Coin renders through Mesa, whose llvmpipe raises FE_INVALID / FE_DIVBYZERO on purpose (with
// traps on for the whole process, the renderer and viewer tests died of SIGFPE in Debug builds).
#include <Inventor/actions/SoGLRenderAction.h>
#include <Inventor/nodes/SoCallback.h>
#include <catch2/catch.hpp>
#include <memory>

#include "NodesTestUtil.h"
#include "bsdeform/forces/Force.h"
#include "bsdeform/OffscreenRenderer.h"
#include "../support/FpTraps.h"

using bsdeform::test::enabledFpTraps;
using bsdeform::test::FpTrapScope;
using bsdeform::test::kTrappedFpExceptions;

namespace {
// Records the trap mask while a GL render traversal passes the SoCallback node.
void recordTrapsWhileRendering(void* data, SoAction* action) {
  if (action->isOfType(SoGLRenderAction::getClassTypeId())) *static_cast<int*>(data) = enabledFpTraps();
}
}  // namespace

TEST_CASE("FP traps: on while a surface steps inside an FpTrapScope, off while Coin renders", "[nodes]") {
  CHECK(enabledFpTraps() == 0);  // nothing traps for the whole nodes test process
  SoSeparator* scene = testutil::read("#Inventor V2.1 ascii\nSeparator { SoBSplineDeformSurface { on FALSE } }");
  REQUIRE(scene);
  auto* surface = testutil::find<SoBSplineDeformSurface>(scene);
  REQUIRE(surface);

  auto seenByCore = std::make_shared<int>(-1);
  auto probe = std::make_shared<bsdeform::PointForce>(
      0.5, 0.5,
      [seenByCore](const bsdeform::SurfaceSample&) {
        *seenByCore = enabledFpTraps();
        return Eigen::Vector3d(0, 0, 2);
      },
      bsdeform::kDependsOnTime);
  surface->addTransientForce(probe);
  {
    FpTrapScope traps;
    REQUIRE(surface->stepSimulation(3));
  }
  CHECK(*seenByCore == kTrappedFpExceptions);
  CHECK(enabledFpTraps() == 0);  // the scope restored the mask
  surface->removeTransientForce(probe.get());

  int seenByRender = -1;
  auto* probeNode = new SoCallback;
  probeNode->setCallback(recordTrapsWhileRendering, &seenByRender);
  scene->insertChild(probeNode, 0);
  bsdeform::Image image;
  std::string error;
  const bool rendered = bsdeform::renderOffscreen(scene, 64, 48, image, error);
  INFO(error);
  REQUIRE(rendered);
  CHECK(seenByRender == 0);
  scene->unref();
}

TEST_CASE("FP traps: an FpTrapScope restores the mask it found, nested or not", "[nodes]") {
  REQUIRE(enabledFpTraps() == 0);
  {
    FpTrapScope outer;
    CHECK(enabledFpTraps() == kTrappedFpExceptions);
    {
      FpTrapScope inner;
      CHECK(enabledFpTraps() == kTrappedFpExceptions);
    }
    CHECK(enabledFpTraps() == kTrappedFpExceptions);  // the inner scope leaves the outer's traps on
  }
  CHECK(enabledFpTraps() == 0);
}
