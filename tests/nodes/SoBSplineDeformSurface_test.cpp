// SPDX-License-Identifier: MIT
#include <Inventor/SbViewportRegion.h>
#include <Inventor/SoOffscreenRenderer.h>
#include <Inventor/SoPickedPoint.h>
#include <Inventor/actions/SoCallbackAction.h>
#include <Inventor/actions/SoGetBoundingBoxAction.h>
#include <Inventor/fields/SoSFTime.h>
#include <Inventor/actions/SoRayPickAction.h>
#include <Inventor/engines/SoCalculator.h>
#include <Inventor/SbTime.h>
#include <Inventor/sensors/SoFieldSensor.h>
#include <Inventor/sensors/SoSensorManager.h>
#include <Inventor/nodes/SoComplexity.h>
#include <catch2/catch.hpp>
#include <limits>
#include <cmath>
#include <memory>
#include <vector>

#include <algorithm>

#include "NodesTestUtil.h"
#include "bsdeform/OffscreenRenderer.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/SceneRunner.h"
#include "bsdeform/SoForceField.h"

using testutil::Coin;

namespace {
// The warning of a surface with `fields` (and on FALSE) after one step: what a refused field says.
std::string warningAfterOneStep(const std::string& fields) {
  SoSeparator* r = testutil::read("#Inventor V2.1 ascii\nSeparator { SoBSplineDeformSurface { " + fields + " on FALSE } }");
  REQUIRE(r);
  auto* n = testutil::find<SoBSplineDeformSurface>(r);
  n->stepSimulation(1);
  const std::string w = n->lastWarning();
  r->unref();
  return w;
}

const char* kScene = R"IV(#Inventor V2.1 ascii
Separator {
  DEF Surf SoBSplineDeformSurface {
    numUControlPoints 7 numVControlPoints 6 uDegree 3 vDegree 2
    w10 0.2 w01 0.15 w11 0.02 w20 0.03 w02 0.01
    massModel NODAL mass 1.5 damping 0.8 timeStep 0.05 integrator EXPLICIT reference REST
    on FALSE speed 2
    forces [ DEF F1 SoForceField { type REGION force 0 0 1 magnitude 40 regionMin 0.3 0.2 regionMax 0.7 0.6 },
             DEF F2 SoForceField { type EXPRESSION expression [ "0", "5*sin(u*pi)", "10*cos(v*pi)*sin(u*pi)" ] },
             DEF F3 SoForceField { type POINT point 0.25 0.75 force 1 -2 3 } ]
  }
}
)IV";

int countTriangles(SoNode* root) {
  int count = 0;
  SoCallbackAction ca;
  ca.addTriangleCallback(
      SoBSplineDeformSurface::getClassTypeId(),
      [](void* data, SoCallbackAction*, const SoPrimitiveVertex*, const SoPrimitiveVertex*, const SoPrimitiveVertex*) {
        ++*static_cast<int*>(data);
      },
      &count);
  ca.apply(root);
  return count;
}
}  // namespace

TEST_CASE("SoBSplineDeformSurface: a scene reads without warnings and write-read-write is identical", "[nodes]") {
  Coin::get().messages.clear();
  SoSeparator* root = testutil::read(kScene);
  REQUIRE(root);
  auto* s = testutil::find<SoBSplineDeformSurface>(root);
  REQUIRE(s);
  CHECK(s->numUControlPoints.getValue() == 7);
  CHECK(s->vDegree.getValue() == 2);
  CHECK(s->w11.getValue() == 0.02);
  CHECK(s->forces.getNum() == 3);
  CHECK(s->simulation().parameters().numU == 7);
  // built with the model: their stiffness sets the sub-step at which a stored state resumes
  CHECK(s->simulation().forces().size() == 3);
  s->stepSimulation(3);
  CHECK(s->simulation().forces().size() == 3);
  CHECK(s->simulation().stepCount() == 3);
  const std::string w1 = testutil::write(root);
  SoSeparator* again = testutil::read(w1);
  REQUIRE(again);
  const std::string w2 = testutil::write(again);
  CHECK(w1 == w2);
  CHECK(Coin::get().messages.empty());
  // the state survives the trip
  auto* s2 = testutil::find<SoBSplineDeformSurface>(again);
  CHECK(s2->simulation().stepCount() == 3);
  CHECK((s2->simulation().current() - s->simulation().current()).cwiseAbs().maxCoeff() < 1e-14);
  root->unref();
  again->unref();
}

TEST_CASE("SoBSplineDeformSurface: resuming from a saved file follows the uninterrupted trajectory", "[nodes]") {
  for (const char* integ : {"EXPLICIT", "IMPLICIT"}) {
    std::string scene = kScene;
    scene.replace(scene.find("EXPLICIT"), 8, integ);
    SoSeparator* a = testutil::read(scene);
    REQUIRE(a);
    auto* sa = testutil::find<SoBSplineDeformSurface>(a);
    sa->stepSimulation(40);
    SoSeparator* b = testutil::read(testutil::write(a));  // save, reload
    REQUIRE(b);
    auto* sb = testutil::find<SoBSplineDeformSurface>(b);
    sa->stepSimulation(60);
    sb->stepSimulation(60);
    INFO(integ);
    CHECK(sb->simulation().time() == Approx(sa->simulation().time()));
    CHECK(sa->simulation().deformationNorm() > 0.01);
    CHECK((sb->simulation().current() - sa->simulation().current()).cwiseAbs().maxCoeff() < 1e-12);
    a->unref();
    b->unref();
  }
}

TEST_CASE("SoBSplineDeformSurface: a SHELL scene resumes from its saved file on the uninterrupted trajectory",
          "[nodes]") {
  const char* shell = R"IV(#Inventor V2.1 ascii
Separator {
  DEF Sheet SoBSplineDeformSurface {
    numUControlPoints 6 numVControlPoints 5
    energy SHELL youngsModulus 2e4 poissonRatio 0.3 thickness 0.002 density 500
    damping 0.3 timeStep 0.01 integrator EXPLICIT on FALSE
    boundaryUMin FREE boundaryUMax FREE boundaryVMin FREE boundaryVMax SIMPLY_SUPPORTED
    forces [ SoForceField { type GRAVITY force 0 0 -9.81 },
             SoForceField { type REGION regionMin 1 0 regionMax 1 1 force 0 0.3 0 } ]
  }
}
)IV";
  for (const char* integ : {"EXPLICIT", "IMPLICIT"}) {
    std::string scene = shell;
    scene.replace(scene.find("EXPLICIT"), 8, integ);
    SoSeparator* a = testutil::read(scene);
    REQUIRE(a);
    auto* sa = testutil::find<SoBSplineDeformSurface>(a);
    REQUIRE(sa->stepSimulation(20));
    REQUIRE(sa->simulation().parameters().energy == bsdeform::EnergyModel::Shell);
    const std::string text = testutil::write(a);
    CHECK(text.find("energy SHELL") != std::string::npos);
    SoSeparator* b = testutil::read(text);  // save, reload
    REQUIRE(b);
    auto* sb = testutil::find<SoBSplineDeformSurface>(b);
    sa->stepSimulation(20);
    sb->stepSimulation(20);
    INFO(integ);
    CHECK(sa->simulation().deformationNorm() > 0.05);  // it swung down
    CHECK((sb->simulation().current() - sa->simulation().current()).cwiseAbs().maxCoeff() < 1e-12);
    a->unref();
    b->unref();
  }
}

