// SPDX-License-Identifier: MIT
// Contact with obstacle meshes (Contact.h): the law at a point, and free cloth resting on and
// sliding off boxes, checked against statics (weight carried, penetration) and Coulomb's rule.
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>

#include "bsdeform/contact/Contact.h"
#include "bsdeform/forces/ForceLaws.h"
#include "bsdeform/dynamics/Simulation.h"
#include "../support/Cotton.h"
#include "../support/ObstacleMeshes.h"

using namespace bsdeform;
using bsdeform::test::box;
using bsdeform::test::worldOf;

namespace {
ModelParameters clothParams() {
  ModelParameters p;
  p.numU = p.numV = 8;
  p.boundaries = Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free};
  p.massModel = MassModel::Lumped;
  p.mass = 1.0;  // rho: mass per unit parameter area
  p.damping = 2.0;
  p.timeStep = 0.01;
  return p;
}

Eigen::Vector3d totalLoad(const Force& f, const Simulation& sim) {
  ControlNet load = ControlNet::Zero(sim.space().numMoving(), 3);
  const LoadContext ctx{sim.space(), sim.current(), sim.previous(), sim.subStepSize(), sim.time()};
  f.addLoad(ctx, load);
  return load.colwise().sum().transpose();
}

// Largest depth tau - s over a grid of surface points.
double maxDepth(const Simulation& sim, const ContactWorld& w, const ContactParameters& p) {
  double deepest = 0.0;
  for (int i = 0; i <= 40; ++i)
    for (int j = 0; j <= 40; ++j) {
      double d = 0.0;
      contactDensity(w, p, sim.evaluate(i / 40.0, j / 40.0).position, Eigen::Vector3d::Zero(), 0.01, &d);
      deepest = std::max(deepest, d);
    }
  return deepest;
}
}  // namespace

TEST_CASE("Contact: the law at a point, above a box, inside it, and on an open sheet", "[core]") {
  const TriangleMesh b = box(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 0));
  REQUIRE(isClosedMesh(b));
  auto w = worldOf(b);
  ContactParameters p;
  p.thickness = 0.1;
  p.stiffness = 100.0;
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  // above the top face, inside the layer: k (tau - h) up
  Eigen::Vector3d f = contactDensity(*w, p, Eigen::Vector3d(0.2, 0.3, 0.04), zero, 0.01);
  CHECK(f.isApprox(Eigen::Vector3d(0, 0, 100.0 * 0.06), 1e-12));
  CHECK(contactDensity(*w, p, Eigen::Vector3d(0.2, 0.3, 0.11), zero, 0.01).norm() == 0.0);
  // inside the closed box, 0.05 below the top: pushed up by k (tau + 0.05)
  double depth = 0.0;
  f = contactDensity(*w, p, Eigen::Vector3d(0.2, 0.3, -0.05), zero, 0.01, &depth);
  CHECK(f.isApprox(Eigen::Vector3d(0, 0, 100.0 * 0.15), 1e-12));
  CHECK(depth == Approx(0.15));
  // near a corner outside: along the direction from the corner
  const Eigen::Vector3d q(1.03, 1.04, 0.0);
  f = contactDensity(*w, p, q, zero, 0.01);
  CHECK(f.normalized().isApprox(Eigen::Vector3d(0.03, 0.04, 0).normalized(), 1e-9));
  CHECK(f.norm() == Approx(100.0 * (0.1 - 0.05)));
  // an open sheet (the top face alone) is two-sided: from below it pushes down
  TriangleMesh sheet;
  sheet.vertices = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  sheet.triangles = {{0, 1, 2}, {0, 2, 3}};
  REQUIRE_FALSE(isClosedMesh(sheet));
  auto ws = worldOf(sheet);
  CHECK(contactDensity(*ws, p, Eigen::Vector3d(0, 0, -0.04), zero, 0.01).isApprox(Eigen::Vector3d(0, 0, -6.0), 1e-12));
  // damping only against the approach, capped at 0.3 rho / dt
  p.damping = 5.0;
  p.massDensity = 1.0;
  f = contactDensity(*w, p, Eigen::Vector3d(0, 0, 0.04), Eigen::Vector3d(0, 0, -0.2), 0.01);
  CHECK(f.z() == Approx(6.0 + 5.0 * 0.2));
  f = contactDensity(*w, p, Eigen::Vector3d(0, 0, 0.04), Eigen::Vector3d(0, 0, -0.2), 1.0);  // cap 0.3
  CHECK(f.z() == Approx(6.0 + 0.3 * 0.2));
  // friction: mu f_n when sliding fast, capped at 0.3 rho |v_t| / dt when slow
  p.damping = 0.0;
  p.friction = 0.5;
  f = contactDensity(*w, p, Eigen::Vector3d(0, 0, 0.04), Eigen::Vector3d(10, 0, 0), 0.01);
  CHECK(f.isApprox(Eigen::Vector3d(-0.5 * 6.0, 0, 6.0), 1e-12));
  f = contactDensity(*w, p, Eigen::Vector3d(0, 0, 0.04), Eigen::Vector3d(0.001, 0, 0), 0.01);
  CHECK(f.x() == Approx(-0.3 * 0.001 / 0.01));
}

