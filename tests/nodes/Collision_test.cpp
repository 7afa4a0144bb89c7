// SPDX-License-Identifier: MIT
// COLLISION through the scene graph: obstacles with their transforms, re-gathered only on
// change, bad entries warned about.
#include <Inventor/SoOffscreenRenderer.h>
#include <Inventor/nodes/SoPerspectiveCamera.h>
#include <Inventor/nodes/SoSeparator.h>
#include <Inventor/nodes/SoTransform.h>
#include <catch2/catch.hpp>
#include <cmath>

#include "NodesTestUtil.h"
#include "bsdeform/contact/BarrierContact.h"
#include "bsdeform/contact/Contact.h"
#include "bsdeform/contact/Distance.h"
#include "bsdeform/OffscreenRenderer.h"
#include "bsdeform/SceneReader.h"
#include "bsdeform/SceneObstacles.h"
#include "bsdeform/dynamics/Simulation.h"
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

// The cloth above a 3 x 3 x 2 Cube whose top is at z = -0.05, moved there by `transform`.
std::string clothOnBox(const char* transform = "Transform { translation 0.5 0.5 -1.05 }") {
  return std::string("#Inventor V2.1 ascii\nSeparator {\nSeparator { ") + transform +
         " DEF Box Cube { width 3 height 3 depth 2 } }\n" + kCloth + "}\n";
}

// Where the cloth rests on that top: the thickness above it, less the penalty's static depth
// rho g / k (mass 1 per unit parameter area, g = 2, k = 2000).
constexpr double kRestingZ = -0.05 + 0.02 - 2.0 / 2000.0;

// Gives every surface of `root` its scene (as SceneRunner and the front ends do); the first.
SoBSplineDeformSurface* prepare(SoSeparator* root) {
  for (SoBSplineDeformSurface* s : bsdeform::sceneSurfaces(root)) s->setScene(root);
  return testutil::find<SoBSplineDeformSurface>(root);
}
}  // namespace

TEST_CASE("Collision: a Transform moves an obstacle exactly as moving its coordinates would", "[nodes][slow]") {
  SoSeparator* a = testutil::read(clothOnBox());
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
  CHECK(za == Approx(kRestingZ).margin(2e-4));  // resting on the box top
  // Coin's geometry is single precision: the Cube's corners pass through a float matrix
  CHECK(std::abs(za - zb) < 1e-6);
  CHECK((sa->simulation().current() - sb->simulation().current()).cwiseAbs().maxCoeff() < 1e-6);
  a->unref();
  b->unref();
}