TEST_CASE("SoBSplineDeformSurface: a model rebuilt for a new mass keeps gravity an acceleration without a new force",
          "[nodes]") {
  // A free sheet under gravity alone falls rigidly at g whatever its mass: the force reads the
  // mass per area (rho t for SHELL, m / (h1 h2) for the paper's model) from the model it acts on,
  // so a changed thickness, density or mass needs no new force (issue 34, the seam).
  const char* text = R"IV(#Inventor V2.1 ascii
Separator {
  SoBSplineDeformSurface {
    numUControlPoints 6 numVControlPoints 5
    ENERGY
    damping 0 timeStep 0.01 integrator BACKWARD_EULER on FALSE
    boundaryUMin FREE boundaryUMax FREE boundaryVMin FREE boundaryVMax FREE
    forces [ SoForceField { type GRAVITY force 0 0 -9.81 } ]
  }
}
)IV";
  const std::pair<const char*, const char*> models[] = {
      {"energy SHELL youngsModulus 2e4 poissonRatio 0.3 thickness 0.002 density 500", "thickness"},
      {"energy SHELL youngsModulus 2e4 poissonRatio 0.3 thickness 0.002 density 500", "density"},
      {"energy PAPER massModel LUMPED mass 1", "mass"}};
  for (const auto& [energy, field] : models) {
    INFO(energy << ", " << field);
    std::string scene = text;
    scene.replace(scene.find("ENERGY"), 6, energy);
    SoSeparator* root = testutil::read(scene);
    REQUIRE(root);
    auto* s = testutil::find<SoBSplineDeformSurface>(root);
    auto fall = [s] {
      REQUIRE(s->stepSimulation(3));
      const bsdeform::Simulation& sim = s->simulation();
      const Eigen::VectorXd fell = sim.current().col(2) - sim.rest().col(2);
      CHECK(fell.maxCoeff() - fell.minCoeff() < 1e-9);  // rigid: every point fell by the same amount
      CHECK((sim.current().leftCols(2) - sim.rest().leftCols(2)).cwiseAbs().maxCoeff() < 1e-9);
      return fell[0];
    };
    const double before = fall();
    CHECK(before < -1e-4);
    const int made = s->forcesMade();
    CHECK(made == 1);
    s->reset.touch();
    static_cast<SoSFDouble*>(s->getField(field))->setValue(3.0 * static_cast<SoSFDouble*>(s->getField(field))->getValue());
    const double after = fall();
    CHECK(after == Approx(before).epsilon(1e-9));
    CHECK(s->forcesMade() == made);  // the same force acts on the rebuilt model
    root->unref();
  }
}

TEST_CASE("SoBSplineDeformSurface: a refused SHELL material names its field and keeps the last valid state",
          "[nodes]") {
  SoSeparator* root = testutil::read("#Inventor V2.1 ascii\nSeparator { SoBSplineDeformSurface { energy SHELL on FALSE } }");
  REQUIRE(root);
  auto* s = testutil::find<SoBSplineDeformSurface>(root);
  REQUIRE(s->stepSimulation(1));
  s->poissonRatio = 0.7;
  CHECK(s->simulation().parameters().material.poissonRatio == 0.3);  // the last valid model
  CHECK_THAT(s->lastWarning(), Catch::Contains("field 'poissonRatio'") && Catch::Contains("(got 0.7)"));
  s->poissonRatio = 0.3;
  s->thickness = -1.0;
  CHECK(s->simulation().parameters().material.thickness == 0.001);
  CHECK_THAT(s->lastWarning(), Catch::Contains("field 'thickness'"));
  root->unref();
}

TEST_CASE("SoBSplineDeformSurface: material NEO_HOOKEAN reads, writes back and reaches the model, and bad values "
          "are refused naming the field",
          "[nodes]") {
  SoSeparator* root = testutil::read("#Inventor V2.1 ascii\nSeparator { SoBSplineDeformSurface { energy SHELL "
                                     "material NEO_HOOKEAN on FALSE } }");
  REQUIRE(root);
  auto* s = testutil::find<SoBSplineDeformSurface>(root);
  CHECK(s->material.getValue() == SoBSplineDeformSurface::NEO_HOOKEAN);
  REQUIRE(s->stepSimulation(1));
  CHECK(s->simulation().parameters().material.law == bsdeform::ShellMaterialLaw::NeoHookean);
  const std::string text = testutil::write(root);
  CHECK(text.find("material NEO_HOOKEAN") != std::string::npos);
  SoSeparator* again = testutil::read(text);
  REQUIRE(again);
  CHECK(testutil::find<SoBSplineDeformSurface>(again)->material.getValue() == SoBSplineDeformSurface::NEO_HOOKEAN);
  again->unref();
  // the default is St. Venant–Kirchhoff, and a default is not written
  SoSeparator* plain = testutil::read("#Inventor V2.1 ascii\nSeparator { SoBSplineDeformSurface { energy SHELL on FALSE } }");
  REQUIRE(plain);
  auto* p = testutil::find<SoBSplineDeformSurface>(plain);
  REQUIRE(p->stepSimulation(1));
  CHECK(p->simulation().parameters().material.law == bsdeform::ShellMaterialLaw::SaintVenantKirchhoff);
  const std::string plainText = testutil::write(plain);
  CHECK(plainText.find("material SAINT_VENANT_KIRCHHOFF") == std::string::npos);
  CHECK(plainText.find("material NEO_HOOKEAN") == std::string::npos);
  plain->unref();
  // a value set from code that names no law: refused, the last valid model kept
  s->material.setValue(7);
  CHECK(s->simulation().parameters().material.law == bsdeform::ShellMaterialLaw::NeoHookean);
  CHECK_THAT(s->lastWarning(), Catch::Contains("field 'material'") && Catch::Contains("7"));
  s->material = SoBSplineDeformSurface::SAINT_VENANT_KIRCHHOFF;
  REQUIRE(s->stepSimulation(1));
  CHECK(s->simulation().parameters().material.law == bsdeform::ShellMaterialLaw::SaintVenantKirchhoff);
  root->unref();
  // an unknown name in a file is Coin's parse error, naming the value
  Coin::get().messages.clear();
  CHECK(testutil::read("#Inventor V2.1 ascii\nSeparator { SoBSplineDeformSurface { material MOONEY_RIVLIN } }") ==
        nullptr);
  REQUIRE(!Coin::get().messages.empty());
  CHECK(Coin::get().messages[0].find("MOONEY_RIVLIN") != std::string::npos);
}