TEST_CASE("Contact: welding forgives float rounding, so a seam closes the mesh", "[core]") {
  // The box of 12 triangles, face by face (24 corners), with the copies of one corner an ulp of
  // float apart, as a Coin shape's seam comes out of single-precision sine, cosine and matrices.
  const TriangleMesh solid = box(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1));
  TriangleMesh soup;
  for (const Eigen::Vector3i& t : solid.triangles) {
    const int first = int(soup.vertices.size());
    for (int k = 0; k < 3; ++k) soup.vertices.push_back(solid.vertices[std::size_t(t[k])]);
    soup.triangles.emplace_back(first, first + 1, first + 2);
  }
  int moved = 0;
  for (Eigen::Vector3d& v : soup.vertices)
    if (v == Eigen::Vector3d(1, 1, 1) && moved++ % 2 == 1) v.x() = double(std::nextafter(1.0f, 0.0f));
  REQUIRE(moved >= 2);
  const TriangleMesh welded = weldVertices(soup);
  CHECK(welded.vertices.size() == 8);
  CHECK(isClosedMesh(welded));
  // exact welding keeps the copies apart: an open shell
  const TriangleMesh exact = weldVertices(soup, 0.0);
  CHECK(exact.vertices.size() == 9);
  CHECK_FALSE(isClosedMesh(exact));
  // the tolerance is relative to the mesh's size: a box a thousandth across keeps its corners
  TriangleMesh tiny = soup;
  for (Eigen::Vector3d& v : tiny.vertices) v = 1e-3 * v + Eigen::Vector3d(0.5, 0.5, 0.5);
  CHECK(weldVertices(tiny).vertices.size() == 8);
  // and vertices a real distance apart (1e-4 of the size) are not merged
  TriangleMesh near = soup;
  near.vertices[0].z() += 1e-4;
  CHECK(weldVertices(near).vertices.size() == 9);
}

