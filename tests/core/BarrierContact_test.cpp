// SPDX-License-Identifier: MIT
// Barrier contact (BarrierContact.h, docs/math.md §18) inside BACKWARD_EULER: its derivatives
// against differences, a fast fall onto a thin plate that does not pass through, a folded sheet
// whose layers do not pass through each other (and do without self-contact), and the refusals
// (another integrator, a start inside an obstacle).
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <memory>

#include "../support/Cotton.h"
#include "../support/ForceFieldCheck.h"
#include "../support/ObstacleMeshes.h"
#include "../support/ThreadSettings.h"
#include "bsdeform/contact/Barrier.h"
#include "bsdeform/contact/BarrierContact.h"
#include "bsdeform/contact/BroadPhase.h"
#include "bsdeform/contact/CollisionProxy.h"
#include "bsdeform/contact/Distance.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/dynamics/SimulationState.h"
#include "bsdeform/forces/ForceLaws.h"

using namespace bsdeform;
using bsdeform::test::box;
using bsdeform::test::worldOf;

namespace {
using test::kCotton;

ModelParameters clothModel(int n, double dt) {
  ModelParameters p;
  p.numU = p.numV = n;
  p.boundaries = Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free};
  p.energy = EnergyModel::Shell;
  p.material = kCotton;
  p.damping = 0.0;
  p.timeStep = dt;
  p.integrator = Integrator::BackwardEuler;
  return p;
}

double rhoT() { return kCotton.density * kCotton.thickness; }

/// The smallest distance over the candidate pairs of `a` and `b` (b null: of `a` against itself,
/// pairs sharing no vertex) within `reach` (the broad phase's candidates; brute force in distance).
double clearance(const ContactMesh& a, const ContactMesh* b, double reach) {
  ContactCandidates c;
  if (b)
    candidatePairs(a, *b, reach, c);
  else
    candidatePairs(a, reach, c);
  const ContactMesh& B = b ? *b : a;
  auto row = [](const ContactMesh& m, Eigen::Index i) { return Eigen::Vector3d(m.start.row(i).transpose()); };
  double d2 = reach * reach;
  for (const auto& [v, t] : c.vertexTriangle)
    d2 = std::min(d2, pointTriangleDistanceSquared(row(a, v), row(B, B.triangles(t, 0)), row(B, B.triangles(t, 1)),
                                                   row(B, B.triangles(t, 2))));
  for (const auto& [t, v] : c.triangleVertex)
    d2 = std::min(d2, pointTriangleDistanceSquared(row(B, v), row(a, a.triangles(t, 0)), row(a, a.triangles(t, 1)),
                                                   row(a, a.triangles(t, 2))));
  for (const auto& [ea, eb] : c.edgeEdge)
    d2 = std::min(d2, edgeEdgeDistanceSquared(row(a, a.edges(ea, 0)), row(a, a.edges(ea, 1)), row(B, B.edges(eb, 0)),
                                              row(B, B.edges(eb, 1))));
  return std::sqrt(d2);
}

/// A wavy free sheet 6 to 7 mm over the top (z = 0) of a plate: point–plane, point–edge,
/// point–point and edge–edge pairs within the barrier's reach (offset 5 mm, dhat 2 mm). Shifted
/// off the diagonal of the plate's top: a vertex right above an edge shared by two triangles sits
/// where its distances change class, and the Hessian jumps there.
ControlNet wavySheet(const SplineSpace& s) {
  ControlNet net = s.grevillePlane();
  for (Eigen::Index r = 0; r < net.rows(); ++r) {
    net(r, 0) += 0.0137;
    net(r, 2) = 0.0062 + 0.0004 * std::sin(7.0 * net(r, 0) + 3.0 * net(r, 1));
  }
  return net;
}

/// The 2 x 2 m plate, 10 cm thick, whose top is the plane z = 0 under the test sheets.
TriangleMesh plateUnder() { return box(Eigen::Vector3d(-0.5, -0.5, -0.1), Eigen::Vector3d(1.5, 1.5, 0.0)); }

/// Barrier contact with an offset and d̂, self-contact on.
BarrierContactParameters selfContactParameters(double offset, double dhat) {
  BarrierContactParameters bp;
  bp.offset = offset;
  bp.dhat = dhat;
  bp.selfContact = true;
  return bp;
}

/// `net` with every point moved by a millimetre in a direction of its own, and `down` lower.
ControlNet shaken(const ControlNet& net, double down) {
  ControlNet out = net;
  for (Eigen::Index r = 0; r < out.rows(); ++r)
    out.row(r) += Eigen::RowVector3d(0.001 * std::sin(3.0 * r), 0.001 * std::cos(5.0 * r),
                                     -down - 0.001 * std::sin(2.0 * r + 1.0));
  return out;
}

/// A Jacobian sink that records every block in the order it came.
struct RecordedBlocks final : JacobianSink {
  std::vector<std::pair<std::pair<Eigen::Index, Eigen::Index>, Eigen::Matrix3d>> calls;
  void add(Eigen::Index p, Eigen::Index q, const Eigen::Matrix3d& B) override { calls.push_back({{p, q}, B}); }
};

/// A Jacobian sink that sums the blocks into a dense matrix (net point = unknown: free sides).
struct DenseJacobian final : JacobianSink {
  Eigen::MatrixXd K;
  explicit DenseJacobian(Eigen::Index n) : K(Eigen::MatrixXd::Zero(n, n)) {}
  void add(Eigen::Index p, Eigen::Index q, const Eigen::Matrix3d& B) override { K.block<3, 3>(3 * p, 3 * q) += B; }
};

/// The same blocks at the same places in the same order, to the last bit.
bool sameBlocks(const RecordedBlocks& a, const RecordedBlocks& b) {
  if (a.calls.size() != b.calls.size()) return false;
  for (size_t k = 0; k < a.calls.size(); ++k)
    if (a.calls[k].first != b.calls[k].first || a.calls[k].second != b.calls[k].second) return false;
  return true;
}

/// The proxy of `net` (`samples` per span) as a ContactMesh at rest.
ContactMesh proxyMesh(const SplineSpace& s, const ControlNet& net, int samples) {
  const CollisionProxy proxy(s, samples);
  ContactMesh a;
  proxy.positions(net, a.start);
  a.end = a.start;
  a.triangles = proxy.triangles();
  a.edges = proxy.edges();
  return a;
}
}  // namespace