TEST_CASE("SoBSplineDeformSurface: holdUMin and SYMMETRY read, write back and reach the model, and misuse is refused "
          "naming the field",
          "[nodes]") {
  SoSeparator* root = testutil::read(
      "#Inventor V2.1 ascii\nSeparator { SoBSplineDeformSurface { energy SHELL numUControlPoints 4 "
      "numVControlPoints 4 boundaryUMin SIMPLY_SUPPORTED holdUMin ( X | Z ) boundaryUMax SIMPLY_SUPPORTED "
      "boundaryVMin SYMMETRY boundaryVMax FREE holdPins Z on FALSE } }");
  REQUIRE(root);
  auto* s = testutil::find<SoBSplineDeformSurface>(root);
  CHECK(s->holdUMin.getValue() == (SoBSplineDeformSurface::X | SoBSplineDeformSurface::Z));
  CHECK(s->holdUMax.getValue() == (SoBSplineDeformSurface::X | SoBSplineDeformSurface::Y | SoBSplineDeformSurface::Z));
  CHECK(s->boundaryVMin.getValue() == SoBSplineDeformSurface::SYMMETRY);
  const bsdeform::ModelParameters& p = s->simulation().parameters();
  CHECK(p.boundaries.uMin == bsdeform::Boundary::Free);  // the components on the unknowns
  CHECK(p.sideSupports[0].kind == bsdeform::SideSupport::Kind::Hinge);
  CHECK(p.sideSupports[0].components == 5u);
  CHECK(p.boundaries.uMax == bsdeform::Boundary::SimplySupported);  // all three: the space's own
  CHECK(p.sideSupports[1].kind == bsdeform::SideSupport::Kind::None);
  CHECK(p.sideSupports[2].kind == bsdeform::SideSupport::Kind::Symmetry);
  CHECK(p.pinComponents == 4u);
  // static only: the steppers refuse, saying so; the static solve takes it
  CHECK(!s->stepSimulation(1));
  CHECK_THAT(s->simulation().statusMessage(), Catch::Contains("not yet by EXPLICIT"));
  const std::string text = testutil::write(root);
  CHECK(text.find("holdUMin (X | Z)") != std::string::npos);
  CHECK(text.find("boundaryVMin SYMMETRY") != std::string::npos);
  // a default is not written (the name appears only in the node's field declarations)
  CHECK(text.find("holdUMax (") == std::string::npos);
  CHECK(text.find("holdUMax X") == std::string::npos);
  SoSeparator* again = testutil::read(text);
  REQUIRE(again);
  CHECK(testutil::find<SoBSplineDeformSurface>(again)->holdUMin.getValue() == 5);
  again->unref();
  root->unref();
  // components on a side that is not SIMPLY_SUPPORTED, on the paper's energy: refused by name
  const auto refusedField = warningAfterOneStep;
  CHECK_THAT(refusedField("energy SHELL boundaryUMin FREE holdUMin X"),
             Catch::Contains("field 'holdUMin'") && Catch::Contains("is neither"));
  CHECK_THAT(refusedField("boundaryUMin SIMPLY_SUPPORTED holdUMin X"),
             Catch::Contains("field 'holdUMin'") && Catch::Contains("SHELL"));
  CHECK_THAT(refusedField("boundaryVMax SYMMETRY"), Catch::Contains("field 'boundaryVMax'") && Catch::Contains("SHELL"));
}

TEST_CASE("SoBSplineDeformSurface: bounding box, triangle count and SoComplexity", "[nodes]") {
  SoSeparator* root = testutil::read("#Inventor V2.1 ascii\nSeparator { SoBSplineDeformSurface { on FALSE } }");
  REQUIRE(root);
  SoGetBoundingBoxAction bba(SbViewportRegion(100, 100));
  bba.apply(root);
  const SbBox3f box = bba.getBoundingBox();
  CHECK(box.getMin()[0] == Approx(0.0).margin(1e-6));
  CHECK(box.getMax()[1] == Approx(1.0).margin(1e-6));
  CHECK(box.getMax()[2] == Approx(0.0).margin(1e-6));
  // default complexity 0.5: max(8 spans * 1.5, 32) = 32 segments per side
  CHECK(countTriangles(root) == 2 * 32 * 32);
  auto* cx = new SoComplexity;
  cx->value = 1.0f;
  root->insertChild(cx, 0);
  CHECK(countTriangles(root) == 2 * 64 * 64);  // max(8 spans * 2.5, 64)
  cx->value = 0.0f;
  CHECK(countTriangles(root) == 2 * 4 * 4);
  // a large net: 1.5 segments per knot span at the default complexity
  root->removeChild(cx);
  testutil::find<SoBSplineDeformSurface>(root)->numUControlPoints = 61;  // 64 spans -> 96 segments
  CHECK(countTriangles(root) == 2 * 96 * 32);
  root->unref();
}

TEST_CASE("SoBSplineDeformSurface: picking reports the (u, v) under the ray", "[nodes]") {
  // a texture transform in the scene must not change the reported (u, v)
  SoSeparator* root = testutil::read("#Inventor V2.1 ascii\nSeparator { Texture2Transform { scaleFactor 8 8 } "
                                     "SoBSplineDeformSurface { on FALSE } }");
  REQUIRE(root);
  for (auto uv : {SbVec2f(0.3f, 0.7f), SbVec2f(0.81f, 0.12f)}) {
    SoRayPickAction rp(SbViewportRegion(100, 100));
    rp.setRay(SbVec3f(uv[0], uv[1], 5.0f), SbVec3f(0, 0, -1));
    rp.apply(root);
    const SoPickedPoint* pp = rp.getPickedPoint();
    REQUIRE(pp);
    float u = -1, v = -1;
    REQUIRE(SoBSplineDeformSurface::pickedParameter(pp, u, v));
    CHECK(u == Approx(uv[0]).margin(1e-5));  // the rest surface is S(u,v) = (u, v, 0)
    CHECK(v == Approx(uv[1]).margin(1e-5));
  }
  // on a deformed surface the (u, v) found for a point of it is where it came from
  auto* s = testutil::find<SoBSplineDeformSurface>(root);
  s->forces.setValue(nullptr);
  auto* push = new SoForceField;
  push->type = SoForceField::REGION;
  push->magnitude = 80.0f;
  push->force.setValue(0.3f, -0.2f, 1.0f);
  s->forces.setValue(push);
  s->stepSimulation(20);
  for (auto uv : {SbVec2f(0.42f, 0.57f), SbVec2f(0.71f, 0.33f)}) {
    const Eigen::Vector3d p = s->simulation().evaluate(uv[0], uv[1], 0).position;
    float u = -1, v = -1;
    s->closestParameter(SbVec3f(float(p.x()), float(p.y()), float(p.z())), u, v);
    CHECK(u == Approx(uv[0]).margin(1e-4));
    CHECK(v == Approx(uv[1]).margin(1e-4));
  }
  root->unref();
}