TEST_CASE("CollisionForce: with modelMass the mass density and the rest area are the model's", "[core]") {
  ModelParameters mp = clothParams();
  mp.mass = 1.3;
  ControlNet rest = Simulation(mp).rest();
  rest.col(0) *= 2.0;  // rest area 3: the law per unit world area, 3 times it per unit parameter area
  rest.col(1) *= 1.5;
  auto w = worldOf(box(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(3, 3, -0.01)));
  ContactParameters fixed;
  fixed.thickness = 0.02;
  fixed.stiffness = 2e3;
  fixed.damping = 5.0;
  fixed.friction = 0.3;
  ContactParameters model = fixed;
  model.modelMass = true;
  Simulation a(mp, rest), b(mp, rest);
  REQUIRE(a.restArea() == Approx(3.0));
  fixed.massDensity = a.massPerArea();
  fixed.areaScale = a.restArea();
  auto fa = std::make_shared<CollisionForce>(w, model);
  LoadContext ctx{a.space(), a.current(), a.previous(), a.subStepSize(), 0.0};
  ctx.massPerArea = 2.5;
  ctx.restArea = 0.5;
  CHECK(fa->parametersFor(ctx).massDensity == 2.5);
  CHECK(fa->parametersFor(ctx).areaScale == 0.5);
  CHECK(CollisionForce(w, fixed).parametersFor(ctx).massDensity == a.massPerArea());
  a.addForce(fa);
  b.addForce(std::make_shared<CollisionForce>(w, fixed));
  for (Simulation* s : {&a, &b}) s->addForce(std::make_shared<GravityForce>(Eigen::Vector3d(0.4, 0, -9.81)));
  a.advance(30);
  b.advance(30);
  REQUIRE(a.status() == Status::Ok);
  CHECK(a.current().col(2).maxCoeff() < 0.01);  // all of it in the contact layer (box top + thickness)
  CHECK((a.current() - b.current()).cwiseAbs().maxCoeff() == 0.0);
}

TEST_CASE("Contact: a free cloth resting on a box carries its weight and stays within the thickness", "[core][slow]") {
  ModelParameters mp = clothParams();
  Simulation sim(mp);
  const Eigen::Vector3d g(0, 0, -2.0);
  sim.addForce(std::make_shared<GravityForce>(mp.mass, g));
  ContactParameters cp;
  cp.thickness = 0.02;
  cp.stiffness = 2e3;
  cp.massDensity = mp.mass;
  auto w = worldOf(box(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(2, 2, -0.05)));
  auto contact = std::make_shared<CollisionForce>(w, cp);
  sim.addForce(contact);
  sim.advance(1500);  // 15 s: falls 0.03, settles under damping 2
  REQUIRE(sim.status() == Status::Ok);
  const Eigen::Vector3d carried = totalLoad(*contact, sim);
  INFO("contact force " << carried.transpose());
  CHECK(carried.z() == Approx(-g.z() * mp.mass).epsilon(0.01));  // the weight, to 1 %
  CHECK(std::abs(carried.x()) < 1e-6);
  CHECK(std::abs(carried.y()) < 1e-6);
  // resting depth rho g / k = 1e-3 into the 0.02 layer; never past the box's surface
  const double deepest = maxDepth(sim, *w, cp);
  CHECK(deepest == Approx(mp.mass * 2.0 / cp.stiffness).epsilon(0.05));
  CHECK(deepest < cp.thickness);
  CHECK(sim.evaluate(0.5, 0.5).position.z() == Approx(-0.05 + 0.02 - 1e-3).margin(2e-4));
}

TEST_CASE("Contact: on a slope the cloth stays when tan(theta) < mu and slides when tan(theta) > mu", "[core][slow]") {
  // The slope's frame: the box top is horizontal and gravity is tilted by theta (a rigid
  // translation costs the cloth no elastic energy, a rotation would).
  const double theta = 0.3;  // tan = 0.309
  const Eigen::Vector3d g(std::sin(theta), 0.0, -std::cos(theta));
  // the cloth (z = 0) starts at its resting depth rho g cos(theta) / k into the 0.02 layer
  const TriangleMesh slope = box(Eigen::Vector3d(-30, -30, -2), Eigen::Vector3d(30, 30, -0.02 + std::cos(theta) / 5e3));
  for (double mu : {0.5, 0.15}) {
    ModelParameters mp = clothParams();
    mp.damping = 0.5;
    Simulation sim(mp);
    sim.addForce(std::make_shared<GravityForce>(mp.mass, g));
    ContactParameters cp;
    cp.thickness = 0.02;
    cp.stiffness = 5e3;
    cp.friction = mu;
    cp.massDensity = mp.mass;
    sim.addForce(std::make_shared<CollisionForce>(worldOf(slope), cp));
    const Eigen::Vector3d start = sim.evaluate(0.5, 0.5).position;
    sim.advance(400);  // 4 s
    REQUIRE(sim.status() == Status::Ok);
    const double moved = sim.evaluate(0.5, 0.5).position.x() - start.x();
    INFO("mu " << mu << " moved " << moved);
    if (mu > std::tan(theta)) {
      // static friction is regularised (Contact.h): held below the Coulomb bound, the cloth
      // creeps at the speed where the capped friction 0.3 rho v / dt balances g sin(theta)
      const double creep = std::sin(theta) * sim.subStepSize() / 0.3;
      INFO("creep speed " << creep);
      CHECK(moved >= 0.0);
      CHECK(moved < 1.2 * creep * 4.0);
      CHECK(moved < 0.05);
    } else {
      // kinetic: a = g (sin - mu cos) - damping; with damping c = 0.5 per unit mass the speed
      // tends to a / c, so over 4 s the cloth moves between half and all of a t^2 / 2
      const double a = std::sin(theta) - mu * std::cos(theta);
      CHECK(moved > 0.45 * 0.5 * a * 16.0);  // free sliding with this damping: 0.57 of it
      CHECK(moved < 0.5 * a * 16.0 * 1.01);
    }
  }
}