TEST_CASE("BarrierContactForce: load, potential and Hessian against differences", "[core][contact]") {
  // a wavy sheet over a plate and a blade whose vertices poke toward it: point–plane,
  // point–edge, point–point and edge–edge pairs, all within reach of the barrier
  const SplineSpace s(3, 3, 4, 4, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
  const ControlNet net = wavySheet(s);
  TriangleMesh plate = plateUnder();
  auto world = worldOf(plate);
  BarrierContactParameters bp;
  bp.offset = 0.005;
  bp.dhat = 0.002;
  bp.projectHessian = false;
  const BarrierContactForce force(world, bp);
  const LoadContext ctx{s, net, net, 0.02, 0.0};
  REQUIRE(force.beginStep(ctx).empty());
  REQUIRE(force.stiffness() > 0.0);
  double phi = 0.0;
  REQUIRE(force.potential(ctx, phi));
  CHECK(phi > 0.0);
  test::ForceFieldCheck check = test::forForce("barrier over a plate", force, s, net);
  test::useOwnDerivatives(check, force, s, net);
  check.step = 1e-7;
  check.tolerance = 1e-5;
  check.run();
}

TEST_CASE("BarrierContactForce: the Jacobian is exact unless its receiver asks for a definite one",
          "[core][contact]") {
  // The sheet and plate above with the default parameters (projectHessian): Newton's exact
  // tangent gets the pairs' exact Hessians, and only a receiver that asks for a definite
  // Jacobian (JacobianSink::wantsDefinite: the projected tangent) gets them projected to PSD
  const SplineSpace s(3, 3, 4, 4, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
  REQUIRE(s.numMoving() == s.netSize());  // free sides: net point = unknown
  const ControlNet net = wavySheet(s);
  BarrierContactParameters bp;
  bp.offset = 0.005;
  bp.dhat = 0.002;
  REQUIRE(bp.projectHessian);
  const BarrierContactForce force(worldOf(plateUnder()), bp);
  const LoadContext ctx{s, net, net, 0.02, 0.0};
  REQUIRE(force.beginStep(ctx).empty());
  test::ForceFieldCheck check = test::forForce("barrier over a plate, default parameters", force, s, net);
  test::useOwnDerivatives(check, force, s, net);
  check.step = 1e-7;
  check.tolerance = 1e-5;
  check.run();
  const Eigen::Index n = 3 * s.numMoving();
  auto jacobian = [&](const BarrierContactForce& f, bool definite) {
    DenseJacobian sink(n);
    sink.wantsDefinite = definite;
    f.addJacobian(ctx, 1.0 / ctx.stepSize, sink);
    return sink.K;
  };
  const Eigen::MatrixXd exact = jacobian(force, false), definite = jacobian(force, true);
  const double scale = exact.norm();
  REQUIRE(scale > 0.0);
  // the exact Hessian is indefinite here (pairs against the plate's edges and corners)
  CHECK(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(exact).eigenvalues().minCoeff() < -1e-6 * scale);
  CHECK(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(definite).eigenvalues().minCoeff() >= -1e-12 * scale);
  CHECK((definite - definite.transpose()).norm() <= 1e-14 * scale);
  // projectHessian false: the exact Hessian even for a receiver that asks for a definite one
  BarrierContactParameters raw = bp;
  raw.projectHessian = false;
  const BarrierContactForce unprojected(worldOf(plateUnder()), raw);
  REQUIRE(unprojected.beginStep(ctx).empty());
  CHECK((jacobian(unprojected, true) - exact).norm() <= 1e-12 * scale);
}

TEST_CASE("BarrierContactForce with friction: load, potential and Hessian against differences", "[core][contact]") {
  // the wavy sheet of the case above, frozen at its start, then slid and turned over the plate:
  // every pair's slip over the step, some below the smoothing's epsilon (sticking) and some above
  const SplineSpace s(3, 3, 4, 4, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
  const ControlNet start = wavySheet(s);
  const TriangleMesh plate = plateUnder();
  BarrierContactParameters bp;
  bp.offset = 0.005;
  bp.dhat = 0.002;
  bp.friction = 0.4;
  bp.epsv = 0.05;  // epsilon = epsv h = 1 mm of slip
  bp.projectHessian = false;  // the barrier's exact Hessian (friction's is PSD as it is)
  const double h = 0.02;
  const BarrierContactForce force(worldOf(plate), bp);
  REQUIRE(force.beginStep(LoadContext{s, start, start, h, 0.0}).empty());
  REQUIRE(force.frictionPairCount() > 0);
  CHECK(force.frictionNormalForce() > 0.0);
  ControlNet net = start;
  for (Eigen::Index r = 0; r < net.rows(); ++r) {  // a slip growing from 0 to 2.5 mm across the sheet
    const double y = start(r, 1);
    net(r, 0) += 0.0025 * y * y;
    net(r, 1) -= 0.0012 * start(r, 0);
    net(r, 2) += 0.0001 * y;
  }
  const BarrierContactForce frictionless(worldOf(plate), [&] {
    BarrierContactParameters q = bp;
    q.friction = 0.0;
    return q;
  }());
  REQUIRE(frictionless.beginStep(LoadContext{s, start, start, h, 0.0}).empty());
  ControlNet with = ControlNet::Zero(s.numMoving(), 3), without = with;
  force.addLoad(LoadContext{s, net, start, h, 0.0}, with);
  frictionless.addLoad(LoadContext{s, net, start, h, 0.0}, without);
  // friction opposes the slip: its load does negative work on the move from the start
  const ControlNet slip = s.gatherMoving(net) - s.gatherMoving(start);
  CHECK(((with - without).array() * slip.array()).sum() < 0.0);
  test::ForceFieldCheck check = test::forForce("barrier and friction over a plate", force, s, net, &start, h);
  test::useOwnDerivatives(check, force, s, net, &start, h);
  check.step = 1e-7;
  check.tolerance = 1e-5;
  check.run();
}

TEST_CASE("BarrierContactForce with friction: on a slope a sheet sticks when tan(theta) < mu and slides at "
          "g (sin(theta) - mu cos(theta)) when tan(theta) > mu",
          "[core][contact][slow]") {
  // The slope's frame, as the penalty's test: the plate horizontal and gravity tilted by theta
  const double mu = 0.5, top = -0.004, dt = 0.01;
  const TriangleMesh plate = box(Eigen::Vector3d(-20, -20, top - 0.1), Eigen::Vector3d(20, 20, top));
  for (double tanTheta : {0.3, 0.7}) {
    const double theta = std::atan(tanTheta);
    ModelParameters mp = clothModel(4, dt);
    mp.material = ShellMaterial{1.495e6, 0.495, 1e-3, 950.0};  // a rubber sheet: flat, no wrinkles
    Simulation sim(mp);
    const double rhoT = 950.0 * 1e-3;
    sim.addForce(std::make_shared<GravityForce>(rhoT, 9.81 * Eigen::Vector3d(std::sin(theta), 0, -std::cos(theta))));
    BarrierContactParameters bp;
    bp.offset = 0.003;
    bp.dhat = 0.002;
    bp.mass = rhoT;
    bp.friction = mu;
    bp.epsv = 1e-3;
    auto contact = std::make_shared<BarrierContactForce>(worldOf(plate), bp);
    sim.addForce(contact);
    std::vector<double> x;  // the middle's x after each step
    for (int step = 0; step < 40; ++step) {
      const Status status = sim.step();
      INFO("tan(theta) " << tanTheta << ", step " << step << ": " << sim.statusMessage());
      REQUIRE(status == Status::Ok);
      x.push_back(sim.evaluate(0.5, 0.5).position.x());
    }
    // the plate carries the weight's normal part: the frozen normal forces sum to it
    CHECK(contact->frictionNormalForce() == Approx(rhoT * 9.81 * std::cos(theta)).epsilon(0.05));
    const double frictionless = 0.5 * 9.81 * std::sin(theta) * 0.4 * 0.4;
    INFO("tan(theta) " << tanTheta << ": moved " << x.back() - x.front() << " (frictionless " << frictionless << ")");
    if (tanTheta < mu) {
      // held: smoothed static friction lets it creep at a fraction of epsv (here 0.37 epsv)
      CHECK(std::abs(x.back() - x.front()) < bp.epsv * 0.4);
    } else {
      // sliding: backward Euler's velocity grows by h a per step, exactly, under a constant force
      const double a = 9.81 * (std::sin(theta) - mu * std::cos(theta));
      const double v1 = (x[19] - x[18]) / dt, v2 = (x[39] - x[38]) / dt;
      CHECK((v2 - v1) / (20 * dt) == Approx(a).epsilon(0.03));
    }
  }
}

TEST_CASE("BarrierContactForce: a sheet falling at 5 m/s onto a 2 mm plate does not pass through", "[core][contact][slow]") {
  // Newton, and L-BFGS (which starts from the step's first tangent with a barrier)
  const NonlinearSolver solver = GENERATE(NonlinearSolver::Newton, NonlinearSolver::LBFGS);
  CAPTURE(int(solver));
  ModelParameters p = clothModel(6, 0.02);
  p.nonlinearSolver = solver;
  Simulation sim(p);
  sim.addForce(std::make_shared<GravityForce>(rhoT(), Eigen::Vector3d(0, 0, -9.81)));
  const double top = -0.05;
  const TriangleMesh plate = box(Eigen::Vector3d(-0.5, -0.5, top - 0.002), Eigen::Vector3d(1.5, 1.5, top));
  BarrierContactParameters bp;
  bp.offset = 0.005;
  bp.dhat = 0.002;
  bp.mass = rhoT();
  bp.samplesPerSpan = 4;  // the free edges whip on impact: a finer proxy keeps the spline close
  auto contact = std::make_shared<BarrierContactForce>(worldOf(plate), bp);
  sim.addForce(contact);
  ControlNet previous = sim.rest();
  previous.col(2).array() += 0.1;  // one step of 5 m/s: twice the gap, fifty times the plate's thickness
  sim.setState(sim.rest(), previous, 0.0, 0);
  double lowest = 1e300;
  for (int step = 0; step < 15; ++step) {  // 0.3 s: lands in the second step, then rests
    const Status status = sim.step();
    INFO("step " << step << ": " << sim.statusMessage());
    REQUIRE(status == Status::Ok);
    const ContactMesh obstacle = staticContactMesh(plate);
    const double gap = clearance(proxyMesh(sim.space(), sim.current(), bp.samplesPerSpan), &obstacle, 1.0);
    CHECK(gap >= bp.offset * (1.0 - 1e-9));
    lowest = std::min(lowest, gap);
    // the spline itself: within the proxy's deviation bound of it
    for (int i = 0; i <= 10; ++i)
      for (int j = 0; j <= 10; ++j)
        CHECK(sim.evaluate(i / 10.0, j / 10.0).position.z() - top >= bp.offset - contact->lastDeviationBound());
  }
  // it reached the plate and rests on it (within the barrier's reach)
  CHECK(lowest < bp.offset + bp.dhat);
}

TEST_CASE("BarrierContactForce: the layers of a folded sheet stay apart with selfContact, and cross without",
          "[core][contact][slow]") {
  // rest: the flat sheet; start: folded along u over a bend of radius 0.1 (a U lying on its
  // side), the upper layer 0.2 above the lower one, which lies on a plate; gravity brings the
  // upper layer down onto the lower
  constexpr double kPi = 3.14159265358979323846;
  const double R = 0.1, straight = 0.4;
  auto folded = [&](double u) {
    if (u <= straight) return Eigen::Vector2d(u, 0.0);
    const double a = (u - straight) / R;
    if (a <= kPi) return Eigen::Vector2d(straight + R * std::sin(a), R - R * std::cos(a));
    return Eigen::Vector2d(straight - (u - straight - kPi * R), 2.0 * R);
  };
  const TriangleMesh plate = box(Eigen::Vector3d(-1.0, -0.5, -0.1), Eigen::Vector3d(1.5, 1.5, -0.008));
  auto run = [&](bool self, double& lowestSelf, double& lastTopMinusBottom) {
    ModelParameters mp = clothModel(10, 0.02);
    mp.damping = 1.0;
    Simulation sim(mp);
    ControlNet start = sim.rest();
    for (Eigen::Index r = 0; r < start.rows(); ++r) {
      const Eigen::Vector2d xz = folded(sim.rest()(r, 0));
      start(r, 0) = xz.x();
      start(r, 2) = xz.y();
    }
    sim.setState(start, start, 0.0, 0);
    sim.addForce(std::make_shared<GravityForce>(rhoT(), Eigen::Vector3d(0, 0, -9.81)));
    BarrierContactParameters bp;
    bp.offset = 0.005;
    bp.dhat = 0.002;
    bp.mass = rhoT();
    bp.selfContact = self;
    sim.addForce(std::make_shared<BarrierContactForce>(worldOf(plate), bp));
    lowestSelf = 1e300;
    for (int step = 0; step < 40; ++step) {
      const Status status = sim.step();
      INFO("step " << step << ": " << sim.statusMessage());
      REQUIRE(status == Status::Ok);
      lowestSelf = std::min(lowestSelf, clearance(proxyMesh(sim.space(), sim.current(), bp.samplesPerSpan), nullptr, 0.05));
    }
    // the upper layer's middle (u = 0.85) against the lower layer's (u = 0.15), same v
    lastTopMinusBottom = sim.evaluate(0.85, 0.5).position.z() - sim.evaluate(0.15, 0.5).position.z();
  };
  double lowest = 0.0, gap = 0.0;
  run(true, lowest, gap);
  CHECK(lowest >= 0.005 * (1.0 - 1e-9));
  CHECK(gap > 0.0);
  CHECK(gap < 0.05);  // it came down onto the lower layer
  run(false, lowest, gap);
  CHECK(gap < 0.0);  // without self-contact the upper layer falls through the lower one
}

TEST_CASE("BarrierContactForce: refused by other integrators and when the surface starts inside the offset",
          "[core][contact]") {
  const TriangleMesh plate = box(Eigen::Vector3d(-0.5, -0.5, -0.1), Eigen::Vector3d(1.5, 1.5, -0.002));
  BarrierContactParameters bp;
  bp.offset = 0.005;
  {
    ModelParameters mp = clothModel(5, 0.01);
    mp.integrator = Integrator::Explicit;
    Simulation sim(mp);
    sim.addForce(std::make_shared<BarrierContactForce>(worldOf(box(Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(1, 1, -0.5))), bp));
    CHECK(sim.step() == Status::Refused);
    CHECK_THAT(sim.statusMessage(), Catch::Contains("BACKWARD_EULER"));
  }
  {
    Simulation sim(clothModel(5, 0.01));
    sim.addForce(std::make_shared<BarrierContactForce>(worldOf(plate), bp));
    CHECK(sim.step() == Status::Refused);  // bad input, not a blow-up: no smaller step starts elsewhere
    CHECK_THAT(sim.statusMessage(), Catch::Contains("within the contact offset") && Catch::Contains("obstacle 1") &&
                                        Catch::Contains("(u, v)"));
    CHECK(sim.current() == sim.rest());  // nothing moved
  }
  {
    // the same, moving: the state refused keeps its position and its velocity
    Simulation sim(clothModel(5, 0.01));
    sim.addForce(std::make_shared<BarrierContactForce>(worldOf(plate), bp));
    ControlNet previous = sim.rest();
    previous.col(0).array() -= 0.001;  // 0.1 m/s along x
    sim.setState(sim.rest(), previous, 0.0, 0);
    const ControlNet current = sim.current(), before = sim.previous();
    CHECK(sim.step() == Status::Refused);
    CHECK(sim.current() == current);
    CHECK(sim.previous() == before);
  }
}

TEST_CASE("BarrierContactForce: a state taken and restored resumes bit for bit, the adapted stiffness with it",
          "[core][contact]") {
  const double top = -0.02;
  const TriangleMesh plate = box(Eigen::Vector3d(-0.5, -0.5, top - 0.05), Eigen::Vector3d(1.5, 1.5, top));
  BarrierContactParameters bp;
  bp.offset = 0.005;
  bp.dhat = 0.002;
  bp.mass = rhoT();
  bp.friction = 0.3;
  auto make = [&](std::shared_ptr<BarrierContactForce>& contact) {
    auto sim = std::make_unique<Simulation>(clothModel(4, 0.02));
    sim->addForce(std::make_shared<GravityForce>(rhoT(), Eigen::Vector3d(0.3, 0, -9.81)));
    contact = std::make_shared<BarrierContactForce>(worldOf(plate), bp);
    sim->addForce(contact);
    return sim;
  };
  std::shared_ptr<BarrierContactForce> ca, cb;
  auto a = make(ca);
  REQUIRE(a->advance(8) == Status::Ok);  // landed (t = 0.07) and sliding
  REQUIRE(ca->frictionPairCount() > 0);
  // κ as the adaptive rule leaves it after gaps that keep shrinking below its threshold
  std::vector<double> adapted = ca->adaptedState();
  REQUIRE(adapted.size() == 3 + 2 + 3 * 8);  // κ, cap, distance; one obstacle of 8 vertices
  adapted[0] *= 4.0;
  adapted[1] = std::max(adapted[1], adapted[0]);
  ca->setAdaptedState(adapted);
  const SimulationState saved = stateOf(*a);
  // gravity adapts nothing; the barrier: κ, its cap, the last distance, and the plate's last pose
  REQUIRE(saved.forces.size() == 2 + adapted.size());
  CHECK(std::vector<double>(saved.forces.begin(), saved.forces.begin() + 5) ==
        std::vector<double>{0.0, double(adapted.size()), adapted[0], adapted[1], adapted[2]});
  CHECK(saved.forces[5] == 1.0);  // one obstacle
  CHECK(saved.forces[6] == 8.0);
  auto b = make(cb);
  restoreState(*b, saved);
  CHECK(cb->stiffness() == ca->stiffness());
  REQUIRE(a->advance(5) == Status::Ok);
  REQUIRE(b->advance(5) == Status::Ok);
  CHECK(sameBits(stateOf(*a), stateOf(*b)));
  // and without it the resumed run parts from the first (so the comparison above can fail)
  auto c = make(cb);
  SimulationState plain = saved;
  plain.forces.clear();
  restoreState(*c, plain);
  REQUIRE(c->advance(5) == Status::Ok);
  CHECK_FALSE(sameBits(stateOf(*a), stateOf(*c)));
  // Reset forgets it; a malformed state is refused by name
  a->reset();
  CHECK(ca->adaptedState().empty());
  CHECK_THROWS_WITH(restoreForceStates(*b, {0.0, 2.0, 1.0}), Catch::Contains("forceState") && Catch::Contains("force 2"));
  CHECK_THROWS_WITH(restoreForceStates(*b, {0.0, 3.0, -1.0, 1.0, 1.0}), Catch::Contains("stiffness (> 0)"));
  CHECK_THROWS_WITH(restoreForceStates(*b, {0.0, 6.0, 1.0, 1.0, -1.0, 1.0, 2.0, 0.5}),
                    Catch::Contains("vertex count runs past the end"));
  // a state with a force state refused is not half put back: nets and stiffness stay as they were
  restoreState(*b, saved);
  const SimulationState kept = stateOf(*b);
  SimulationState bad = saved;
  bad.current.array() += 0.01;
  bad.forces = {0.0, 3.0, -1.0, 1.0, 1.0};
  CHECK_THROWS(restoreState(*b, bad));
  CHECK(sameBits(stateOf(*b), kept));
}

TEST_CASE("BarrierContactForce: an obstacle moved between steps is swept into place, pushing the sheet without "
          "anything crossing",
          "[core][contact][slow]") {
  // a sheet resting on a plate; the plate then rises by `lift` per step (a Transform an engine
  // drives moves the obstacle's triangles between steps; TriangleTree::update here)
  auto run = [](double lift, int steps, double& rise) {
    const double top0 = -0.0065;
    TriangleMesh plate = box(Eigen::Vector3d(-0.5, -0.5, top0 - 0.05), Eigen::Vector3d(1.5, 1.5, top0));
    auto tree = std::make_shared<TriangleTree>(plate);
    auto world = std::make_shared<ContactWorld>();
    world->obstacles.push_back({tree, true});
    Simulation sim(clothModel(4, 0.02));
    sim.addForce(std::make_shared<GravityForce>(rhoT(), Eigen::Vector3d(0, 0, -9.81)));
    BarrierContactParameters bp;
    bp.offset = 0.005;
    bp.dhat = 0.002;
    bp.mass = rhoT();
    sim.addForce(std::make_shared<BarrierContactForce>(world, bp));
    REQUIRE(sim.advance(5) == Status::Ok);  // settles on the plate
    const double start = sim.evaluate(0.5, 0.5).position.z();
    for (int step = 0; step < steps; ++step) {
      for (Eigen::Vector3d& v : plate.vertices) v.z() += lift;
      tree->update(plate.vertices);
      const Status status = sim.step();
      INFO("lift " << lift << ", step " << step << ": " << sim.statusMessage());
      REQUIRE(status == Status::Ok);
      const ContactMesh obstacle = staticContactMesh(plate);
      CHECK(clearance(proxyMesh(sim.space(), sim.current(), bp.samplesPerSpan), &obstacle, 1.0) >= bp.offset * (1.0 - 1e-9));
    }
    rise = sim.evaluate(0.5, 0.5).position.z() - start;
  };
  double rise = 0.0;
  run(0.005, 10, rise);  // 0.25 m/s: carried up with the plate
  CHECK(rise == Approx(0.05).epsilon(0.05));
  run(0.04, 4, rise);  // 2 m/s, 8 times the barrier's reach per step: still nothing crosses
  CHECK(rise == Approx(0.16).epsilon(0.05));
}

TEST_CASE("BarrierContactForce: a sheet pushed by a fast obstacle is carried along in a few Newton solves a step, "
          "not one per barrier gap",
          "[core][contact]") {
  // a plate rising 4 cm a step (2 m/s, 6 times the barrier's reach) under a resting sheet: each
  // pass after the first moves the plate and the sheet along as the last pass did (up to 4 times
  // as far); alone, the plate would close 90 % of a gap of a few millimetres per pass
  const double top0 = -0.0065;
  TriangleMesh plate = box(Eigen::Vector3d(-0.5, -0.5, top0 - 0.05), Eigen::Vector3d(1.5, 1.5, top0));
  auto tree = std::make_shared<TriangleTree>(plate);
  auto world = std::make_shared<ContactWorld>();
  world->obstacles.push_back({tree, true});
  Simulation sim(clothModel(4, 0.02));
  sim.addForce(std::make_shared<GravityForce>(rhoT(), Eigen::Vector3d(0, 0, -9.81)));
  BarrierContactParameters bp;
  bp.offset = 0.005;
  bp.dhat = 0.002;
  bp.mass = rhoT();
  sim.addForce(std::make_shared<BarrierContactForce>(world, bp));
  REQUIRE(sim.advance(5) == Status::Ok);
  const double start = sim.evaluate(0.5, 0.5).position.z();
  sim.resetStepCosts();
  const int steps = 6;
  for (int step = 0; step < steps; ++step) {
    for (Eigen::Vector3d& v : plate.vertices) v.z() += 0.04;
    tree->update(plate.vertices);
    INFO("step " << step << ": " << sim.statusMessage());
    REQUIRE(sim.step() == Status::Ok);
    const ContactMesh obstacle = staticContactMesh(plate);
    CHECK(clearance(proxyMesh(sim.space(), sim.current(), bp.samplesPerSpan), &obstacle, 1.0) >= bp.offset * (1.0 - 1e-9));
  }
  const double perStep = double(sim.stepCosts().iterations) / steps;
  INFO("Newton iterations a step: " << perStep);
  CHECK(sim.evaluate(0.5, 0.5).position.z() - start == Approx(steps * 0.04).epsilon(0.02));
  CHECK(perStep < 40.0);
}

TEST_CASE("BarrierContactForce: friction acts on the slip relative to a moving obstacle: a plate sliding sideways "
          "carries a sheet with friction and leaves it without",
          "[core][contact]") {
  auto run = [](double mu) {
    const double top0 = -0.0065;
    TriangleMesh plate = box(Eigen::Vector3d(-2, -0.5, top0 - 0.05), Eigen::Vector3d(3, 1.5, top0));
    auto tree = std::make_shared<TriangleTree>(plate);
    auto world = std::make_shared<ContactWorld>();
    world->obstacles.push_back({tree, true});
    ModelParameters mp = clothModel(4, 0.02);
    mp.material = ShellMaterial{1.495e6, 0.495, 1e-3, 950.0};  // rubber: stays flat
    Simulation sim(mp);
    const double rhoT = 0.95;
    sim.addForce(std::make_shared<GravityForce>(rhoT, Eigen::Vector3d(0, 0, -9.81)));
    BarrierContactParameters bp;
    bp.offset = 0.005;
    bp.dhat = 0.002;
    bp.mass = rhoT;
    bp.friction = mu;
    sim.addForce(std::make_shared<BarrierContactForce>(world, bp));
    REQUIRE(sim.advance(5) == Status::Ok);
    const double start = sim.evaluate(0.5, 0.5).position.x();
    for (int step = 0; step < 10; ++step) {  // 5 mm per step: 0.25 m/s
      for (Eigen::Vector3d& v : plate.vertices) v.x() += 0.005;
      tree->update(plate.vertices);
      INFO("step " << step << ": " << sim.statusMessage());
      REQUIRE(sim.step() == Status::Ok);
    }
    return sim.evaluate(0.5, 0.5).position.x() - start;
  };
  // it starts at rest on a plate that jumps to 0.25 m/s: friction accelerates it at mu g until it
  // sticks, then it rides along; backward Euler's velocities are min(n h mu g, 0.25) and each step
  // moves it h times its velocity (4.1 mm behind the plate, 6.4 mm in continuous time)
  double expected = 0.0;
  for (int n = 1; n <= 10; ++n) expected += 0.02 * std::min(n * 0.02 * 0.5 * 9.81, 0.25);
  CHECK(run(0.5) == Approx(expected).epsilon(0.02));
  CHECK(std::abs(run(0.0)) < 1e-3);
}

TEST_CASE("BarrierContactForce: a step taken again from its start (a failed attempt) sweeps a moved obstacle again "
          "from where it was",
          "[core][contact]") {
  // the obstacle rises 4 cm into a sheet 6.5 mm above it; a first attempt carries the sheet
  // (and so the obstacle) up 3 cm and fails; the step is taken again from the start, where the
  // obstacle, left where the attempt brought it, would be inside the sheet
  const SplineSpace s(3, 3, 4, 4, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
  const ControlNet start = s.grevillePlane();
  TriangleMesh plate = box(Eigen::Vector3d(-0.5, -0.5, -0.1), Eigen::Vector3d(1.5, 1.5, -0.0065));
  auto tree = std::make_shared<TriangleTree>(plate);
  auto world = std::make_shared<ContactWorld>();
  world->obstacles.push_back({tree, true});
  BarrierContactParameters bp;
  bp.offset = 0.005;
  bp.dhat = 0.002;
  const BarrierContactForce force(world, bp);
  const LoadContext atStart{s, start, start, 0.02, 0.0};
  REQUIRE(force.beginStep(atStart).empty());
  for (Eigen::Vector3d& v : plate.vertices) v.z() += 0.04;
  tree->update(plate.vertices);
  REQUIRE(force.beginStep(atStart).empty());
  ControlNet lifted = start;
  lifted.col(2).array() += 0.03;
  CHECK(force.advanceObstacles(LoadContext{s, lifted, start, 0.02, 0.0}) > 0.0);  // up to the lifted sheet
  CHECK(force.beginStep(atStart).empty());  // again from the start: the plate back where it was
  CHECK(force.lastMinimumDistance() == Approx(0.0065).epsilon(1e-6));
  CHECK(force.advanceObstacles(atStart) > 0.0);  // and it sweeps from there
  CHECK(force.lastMinimumDistance() >= bp.offset);
}

TEST_CASE("BarrierContactForce: a retaken step rewinds only what moved in it, and a state put back forgets the sweep",
          "[core][contact]") {
  // a plate under the sheet and a box far from it; in step n the plate rises 2 cm, the sheet
  // with it; in step n + 1 only the box moves, and that step is retaken
  const SplineSpace s(3, 3, 4, 4, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
  const ControlNet start = s.grevillePlane();
  TriangleMesh plate = box(Eigen::Vector3d(-0.5, -0.5, -0.1), Eigen::Vector3d(1.5, 1.5, -0.0065));
  TriangleMesh far = box(Eigen::Vector3d(5, 5, 5), Eigen::Vector3d(6, 6, 6));
  auto plateTree = std::make_shared<TriangleTree>(plate);
  auto farTree = std::make_shared<TriangleTree>(far);
  auto world = std::make_shared<ContactWorld>();
  world->obstacles.push_back({plateTree, true});
  world->obstacles.push_back({farTree, true});
  BarrierContactParameters bp;
  bp.offset = 0.005;
  bp.dhat = 0.002;
  const BarrierContactForce force(world, bp);
  REQUIRE(force.beginStep(LoadContext{s, start, start, 0.02, 0.0}).empty());
  // step n: the plate rises 2 cm; the step ends with the sheet 2 cm up and the plate swept there
  for (Eigen::Vector3d& v : plate.vertices) v.z() += 0.02;
  plateTree->update(plate.vertices);
  REQUIRE(force.beginStep(LoadContext{s, start, start, 0.02, 0.0}).empty());
  ControlNet up = start;
  up.col(2).array() += 0.02;
  CHECK(force.advanceObstacles(LoadContext{s, up, start, 0.02, 0.0}) == 0.0);
  // step n + 1 from there: the box moves, the step is retaken
  for (Eigen::Vector3d& v : far.vertices) v.x() += 0.1;
  farTree->update(far.vertices);
  const LoadContext next{s, up, up, 0.02, 0.0};
  REQUIRE(force.beginStep(next).empty());
  CHECK(force.advanceObstacles(next) == 0.0);
  CHECK(force.beginStep(next).empty());
  CHECK(force.lastMinimumDistance() == Approx(0.0065).epsilon(1e-6));  // the plate stayed where step n left it
  CHECK(force.advanceObstacles(next) == 0.0);
  // a state put back (reset, the timeline): the obstacles are taken where they are, no sweep
  force.setAdaptedState({});
  for (Eigen::Vector3d& v : plate.vertices) v.z() -= 0.02;
  plateTree->update(plate.vertices);
  CHECK(force.beginStep(LoadContext{s, start, start, 0.02, 0.0}).empty());
  CHECK(force.advanceObstacles(LoadContext{s, start, start, 0.02, 0.0}) == 0.0);
  CHECK(force.lastMinimumDistance() == Approx(0.0065).epsilon(1e-6));
}

TEST_CASE("BarrierContactForce: a joint move of the sheet and a moved obstacle is cut where a pair would come "
          "within the offset, and the obstacles then go that far",
          "[core][contact]") {
  // the plate rises 4 cm toward a sheet 6.5 mm above it (1.5 mm beyond the offset); the joint
  // CCD keeps 40 % of each pair's gap above the offset (the line search's rescaling)
  const SplineSpace s(3, 3, 4, 4, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
  const ControlNet start = s.grevillePlane();
  TriangleMesh plate = box(Eigen::Vector3d(-0.5, -0.5, -0.1), Eigen::Vector3d(1.5, 1.5, -0.0065));
  auto tree = std::make_shared<TriangleTree>(plate);
  auto world = std::make_shared<ContactWorld>();
  world->obstacles.push_back({tree, true});
  BarrierContactParameters bp;
  bp.offset = 0.005;
  bp.dhat = 0.002;
  const BarrierContactForce force(world, bp);
  const LoadContext atStart{s, start, start, 0.02, 0.0};
  REQUIRE(force.beginStep(atStart).empty());
  for (Eigen::Vector3d& v : plate.vertices) v.z() += 0.04;
  tree->update(plate.vertices);
  REQUIRE(force.beginStep(atStart).empty());
  auto lifted = [&](double dz) {
    ControlNet net = start;
    net.col(2).array() += dz;
    return net;
  };
  const double gap = 0.0015, kept = 0.4 * gap;
  // the sheet where it is: the plate closes 60 % of the gap
  CHECK(force.jointAdvanceFraction(atStart, start, 1.0) == Approx((gap - kept) / 0.04).epsilon(1e-6));
  // carried along all the way, or half of the plate's move with the sheet moving half as far
  CHECK(force.jointAdvanceFraction(atStart, lifted(0.04), 1.0) == 1.0);
  CHECK(force.jointAdvanceFraction(atStart, lifted(0.02), 0.5) == 1.0);
  // the sheet lifted half as far as the plate rises: the gap closes at 2 cm per unit
  CHECK(force.jointAdvanceFraction(atStart, lifted(0.02), 1.0) == Approx((gap - kept) / 0.02).epsilon(1e-6));
  // the sheet falling 1 cm while the plate rises: the gap closes at 5 cm per unit
  CHECK(force.jointAdvanceFraction(atStart, lifted(-0.01), 1.0) == Approx((gap - kept) / 0.05).epsilon(1e-6));
  // the queries moved nothing: the plate stands where the step began (a sheet that keeps still
  // meets nothing; a plate left swept would be met) and sweeps from there
  CHECK(force.admissibleFraction(atStart, start) == 1.0);
  CHECK(force.advanceObstaclesBy(atStart, 0.0) == 1.0);
  // a quarter of the move with the sheet lifted 1 cm: three quarters left, the gap as it was
  const LoadContext atQuarter{s, lifted(0.01), start, 0.02, 0.0};
  CHECK(force.advanceObstaclesBy(atQuarter, 0.25) == Approx(0.75).epsilon(1e-12));
  CHECK(force.jointAdvanceFraction(atQuarter, lifted(0.04), 1.0) == 1.0);
  CHECK(force.jointAdvanceFraction(atQuarter, lifted(0.01), 1.0) == Approx((gap - kept) / 0.03).epsilon(1e-6));
  // the rest of the way, the sheet lifted with it: nothing left, nothing for advanceObstacles
  const LoadContext atTop{s, lifted(0.04), start, 0.02, 0.0};
  CHECK(force.advanceObstaclesBy(atTop, 1.0) == 0.0);
  CHECK(force.advanceObstacles(atTop) == 0.0);
  CHECK(force.admissibleFraction(atTop, lifted(0.04 - 0.002)) == Approx((gap - kept) / 0.002).epsilon(1e-6));
}

TEST_CASE("BarrierContactForce: candidates kept across evaluations give the same bits as a fresh search, and are "
          "searched again once the proxy moved more than the skin",
          "[core][contact]") {
  const SplineSpace s(3, 3, 4, 4, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
  const ControlNet net0 = wavySheet(s);
  const TriangleMesh plate = plateUnder();
  auto world = worldOf(plate);
  BarrierContactParameters bp = selfContactParameters(0.005, 0.002);
  const BarrierContactForce kept(world, bp);
  REQUIRE(kept.beginStep(LoadContext{s, net0, net0, 0.02, 0.0}).empty());
  const long searches = kept.candidateSearches();
  // moved by up to 1.8 mm (the skin is half the reach, 3.5 mm): answered from the kept pairs
  const ControlNet net1 = shaken(net0, 0.0);
  ControlNet net2 = net1;
  net2.col(2).array() -= 0.0015;  // toward the plate: CCD cuts it (still within the skin of net0)
  const LoadContext at1{s, net1, net0, 0.02, 0.0};
  double phiKept = 0.0, phiFresh = 0.0;
  REQUIRE(kept.potential(at1, phiKept));
  ControlNet loadKept = ControlNet::Zero(s.numMoving(), 3), loadFresh = loadKept;
  kept.addLoad(at1, loadKept);
  const double fractionKept = kept.admissibleFraction(at1, net2);
  CHECK(kept.candidateSearches() == searches);
  // a force that searches at net1 itself, with the same adapted stiffness
  const BarrierContactForce fresh(world, bp);
  REQUIRE(fresh.beginStep(LoadContext{s, net0, net0, 0.02, 0.0}).empty());
  fresh.setAdaptedState(kept.adaptedState());
  ControlNet far = net0;
  far.col(2).array() += 1.0;  // a search far from net1, so that fresh's kept pairs are useless there
  double unused = 0.0;
  fresh.potential(LoadContext{s, far, far, 0.02, 0.0}, unused);
  REQUIRE(fresh.potential(at1, phiFresh));
  fresh.addLoad(at1, loadFresh);
  const double fractionFresh = fresh.admissibleFraction(at1, net2);
  CHECK(phiKept > 0.0);
  CHECK(phiKept == phiFresh);
  CHECK(loadKept == loadFresh);
  CHECK(fractionKept < 1.0);
  CHECK(fractionKept == fractionFresh);
  // moved by more than the skin: searched again
  ControlNet net3 = net0;
  net3.col(0).array() += 0.01;
  kept.potential(LoadContext{s, net3, net0, 0.02, 0.0}, unused);
  CHECK(kept.candidateSearches() == searches + 1);
}

TEST_CASE("BarrierContactForce: a long CCD query's move is searched once and the iterates on it keep its "
          "candidates with the same bits",
          "[core][contact]") {
  // a step's first CCD query spans the whole predicted move (a falling sheet: centimetres, far
  // more than the skin); the iterates that follow lie on that segment or near it
  const SplineSpace s(3, 3, 4, 4, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
  const TriangleMesh plate = plateUnder();
  auto world = worldOf(plate);
  for (const bool self : {false, true}) {
    CAPTURE(self);
    BarrierContactParameters bp = selfContactParameters(0.005, 0.002);
    bp.selfContact = self;
    const ControlNet end = wavySheet(s);  // 5.8 to 6.6 mm above the plate: within reach
    ControlNet start = end;
    start.col(2).array() += 0.05;  // 5 cm above that
    const BarrierContactForce kept(world, bp);
    REQUIRE(kept.beginStep(LoadContext{s, start, start, 0.02, 0.0}).empty());
    const LoadContext atStart{s, start, start, 0.02, 0.0};
    REQUIRE(kept.admissibleFraction(atStart, end) == 1.0);
    const long searches = kept.candidateSearches();
    // the move's end and a point on it 0.5 mm above: the kept pairs answer
    const LoadContext atEnd{s, end, start, 0.02, 0.0};
    double phiKept = 0.0, unused = 0.0;
    REQUIRE(kept.potential(atEnd, phiKept));
    ControlNet loadKept = ControlNet::Zero(s.numMoving(), 3);
    kept.addLoad(atEnd, loadKept);
    const LoadContext atLate{s, end + 0.01 * (start - end), start, 0.02, 0.0};  // 0.5 mm above the end
    double phiLateKept = 0.0;
    REQUIRE(kept.potential(atLate, phiLateKept));
    CHECK(kept.candidateSearches() == searches);
    // Newton's step from the end (0.5 to 2.5 mm down, into the offset: CCD cuts it), up to
    // 2.9 mm off the segment: within the skin of half the reach (3.5 mm), and beyond the eighth
    // (0.875 mm) that a list takes after a move that left the last one by more than half the
    // reach, with self-contact (the sheet's pairs with itself are most of its list)
    const ControlNet nearEnd = shaken(end, 0.0015);
    const double fractionKept = kept.admissibleFraction(atEnd, nearEnd);
    CHECK(kept.candidateSearches() == searches + (self ? 1 : 0));
    // the same from a force that searches there itself
    const BarrierContactForce fresh(world, bp);
    REQUIRE(fresh.beginStep(LoadContext{s, start, start, 0.02, 0.0}).empty());
    fresh.setAdaptedState(kept.adaptedState());
    double phiFresh = 0.0;
    REQUIRE(fresh.potential(atEnd, phiFresh));
    ControlNet loadFresh = ControlNet::Zero(s.numMoving(), 3);
    fresh.addLoad(atEnd, loadFresh);
    double phiLateFresh = 0.0;
    REQUIRE(fresh.potential(atLate, phiLateFresh));
    CHECK(phiKept > 0.0);
    CHECK(phiKept == phiFresh);
    CHECK(loadKept == loadFresh);
    CHECK(phiLateKept > 0.0);
    CHECK(phiLateKept == phiLateFresh);
    CHECK(fractionKept < 1.0);
    CHECK(fractionKept == fresh.admissibleFraction(atEnd, nearEnd));
    // off the segment by more than the skin: searched again
    const long before = kept.candidateSearches();
    ControlNet aside = end;
    aside.col(0).array() += 0.01;
    kept.potential(LoadContext{s, aside, start, 0.02, 0.0}, unused);
    CHECK(kept.candidateSearches() == before + 1);
  }
}

TEST_CASE("BarrierContactForce: its terms are the same bits on one kernel thread and on two", "[core][contact]") {
  // With kernel threads the pairs' terms are computed in parts and handed on in the pairs' order, and
  // the Jacobian's element pairs summed in parts, each its own sums in the same order.
  ThreadSettingsGuard guard;
  const SplineSpace s(3, 3, 6, 6, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
  ControlNet net = wavySheet(s);
  const TriangleMesh plate = plateUnder();
  setKernelThreads(2);  // before the obstacle's Embree device (which takes the kernels' count)
  const int available = effectiveKernelThreads();  // 2, or 1 on a machine of one CPU
  auto world = worldOf(plate);
  BarrierContactParameters bp = selfContactParameters(0.005, 0.01);
  bp.friction = 0.3;
  struct Result {
    double phi = 0.0, closest = 0.0;
    ControlNet load;
    RecordedBlocks jacobian;
  };
  auto evaluate = [&](int threads) {
    setKernelThreads(threads);
    CHECK(effectiveKernelThreads() == std::min(threads, available));
    const BarrierContactForce force(world, bp);
    Result r;
    REQUIRE(force.beginStep(LoadContext{s, net, net, 0.02, 0.0}).empty());
    ControlNet moved = net;
    moved.col(0).array() += 0.001;  // a slip for the friction
    const LoadContext ctx{s, moved, net, 0.02, 0.0};
    REQUIRE(force.potential(ctx, r.phi));
    r.load = ControlNet::Zero(s.numMoving(), 3);
    force.addLoad(ctx, r.load);
    force.addJacobian(ctx, 50.0, r.jacobian);
    r.closest = force.lastMinimumDistance();
    return r;
  };
  const Result one = evaluate(1), two = evaluate(2);
  REQUIRE(one.phi > 0.0);
  REQUIRE(one.jacobian.calls.size() > 100);  // more than 64 pairs: the pairs split into parts
  CHECK(one.phi == two.phi);
  CHECK(one.closest == two.closest);
  CHECK(one.load == two.load);
  CHECK(sameBlocks(one.jacobian, two.jacobian));
}

TEST_CASE("BarrierContactForce: a Jacobian after an evaluation at the same nets visits only the pairs that one "
          "found within reach and is the same bits as one made first there",
          "[core][contact]") {
  // The first evaluation at a net keeps the candidates within the barrier's reach (offset + d̂);
  // later ones at the same net visit only those. A sheet tilted over the plate, so that some of its
  // candidates are within reach and some beyond, self-contact on. Both forces start their step at
  // `net`; the reference's Jacobian is its first evaluation at `moved`.
  ThreadSettingsGuard guard;
  const SplineSpace s(3, 3, 6, 6, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
  ControlNet net = s.grevillePlane();
  for (Eigen::Index r = 0; r < net.rows(); ++r) net(r, 2) = 0.0058 + 0.006 * net(r, 0) + 0.0003 * std::sin(9.0 * net(r, 1));
  const TriangleMesh plate = plateUnder();
  setKernelThreads(2);  // before the obstacle's Embree device (which takes the kernels' count)
  auto world = worldOf(plate);
  BarrierContactParameters bp = selfContactParameters(0.005, 0.002);
  bp.friction = 0.3;
  const int threads = GENERATE(1, 2);
  CAPTURE(threads);
  setKernelThreads(threads);
  ControlNet moved = net;
  moved.col(0).array() += 0.0004;  // a slip for the friction
  const LoadContext ctx{s, moved, net, 0.02, 0.0};
  const BarrierContactForce evaluatedFirst(world, bp), reference(world, bp);
  REQUIRE(evaluatedFirst.beginStep(LoadContext{s, net, net, 0.02, 0.0}).empty());
  REQUIRE(reference.beginStep(LoadContext{s, net, net, 0.02, 0.0}).empty());
  // the value alone first (the kept list then comes from a call without derivatives)
  double phi = 0.0;
  const long before = evaluatedFirst.costs().pairsComputed;
  REQUIRE(evaluatedFirst.potential(ctx, phi));
  REQUIRE(phi > 0.0);
  const long all = evaluatedFirst.costs().pairsComputed - before;
  RecordedBlocks kept, fresh;
  evaluatedFirst.addJacobian(ctx, 50.0, kept);
  const long within = evaluatedFirst.costs().pairsComputed - before - all;
  const long referenceBefore = reference.costs().pairsComputed;
  reference.addJacobian(ctx, 50.0, fresh);
  REQUIRE(fresh.calls.size() > 10);
  CHECK(sameBlocks(kept, fresh));
  // the reference computed the candidates at `moved` that the distance bounds keep (its kept
  // list from `net` was dropped), the Jacobian after the potential only those within reach (fewer
  // here: on the tilted sheet some edge pairs pass the bounds and lie beyond the reach)
  CHECK(reference.costs().pairsComputed - referenceBefore == all);
  CHECK(within > 0);
  CHECK(within < all);
  // the smallest distance is a pair's within reach: the sheet's low side, about 5.8 mm up
  CHECK(evaluatedFirst.lastMinimumDistance() == reference.lastMinimumDistance());
  CHECK(evaluatedFirst.lastMinimumDistance() < bp.offset + bp.dhat);
  // lifted beyond the reach everywhere: no pair within it, no term, no smallest distance (-1 in
  // the adapted state)
  ControlNet high = net;
  high.col(2).array() += 0.02;
  const BarrierContactForce above(world, bp);
  REQUIRE(above.beginStep(LoadContext{s, high, high, 0.02, 0.0}).empty());
  double none = -1.0;
  REQUIRE(above.potential(LoadContext{s, high, high, 0.02, 0.0}, none));
  CHECK(none == 0.0);
  CHECK(above.lastMinimumDistance() == std::numeric_limits<double>::infinity());
  REQUIRE(above.adaptedState().size() >= 3);
  CHECK(above.adaptedState()[2] == -1.0);
}

TEST_CASE("BarrierContactForce: its potential after a load at the same nets is the load's terms summed, the same "
          "bits, and anything that changes the terms computes it anew",
          "[core][contact]") {
  const SplineSpace s(3, 3, 4, 4, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
  const ControlNet net = wavySheet(s);
  const TriangleMesh plate = plateUnder();
  auto world = worldOf(plate);
  BarrierContactParameters bp;
  bp.offset = 0.005;
  bp.dhat = 0.002;
  bp.friction = GENERATE(0.0, 0.3);
  CAPTURE(bp.friction);
  const BarrierContactForce loaded(world, bp), bare(world, bp);
  REQUIRE(loaded.beginStep(LoadContext{s, net, net, 0.02, 0.0}).empty());
  REQUIRE(bare.beginStep(LoadContext{s, net, net, 0.02, 0.0}).empty());
  ControlNet moved = net;
  moved.col(0).array() += 0.0005;  // a slip for the friction
  const LoadContext ctx{s, moved, net, 0.02, 0.0};
  ControlNet load = ControlNet::Zero(s.numMoving(), 3);
  loaded.addLoad(ctx, load);
  double afterLoad = 0.0, alone = 0.0;
  REQUIRE(loaded.potential(ctx, afterLoad));
  REQUIRE(bare.potential(ctx, alone));
  CHECK(afterLoad > 0.0);
  CHECK(afterLoad == alone);
  // another net (the previous one, the step): not the kept value
  ControlNet lower = moved;
  lower.col(2).array() -= 0.0003;
  for (const LoadContext& other : {LoadContext{s, lower, net, 0.02, 0.0}, LoadContext{s, moved, moved, 0.02, 0.0},
                                   LoadContext{s, moved, net, 0.01, 0.0}}) {
    double a = 0.0, b = 0.0;
    loaded.addLoad(ctx, load);
    REQUIRE(loaded.potential(other, a));
    REQUIRE(bare.potential(other, b));
    CHECK(a == b);
  }
  if (bp.friction == 0.0) {
    // the stiffness doubled (a state put back): every term doubles, exactly
    loaded.addLoad(ctx, load);
    std::vector<double> state = loaded.adaptedState();
    REQUIRE(state.size() >= 2);
    state[0] *= 2.0;
    state[1] = std::max(state[1], state[0]);
    loaded.setAdaptedState(state);
    double doubled = 0.0;
    REQUIRE(loaded.potential(ctx, doubled));
    CHECK(doubled == 2.0 * afterLoad);
  }
}

TEST_CASE("BarrierContactForce and Simulation: where the steps' time goes is counted by phase, and the phases lie "
          "within the steps",
          "[core][contact]") {
  ModelParameters p = clothModel(6, 0.02);
  Simulation sim(p);
  sim.addForce(std::make_shared<GravityForce>(rhoT(), Eigen::Vector3d(0, 0, -9.81)));
  const TriangleMesh plate = box(Eigen::Vector3d(-0.5, -0.5, -0.05), Eigen::Vector3d(1.5, 1.5, -0.006));
  BarrierContactParameters bp;
  bp.offset = 0.005;
  bp.dhat = 0.002;
  bp.mass = rhoT();
  bp.friction = 0.3;
  auto contact = std::make_shared<BarrierContactForce>(worldOf(plate), bp);
  sim.addForce(contact);
  const StepCosts& c = sim.stepCosts();
  CHECK(c.steps == 0);
  CHECK(c.total == 0.0);
  long iterations = 0;
  for (int step = 0; step < 6; ++step) {  // it lands on the plate 1 mm below the offset's reach
    REQUIRE(sim.step() == Status::Ok);
    iterations += sim.lastNewtonIterations();
  }
  CHECK(c.steps == 6);
  CHECK(c.iterations == iterations);
  CHECK(c.factorisations >= c.steps);  // each step starts with a factorisation of its own
  CHECK(c.factorisations <= c.iterations);
  for (double phase : {c.elastic, c.loads, c.collisionChecks, c.factorisation, c.solve}) CHECK(phase > 0.0);
  CHECK(c.elastic + c.loads + c.collisionChecks + c.factorisation + c.solve <= c.total);
  CHECK(c.other() >= 0.0);
  const BarrierContactForce::Costs& b = contact->costs();
  for (double part : {b.proxy, b.broadPhase, b.pairs, b.push, b.ccd}) CHECK(part > 0.0);
  // the contact's parts are inside the steps (its pairs inside the loads, the start's search
  // and friction inside the rest of the step)
  CHECK(b.proxy + b.broadPhase + b.pairs + b.push + b.ccd <= c.total);
  CHECK(b.ccd <= c.collisionChecks);
  sim.resetStepCosts();
  contact->resetCosts();
  CHECK(sim.stepCosts().total == 0.0);
  CHECK(sim.stepCosts().iterations == 0);
  CHECK(contact->costs().pairs == 0.0);
  REQUIRE(sim.step() == Status::Ok);
  CHECK(sim.stepCosts().steps == 1);
  CHECK(sim.stepCosts().iterations == sim.lastNewtonIterations());
}

TEST_CASE("BarrierContactForce with selfContact: its Jacobian is every non-adjacent pair's Hessian through the "
          "proxy's weights, the blocks between the two parts of each pair included",
          "[core][contact]") {
  // A helicoid ribbon of two turns (radius 0.04 to 0.06 m) whose turns lie 2.7 mm apart, inside
  // the barrier's reach (offset 2 mm, d̂ 1 mm): every pair couples points of one turn to points
  // of the next, which share no element. Against a brute force over all pairs of the proxy that
  // share no vertex; without the blocks between a pair's two parts (left out before: Newton then
  // converged only linearly in self-contact) the difference is of the Jacobian's own size.
  constexpr double kPi = 3.14159265358979323846;
  const SplineSpace s(2, 2, 40, 2, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
  ControlNet net = s.grevillePlane();
  for (Eigen::Index r = 0; r < net.rows(); ++r) {
    // 1.95 turns and a radius growing 2.3 mm a turn: the proxy's vertices of one turn do not lie
    // over those of the next
    const double turn = 1.95 * net(r, 0), radius = 0.04 + 0.02 * net(r, 1) + 0.0023 * turn;
    net.row(r) << radius * std::cos(2.0 * kPi * turn), radius * std::sin(2.0 * kPi * turn), 0.0027 * turn;
  }
  REQUIRE(s.numMoving() == s.netSize());  // free sides: net point = unknown
  const TriangleMesh far = box(Eigen::Vector3d(5.0, 5.0, 5.0), Eigen::Vector3d(6.0, 6.0, 6.0));
  BarrierContactParameters bp = selfContactParameters(0.002, 0.001);
  bp.samplesPerSpan = 2;
  bp.projectHessian = false;
  const BarrierContactForce force(worldOf(far), bp);
  // at rest the ribbon is flat: the turns are far apart there (contacts, not neighbours)
  const ControlNet flat = s.grevillePlane();
  LoadContext ctx{s, net, net, 0.02, 0.0};
  ctx.rest = &flat;
  REQUIRE(force.beginStep(ctx).empty());
  double phi = 0.0;
  REQUIRE(force.potential(ctx, phi));
  REQUIRE(phi > 0.0);  // the turns are within reach of each other
  const Eigen::Index n = 3 * s.numMoving();
  DenseJacobian sink(n);
  force.addJacobian(ctx, 1.0 / ctx.stepSize, sink);
  // the brute force: every pair of the proxy sharing no vertex, its Hessian through the weights
  const CollisionProxy proxy(s, bp.samplesPerSpan);
  Eigen::MatrixX3d X, X0;
  proxy.positions(net, X);
  proxy.positions(flat, X0);
  const double reach2 = (bp.offset + bp.dhat) * (bp.offset + bp.dhat);
  const Eigen::MatrixX3i& T = proxy.triangles();
  const Eigen::MatrixX2i& E = proxy.edges();
  BarrierParameters b;
  b.offset = bp.offset;
  b.dhat = bp.dhat;
  b.stiffness = force.stiffness();
  auto at = [&](Eigen::Index i) { return Eigen::Vector3d(X.row(i).transpose()); };
  auto atRest = [&](Eigen::Index i) { return Eigen::Vector3d(X0.row(i).transpose()); };
  long neighboursAtRest = 0;  // pairs sharing no vertex but within reach at rest: not contacts
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(n, n);
  long between = 0;  // pairs whose points lie in elements of different turns
  auto push = [&](const std::array<Eigen::Index, 4>& v, const Matrix12d& h) {
    for (int a = 0; a < 4; ++a)
      for (int c = 0; c < 4; ++c)
        for (const auto& wa : proxy.netWeights(v[size_t(a)]))
          for (const auto& wc : proxy.netWeights(v[size_t(c)]))
            expected.block<3, 3>(3 * wa.index, 3 * wc.index) += wa.weight * wc.weight * h.block<3, 3>(3 * a, 3 * c);
    between += std::abs(X(v[0], 2) - X(v[3], 2)) > 0.001;
  };
  Vector12d g;
  Matrix12d h;
  for (Eigen::Index v = 0; v < X.rows(); ++v)
    for (Eigen::Index f = 0; f < T.rows(); ++f)
      if (T(f, 0) != v && T(f, 1) != v && T(f, 2) != v &&
          (pointTriangleDistanceSquared(atRest(v), atRest(T(f, 0)), atRest(T(f, 1)), atRest(T(f, 2))) >= reach2 ||
           (++neighboursAtRest, false)) &&
          pointTriangleBarrier(at(v), at(T(f, 0)), at(T(f, 1)), at(T(f, 2)), b, &g, &h, BarrierHessian::Exact) != 0.0)
        push({v, T(f, 0), T(f, 1), T(f, 2)}, h);
  for (Eigen::Index e = 0; e < E.rows(); ++e)
    for (Eigen::Index q = e + 1; q < E.rows(); ++q) {
      if (E(e, 0) == E(q, 0) || E(e, 0) == E(q, 1) || E(e, 1) == E(q, 0) || E(e, 1) == E(q, 1)) continue;
      if (edgeEdgeDistanceSquared(atRest(E(e, 0)), atRest(E(e, 1)), atRest(E(q, 0)), atRest(E(q, 1))) < reach2) {
        ++neighboursAtRest;
        continue;
      }
      const double threshold =
          edgeEdgeMollifierThreshold(atRest(E(e, 0)), atRest(E(e, 1)), atRest(E(q, 0)), atRest(E(q, 1)));
      if (edgeEdgeBarrier(at(E(e, 0)), at(E(e, 1)), at(E(q, 0)), at(E(q, 1)), threshold, b, &g, &h,
                          BarrierHessian::Exact) != 0.0 ||
          !h.isZero(0.0))
        push({E(e, 0), E(e, 1), E(q, 0), E(q, 1)}, h);
    }
  CHECK(between > 100);
  CHECK(neighboursAtRest == 0);  // the flat ribbon's proxy is coarser than the reach
  CHECK(expected.norm() > 0.0);
  CHECK((sink.K - expected).norm() <= 1e-12 * expected.norm());
}

TEST_CASE("BarrierContactForce with selfContact: load, potential and Hessian against differences", "[core][contact]") {
  // The helicoid above: pairs between the turns, and pairs of exactly parallel edges within reach
  // (no value, no gradient, a Hessian: left out of the Jacobian before, 107 of 439 on a diagonal)
  constexpr double kPi = 3.14159265358979323846;
  const SplineSpace s(2, 2, 40, 2, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
  ControlNet net = s.grevillePlane();
  for (Eigen::Index r = 0; r < net.rows(); ++r) {
    const double turn = 1.95 * net(r, 0), radius = 0.04 + 0.02 * net(r, 1) + 0.0023 * turn;
    net.row(r) << radius * std::cos(2.0 * kPi * turn), radius * std::sin(2.0 * kPi * turn), 0.0027 * turn;
  }
  const TriangleMesh far = box(Eigen::Vector3d(5.0, 5.0, 5.0), Eigen::Vector3d(6.0, 6.0, 6.0));
  BarrierContactParameters bp = selfContactParameters(0.002, 0.001);
  bp.samplesPerSpan = 2;
  bp.projectHessian = false;
  const BarrierContactForce force(worldOf(far), bp);
  const ControlNet flat = s.grevillePlane();  // at rest the turns are far apart
  LoadContext ctx{s, net, net, 0.02, 0.0};
  ctx.rest = &flat;
  REQUIRE(force.beginStep(ctx).empty());
  test::ForceFieldCheck check = test::forForce("barrier between a helicoid's turns", force, s, net);
  test::useOwnDerivatives(check, force, s, net);
  check.step = 1e-8;
  check.tolerance = 1e-5;
  check.run();
}

TEST_CASE("BarrierContactForce: a Jacobian at the net of the last load takes that load's pairs and gives a fresh "
          "force's bits - and a moved obstacle or another net is searched again",
          "[core][contact]") {
  const SplineSpace s(3, 3, 4, 4, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
  const ControlNet net = wavySheet(s);
  TriangleMesh plate = plateUnder();
  auto tree = std::make_shared<TriangleTree>(plate);
  auto world = std::make_shared<ContactWorld>();
  world->obstacles.push_back({tree, true});
  BarrierContactParameters bp = selfContactParameters(0.005, 0.002);
  // the Jacobian of a force that has seen nothing else: the reference
  auto freshJacobian = [&](const LoadContext& ctx) {
    const BarrierContactForce force(world, bp);
    REQUIRE(force.beginStep(LoadContext{s, net, net, 0.02, 0.0}).empty());
    RecordedBlocks b;
    force.addJacobian(ctx, 50.0, b);
    return b;
  };
  const BarrierContactForce force(world, bp);
  REQUIRE(force.beginStep(LoadContext{s, net, net, 0.02, 0.0}).empty());
  ControlNet lower = net;
  lower.col(2).array() -= 0.0005;  // 5.7 to 6.7 mm over the plate: more pairs within reach
  const LoadContext atNet{s, net, net, 0.02, 0.0}, atLower{s, lower, net, 0.02, 0.0};
  ControlNet load = ControlNet::Zero(s.numMoving(), 3);
  force.addLoad(atNet, load);
  RecordedBlocks kept;
  force.addJacobian(atNet, 50.0, kept);  // from the load's pairs
  const RecordedBlocks reference = freshJacobian(atNet);
  REQUIRE(reference.calls.size() > 10);
  CHECK(sameBlocks(kept, reference));
  // another net after that load: its own pairs
  RecordedBlocks other;
  force.addJacobian(atLower, 50.0, other);
  const RecordedBlocks otherReference = freshJacobian(atLower);
  CHECK(!sameBlocks(other, reference));
  CHECK(sameBlocks(other, otherReference));
  // the plate slides 0.6 m along x after a load at `lower` (out from under the sheet's edge) and is
  // swept there at the next step's start: the Jacobian at the same net sees it where it is now (a
  // twin given the same stiffness and poses)
  force.addLoad(atLower, load);
  for (Eigen::Vector3d& v : plate.vertices) v.x() += 0.6;
  tree->update(plate.vertices);
  const LoadContext start{s, lower, lower, 0.02, 0.0};
  REQUIRE(force.beginStep(start).empty());
  force.advanceObstacles(start);
  const BarrierContactForce twin(world, bp);
  twin.setAdaptedState(force.adaptedState());
  RecordedBlocks afterMove, twinBlocks;
  force.addJacobian(atLower, 50.0, afterMove);
  twin.addJacobian(atLower, 50.0, twinBlocks);
  CHECK(!sameBlocks(afterMove, other));
  CHECK(sameBlocks(afterMove, twinBlocks));
}

TEST_CASE("BarrierContactForce with selfContact: a flat sheet whose proxy is finer than the reach feels nothing at "
          "rest - its neighbours at rest are not contacts - and folded layers still are",
          "[core][contact]") {
  // a 1 m sheet, 8 proxy intervals a knot span: triangles that share no vertex lie within the
  // reach (5 + 1 cm) of each other at rest. They are neighbours in the sheet, not contacts: no
  // refusal, and no barrier pushing them apart in the sheet's own plane.
  BarrierContactParameters bp = selfContactParameters(0.05, 0.01);
  bp.samplesPerSpan = 8;
  Simulation sim(clothModel(6, 0.01));
  sim.addForce(std::make_shared<BarrierContactForce>(std::make_shared<ContactWorld>(), bp));
  CHECK(sim.step() == Status::Ok);
  const SplineSpace& s = sim.space();
  const ControlNet rest = sim.rest();
  {
    // no force at all at rest, not even in its plane
    const BarrierContactForce atRest(std::make_shared<ContactWorld>(), bp);
    LoadContext ctx{s, rest, rest, 0.01, 0.0};
    ctx.rest = &rest;
    REQUIRE(atRest.beginStep(ctx).empty());
    double phi = -1.0;
    REQUIRE(atRest.potential(ctx, phi));
    CHECK(phi == 0.0);
    ControlNet load = ControlNet::Zero(s.numMoving(), 3);
    atRest.addLoad(ctx, load);
    CHECK(load.isZero(0.0));
  }
  // the same proxy, the sheet folded over onto itself 3 cm above (x > 0.7 turned back over x < 0.7):
  // the two layers are far apart at rest, and they meet here
  ControlNet folded = rest;
  for (Eigen::Index r = 0; r < folded.rows(); ++r)
    if (rest(r, 0) > 0.7) folded.row(r) << 1.4 - rest(r, 0), rest(r, 1), 0.03;
  const BarrierContactForce force(std::make_shared<ContactWorld>(), bp);
  LoadContext ctx{s, folded, folded, 0.01, 0.0};
  ctx.rest = &rest;
  const std::string why = force.beginStep(ctx);
  CHECK_THAT(why, Catch::Contains("m of itself near"));  // 3 cm: inside the offset of 5 cm
}