TEST_CASE("SoForceField: a uniform force settles to the core solver's static deflection", "[nodes]") {
  SoSeparator* root = testutil::read(R"(#Inventor V2.1 ascii
Separator { SoBSplineDeformSurface { numUControlPoints 6 numVControlPoints 6 damping 2 on FALSE
  forces SoForceField { type UNIFORM force 0 0 1 magnitude 20 } } })");
  REQUIRE(root);
  auto* s = testutil::find<SoBSplineDeformSurface>(root);
  s->stepSimulation(3000);
  bsdeform::ModelParameters p;
  p.numU = p.numV = 6;
  p.damping = 2;
  bsdeform::Simulation ref(p);
  ref.addForce(std::make_shared<bsdeform::DistributedForce>(Eigen::Vector3d(0, 0, 20)));
  const bsdeform::ControlNet eq = ref.staticSolution();
  CHECK((s->simulation().current() - eq).cwiseAbs().maxCoeff() < 1e-8);
  CHECK(s->simulation().evaluate(0.5, 0.5).position.z() > 1.0);
  root->unref();
}

TEST_CASE("SoForceField: every force type moves the surface the expected way", "[nodes]") {
  struct Case {
    const char* force;
    double dz;  // expected sign of the centre's z displacement (0: check x instead)
  } cases[] = {
      {"type UNIFORM force 0 0 -1 magnitude 5", -1},
      {"type POINT point 0.5 0.5 force 0 0 1 magnitude 0.5", +1},
      {"type REGION force 0 0 1 magnitude 30 regionMin 0.4 0.4 regionMax 0.6 0.6", +1},
      {"type EXPRESSION expression [ \"0\", \"0\", \"-10*sin(u*pi)*sin(v*pi)\" ]", -1},
      {"type GRAVITY force 0 0 -9.81", -1},
      {"type SPRING point 0.5 0.5 anchor 0.5 0.5 2 stiffness 2", +1},
      {"type PRESSURE magnitude 3", +1},
      {"type PLANE_COLLISION center 0 0 0.2 normal 0 0 1 stiffness 50", +1},
      {"type SPHERE_COLLISION center 0.5 0.5 -0.2 radius 0.4 stiffness 50", +1},
  };
  for (const Case& c : cases) {
    const std::string scene = std::string("#Inventor V2.1 ascii\nSeparator { SoBSplineDeformSurface { numUControlPoints 8 "
                                          "numVControlPoints 8 damping 2 on FALSE forces SoForceField { ") +
                              c.force + " } } }";
    Coin::get().messages.clear();
    SoSeparator* root = testutil::read(scene);
    REQUIRE(root);
    auto* s = testutil::find<SoBSplineDeformSurface>(root);
    s->stepSimulation(200);
    INFO(c.force);
    CHECK(Coin::get().messages.empty());
    CHECK(s->simulation().status() == bsdeform::Status::Ok);
    const double z = s->simulation().evaluate(0.5, 0.5).position.z();
    CHECK(z * c.dz > 1e-3);
    root->unref();
  }
  // drag only damps: with an initial push it slows the surface down faster than without
  auto kinetic = [](const char* extra) {
    const std::string scene = std::string("#Inventor V2.1 ascii\nSeparator { SoBSplineDeformSurface { damping 0 on FALSE "
                                          "forces [ DEF P SoForceField { type UNIFORM force 0 0 10 } ") +
                              extra + " ] } }";
    SoSeparator* root = testutil::read(scene);
    auto* s = testutil::find<SoBSplineDeformSurface>(root);
    s->stepSimulation(10);
    testutil::named<SoForceField>("P")->on = FALSE;
    s->stepSimulation(30);
    const double k = s->simulation().kineticEnergy() + s->simulation().strainEnergy().total;
    root->unref();
    return k;
  };
  CHECK(kinetic(", SoForceField { type DRAG coefficient 50 }") < 0.5 * kinetic(""));
}

TEST_CASE("SoForceField: field changes and engine connections take effect on the next step", "[nodes]") {
  SoSeparator* root = testutil::read(R"(#Inventor V2.1 ascii
Separator {
  SoBSplineDeformSurface { on FALSE damping 3
    forces DEF F SoForceField { type UNIFORM force 0 0 1
      magnitude 0 = DEF C Calculator { a 0 expression "oa = a * 2" } . oa } } })");
  REQUIRE(root);
  auto* s = testutil::find<SoBSplineDeformSurface>(root);
  s->stepSimulation(20);
  CHECK(s->simulation().deformationNorm() == 0.0);
  auto* calc = testutil::named<SoCalculator>("C");
  REQUIRE(calc);
  calc->a.setValue(5.0f);  // magnitude becomes 10 through the connection
  s->stepSimulation(20);
  const double n1 = s->simulation().deformationNorm();
  CHECK(n1 > 0.0);
  auto* f = testutil::named<SoForceField>("F");
  REQUIRE(f);
  f->force.setValue(0, 0, -1);  // flip: moves back down
  s->stepSimulation(200);
  CHECK(s->simulation().evaluate(0.5, 0.5).position.z() < 0.0);
  // writing keeps the connection
  const std::string text = testutil::write(root);
  CHECK(text.find("DEF C Calculator") != std::string::npos);
  root->unref();
}

TEST_CASE("SoBSplineDeformSurface: bad values warn once, name node and field, and keep the last state", "[nodes]") {
  SoSeparator* root = testutil::read("#Inventor V2.1 ascii\nSeparator { DEF Bad SoBSplineDeformSurface { on FALSE "
                                     "forces DEF G SoForceField { type UNIFORM force 0 0 5 } } }");
  REQUIRE(root);
  auto* s = testutil::find<SoBSplineDeformSurface>(root);
  s->stepSimulation(10);
  const bsdeform::ControlNet before = s->simulation().current();
  Coin::get().messages.clear();
  s->uDegree = 0;
  s->stepSimulation(1);
  REQUIRE(Coin::get().messages.size() == 1);
  CHECK(Coin::get().messages[0].find("'Bad'") != std::string::npos);
  CHECK(Coin::get().messages[0].find("uDegree") != std::string::npos);
  CHECK(Coin::get().messages[0].find("got 0") != std::string::npos);
  CHECK(s->simulation().parameters().degreeU == 3);
  CHECK(s->simulation().stepCount() == 11);  // still running on the last valid model
  s->stepSimulation(1);
  CHECK(Coin::get().messages.size() == 1);  // not repeated
  for (auto set : {+[](SoBSplineDeformSurface* n) { n->timeStep = -1.0; }, +[](SoBSplineDeformSurface* n) { n->mass = NAN; },
                   +[](SoBSplineDeformSurface* n) { n->numVControlPoints = 0; }}) {
    s->uDegree = 3;
    s->stepSimulation(1);
    Coin::get().messages.clear();
    set(s);
    s->stepSimulation(1);
    CHECK(Coin::get().messages.size() == 1);
  }
  // an expression that does not parse: warning with its position, the old force stays
  s->timeStep = 0.1;
  s->mass = 1.0;
  s->numVControlPoints = 5;
  s->stepSimulation(1);
  Coin::get().messages.clear();
  auto* g = testutil::named<SoForceField>("G");
  g->type = SoForceField::EXPRESSION;
  g->expression.set1Value(2, "3*sin(u*pi");
  s->stepSimulation(1);
  REQUIRE(Coin::get().messages.size() == 1);
  CHECK(Coin::get().messages[0].find("expression") != std::string::npos);
  CHECK(Coin::get().messages[0].find("position") != std::string::npos);
  CHECK(s->simulation().forces().size() == 1);
  (void)before;
  root->unref();
  // a scene with a bad value still loads the rest; the node warns and draws the default model
  Coin::get().messages.clear();
  SoSeparator* r2 = testutil::read("#Inventor V2.1 ascii\nSeparator { Cube {} DEF B2 SoBSplineDeformSurface { "
                                   "uDegree 0 timeStep -1 } Sphere {} }");
  REQUIRE(r2);
  CHECK(r2->getNumChildren() == 3);
  SoGetBoundingBoxAction bba(SbViewportRegion(100, 100));
  bba.apply(r2);  // computeBBox of the bad node: no throw, a warning
  REQUIRE(Coin::get().messages.size() == 1);
  CHECK(Coin::get().messages[0].find("'B2'") != std::string::npos);
  CHECK(Coin::get().messages[0].find("uDegree") != std::string::npos);
  r2->unref();
  // an unknown enumeration name is a Coin parse error of the file, naming the field
  Coin::get().messages.clear();
  CHECK(testutil::read("#Inventor V2.1 ascii\nSeparator { SoBSplineDeformSurface { integrator BOGUS } }") == nullptr);
  REQUIRE(!Coin::get().messages.empty());
  CHECK(Coin::get().messages[0].find("BOGUS") != std::string::npos);
}

