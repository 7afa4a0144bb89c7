// SPDX-License-Identifier: MIT
// Who drives time (Coin's realTime, read by each surface's own sensor; SceneRunner for exact
// runs), how a surface hears its force fields (their `revision` outputs, not polling) and what
// it tells its listeners (SoBSplineDeformSurface::addCallback). No test waits on the wall
// clock: realTime is set and the sensor queue processed.
#include <Inventor/SoDB.h>
#include <Inventor/fields/SoSFTime.h>
#include <Inventor/sensors/SoSensorManager.h>
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "NodesTestUtil.h"
#include "bsdeform/OffscreenRenderer.h"
#include "bsdeform/SceneRunner.h"

using testutil::Coin;

namespace {

SoSFTime& realTime() { return *static_cast<SoSFTime*>(SoDB::getGlobalField(SbName("realTime"))); }

// Sets realTime and lets Coin deliver what it notified (the sensors in the delay queue).
void setRealTime(double t) {
  realTime().setValue(SbTime(t));
  SoDB::getSensorManager()->processDelayQueue(FALSE);
}

const char* kTwo = R"(#Inventor V2.1 ascii
Separator {
  DEF Fine SoBSplineDeformSurface { numUControlPoints 4 numVControlPoints 4 timeStep 0.05
    forces [ DEF Push SoForceField { type UNIFORM force 0 0 1 } ] }
  DEF Coarse SoBSplineDeformSurface { numUControlPoints 4 numVControlPoints 4 timeStep 0.12
    forces [ SoForceField { type UNIFORM force 0 0 1 } ] }
}
)";

}  // namespace

TEST_CASE("Clock: a surface follows Coin's realTime, as SoElapsedTime does, times its speed", "[nodes]") {
  Coin::get();
  setRealTime(1000.0);
  SoSeparator* root = testutil::read(kTwo);
  REQUIRE(root);
  auto* fine = testutil::named<SoBSplineDeformSurface>("Fine");
  auto* coarse = testutil::named<SoBSplineDeformSurface>("Coarse");
  coarse->speed = 2.0f;
  coarse->simulation();
  fine->simulation();
  setRealTime(1000.0);  // the surfaces count from the first time they see
  setRealTime(1000.2);
  CHECK(fine->simulation().stepCount() == 4);    // 0.2 s in steps of 0.05
  CHECK(coarse->simulation().stepCount() == 3);  // 0.4 simulated s in steps of 0.12, 0.04 owed
  setRealTime(1000.22);
  CHECK(coarse->simulation().stepCount() == 3);  // 0.04 owed + 0.04: not yet a step
  setRealTime(1000.24);
  CHECK(coarse->simulation().stepCount() == 4);  // the remainder was kept
  root->unref();
}

TEST_CASE("Clock: steps that cannot keep up with realTime are taken one per tick, unless told to catch up", "[nodes]") {
  Coin::get();
  REQUIRE_FALSE(SoBSplineDeformSurface::realTimeCatchUp());  // the default: interaction
  setRealTime(300.0);
  SoSeparator* root = testutil::read(kTwo);
  REQUIRE(root);
  auto* fine = testutil::named<SoBSplineDeformSurface>("Fine");
  fine->speed = 1048576.0f;  // 2^20 simulated seconds per second: no step keeps up with that
  const double tick = 1.0 / 1048576.0;  // one simulated second, exactly
  fine->simulation();
  setRealTime(300.0);
  bsdeform::Image image;
  std::string error;
  auto frame = [&] { REQUIRE(bsdeform::renderOffscreen(root, 16, 16, image, error)); };
  setRealTime(300.0 + tick);  // one simulated second: 20 steps, before their cost is known
  CHECK(fine->simulation().stepCount() == 20);
  frame();
  setRealTime(300.0 + 2 * tick);  // now known to be slower than realTime: one step, a frame after it
  CHECK(fine->simulation().stepCount() == 21);
  setRealTime(300.0 + 3 * tick);  // no frame yet since that step: this tick waits for it
  CHECK(fine->simulation().stepCount() == 21);
  frame();
  setRealTime(300.0 + 4 * tick);
  CHECK(fine->simulation().stepCount() == 22);  // the time dropped is not owed
  SoBSplineDeformSurface::setRealTimeCatchUp(true);
  setRealTime(300.0 + 5 * tick);
  CHECK(fine->simulation().stepCount() == 42);  // every step due
  SoBSplineDeformSurface::setRealTimeCatchUp(false);
  root->unref();
}