TEST_CASE("CollisionForce: skipping far elements and points gives the load of every quadrature point", "[core][slow]") {
  // A free cloth falls on a box and slides off its edge, in a rotated and scaled frame; half
  // way the box moves (a refit). At every step the culled load must equal the load of the same
  // density integrated at every quadrature point (a plain DistributedForce), while most
  // elements are skipped and the clearances are reused over several steps.
  const TriangleMesh b = box(Eigen::Vector3d(-0.3, -0.3, -1), Eigen::Vector3d(0.1, 0.3, 0));
  auto tree = std::make_shared<TriangleTree>(b);
  auto w = std::make_shared<ContactWorld>();
  w->obstacles.push_back({tree, true});
  // rotated, scaled and sheared: the world area per local area varies with the normal
  Eigen::Matrix3d shear = Eigen::Matrix3d::Identity();
  shear(0, 2) = 0.2;
  w->linear = 1.5 * Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix() * shear;
  w->offset = Eigen::Vector3d(0.1, -0.2, 0.05);
  // the cloth's frame is rotated: express gravity and the start height in it
  const Eigen::Matrix3d Ainv = w->linear.inverse();
  ModelParameters mp = clothParams();
  mp.numU = mp.numV = 24;
  mp.timeStep = 0.005;
  Simulation sim(mp);
  ControlNet start = sim.current();
  for (Eigen::Index i = 0; i < start.rows(); ++i) {
    const Eigen::Vector3d world(start(i, 0) * 2.0 - 1.0, start(i, 1) * 2.0 - 1.0, 0.08 + 0.02 * start(i, 0));
    start.row(i) = (Ainv * (world - w->offset)).transpose();
  }
  sim.setState(start, start, 0.0, 0);
  ContactParameters cp;
  cp.thickness = 0.03;
  cp.stiffness = 2000.0;
  cp.damping = 1.0;
  cp.friction = 0.4;
  auto contact = std::make_shared<CollisionForce>(w, cp);
  const Eigen::Matrix3d cofactor = w->linear.determinant() * w->linear.inverse().transpose();
  const DistributedForce everywhere(
      [&](const SurfaceSample& s) {
        // per unit world area (area scale a = 1 here): times the world area per local area gamma
        const double gamma = (cofactor * s.normal).norm();
        return Eigen::Vector3d(gamma * w->linear.transpose() *
                               contactDensity(*w, cp, w->linear * s.position + w->offset, w->linear * s.velocity,
                                              s.stepSize, w->linear, gamma));
      },
      kDependsOnPosition | kDependsOnVelocity | kDependsOnNormal);
  sim.addForce(contact);
  sim.addForce(std::make_shared<DistributedForce>(Ainv * Eigen::Vector3d(0, 0, -9.81)));
  int skipped = 0, compared = 0, touching = 0;
  double worst = 0.0;
  for (int step = 0; step < 120; ++step) {
    if (step == 60) {
      std::vector<Eigen::Vector3d> moved = tree->mesh().vertices;
      for (Eigen::Vector3d& v : moved) v += Eigen::Vector3d(-0.05, 0.02, 0.0);
      tree->update(moved);
    }
    ControlNet a = ControlNet::Zero(sim.space().numMoving(), 3), e = a;
    const LoadContext ctx{sim.space(), sim.current(), sim.previous(), sim.subStepSize(), sim.time()};
    contact->addLoad(ctx, a);
    everywhere.addLoad(ctx, e);
    const double scale = std::max(1e-300, e.cwiseAbs().maxCoeff());
    worst = std::max(worst, (a - e).cwiseAbs().maxCoeff() / scale);
    if (e.cwiseAbs().maxCoeff() > 0.0) ++touching;
    if (contact->counters().activeElements < contact->counters().elements) ++skipped;
    ++compared;
    REQUIRE(sim.step() == Status::Ok);
  }
  const CollisionForce::Counters& n = contact->counters();
  INFO("references " << n.references << " of " << n.loads << " loads; points queried " << n.pointQueries
                     << ", skipped " << n.pointsSkipped);
  CHECK(worst < 1e-12);
  CHECK(n.pointsSkipped > n.pointQueries / 2);  // within evaluated elements many points are skipped too
  CHECK(touching > 40);         // the comparison is about real contact
  CHECK(skipped > compared * 3 / 4);  // most of the time part of the cloth is far from the box
  CHECK(contact->counters().references < contact->counters().loads / 2);
  CHECK(contact->counters().references >= 2);  // at least the first and the refit
}