TEST_CASE("SoBSplineDeformSurface: every field of both classes round-trips with non-default values", "[nodes]") {
  // a non-planar rest net for numU = numV = 2, degrees (2, 1): (2 + 4) x (2 + 2) = 24 points
  std::string rest;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 4; ++j)
      rest += std::to_string(0.25 * i - 0.5) + " " + std::to_string(j / 3.0) + " " + std::to_string(0.1 * i * j) + ", ";
  const std::string scene = "#Inventor V2.1 ascii\nSeparator { DEF S SoBSplineDeformSurface {\n"
      "numUControlPoints 2 numVControlPoints 2 uDegree 2 vDegree 1 w10 0.3 w01 0.4 w11 0.05 w20 0.06 w02 0.07\n"
      "massModel LUMPED mass 30 damping 2.5 timeStep 0.02 integrator IMPLICIT reference ABSOLUTE on FALSE speed 0.5\n"
      "restNet [ " + rest + " ]\n"
      "forces [ SoForceField { type SPRING on FALSE force 1 2 3 magnitude 2 point 0.1 0.9 regionMin 0.1 0.2 "
      "regionMax 0.8 0.9 expression [ \"u\", \"v\", \"t\" ] anchor 1 2 3 center 4 5 6 normal 0 1 0 radius 0.5 "
      "stiffness 7 coefficient 8 } ] } }";
  Coin::get().messages.clear();
  SoSeparator* a = testutil::read(scene);
  REQUIRE(a);
  auto* s = testutil::find<SoBSplineDeformSurface>(a);
  s->stepSimulation(5);
  CHECK(Coin::get().messages.empty());
  const std::string w1 = testutil::write(a);
  SoSeparator* b = testutil::read(w1);
  REQUIRE(b);
  CHECK(testutil::write(b) == w1);
  auto* t = testutil::find<SoBSplineDeformSurface>(b);
  const bsdeform::ModelParameters& p = t->simulation().parameters();
  CHECK(p.degreeU == 2);
  CHECK(p.degreeV == 1);
  CHECK(p.weights.w02 == 0.07);
  CHECK(p.massModel == bsdeform::MassModel::Lumped);
  CHECK(p.mass == 30.0);
  CHECK(p.timeStep == 0.02);
  CHECK(p.integrator == bsdeform::Integrator::Implicit);
  CHECK(p.reference == bsdeform::ElasticReference::Absolute);
  CHECK(t->speed.getValue() == 0.5f);
  CHECK(t->simulation().rest()(23, 2) == Approx(0.1 * 5 * 3));
  CHECK(t->simulation().stepCount() == 5);
  auto* f = static_cast<SoForceField*>(t->forces[0]);
  CHECK(f->type.getValue() == SoForceField::SPRING);
  CHECK(f->on.getValue() == FALSE);
  CHECK(f->expression[2] == "t");
  CHECK(f->coefficient.getValue() == 8.0f);
  CHECK(f->normal.getValue() == SbVec3d(0, 1, 0));
  for (const char* word : {"regionMin", "regionMax", "anchor", "center", "radius", "stiffness", "magnitude", "point"})
    CHECK(w1.find(word) != std::string::npos);
  a->unref();
  b->unref();
}

TEST_CASE("SoBSplineDeformSurface: Coin's realTime animates the node, on FALSE pauses it, transient forces act", "[nodes]") {
  testutil::Coin::get();
  auto* realTime = static_cast<SoSFTime*>(SoDB::getGlobalField(SbName("realTime")));
  realTime->setValue(SbTime(100.0));
  SoSeparator* root = testutil::read("#Inventor V2.1 ascii\nSeparator { SoBSplineDeformSurface { timeStep 0.01 speed 1 "
                                     "forces SoForceField { type UNIFORM force 0 0 5 } } }");
  REQUIRE(root);
  auto* s = testutil::find<SoBSplineDeformSurface>(root);
  // what any Coin viewer does as time passes: realTime moves on, the sensor queue is processed
  for (int i = 1; i <= 6; ++i) {
    realTime->setValue(SbTime(100.0 + 0.025 * i));
    SoDB::getSensorManager()->processDelayQueue(FALSE);
  }
  const long steps = s->simulation().stepCount();
  CHECK(steps == 15);  // 0.15 s at 0.01 s per step
  s->on = FALSE;       // pauses
  realTime->setValue(SbTime(100.5));
  SoDB::getSensorManager()->processDelayQueue(FALSE);
  CHECK(s->simulation().stepCount() == steps);
  // a transient spring (the viewer's mouse drag) pulls a point towards its anchor
  s->resetSimulation();
  auto spring = std::make_shared<bsdeform::PointForce>(
      0.3, 0.3, [](const bsdeform::SurfaceSample& p) { return Eigen::Vector3d(5.0 * (Eigen::Vector3d(0.3, 0.3, -1) - p.position)); },
      bsdeform::kDependsOnPosition, 5.0);
  s->addTransientForce(spring);
  s->stepSimulation(300);
  const double z = s->simulation().evaluate(0.3, 0.3).position.z();
  s->removeTransientForce(spring.get());
  s->stepSimulation(600);
  const double zAfter = s->simulation().evaluate(0.3, 0.3).position.z();
  CHECK(z < zAfter);  // pulled down while held, back up under the uniform force when released
  CHECK(testutil::write(root).find("PointForce") == std::string::npos);
  root->unref();
}