TEST_CASE("Clock: `on FALSE` stands still, a clock set back is a new origin, a slow frame is not made up", "[nodes]") {
  Coin::get();
  setRealTime(50.0);
  SoSeparator* root = testutil::read(kTwo);
  REQUIRE(root);
  auto* fine = testutil::named<SoBSplineDeformSurface>("Fine");
  auto* coarse = testutil::named<SoBSplineDeformSurface>("Coarse");
  coarse->on = FALSE;
  setRealTime(50.1);
  CHECK(fine->simulation().stepCount() == 2);
  CHECK(coarse->simulation().stepCount() == 0);
  setRealTime(10.0);  // back: nothing to make up
  CHECK(fine->simulation().stepCount() == 2);
  setRealTime(10.05);
  CHECK(fine->simulation().stepCount() == 3);
  setRealTime(20.0);  // ten seconds in one frame: a quarter second of them is taken
  CHECK(fine->simulation().stepCount() == 3 + 5);
  CHECK(coarse->simulation().stepCount() == 0);
  root->unref();
}

TEST_CASE("SceneRunner: every surface to a common time, realTime following, the surfaces' own clocks off", "[nodes]") {
  Coin::get();
  SoSeparator* root = testutil::read(kTwo);
  REQUIRE(root);
  auto* fine = testutil::named<SoBSplineDeformSurface>("Fine");
  auto* coarse = testutil::named<SoBSplineDeformSurface>("Coarse");
  {
    bsdeform::SceneRunner runner(root);
    REQUIRE(runner.surfaces().size() == 2);
    CHECK(runner.timeStep() == 0.05);
    CHECK(runner.startTime() == 0.0);
    CHECK(fine->scene() == root);
    CHECK(coarse->scene() == root);
    for (int k = 1; k <= 20; ++k) {
      REQUIRE(runner.advanceTo(k * 0.05));
      CHECK(realTime().getValue().getValue() == Approx(k * 0.05));
      // each within half its own step of the common time
      CHECK(std::abs(fine->simulation().time() - k * 0.05) <= 0.5 * 0.05 + 1e-12);
      CHECK(std::abs(coarse->simulation().time() - k * 0.05) <= 0.5 * 0.12 + 1e-12);
    }
    CHECK(fine->simulation().stepCount() == 20);
    CHECK(coarse->simulation().stepCount() == 8);  // 8 x 0.12 = 0.96 <= 1 - 0.06
    // realTime moved by a runner's hand does not step the surfaces a second time
    SoDB::getSensorManager()->processDelayQueue(FALSE);
    CHECK(fine->simulation().stepCount() == 20);
    CHECK(runner.step());
    CHECK(fine->simulation().stepCount() == 21);
    // `on` and `speed` are not touched
    CHECK(fine->on.getValue());
    CHECK(fine->on.isDefault());
    CHECK(fine->speed.isDefault());
  }
  // released: the surfaces follow realTime again, from where it is
  const double t = realTime().getValue().getValue();
  setRealTime(t + 0.1);
  CHECK(fine->simulation().stepCount() == 23);
  root->unref();
}

TEST_CASE("SceneRunner: a surface that blows up stops, the others go on", "[nodes]") {
  Coin::get();
  SoSeparator* root = testutil::read(R"(#Inventor V2.1 ascii
Separator {
  DEF Calm SoBSplineDeformSurface { numUControlPoints 4 numVControlPoints 4 timeStep 0.1 }
  DEF Wild SoBSplineDeformSurface { numUControlPoints 4 numVControlPoints 4 timeStep 0.1
    forces [ SoForceField { type EXPRESSION expression [ "0", "0", "-1e7*z + 1" ] } ] }
}
)");
  REQUIRE(root);
  auto* calm = testutil::named<SoBSplineDeformSurface>("Calm");
  auto* wild = testutil::named<SoBSplineDeformSurface>("Wild");
  bsdeform::SceneRunner runner(root);
  bool ok = true;
  for (int k = 1; k <= 30; ++k) ok &= runner.advanceTo(0.1 * k);
  CHECK(!ok);
  REQUIRE(runner.failed().size() == 1);
  CHECK(runner.failed()[0] == wild);
  CHECK(wild->problem().kind == SoBSplineDeformSurface::Problem::STOPPED);
  CHECK(calm->simulation().stepCount() == 30);
  CHECK(calm->problem().kind == SoBSplineDeformSurface::Problem::NONE);
  root->unref();
}

TEST_CASE("Notification: a force is remade when its force field tells of a change, not before every step", "[nodes]") {
  Coin::get();
  SoSeparator* root = testutil::read(kTwo);
  REQUIRE(root);
  auto* fine = testutil::named<SoBSplineDeformSurface>("Fine");
  auto* push = testutil::named<SoForceField>("Push");
  fine->on = FALSE;
  REQUIRE(fine->stepSimulation(1));
  const int made = fine->forcesMade();
  REQUIRE(fine->stepSimulation(10));
  CHECK(fine->forcesMade() == made);  // nothing changed: nothing remade
  const double z = fine->simulation().evaluate(0.5, 0.5).position.z();
  push->force.setValue(0, 0, -1);  // the engine notifies the surface through its revision output
  REQUIRE(fine->stepSimulation(1));
  CHECK(fine->forcesMade() == made + 1);
  REQUIRE(fine->stepSimulation(30));
  CHECK(fine->simulation().evaluate(0.5, 0.5).position.z() < z);  // the new force acts
  // a force field added to the list is heard too
  auto* more = new SoForceField;
  more->type = SoForceField::GRAVITY;
  fine->forces.set1Value(1, more);
  REQUIRE(fine->stepSimulation(1));
  CHECK(fine->simulation().forces().size() == 2);
  const int made2 = fine->forcesMade();
  more->magnitude = 2.0;
  REQUIRE(fine->stepSimulation(1));
  CHECK(fine->forcesMade() == made2 + 1);
  // the hidden connection is not written: the file is as before
  CHECK(testutil::write(root).find("revision") == std::string::npos);
  root->unref();
}