TEST_CASE("Collision: a static obstacle is gathered once, a moved Transform refits it", "[nodes][slow]") {
  SoSeparator* root = testutil::read(clothOnBox("DEF Move Transform { translation 0.5 0.5 -1.05 }"));
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

TEST_CASE("Collision: an image from a short-lived graph around the scene keeps the obstacles' frames", "[nodes][slow]") {
  // An offscreen image puts a camera and a light above the scene and deletes them afterwards:
  // the surface keeps the scene it was given, or the Cube would lose its Transform (and the
  // cloth would fall through it) after the first image.
  SoSeparator* root = testutil::read(clothOnBox());
  REQUIRE(root);
  SoBSplineDeformSurface* s = prepare(root);
  REQUIRE(s->stepSimulation(100));
  bsdeform::Image image;
  std::string error;
  REQUIRE(bsdeform::renderOffscreen(root, 64, 48, image, error));
  CHECK(s->scene() == root);
  REQUIRE(s->stepSimulation(500));
  CHECK(s->simulation().evaluate(0.5, 0.5).position.z() == Approx(kRestingZ).margin(2e-4));
  root->unref();
}

TEST_CASE("Collision: a surface given no scene (a plain Coin viewer) takes its render's once", "[nodes][slow]") {
  SoSeparator* root = testutil::read(clothOnBox());
  REQUIRE(root);
  auto* s = testutil::find<SoBSplineDeformSurface>(root);
  CHECK(s->scene() == nullptr);
  bsdeform::Image image;
  std::string error;
  REQUIRE(bsdeform::renderOffscreen(new SoSeparator, 8, 8, image, error));  // GL contexts for Coin
  auto* viewerRoot = new SoSeparator;  // a plain viewer's graph: its camera, then the scene
  viewerRoot->ref();
  viewerRoot->addChild(new SoPerspectiveCamera);
  viewerRoot->addChild(root);
  SoOffscreenRenderer renderer(SbViewportRegion(64, 48));  // Coin's own, as such a program uses
  REQUIRE(renderer.render(viewerRoot));
  CHECK(s->scene() == viewerRoot);
  REQUIRE(s->stepSimulation(600));
  CHECK(s->simulation().evaluate(0.5, 0.5).position.z() == Approx(kRestingZ).margin(2e-4));  // on the box
  viewerRoot->unref();
}

TEST_CASE("Collision: Coin's solids are gathered as closed meshes, under any transform", "[nodes]") {
  // Closed: contact is one-sided and knows the inside. Coin's Sphere, Cone and Cylinder have
  // seams whose copies differ in the last float digit; the gathering must weld them.
  SoSeparator* root = testutil::read(
      "#Inventor V2.1 ascii\nSeparator {\n"
      " Transform { translation 0.3 -2 5 rotation 1 2 3 0.7 scaleFactor 1.5 1.5 1.5 }\n"
      " DEF S Sphere { radius 0.25 }  DEF C Cone { }  DEF Y Cylinder { }  DEF B Cube { }\n"
      " DEF Fine Separator { Complexity { value 1 } Sphere { } }\n"
      " DEF Sheet Separator { Coordinate3 { point [ 0 0 0, 1 0 0, 0 1 0 ] } FaceSet { } }\n"
      "}\n");
  REQUIRE(root);
  auto* field = new SoForceField;
  field->ref();
  field->type = SoForceField::COLLISION;
  for (const char* name : {"S", "C", "Y", "B", "Fine", "Sheet"}) field->obstacles.set1Value(field->obstacles.getNum(), testutil::named<SoNode>(name));
  bsdeform::SceneObstacles gathered;
  std::vector<std::string> warnings;
  gathered.update(root, nullptr, field->obstacles, field->obstacleNames, true, warnings);
  CHECK(warnings.empty());
  const auto& obstacles = gathered.world()->obstacles;
  REQUIRE(obstacles.size() == 6);
  for (int i = 0; i < 5; ++i) {
    INFO("obstacle " << i);
    CHECK(obstacles[std::size_t(i)].closed);
    CHECK(obstacles[std::size_t(i)].tree->droppedTriangles() == 0);
  }
  CHECK_FALSE(obstacles[5].closed);  // a single triangle is an open sheet
  field->unref();
  root->unref();
}

TEST_CASE("Collision: NULL, an unknown name, the surface itself and an empty subgraph are warned about, the rest collide", "[nodes]") {
  auto& messages = testutil::Coin::get().messages;
  messages.clear();
  SoSeparator* root = testutil::read(
      "#Inventor V2.1 ascii\nSeparator {\n"
      "Separator { Transform { translation 0.5 0.5 -1.05 } DEF Box Cube { width 3 height 3 depth 2 } }\n"
      "DEF Empty Separator { }\n"
      "DEF Cloth SoBSplineDeformSurface { on FALSE numUControlPoints 6 numVControlPoints 6\n"
      "  boundaryUMin FREE boundaryUMax FREE boundaryVMin FREE boundaryVMax FREE massModel LUMPED damping 2 timeStep 0.01\n"
      "  forces [ SoForceField { type GRAVITY force 0 0 -2 },\n"
      "    SoForceField { type COLLISION obstacles [ USE Empty , USE Box ] obstacleNames [ \"Nowhere\", \"Cloth\" ]\n"
      "      thickness 0.02 stiffness 2000 } ] }\n"
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
  CHECK(all.find("field 'obstacleNames' [0] 'Nowhere': no node of that name in the scene") != std::string::npos);
  CHECK(all.find("field 'obstacleNames' [1] (SoBSplineDeformSurface 'Cloth') is the surface itself") != std::string::npos);
  CHECK(cloth->simulation().evaluate(0.5, 0.5).position.z() > -0.05);  // still resting on the box
  root->unref();
}


TEST_CASE("Collision: an indexed shape with indices out of range is skipped with a warning, not read", "[nodes][slow]") {
  // Coin reads coordinates at coordIndex without a range check (the fuzzer found the crash);
  // the bad shape is left out, the good one in the same obstacle still holds the cloth.
  auto& messages = testutil::Coin::get().messages;
  messages.clear();
  SoSeparator* root = testutil::read(std::string("#Inventor V2.1 ascii\nSeparator {\n"
                                                 "DEF Mesh Separator {\n"
                                                 " Coordinate3 { point [ -1 -1 -0.05, 2 -1 -0.05, 2 2 -0.05, -1 2 -0.05 ] }\n"
                                                 " DEF Bad IndexedFaceSet { coordIndex [ 0, 1, 40000, -1 ] }\n"
                                                 " Separator { Normal { vector [ 0 0 1, 0 0 1 ] }\n"
                                                 "  DEF BadNormal IndexedFaceSet { coordIndex [ 0, 1, 2, -1 ] normalIndex [ 0, 1, 7, -1 ] } }\n"
                                                 " IndexedFaceSet { coordIndex [ 0, 1, 2, 3, -1 ] }\n"
                                                 "}\n") +
                                     std::string(kCloth).replace(std::string(kCloth).find("USE Box"), 7, "USE Mesh") + "}\n");
  REQUIRE(root);
  SoBSplineDeformSurface* s = prepare(root);
  REQUIRE(s->stepSimulation(600));
  std::string all;
  for (const auto& m : messages) all += m + "\n";
  INFO(all);
  CHECK(all.find("IndexedFaceSet 'Bad' skipped: coordIndex [2] = 40000 with 4 coordinates") != std::string::npos);
  CHECK(all.find("IndexedFaceSet 'BadNormal' skipped: normalIndex [2] = 7 with 2 normals") != std::string::npos);
  CHECK(s->simulation().evaluate(0.5, 0.5).position.z() == Approx(kRestingZ).margin(2e-4));
  root->unref();
}

TEST_CASE("Collision: two surfaces that list each other collide both ways with equal and opposite forces",
          "[nodes][slow]") {
  // A lower cloth B lies on a Cube; an upper cloth A, of another size and resolution, falls on
  // it. Each lists the other as an obstacle: A lists B in `obstacles`, B names A in
  // `obstacleNames` (a file cannot USE a node before its definition). At rest the contact carries A's weight, and what B feels from A is what A feels
  // from B, with the sign reversed, to within the two quadratures and tessellations.
  SoSeparator* root = testutil::read(R"(#Inventor V2.1 ascii
Separator {
  Separator { Transform { translation 0.5 0.5 -1 } DEF Box Cube { width 4 height 4 depth 2 } }
  Separator {
    Transform { translation -0.25 -0.25 0.0199 scaleFactor 1.5 1.5 1 }
    DEF B SoBSplineDeformSurface {
      on FALSE numUControlPoints 12 numVControlPoints 12
      boundaryUMin FREE boundaryUMax FREE boundaryVMin FREE boundaryVMax FREE
      massModel LUMPED damping 4 timeStep 0.01 mass 1
      forces [ SoForceField { type GRAVITY force 0 0 -2 },
               SoForceField { type COLLISION obstacles [ USE Box ] thickness 0.02 stiffness 20000 damping 30 },
               DEF FromA SoForceField { type COLLISION obstacleNames "A" thickness 0.02 stiffness 5000 damping 30 } ]
    }
  }
  Separator {
    Transform { translation 0.2 0.2 0.08 }
    DEF A SoBSplineDeformSurface {
      on FALSE numUControlPoints 9 numVControlPoints 9
      boundaryUMin FREE boundaryUMax FREE boundaryVMin FREE boundaryVMax FREE
      massModel LUMPED damping 4 timeStep 0.01 mass 1
      w10 0.2 w01 0.2
      forces [ SoForceField { type GRAVITY force 0 0 -2 },
               SoForceField { type COLLISION obstacles [ USE B ] thickness 0.02 stiffness 5000 damping 30 } ]
    }
  }
}
)");
  REQUIRE(root);
  auto* a = static_cast<SoBSplineDeformSurface*>(SoNode::getByName("A"));
  auto* b = static_cast<SoBSplineDeformSurface*>(SoNode::getByName("B"));
  auto* fromA = static_cast<SoForceField*>(SoBase::getNamedBase("FromA", SoForceField::getClassTypeId()));
  REQUIRE(a);
  REQUIRE(b);
  REQUIRE(fromA);
  prepare(root);
  for (int k = 0; k < 300; ++k) {
    REQUIRE(b->stepSimulation(1));
    REQUIRE(a->stepSimulation(1));
  }
  INFO("A at " << a->simulation().evaluate(0.5, 0.5).position.transpose() << ", B at "
               << b->simulation().evaluate(0.5, 0.5).position.transpose() << ", A forces " << a->simulation().forces().size());
  const Eigen::Vector3d onA = testutil::contactLoadFrom(a, b);
  const Eigen::Vector3d onB = testutil::contactLoadFrom(b, a);
  INFO("on A " << onA.transpose() << ", on B " << onB.transpose());
  // A (unit parameter square, mass 1 per unit parameter area, g = 2) rests: the contact carries 2
  CHECK(onA.z() == Approx(2.0).epsilon(0.02));
  CHECK((onA + onB).norm() < 0.02 * onA.norm());
  // A rests on B at the penalty's static depth: tau - rho g / k = 0.02 - 2 / 5000 above it
  const double gap = (a->simulation().evaluate(0.5, 0.5).position.z() + 0.08) -
                     (b->simulation().evaluate(0.5, 0.5).position.z() + 0.0199);
  CHECK(gap == Approx(0.02 - 2.0 / 5000.0).margin(2e-5));
  root->unref();
}

namespace {
// The sheet of the BARRIER cases over the box top at z = -0.05 (thickness 0.01, dhat 0.002):
// 0.6 s in which it falls 0.04 onto the wider top and lies there, never below the offset.
void settlesOnBoxTop(SoBSplineDeformSurface* s) {
  for (int k = 0; k < 30; ++k) {
    const bool ok = s->stepSimulation(1);
    INFO("step " << k << ": " << s->simulation().statusMessage());
    REQUIRE(ok);
    CHECK(s->simulation().evaluate(0.5, 0.5).position.z() > -0.05 + 0.01 - 1e-9);
  }
  CHECK(s->simulation().evaluate(0.5, 0.5).position.z() < -0.05 + 0.01 + 0.002 + 1e-3);  // it got there
}
}  // namespace

TEST_CASE("Collision: method BARRIER reads its fields, keeps a SHELL cloth off a box and is refused by EXPLICIT",
          "[nodes][slow]") {
  auto scene = [](const char* integrator) {
    return std::string("#Inventor V2.1 ascii\nSeparator {\n"
                       "Separator { Transform { translation 0.5 0.5 -1.05 } DEF Box Cube { width 1.4 height 1.4 depth 2 } }\n"
                       "DEF Cloth SoBSplineDeformSurface {\n"
                       "  on FALSE numUControlPoints 6 numVControlPoints 6\n"
                       "  boundaryUMin FREE boundaryUMax FREE boundaryVMin FREE boundaryVMax FREE\n"
                       "  energy SHELL youngsModulus 0.821e6 poissonRatio 0.243 thickness 0.318e-3 density 472.6\n"
                       "  damping 1 timeStep 0.02 integrator ") +
           integrator +
           "\n  forces [ SoForceField { type GRAVITY force 0 0 -9.81 },\n"
           "           DEF Contact SoForceField { type COLLISION obstacles [ USE Box ] method BARRIER thickness 0.01"
           " dhat 0.002 proxySamples 3 } ]\n}\n}\n";
  };
  SoSeparator* root = testutil::read(scene("BACKWARD_EULER"));
  REQUIRE(root);
  SoBSplineDeformSurface* s = prepare(root);
  REQUIRE(s->forces.getNum() == 2);
  auto* contact = static_cast<SoForceField*>(s->forces[1]);
  CHECK(contact->method.getValue() == SoForceField::BARRIER);
  CHECK(contact->proxySamples.getValue() == 3);
  CHECK(contact->dhat.getValue() == 0.002);
  CHECK_FALSE(contact->selfContact.getValue());
  settlesOnBoxTop(s);
  root->unref();

  root = testutil::read(scene("EXPLICIT"));
  REQUIRE(root);
  s = prepare(root);
  CHECK_FALSE(s->stepSimulation(1));
  CHECK_THAT(s->simulation().statusMessage(), Catch::Contains("BACKWARD_EULER"));
  root->unref();
}

TEST_CASE("Collision: method BARRIER refuses a cloth that starts inside an obstacle and names the obstacle and where",
          "[nodes]") {
  // the Cube's top at z = 0.05: the flat cloth at z = 0 starts inside it
  SoSeparator* root = testutil::read(
      "#Inventor V2.1 ascii\nSeparator {\n"
      "Separator { Transform { translation 0.5 0.5 -0.95 } DEF Block Cube { width 0.6 height 0.6 depth 2 } }\n"
      "DEF Cloth SoBSplineDeformSurface {\n"
      "  on FALSE numUControlPoints 6 numVControlPoints 6\n"
      "  boundaryUMin FREE boundaryUMax FREE boundaryVMin FREE boundaryVMax FREE\n"
      "  energy SHELL youngsModulus 0.821e6 poissonRatio 0.243 thickness 0.318e-3 density 472.6\n"
      "  damping 1 timeStep 0.02 integrator BACKWARD_EULER\n"
      "  forces [ SoForceField { type GRAVITY force 0 0 -9.81 },\n"
      "           SoForceField { type COLLISION obstacles [ USE Block ] method BARRIER thickness 0.01"
      " dhat 0.002 proxySamples 3 } ]\n}\n}\n");
  REQUIRE(root);
  SoBSplineDeformSurface* s = prepare(root);
  const bsdeform::ControlNet before = s->simulation().current();
  CHECK_FALSE(s->stepSimulation(1));
  CHECK(s->simulation().status() == bsdeform::Status::Refused);
  CHECK_THAT(s->simulation().statusMessage(),
             Catch::Contains("obstacle 1 (Cube 'Block')") && Catch::Contains("(u, v) = (") &&
                 Catch::Contains("within the contact offset thickness 0.01 m"));
  CHECK(s->simulation().current() == before);
  root->unref();
}

TEST_CASE("Collision: method BARRIER under the paper's energy with BACKWARD_EULER keeps a sheet off a box", "[nodes]") {
  SoSeparator* root = testutil::read(
      "#Inventor V2.1 ascii\nSeparator {\n"
      "Separator { Transform { translation 0.5 0.5 -1.05 } DEF Box Cube { width 1.4 height 1.4 depth 2 } }\n"
      "DEF Sheet SoBSplineDeformSurface {\n"
      "  on FALSE numUControlPoints 6 numVControlPoints 6\n"
      "  boundaryUMin FREE boundaryUMax FREE boundaryVMin FREE boundaryVMax FREE\n"
      "  massModel LUMPED mass 0.15 damping 0.02 timeStep 0.02 integrator BACKWARD_EULER\n"
      "  forces [ SoForceField { type GRAVITY force 0 0 -9.81 },\n"
      "           SoForceField { type COLLISION obstacles [ USE Box ] method BARRIER thickness 0.01"
      " dhat 0.002 proxySamples 3 } ]\n}\n}\n");
  REQUIRE(root);
  SoBSplineDeformSurface* s = prepare(root);
  REQUIRE(s->energy.getValue() == SoBSplineDeformSurface::PAPER_ENERGY);
  settlesOnBoxTop(s);
  root->unref();
}

TEST_CASE("Collision: two surfaces with method BARRIER, one dropped on the other, never come within the offset",
          "[nodes][slow]") {
  // the lower sheet lies on a plate; the upper, turned by 45 degrees, falls onto it; each lists
  // the other (the lower by name: a file cannot USE a node before its definition)
  using namespace bsdeform;
  const std::string sheet = "  on FALSE numUControlPoints 6 numVControlPoints 6\n"
                            "  boundaryUMin FREE boundaryUMax FREE boundaryVMin FREE boundaryVMax FREE\n"
                            "  energy SHELL youngsModulus 0.821e6 poissonRatio 0.243 thickness 0.318e-3 density 472.6\n"
                            "  damping 1 timeStep 0.02 integrator BACKWARD_EULER maxNewtonIterations 200\n";
  const std::string contact = " method BARRIER thickness 0.01 dhat 0.002 proxySamples 3 friction 0.3 }";
  SoSeparator* root = testutil::read(
      "#Inventor V2.1 ascii\nSeparator {\n"
      "DEF Plate Separator { Transform { translation 0.5 0.5 -0.1 } Cube { width 3 height 3 depth 0.17 } }\n"
      "DEF Lower SoBSplineDeformSurface {\n" + sheet +
      "  forces [ SoForceField { type GRAVITY force 0 0 -9.81 },\n"
      "           SoForceField { type COLLISION obstacles [ USE Plate ] obstacleNames \"Upper\"" + contact + " ]\n}\n"
      "Separator { Transform { translation 0.5 0.5 0.06 rotation 0 0 1 0.785 } Transform { translation -0.5 -0.5 0 }\n"
      "DEF Upper SoBSplineDeformSurface {\n" + sheet +
      "  forces [ SoForceField { type GRAVITY force 0 0 -9.81 },\n"
      "           SoForceField { type COLLISION obstacles [ USE Plate, USE Lower ]" + contact + " ]\n}\n}\n}\n");
  REQUIRE(root);
  prepare(root);
  const std::vector<SoBSplineDeformSurface*> surfaces = bsdeform::sceneSurfaces(root);
  REQUIRE(surfaces.size() == 2);
  // a surface's proxy in the world
  auto proxy = [&](SoBSplineDeformSurface* s, ContactMesh& m) {
    std::vector<Eigen::Vector3d> v;
    std::vector<Eigen::Vector3i> t;
    s->collisionProxyMesh(v, t);
    Eigen::Matrix3d A;
    Eigen::Vector3d b;
    REQUIRE(bsdeform::surfaceFrame(root, s, A, b));
    m.start.resize(Eigen::Index(v.size()), 3);
    for (size_t i = 0; i < v.size(); ++i) m.start.row(Eigen::Index(i)) = (A * v[i] + b).transpose();
    m.end = m.start;
    TriangleMesh tm;
    tm.vertices = v;
    tm.triangles = t;
    const ContactMesh shape = staticContactMesh(tm);
    m.triangles = shape.triangles;
    m.edges = shape.edges;
  };
  auto clearance = [](const ContactMesh& a, const ContactMesh& b) {  // brute force, every pair
    auto row = [](const ContactMesh& m, Eigen::Index i) { return Eigen::Vector3d(m.start.row(i).transpose()); };
    double d2 = 1e300;
    for (int k = 0; k < 2; ++k) {
      const ContactMesh& p = k ? b : a;
      const ContactMesh& q = k ? a : b;
      for (Eigen::Index v = 0; v < p.start.rows(); ++v)
        for (Eigen::Index t = 0; t < q.triangles.rows(); ++t)
          d2 = std::min(d2, pointTriangleDistanceSquared(row(p, v), row(q, q.triangles(t, 0)), row(q, q.triangles(t, 1)),
                                                         row(q, q.triangles(t, 2))));
    }
    for (Eigen::Index e = 0; e < a.edges.rows(); ++e)
      for (Eigen::Index f = 0; f < b.edges.rows(); ++f)
        d2 = std::min(d2, edgeEdgeDistanceSquared(row(a, a.edges(e, 0)), row(a, a.edges(e, 1)), row(b, b.edges(f, 0)),
                                                  row(b, b.edges(f, 1))));
    return std::sqrt(d2);
  };
  double gap = 0.0;
  for (int k = 0; k < 25; ++k) {  // 0.5 s: the upper sheet lands at about t = 0.2
    for (SoBSplineDeformSurface* s : surfaces) {
      const bool ok = s->stepSimulation(1);
      INFO("step " << k << ", " << s->getName().getString() << ": " << s->simulation().statusMessage());
      REQUIRE(ok);
    }
    ContactMesh lower, upper;
    proxy(surfaces[0], lower);
    proxy(surfaces[1], upper);
    gap = clearance(lower, upper);
    INFO("step " << k);
    CHECK(gap >= 0.01 * (1.0 - 1e-9));
  }
  CHECK(gap < 0.01 + 0.002 + 0.002);  // it came down and lies on the lower sheet
  root->unref();
}