TEST_CASE("SoBSplineDeformSurface: real time advances in whole steps, scaled by speed, with on and reset", "[nodes]") {
  SoSeparator* root = testutil::read("#Inventor V2.1 ascii\nSeparator { SoBSplineDeformSurface { on FALSE timeStep 0.1 "
                                     "forces SoForceField { type UNIFORM force 0 0 5 } } }");
  auto* s = testutil::find<SoBSplineDeformSurface>(root);
  CHECK(s->advanceRealTime(0.25) == 2);  // 0.25 s: two whole steps, 0.05 s kept
  CHECK(s->advanceRealTime(0.05) == 1);  // 0.05 + 0.05 = one more
  CHECK(s->simulation().stepCount() == 3);
  s->speed = 2.0f;
  CHECK(s->advanceRealTime(0.2) == 4);
  CHECK(s->advanceRealTime(10.0) == 5);  // a stalled frame is capped at 0.25 s
  CHECK(s->simulation().time() == Approx(1.2));
  s->reset.touch();
  CHECK(s->simulation().stepCount() == 0);
  CHECK(s->simulation().deformationNorm() == 0.0);
  root->unref();
  // In a file a trigger is driven by a connection (Coin ignores a bare `reset` when reading):
  // here a Calculator output; any change of it resets the surface.
  SoSeparator* wired = testutil::read("#Inventor V2.1 ascii\nSeparator { SoBSplineDeformSurface { on FALSE "
                                      "reset = DEF R Calculator { a 0 expression \"oa = a\" } . oa "
                                      "forces SoForceField { type UNIFORM force 0 0 5 } } }");
  REQUIRE(wired);
  auto* w = testutil::find<SoBSplineDeformSurface>(wired);
  w->stepSimulation(5);
  CHECK(w->simulation().stepCount() == 5);
  testutil::named<SoCalculator>("R")->a.setValue(1.0f);
  CHECK(w->simulation().stepCount() == 0);
  CHECK(w->simulation().deformationNorm() == 0.0);
  wired->unref();
}

TEST_CASE("SoBSplineDeformSurface: simulationTime and stepCount are live (steps, clock, reset), the nets are not",
          "[nodes]") {
  SoSeparator* root = testutil::read("#Inventor V2.1 ascii\nSeparator { SoBSplineDeformSurface { on FALSE timeStep 0.1 "
                                     "forces SoForceField { type UNIFORM force 0 0 5 } } }");
  REQUIRE(root);
  auto* s = testutil::find<SoBSplineDeformSurface>(root);
  // A field sensor sees the change, as a field editor or a script polling the field does.
  int fired = 0;
  SoFieldSensor sensor([](void* data, SoSensor*) { ++*static_cast<int*>(data); }, &fired);
  sensor.setPriority(0);  // immediate: fires inside setValue
  sensor.attach(&s->stepCount);
  s->stepSimulation(3);
  CHECK(s->stepCount.getValue() == 3);
  CHECK(s->simulationTime.getValue() == s->simulation().time());
  CHECK(s->simulationTime.getValue() == Approx(0.3));
  CHECK(fired == 1);
  SbString text;
  s->stepCount.get(text);  // what the viewer's field editor shows
  CHECK(std::string(text.getString()) == "3");
  CHECK(s->advanceRealTime(0.2) == 2);  // the clock's path
  CHECK(s->stepCount.getValue() == 5);
  CHECK(s->simulationTime.getValue() == Approx(0.5));
  CHECK(s->controlNet.getNum() == 0);  // large: written with the scene only
  // The live values do not count as a new state: stepping on continues the same motion.
  const double z5 = s->simulation().evaluate(0.5, 0.5).position.z();
  s->stepSimulation(1);
  CHECK(s->simulation().stepCount() == 6);
  CHECK(s->simulation().evaluate(0.5, 0.5).position.z() != z5);
  s->reset.touch();
  CHECK(s->stepCount.getValue() == 0);
  CHECK(s->simulationTime.getValue() == 0.0);
  s->stepSimulation(2);
  s->resetSimulation();
  CHECK(s->stepCount.getValue() == 0);
  CHECK(s->simulationTime.getValue() == 0.0);
  // At rest again: written as defaults (no state values in the file).
  const std::string written = testutil::write(root);
  CHECK(s->stepCount.isDefault());
  CHECK(s->simulationTime.isDefault());
  CHECK(written.find("stepCount 0") == std::string::npos);
  CHECK(written.find("simulationTime 0") == std::string::npos);
  sensor.detach();
  root->unref();
}

TEST_CASE("SoBSplineDeformSurface: a field edited at rest (built or reset) runs as if the file held it", "[nodes]") {
  const std::string head = "#Inventor V2.1 ascii\nSeparator { SoBSplineDeformSurface { on FALSE ";
  const std::string tail = "forces SoForceField { type REGION force 0 0 30 regionMin 0.3 0.3 regionMax 0.7 0.6 } } }";
  SoSeparator* edited = testutil::read(head + tail);
  SoSeparator* filed = testutil::read(head + "w10 5 w01 3 " + tail);
  REQUIRE(edited);
  REQUIRE(filed);
  auto* e = testutil::find<SoBSplineDeformSurface>(edited);
  auto* f = testutil::find<SoBSplineDeformSurface>(filed);
  f->stepSimulation(6);
  const bsdeform::ControlNet want = f->simulation().current();
  e->stepSimulation(0);  // built, as a first render does
  e->w10 = 5.0;
  e->w01 = 3.0;
  e->stepSimulation(6);
  CHECK(e->simulation().current() == want);  // the start rule of the new model applied
  e->stepSimulation(4);  // and after a reset
  e->resetSimulation();
  e->w10 = 0.1;
  e->w10 = 5.0;
  e->stepSimulation(6);
  CHECK(e->simulation().current() == want);
  edited->unref();
  filed->unref();
}

TEST_CASE("SoForceField: one force field (DEF/USE) acts on two surfaces", "[nodes]") {
  SoSeparator* root = testutil::read("#Inventor V2.1 ascii\nSeparator { DEF A SoBSplineDeformSurface { on FALSE "
                                     "forces DEF Shared SoForceField { type UNIFORM force 0 0 4 } } "
                                     "DEF B SoBSplineDeformSurface { on FALSE numUControlPoints 7 forces USE Shared } }");
  REQUIRE(root);
  auto* a = static_cast<SoBSplineDeformSurface*>(SoNode::getByName("A"));
  auto* b = static_cast<SoBSplineDeformSurface*>(SoNode::getByName("B"));
  REQUIRE((a && b));
  CHECK(a->forces[0] == b->forces[0]);
  a->stepSimulation(10);
  b->stepSimulation(10);
  CHECK(a->simulation().evaluate(0.5, 0.5).position.z() > 0.0);
  CHECK(b->simulation().evaluate(0.5, 0.5).position.z() > 0.0);
  testutil::named<SoForceField>("Shared")->force.setValue(0, 0, -40);  // both feel the change
  a->stepSimulation(100);
  b->stepSimulation(100);
  CHECK(a->simulation().evaluate(0.5, 0.5).position.z() < 0.0);
  CHECK(b->simulation().evaluate(0.5, 0.5).position.z() < 0.0);
  const std::string text = testutil::write(root);
  CHECK(text.find("USE Shared") != std::string::npos);
  root->unref();
}