TEST_CASE("Contact: a cotton cloth dropped on a box with BACKWARD_EULER stays bounded for 10 s and rests on the box",
          "[core][slow]") {
  // cloth_on_cube_penalty's cotton (SHELL), a coarser net; the implicit step freezing the penalty used
  // to gain energy without bound here (7e9 J after 2 s)
  ModelParameters mp;
  mp.numU = mp.numV = 8;
  mp.boundaries = Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free};
  mp.energy = EnergyModel::Shell;
  mp.material = test::kCotton;
  mp.damping = 1.0;
  mp.timeStep = 0.02;
  mp.integrator = Integrator::BackwardEuler;
  Simulation sim(mp);
  const double rhoT = mp.material.density * mp.material.thickness;
  sim.addForce(std::make_shared<GravityForce>(rhoT, Eigen::Vector3d(0, 0, -9.81)));
  ContactParameters cp;
  cp.thickness = 0.015;
  cp.stiffness = 2e4;
  cp.friction = 0.3;
  cp.massDensity = rhoT;
  const double top = -0.1;
  sim.addForce(std::make_shared<CollisionForce>(worldOf(box(Eigen::Vector3d(0.2, 0.2, -0.7), Eigen::Vector3d(0.8, 0.8, top))), cp));
  double highest = 0.0;
  for (int s = 0; s < 500; ++s) {
    REQUIRE(sim.step() == Status::Ok);
    highest = std::max(highest, sim.current().cwiseAbs().maxCoeff());
    // the middle of the cloth never goes through the box's top
    REQUIRE(sim.evaluate(0.5, 0.5).position.z() > top);
  }
  CHECK(highest < 2.0);  // bounded: the net stays near its 1 m square
  // resting on the box: over the box's top (the middle of the cloth) the lowest point lies in
  // the contact layer (the layer's penalty carries it; folds may lift the rest), and still
  double lowest = 1e30;
  for (double u = 0.35; u <= 0.651; u += 0.05)
    for (double v = 0.35; v <= 0.651; v += 0.05) lowest = std::min(lowest, sim.evaluate(u, v).position.z());
  CHECK(lowest > top);
  CHECK(lowest < top + cp.thickness);
  CHECK(sim.kineticEnergy() < 1e-4);
}
