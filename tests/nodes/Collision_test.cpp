// SPDX-License-Identifier: MIT
// COLLISION through the scene graph: obstacles with their transforms, re-gathered only on
// change, bad entries warned about.
#include <Inventor/actions/SoGetBoundingBoxAction.h>
#include <Inventor/nodes/SoTransform.h>
#include <catch2/catch.hpp>
#include <cmath>

#include "NodesTestUtil.h"
#include "bsdeform/Simulation.h"
#include "bsdeform/SoForceField.h"

namespace {
const char* kCloth = R"(
  DEF Cloth SoBSplineDeformSurface {
    on FALSE numUControlPoints 8 numVControlPoints 8
    boundaryUMin FREE boundaryUMax FREE boundaryVMin FREE boundaryVMax FREE
    massModel LUMPED damping 2 timeStep 0.01
    forces [ SoForceField { type GRAVITY force 0 0 -2 },
             DEF Contact SoForceField { type COLLISION obstacles [ USE Box ] thickness 0.02 stiffness 2000 } ]
  }
)";

// Applies an action so that the surface knows its scene (as rendering does), then steps.
SoBSplineDeformSurface* prepare(SoSeparator* root) {
  SoGetBoundingBoxAction bb(SbViewportRegion(100, 100));
  bb.apply(root);
  return testutil::find<SoBSplineDeformSurface>(root);
}
}  // namespace

TEST_CASE("Collision: a Transform moves an obstacle exactly as moving its coordinates would", "[nodes]") {
  SoSeparator* a = testutil::read(std::string("#Inventor V2.1 ascii\nSeparator {\n"
                                              "Separator { Transform { translation 0.5 0.5 -1.05 } DEF Box Cube { width 3 height 3 depth 2 } }\n") +
                                  kCloth + "}\n");
  SoSeparator* b = testutil::read(std::string("#Inventor V2.1 ascii\nSeparator {\n"
                                              "Separator { Coordinate3 { point [ -1 -1 -2.05, 2 -1 -2.05, -1 2 -2.05, 2 2 -2.05,"
                                              " -1 -1 -0.05, 2 -1 -0.05, -1 2 -0.05, 2 2 -0.05 ] }\n"
                                              " DEF Box IndexedFaceSet { coordIndex [ 0 2 3 1 -1, 4 5 7 6 -1, 0 1 5 4 -1,"
                                              " 2 6 7 3 -1, 0 4 6 2 -1, 1 3 7 5 -1 ] } }\n") +
                                  kCloth + "}\n");
  REQUIRE(a);
  REQUIRE(b);
  SoBSplineDeformSurface* sa = prepare(a);
  SoBSplineDeformSurface* sb = prepare(b);
  REQUIRE(sa->stepSimulation(600));
  REQUIRE(sb->stepSimulation(600));
  const double za = sa->simulation().evaluate(0.5, 0.5).position.z();
  const double zb = sb->simulation().evaluate(0.5, 0.5).position.z();
  CHECK(za == Approx(-0.05 + 0.02 - 2.0 / 2000.0).margin(2e-4));  // resting on the box top
  // Coin's geometry is single precision: the Cube's corners pass through a float matrix
  CHECK(std::abs(za - zb) < 1e-6);
  CHECK((sa->simulation().current() - sb->simulation().current()).cwiseAbs().maxCoeff() < 1e-6);
  a->unref();
  b->unref();
}

TEST_CASE("Collision: a static obstacle is gathered once, a moved Transform refits it", "[nodes]") {
  SoSeparator* root = testutil::read(std::string("#Inventor V2.1 ascii\nSeparator {\n"
                                                 "Separator { DEF Move Transform { translation 0.5 0.5 -1.05 } DEF Box Cube { width 3 height 3 depth 2 } }\n") +
                                     kCloth + "}\n");
  REQUIRE(root);
  SoBSplineDeformSurface* s = prepare(root);
  REQUIRE(s->stepSimulation(50));
  CHECK(s->obstacleBuilds() == 1);
  CHECK(s->obstacleRefits() == 0);
  REQUIRE(s->stepSimulation(50));
  CHECK(s->obstacleBuilds() == 1);  // nothing moved: no rebuild, no refit
  CHECK(s->obstacleRefits() == 0);
  const double before = s->simulation().evaluate(0.5, 0.5).position.z();
  // the box rises by 0.03 (less than the thickness: a faster obstacle would pass through)
  testutil::named<SoTransform>("Move")->translation.setValue(0.5f, 0.5f, -1.02f);
  REQUIRE(s->stepSimulation(800));
  CHECK(s->obstacleBuilds() == 1);
  CHECK(s->obstacleRefits() == 1);
  // resting on the new top: -0.02 + thickness 0.02 - rho g / k
  CHECK(s->simulation().evaluate(0.5, 0.5).position.z() == Approx(-0.001).margin(2e-4));
  CHECK(before < -0.02);  // below the new top before the move
  root->unref();
}

TEST_CASE("Collision: NULL, the surface itself and an empty subgraph are warned about, the rest collide", "[nodes]") {
  auto& messages = testutil::Coin::get().messages;
  messages.clear();
  SoSeparator* root = testutil::read(
      "#Inventor V2.1 ascii\nSeparator {\n"
      "Separator { Transform { translation 0.5 0.5 -1.05 } DEF Box Cube { width 3 height 3 depth 2 } }\n"
      "DEF Empty Separator { }\n"
      "DEF Cloth SoBSplineDeformSurface { on FALSE numUControlPoints 6 numVControlPoints 6\n"
      "  boundaryUMin FREE boundaryUMax FREE boundaryVMin FREE boundaryVMax FREE massModel LUMPED damping 2 timeStep 0.01\n"
      "  forces [ SoForceField { type GRAVITY force 0 0 -2 },\n"
      "    SoForceField { type COLLISION obstacles [ USE Empty , USE Box ] thickness 0.02 stiffness 2000 } ] }\n"
      "}\n");
  REQUIRE(root);
  auto* cloth = prepare(root);
  // NULL and the surface itself, added in code (Coin reads no NULL in a node list, and a file
  // cannot USE a node inside its own definition)
  auto* contact = static_cast<SoForceField*>(static_cast<SoEngine*>(cloth->forces[1]));
  contact->obstacles.set1Value(2, nullptr);
  contact->obstacles.set1Value(3, cloth);
  REQUIRE(cloth->stepSimulation(400));
  std::string all;
  for (const auto& m : messages) all += m + "\n";
  INFO(all);
  CHECK(all.find("'obstacles' [2] is NULL") != std::string::npos);
  CHECK(all.find("[0] (Separator 'Empty') has no triangles") != std::string::npos);
  CHECK(all.find("is the surface itself") != std::string::npos);
  CHECK(cloth->simulation().evaluate(0.5, 0.5).position.z() > -0.05);  // still resting on the box
  root->unref();
}