TEST_CASE("SoBSplineDeformSurface: a huge speed or a tiny step takes at most 10000 steps per call, owing nothing",
          "[nodes]") {
  // speed 1e30 asked for 2.5e30 steps in one call: a double -> int overflow (undefined behaviour).
  SoSeparator* root = testutil::read("#Inventor V2.1 ascii\nSeparator { SoBSplineDeformSurface { on FALSE timeStep 0.1 "
                                     "numUControlPoints 2 numVControlPoints 2 speed 1e30 } }");
  auto* s = testutil::find<SoBSplineDeformSurface>(root);
  CHECK(s->advanceRealTime(0.1) == 10000);
  CHECK(s->simulation().stepCount() == 10000);
  s->speed = 1.0f;
  CHECK(s->advanceRealTime(0.1) == 1);  // the dropped budget is not owed
  s->speed = std::numeric_limits<float>::infinity();
  CHECK(s->advanceRealTime(0.1) == 10000);
  s->speed = 1.0f;
  CHECK(s->advanceRealTime(0.1) == 1);
  root->unref();
}

TEST_CASE("SoBSplineDeformSurface: maxSubSteps refuses a step that would run for minutes, and is a field", "[nodes]") {
  auto& messages = testutil::Coin::get().messages;
  messages.clear();
  SoSeparator* root = testutil::read("#Inventor V2.1 ascii\nSeparator { SoBSplineDeformSurface { on FALSE timeStep 1e8 "
                                     "forces SoForceField { type UNIFORM force 0 0 5 } } }");
  auto* s = testutil::find<SoBSplineDeformSurface>(root);
  CHECK_FALSE(s->stepSimulation(1));
  CHECK(s->simulation().status() == bsdeform::Status::Refused);
  CHECK(s->simulation().stepCount() == 0);
  bool named = false;
  for (const auto& m : messages) named |= m.find("maxSubSteps") != std::string::npos;
  CHECK(named);
  s->timeStep = 100.0;  // needs about a hundred sub-steps: over a cap of 50, under the default
  s->maxSubSteps = 50;
  CHECK_FALSE(s->stepSimulation(1));
  s->maxSubSteps = 10000;
  CHECK(s->stepSimulation(1));
  CHECK(s->simulation().subSteps() > 50);
  root->unref();
}

TEST_CASE("SoBSplineDeformSurface: drawing from GL buffers follows the simulation and the complexity", "[nodes]") {
  // One renderer (one GL context, the node's buffers kept in it) against a fresh renderer for
  // each picture: the kept buffers must be uploaded again after steps (new positions) and
  // after a complexity change (a new grid size, new indices), and then give the same pixels.
  std::string error;
  INFO(error);
  REQUIRE(bsdeform::installEglOffscreenContexts(&error));
  SoSeparator* root = testutil::read(
      "#Inventor V2.1 ascii\nSeparator { PerspectiveCamera { position 0.5 -1.0 1.4 orientation 1 0 0 0.6 } "
      "DirectionalLight { direction 0.2 0.3 -1 } DEF C Complexity { value 0.5 } "
      "SoBSplineDeformSurface { numUControlPoints 10 numVControlPoints 10 on FALSE "
      "forces SoForceField { type REGION force 0.3 0 1 magnitude 80 } } }");
  REQUIRE(root);
  const SbViewportRegion viewport(160, 120);
  auto pixels = [&](SoOffscreenRenderer& r) {
    REQUIRE(r.render(root));
    const unsigned char* b = r.getBuffer();
    return std::vector<unsigned char>(b, b + 160 * 120 * 3);
  };
  auto fresh = [&] {
    SoOffscreenRenderer r(viewport);
    r.setComponents(SoOffscreenRenderer::RGB);
    return pixels(r);
  };
  SoOffscreenRenderer kept(viewport);
  kept.setComponents(SoOffscreenRenderer::RGB);
  const std::vector<unsigned char> flat = pixels(kept);
  CHECK(flat == fresh());
  testutil::find<SoBSplineDeformSurface>(root)->stepSimulation(30);
  const std::vector<unsigned char> bent = pixels(kept);
  size_t differing = 0;
  for (size_t i = 0; i < flat.size(); ++i) differing += flat[i] != bent[i];
  CHECK(differing > flat.size() / 20);  // the picture did change
  CHECK(bent == fresh());
  static_cast<SoComplexity*>(SoNode::getByName("C"))->value = 1.0f;
  const std::vector<unsigned char> fine = pixels(kept);
  CHECK(fine == fresh());
}

TEST_CASE("SoBSplineDeformSurface: SIMPLY_SUPPORTED and BUILT_IN sides from a file: round trip, resume, rest shapes, "
          "refusals",
          "[nodes]") {
  // a cone whose base (v = 0) is a hinge, inflated, on both integrators; written, read back and
  // resumed: the same trajectory, the base circle where it was
  for (const char* integ : {"EXPLICIT", "IMPLICIT"}) {
    const std::string scene = std::string("#Inventor V2.1 ascii\nSeparator { DEF Cone SoBSplineDeformSurface {\n"
                                          "numUControlPoints 12 numVControlPoints 8 restShape CONE on FALSE integrator ") +
                              integ +
                              " timeStep 0.05 massModel LUMPED mass 2 damping 2\n"
                              "boundaryVMin SIMPLY_SUPPORTED\n"
                              "forces [ SoForceField { type PRESSURE magnitude 0.5 } ] } }";
    Coin::get().messages.clear();
    SoSeparator* a = testutil::read(scene);
    REQUIRE(a);
    auto* sa = testutil::find<SoBSplineDeformSurface>(a);
    sa->stepSimulation(20);
    CHECK(Coin::get().messages.empty());
    CHECK(sa->simulation().parameters().boundaries.vMin == bsdeform::Boundary::SimplySupported);
    const std::string text = testutil::write(a);
    CHECK(text.find("boundaryVMin SIMPLY_SUPPORTED") != std::string::npos);
    SoSeparator* b = testutil::read(text);
    REQUIRE(b);
    auto* sb = testutil::find<SoBSplineDeformSurface>(b);
    sa->stepSimulation(20);
    sb->stepSimulation(20);
    INFO(integ);
    CHECK(sa->simulation().deformationNorm() > 0.01);
    CHECK((sb->simulation().current() - sa->simulation().current()).cwiseAbs().maxCoeff() < 1e-12);
    // the base circle stays at rest
    double base = 0.0;
    for (int k = 0; k <= 20; ++k) {
      const double u = k / 20.0;
      base = std::max(base, (sb->simulation().evaluate(u, 0.0).position -
                             sb->simulation().space().evaluate(sb->simulation().rest(), u, 0.0).position)
                                .norm());
    }
    CHECK(base < 1e-12);
    a->unref();
    b->unref();
  }
  // a BUILT_IN side facing a PERIODIC one: one warning naming both fields, the last model stays
  SoSeparator* root = testutil::read("#Inventor V2.1 ascii\nSeparator { DEF Edge SoBSplineDeformSurface { on FALSE "
                                     "boundaryUMin BUILT_IN } }");
  REQUIRE(root);
  auto* s = testutil::find<SoBSplineDeformSurface>(root);
  s->stepSimulation(1);
  Coin::get().messages.clear();
  s->boundaryUMax = SoBSplineDeformSurface::PERIODIC;
  s->stepSimulation(1);
  REQUIRE(Coin::get().messages.size() == 1);
  CHECK(Coin::get().messages[0].find("'Edge'") != std::string::npos);
  CHECK(Coin::get().messages[0].find("field 'boundaryUMax' is PERIODIC but boundaryUMin is BUILT_IN") != std::string::npos);
  CHECK(s->problem().kind == SoBSplineDeformSurface::Problem::FIELD);
  CHECK(s->problem().field == "boundaryUMax");
  CHECK(s->problem().node == "Edge");
  CHECK(s->simulation().parameters().boundaries.uMax == bsdeform::Boundary::Clamped);
  root->unref();
}

