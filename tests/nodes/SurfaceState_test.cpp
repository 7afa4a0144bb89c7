// SPDX-License-Identifier: MIT
// SoBSplineDeformSurface::state() / restoreState(): the viewer's timeline puts states back
// through these, into the surface's current model.
#include <catch2/catch.hpp>
#include <cstdio>
#include <string>
#include <vector>

#include "NodesTestUtil.h"
#include "bsdeform/dynamics/SimulationState.h"

namespace {
const char* kScene = R"IV(#Inventor V2.1 ascii
Separator {
  DEF Surf SoBSplineDeformSurface {
    numUControlPoints 6 numVControlPoints 5 damping 0.4 timeStep 0.05 integrator %s on FALSE
    pins [ 0.5 0.5 ]
    forces [ DEF F1 SoForceField { type UNIFORM force 0 0 1 magnitude 30 },
             DEF F2 SoForceField { type POINT point 0.25 0.75 force 1 -2 3 } ]
  }
}
)IV";

std::string scene(const char* integrator) {
  std::vector<char> text(std::string(kScene).size() + 32);
  std::snprintf(text.data(), text.size(), kScene, integrator);
  return text.data();
}
}  // namespace

TEST_CASE("SoBSplineDeformSurface: restoreState puts a state back exactly, in the same model, and tells STATE_CHANGED",
          "[nodes]") {
  for (const char* integrator : {"EXPLICIT", "IMPLICIT"}) {
    INFO(integrator);
    SoSeparator* root = testutil::read(scene(integrator));
    REQUIRE(root);
    auto* s = testutil::find<SoBSplineDeformSurface>(root);
    REQUIRE(s->stepSimulation(8));
    const bsdeform::SimulationState middle = s->state();
    REQUIRE(s->stepSimulation(6));
    const bsdeform::SimulationState end = s->state();
    const bsdeform::Simulation* model = &s->simulation();
    const int forcesMade = s->forcesMade();
    std::vector<SoBSplineDeformSurface::Event> told;
    const int id = s->addCallback([&told](SoBSplineDeformSurface*, SoBSplineDeformSurface::Event e) { told.push_back(e); });

    std::string error;
    REQUIRE(s->restoreState(middle, &error));
    CHECK(error.empty());
    CHECK(told == std::vector<SoBSplineDeformSurface::Event>{SoBSplineDeformSurface::STATE_CHANGED});
    CHECK(bsdeform::sameBits(s->state(), middle));
    CHECK(&s->simulation() == model);       // no rebuild: the cached model stays
    CHECK(s->forcesMade() == forcesMade);   // nor are the forces remade
    CHECK(s->simulationTime.getValue() == middle.time);  // the live fields follow
    CHECK(s->stepCount.getValue() == middle.steps);
    s->removeCallback(id);
    REQUIRE(s->stepSimulation(6));
    CHECK(bsdeform::sameBits(s->state(), end));

    // written after a restore, the file holds the restored state
    REQUIRE(s->restoreState(middle, &error));
    SoSeparator* copy = testutil::read(testutil::write(root));
    REQUIRE(copy);
    auto* c = testutil::find<SoBSplineDeformSurface>(copy);
    REQUIRE(c->stepSimulation(6));
    CHECK((c->simulation().current() - end.current).cwiseAbs().maxCoeff() < 1e-12);
    copy->unref();
    root->unref();
  }
}

TEST_CASE("SoBSplineDeformSurface: restoreState refuses a state of another net size and changes nothing", "[nodes]") {
  SoSeparator* root = testutil::read(scene("EXPLICIT"));
  REQUIRE(root);
  auto* s = testutil::find<SoBSplineDeformSurface>(root);
  REQUIRE(s->stepSimulation(3));
  const bsdeform::SimulationState before = s->state();
  bsdeform::SimulationState foreign = before;
  foreign.current.conservativeResize(foreign.current.rows() - 1, 3);
  int told = 0;
  s->addCallback([&told](SoBSplineDeformSurface*, SoBSplineDeformSurface::Event) { ++told; });
  std::string error;
  CHECK_FALSE(s->restoreState(foreign, &error));
  CHECK(error.find("current net") != std::string::npos);
  CHECK(told == 0);
  CHECK(bsdeform::sameBits(s->state(), before));
  root->unref();
}