TEST_CASE("Callbacks: one STEPPED per step, STATE_CHANGED on reset and on a new state, PROBLEM_CHANGED", "[nodes]") {
  Coin::get();
  SoSeparator* root = testutil::read(kTwo);
  REQUIRE(root);
  auto* fine = testutil::named<SoBSplineDeformSurface>("Fine");
  fine->on = FALSE;
  fine->simulation();
  std::vector<SoBSplineDeformSurface::Event> events;
  std::vector<long> stepsSeen;
  const int id = fine->addCallback([&](SoBSplineDeformSurface* s, SoBSplineDeformSurface::Event e) {
    events.push_back(e);
    if (e == SoBSplineDeformSurface::STEPPED) stepsSeen.push_back(s->simulation().stepCount());
  });
  REQUIRE(fine->stepSimulation(5));
  CHECK(stepsSeen == std::vector<long>({1, 2, 3, 4, 5}));
  events.clear();
  fine->resetSimulation();
  CHECK(events == std::vector<SoBSplineDeformSurface::Event>({SoBSplineDeformSurface::STATE_CHANGED}));
  events.clear();
  fine->damping = 0.7;  // a live edit: the motion goes on
  fine->simulation();
  CHECK(events == std::vector<SoBSplineDeformSurface::Event>({SoBSplineDeformSurface::MODEL_CHANGED}));
  events.clear();
  fine->timeStep = -1.0;  // refused
  fine->simulation();
  REQUIRE(events.size() == 1);
  CHECK(events[0] == SoBSplineDeformSurface::PROBLEM_CHANGED);
  CHECK(fine->problem().kind == SoBSplineDeformSurface::Problem::FIELD);
  CHECK(fine->problem().field == "timeStep");
  CHECK(fine->problem().node == "Fine");
  events.clear();
  fine->timeStep = 0.05;
  fine->simulation();
  CHECK(fine->problem().kind == SoBSplineDeformSurface::Problem::NONE);
  CHECK(events.front() == SoBSplineDeformSurface::PROBLEM_CHANGED);
  fine->removeCallback(id);
  events.clear();
  REQUIRE(fine->stepSimulation(2));
  CHECK(events.empty());
  root->unref();
}

TEST_CASE("Problems: each refused field is named by the field, from the core's typed error", "[nodes]") {
  Coin::get();
  struct Case {
    const char* text;
    const char* field;
  };
  // values the core refuses (the node checks none of these itself)
  const Case cases[] = {{"numUControlPoints 0", "numUControlPoints"}, {"vDegree 9", "vDegree"},
                        {"uDegree 0", "uDegree"},                     {"w11 -1", "w11"},
                        {"mass 0", "mass"},                           {"damping -2", "damping"},
                        {"timeStep 0", "timeStep"},                   {"maxSubSteps 0", "maxSubSteps"},
                        {"energy SHELL poissonRatio 0.7", "poissonRatio"},
                        {"energy SHELL thickness -1", "thickness"},
                        {"restShape SPHERE radius -1", "radius"},
                        {"restShape ELLIPSOID radii 1 0 1", "radii"},
                        {"newtonTolerance 2", "newtonTolerance"},
                        {"boundaryUMin PERIODIC", "boundaryUMin"}};
  for (const Case& c : cases) {
    INFO(c.text);
    SoSeparator* root = testutil::read(std::string("#Inventor V2.1 ascii\nSeparator { DEF Bad SoBSplineDeformSurface { on FALSE ") +
                                       c.text + " } }");
    REQUIRE(root);
    auto* s = testutil::find<SoBSplineDeformSurface>(root);
    s->simulation();
    CHECK(s->problem().kind == SoBSplineDeformSurface::Problem::FIELD);
    CHECK(s->problem().field == c.field);
    CHECK(s->problem().node == "Bad");
    CHECK_THAT(s->problem().message, Catch::Contains(std::string("field '") + c.field + "'"));
    // a new state (Reset, a kept state put back) does not make the refusal go: the field is as it was
    s->resetSimulation();
    CHECK(s->problem().kind == SoBSplineDeformSurface::Problem::FIELD);
    CHECK(s->problem().field == c.field);
    root->unref();
  }
}