TEST_CASE("SoBSplineDeformSurface: every refused field is listed, not only the first", "[nodes]") {
  // Issue 37, item 3: the first refused value hid the others.
  SoSeparator* root = testutil::read("#Inventor V2.1 ascii\nSeparator { DEF Cloth SoBSplineDeformSurface {\n"
                                     "  energy SHELL uDegree 9 poissonRatio 0.7 thickness -0.001 numVControlPoints 4 } }\n");
  REQUIRE(root);
  auto* s = testutil::named<SoBSplineDeformSurface>("Cloth");
  REQUIRE(s);
  s->simulation();
  std::vector<std::string> fields;
  for (const auto& r : s->refusals()) {
    fields.push_back(r.field);
    CHECK(r.kind == SoBSplineDeformSurface::Problem::FIELD);
    CHECK(r.node == "Cloth");
    CHECK(r.message.find(r.field) != std::string::npos);  // the sentence names its field
  }
  std::sort(fields.begin(), fields.end());
  CHECK(fields == std::vector<std::string>{"poissonRatio", "thickness", "uDegree"});
  CHECK(s->problem().kind == SoBSplineDeformSurface::Problem::FIELD);
  // the fields themselves are left as the file has them
  CHECK(s->uDegree.getValue() == 9);
  CHECK(s->poissonRatio.getValue() == 0.7);  // snapped on read (item 4)
  CHECK(s->thickness.getValue() == -0.001);
  // one fixed: two left; all fixed: none
  s->uDegree = 3;
  s->simulation();
  CHECK(s->refusals().size() == 2);
  s->poissonRatio = 0.3;
  s->thickness = 0.001;
  s->simulation();
  CHECK(s->refusals().empty());
  CHECK(s->problem().kind == SoBSplineDeformSurface::Problem::NONE);
  root->unref();
}

TEST_CASE("SoBSplineDeformSurface: motionUMax moves a CLAMPED side, set or driven by an engine on the clock, its "
          "state writes back and reads in, misuse is refused naming the field",
          "[nodes]") {
  const std::string strip =
      "energy SHELL numUControlPoints 6 numVControlPoints 3 boundaryVMin FREE boundaryVMax FREE "
      "youngsModulus 1e6 thickness 0.01 density 1000 damping 10 timeStep 0.01 integrator BACKWARD_EULER on FALSE ";
  auto heldGap = [](SoBSplineDeformSurface* s, const Eigen::Vector3d& lift) {
    // the three layers side u = 1 holds, against rest + lift
    const bsdeform::Simulation& sim = s->simulation();
    const int cols = sim.space().netCols(), rows = sim.space().netRows();
    double gap = 0.0;
    for (int i = rows - 3; i < rows; ++i)
      for (int j = 0; j < cols; ++j) {
        const Eigen::Index r = Eigen::Index(i) * cols + j;
        gap = std::max(gap, (sim.current().row(r) - sim.rest().row(r) - lift.transpose()).norm());
      }
    return gap;
  };
  {  // a set map: reached at the end of the first step, kept
    SoSeparator* root = testutil::read("#Inventor V2.1 ascii\nSeparator { SoBSplineDeformSurface { " + strip +
                                       "motionUMax 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0.25 1 } }");
    REQUIRE(root);
    auto* s = testutil::find<SoBSplineDeformSurface>(root);
    REQUIRE(s->stepSimulation(3));
    CHECK(s->simulation().sideMoved(1));
    CHECK(!s->simulation().sideMoved(0));
    CHECK(heldGap(s, Eigen::Vector3d(0, 0, 0.25)) == 0.0);
    // written with its state (the moved layers off rest) and read in: the same net
    s->syncStateFields();
    const std::string text = testutil::write(root);
    CHECK(text.find("motionUMax") != std::string::npos);
    SoSeparator* again = testutil::read(text);
    REQUIRE(again);
    auto* t = testutil::find<SoBSplineDeformSurface>(again);
    CHECK(t->lastWarning().empty());
    CHECK((t->simulation().current() - s->simulation().current()).cwiseAbs().maxCoeff() < 1e-12);
    again->unref();
    // back to the identity: the side returns to rest in the next step
    s->motionUMax.setValue(SbMatrix::identity());
    REQUIRE(s->stepSimulation(1));
    CHECK(!s->simulation().sideMoved(1));
    CHECK(heldGap(s, Eigen::Vector3d::Zero()) == 0.0);
    root->unref();
  }
  {  // driven by the clock through ComposeMatrix (its MFMatrix output into the SFMatrix field)
    // the clock from 0, as bsdeform-run sets it before reading a scene (SoElapsedTime counts from
    // the realTime it was made at)
    static_cast<SoSFTime*>(SoDB::getGlobalField(SbName("realTime")))->setValue(SbTime(0.0));
    SoSeparator* root = testutil::read(
        "#Inventor V2.1 ascii\nSeparator { SoBSplineDeformSurface { " + strip +
        "motionUMax 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1 = ComposeMatrix { translation 0 0 0 = Calculator { "
        "a 0 = ElapsedTime { } . timeOut expression \"oA = vec3f(0, 0, 0.1 * a)\" } . oA } . matrix } }");
    REQUIRE(root);
    auto* s = testutil::find<SoBSplineDeformSurface>(root);
    s->on = TRUE;
    {
      bsdeform::SceneRunner runner(root);
      const bool ok = runner.advanceTo(0.2);
      INFO(s->lastWarning() << " / " << s->simulation().statusMessage());
      REQUIRE(ok);
      CHECK(s->simulation().stepCount() == 20);
      CHECK(heldGap(s, Eigen::Vector3d(0, 0, 0.02)) < 1e-8);  // the matrix is float
      REQUIRE(runner.advanceTo(0.5));
      CHECK(heldGap(s, Eigen::Vector3d(0, 0, 0.05)) < 1e-8);
    }
    root->unref();
  }
  auto refusedField = [&strip](const std::string& fields) {
    return warningAfterOneStep(strip + fields + " motionUMax 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0.1 1");
  };
  CHECK_THAT(refusedField("boundaryUMax FREE"), Catch::Contains("field 'motionUMax'") && Catch::Contains("CLAMPED"));
  CHECK_THAT(refusedField("integrator EXPLICIT"),
             Catch::Contains("field 'motionUMax'") && Catch::Contains("BACKWARD_EULER"));
  CHECK_THAT(refusedField("boundaryVMin CLAMPED"), Catch::Contains("motionUMax") && Catch::Contains("make that side FREE"));
}
