// SPDX-License-Identifier: MIT
// Every force law through one finite-difference fixture (support/ForceFieldCheck.h, after SOFA's
// ForceField_test): the load is minus the derivative of the law's energy where it has one, its
// Jacobian the law's formula where it has one, and symmetric where the law is conservative.
// Uniform, region, line, point, spring, gravity, a position-dependent callable, plane, sphere and
// mesh contact are conservative; pressure (a follower load) and drag (damping) get the Jacobian
// check only. A new law is a few lines here.
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "../support/ForceFieldCheck.h"
#include "bsdeform/contact/Contact.h"
#include "bsdeform/forces/ForceLaws.h"

using namespace bsdeform;
using namespace bsdeform::test;

namespace {

/// The spaces every law is checked on: clamped, all free, periodic in u.
std::vector<SplineSpace> spaces() {
  using B = Boundary;
  return {SplineSpace(3, 2, 4, 3), SplineSpace(2, 3, 3, 3, {B::Free, B::Free, B::Free, B::Free}),
          SplineSpace(3, 3, 5, 4, {B::Periodic, B::Periodic, B::Clamped, B::Clamped})};
}

std::string spaceName(const SplineSpace& s) {
  return "degrees " + std::to_string(s.degreeU()) + ", " + std::to_string(s.degreeV()) + ", sides " +
         boundaryName(s.boundaries().uMin) + " / " + boundaryName(s.boundaries().vMin);
}

/// The energy of a constant density f on the rule's points: -f . integral of S.
std::function<double(const ControlNet&)> constantDensityEnergy(const SplineSpace& s, const Eigen::Vector3d& f,
                                                               std::vector<QPoint> rule) {
  return [&s, f, rule = std::move(rule)](const ControlNet& net) {
    return surfaceEnergy(s, net, rule, [&](const Eigen::Vector3d& x) { return -f.dot(x); });
  };
}

/// A law whose load does not depend on the position: dL/dP = 0.
ControlNet noStiffness(const ControlNet& d) { return ControlNet::Zero(d.rows(), 3); }

/// -k G (x) I over a rule (G the Gram matrix of the moving B-splines: exact with n + 1 points).
Eigen::MatrixXd gramJacobian(const SplineSpace& s, const std::vector<QPoint>& rule, double k) {
  return quadratureJacobian(s, rule, [&](const QPoint&, const MovingBasis& mb, Eigen::Index n) {
    return Eigen::Matrix3d(-k * mb.b[n] * Eigen::Matrix3d::Identity());
  });
}

}  // namespace

TEST_CASE("ForceField: uniform, region and line loads are minus the derivative of their energy", "[core]") {
  const Eigen::Vector3d f(0.3, -1.2, 2.5);
  for (const SplineSpace& s : spaces()) {
    const ControlNet net = deformedNet(s, 0.3);
    const int su = s.basisU().numSpans(), sv = s.basisV().numSpans();
    const std::vector<QPoint> whole = tensorRule(s, s.degreeU() + 1, s.degreeV() + 1);
    const DistributedForce uniform(f);
    ForceFieldCheck c = forForce("uniform, " + spaceName(s), uniform, s, net);
    c.energy = constantDensityEnergy(s, f, whole);
    c.jacobianProduct = noStiffness;
    c.run();

    const ParamRect rect{1.0 / su, double(su - 1) / su, 0.0, double(sv - 1) / sv};  // edges on knots
    const DistributedForce region(f, rect);
    c = forForce("region, " + spaceName(s), region, s, net);
    c.energy = constantDensityEnergy(s, f, tensorRule(s, s.degreeU() + 1, s.degreeV() + 1, rect));
    c.jacobianProduct = noStiffness;
    c.run();

    // the line u = 0.4 from v = 0 to the last knot but one, per unit parameter length
    const ParamRect line{0.4, 0.4, 0.0, double(sv - 1) / sv};
    std::vector<QPoint> lineRule;
    const QuadratureRule& g = gaussLegendre(s.degreeV() + 1);
    for (int b = 0; b < sv - 1; ++b)
      for (size_t q = 0; q < g.nodes.size(); ++q) lineRule.push_back({line.u0, (b + g.nodes[q]) / sv, g.weights[q] / sv});
    const DistributedForce lineLoad(f, line);
    c = forForce("line, " + spaceName(s), lineLoad, s, net);
    c.energy = constantDensityEnergy(s, f, lineRule);
    c.jacobianProduct = noStiffness;
    c.run();
  }
}

TEST_CASE("ForceField: point force, spring and gravity", "[core]") {
  for (const SplineSpace& s : spaces()) {
    const ControlNet net = deformedNet(s, 0.3);
    const Eigen::Vector3d F(1.0, -0.5, 2.0);
    for (const Eigen::Vector2d& uv : {Eigen::Vector2d(0.37, 0.61), Eigen::Vector2d(0.02, 0.5), Eigen::Vector2d(1.0, 0.3),
                                      Eigen::Vector2d(1.0, 0.0)}) {
      const std::string at = " at (" + std::to_string(uv.x()) + ", " + std::to_string(uv.y()) + "), " + spaceName(s);
      auto S = [&s, uv](const ControlNet& n) { return s.evaluate(n, uv.x(), uv.y(), 0).position; };
      const PointForce point(uv.x(), uv.y(), F);
      ForceFieldCheck c = forForce("point" + at, point, s, net);
      c.energy = [&](const ControlNet& n) { return -F.dot(S(n)); };
      c.jacobianProduct = noStiffness;
      c.run();

      // a spring: E = k/2 |a - S(u0, v0)|^2, dL/dP = -k beta beta^T (beta: the B-splines at (u0, v0),
      // from a unit point force, whose load is exact: Force_test)
      const double k = 37.0;
      const Eigen::Vector3d anchor(0.4, 0.7, 1.2);
      const SpringForce spring(uv.x(), uv.y(), anchor, k);
      const Eigen::VectorXd beta =
          forForce("", PointForce(uv.x(), uv.y(), Eigen::Vector3d(1, 0, 0)), s, net).loadAt(s.gatherMoving(net)).col(0);
      Eigen::MatrixXd J = Eigen::MatrixXd::Zero(3 * beta.size(), 3 * beta.size());
      for (Eigen::Index m = 0; m < beta.size(); ++m)
        for (Eigen::Index n = 0; n < beta.size(); ++n)
          J.block<3, 3>(3 * m, 3 * n) = -k * beta[m] * beta[n] * Eigen::Matrix3d::Identity();
      c = forForce("spring" + at, spring, s, net);
      c.energy = [&](const ControlNet& n) { return 0.5 * k * (anchor - S(n)).squaredNorm(); };
      c.jacobianProduct = productOf(J);
      c.run();
    }
    const GravityForce gravity(2.5, Eigen::Vector3d(0.0, -1.0, -9.81));
    ForceFieldCheck c = forForce("gravity, " + spaceName(s), gravity, s, net);
    c.energy = constantDensityEnergy(s, 2.5 * Eigen::Vector3d(0.0, -1.0, -9.81),
                                     tensorRule(s, s.degreeU() + 1, s.degreeV() + 1));
    c.jacobianProduct = noStiffness;
    c.run();
  }
}

TEST_CASE("ForceField: a position-dependent density callable (the general quadrature)", "[core]") {
  // f = -kappa (S - c): the potential kappa/2 |S - c|^2, Jacobian -kappa G (x) I
  const double kappa = 3.0;
  const Eigen::Vector3d centre(0.5, 0.2, -0.4);
  for (const SplineSpace& s : spaces()) {
    const ControlNet net = deformedNet(s, 0.3);
    const DistributedForce pull([&](const SurfaceSample& x) { return Eigen::Vector3d(-kappa * (x.position - centre)); },
                                kDependsOnPosition, ParamRect(), 2, kappa);
    ForceFieldCheck c = forForce("callable, " + spaceName(s), pull, s, net);
    const std::vector<QPoint> rule = classRule(s);
    c.energy = [&](const ControlNet& n) {
      return surfaceEnergy(s, n, rule, [&](const Eigen::Vector3d& x) { return 0.5 * kappa * (x - centre).squaredNorm(); });
    };
    c.jacobianProduct = productOf(gramJacobian(s, rule, kappa));
    c.run();
  }
}

TEST_CASE("ForceField: plane and sphere contact", "[core]") {
  const double k = 50.0;
  for (const SplineSpace& s : spaces()) {
    const ControlNet net = deformedNet(s, 0.3);
    const std::vector<QPoint> rule = classRule(s);
    // fully penetrating (every point, Jacobian -k G (x) n n^T) and partly
    for (const Eigen::Vector3d& c0 : {Eigen::Vector3d(0.5, 0.5, 3.0), Eigen::Vector3d(0.0, 0.0, 0.12)}) {
      const Eigen::Vector3d n = Eigen::Vector3d(0.1, 0.05, 1.0).normalized();
      const PlaneContactForce plane(c0, n, k);
      auto depth = [&](const Eigen::Vector3d& x) { return std::max(-(x - c0).dot(n), 0.0); };
      ForceFieldCheck c = forForce("plane through z = " + std::to_string(c0.z()) + ", " + spaceName(s), plane, s, net);
      c.energy = [&](const ControlNet& net2) {
        return surfaceEnergy(s, net2, rule, [&](const Eigen::Vector3d& x) { return 0.5 * k * depth(x) * depth(x); });
      };
      c.jacobianProduct = productOf(quadratureJacobian(s, rule, [&](const QPoint& q, const MovingBasis& mb, Eigen::Index m) {
        const bool in = depth(s.evaluate(net, q.u, q.v, 0).position) > 0.0;
        return Eigen::Matrix3d(in ? Eigen::Matrix3d(-k * mb.b[m] * n * n.transpose()) : Eigen::Matrix3d::Zero());
      }));
      c.run();
    }

    const Eigen::Vector3d centre(0.45, 0.55, -0.4);
    const double r = 0.75;
    const SphereContactForce sphere(centre, r, 80.0);
    ForceFieldCheck c = forForce("sphere, " + spaceName(s), sphere, s, net);
    c.energy = [&](const ControlNet& net2) {
      return surfaceEnergy(s, net2, rule, [&](const Eigen::Vector3d& x) {
        const double d = std::max(r - (x - centre).norm(), 0.0);
        return 0.5 * 80.0 * d * d;
      });
    };
    c.jacobianProduct = productOf(quadratureJacobian(s, rule, [&](const QPoint& q, const MovingBasis& mb, Eigen::Index m) {
      const Eigen::Vector3d d = s.evaluate(net, q.u, q.v, 0).position - centre;
      const double len = d.norm();
      if (len >= r) return Eigen::Matrix3d(Eigen::Matrix3d::Zero());
      // df/dS = -k e e^T + k (r/|d| - 1)(I - e e^T)
      const Eigen::Matrix3d P = (d / len) * (d / len).transpose();
      return Eigen::Matrix3d(mb.b[m] * 80.0 * (-P + (r / len - 1.0) * (Eigen::Matrix3d::Identity() - P)));
    }));
    c.run();
  }
}

TEST_CASE("ForceField: mesh contact without damping and friction is the penalty k/2 depth^2", "[core]") {
  // a box under the whole sheet whose top face the sheet reaches through (not deeper than the
  // search distance 3 tau, past which a closed obstacle lets go)
  TriangleMesh box;
  const Eigen::Vector3d lo(-0.5, -0.5, -1.0), hi(1.5, 1.5, 0.05);
  for (int i = 0; i < 8; ++i)
    box.vertices.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    box.triangles.emplace_back(f[0], f[1], f[2]);
    box.triangles.emplace_back(f[0], f[2], f[3]);
  }
  auto world = std::make_shared<ContactWorld>();
  world->obstacles.push_back({std::make_shared<TriangleTree>(box), isClosedMesh(box)});
  REQUIRE(world->obstacles.front().closed);
  ContactParameters p;
  p.thickness = 0.1;
  p.stiffness = 200.0;
  for (const SplineSpace& s : spaces()) {
    const ControlNet net = deformedNet(s, 0.3);
    const CollisionForce contact(world, p);
    ForceFieldCheck c = forForce("mesh contact, " + spaceName(s), contact, s, net);
    const std::vector<QPoint> rule = classRule(s);
    c.energy = [&](const ControlNet& net2) {
      return surfaceEnergy(s, net2, rule, [&](const Eigen::Vector3d& x) {
        double depth = 0.0;
        contactDensity(*world, p, x, Eigen::Vector3d::Zero(), 0.1, &depth);
        return 0.5 * p.areaScale * p.stiffness * depth * depth;
      });
    };
    REQUIRE(c.loadAt(c.P).norm() > 0.0);  // in contact
    c.run();

    // its own Jacobian (every contact point inside the top face: exact), with normal damping:
    // the state moving down at 0.3 per unit time, the step's velocity part scaled by 1/dt
    ContactParameters damped = p;
    damped.damping = 2.0;
    const CollisionForce dampedContact(world, damped);
    ControlNet previous = net;
    previous.col(2).array() += 0.03;
    ForceFieldCheck own = forForce("mesh contact's own Jacobian, " + spaceName(s), dampedContact, s, net, &previous, 0.1);
    useOwnDerivatives(own, dampedContact, s, net, &previous, 0.1);
    own.energy = nullptr;
    own.run();
  }
}

TEST_CASE("ForceField: pressure (a follower load) and drag (damping): the Jacobian only", "[core]") {
  const double pressure = 6.0;
  for (const SplineSpace& s : spaces()) {
    const std::vector<QPoint> rule = classRule(s);
    for (double amp : {0.0, 0.3, 0.8}) {
      const ControlNet net = deformedNet(s, amp);
      const PressureForce force(pressure);
      ForceFieldCheck c = forForce("pressure, bump " + std::to_string(amp) + ", " + spaceName(s), force, s, net);
      // d n / d P_m = (I - n n^T) (B_m,u [.] x S_v + B_m,v S_u x [.]) / |N|
      c.jacobianProduct = productOf(quadratureJacobian(s, rule, [&](const QPoint& q, const MovingBasis& mb, Eigen::Index m) {
        const SurfacePoint sp = s.evaluate(net, q.u, q.v, 1);
        const Eigen::Vector3d N = sp.du.cross(sp.dv), n = N.normalized();
        const Eigen::Matrix3d dN = -mb.bu[m] * crossMatrix(sp.dv) + mb.bv[m] * crossMatrix(sp.du);
        return Eigen::Matrix3d(pressure * (Eigen::Matrix3d::Identity() - n * n.transpose()) * dN / N.norm());
      }));
      c.run();
    }
    // drag: f = -c (S - S_prev) / dt, so dL/dP = -(c / dt) G (x) I whatever the velocity
    const ControlNet net = deformedNet(s, 0.2);
    ControlNet previous = net;
    previous.rowwise() -= 0.05 * Eigen::RowVector3d(0.3, -0.2, 1.5);
    const double dt = 0.05, coefficient = 4.0;
    const DragForce drag(coefficient);
    ForceFieldCheck c = forForce("drag, " + spaceName(s), drag, s, net, &previous, dt);
    c.jacobianProduct = productOf(gramJacobian(s, rule, coefficient / dt));
    c.run();
  }
}

TEST_CASE("ForceField: every force's own Jacobian and potential against differences, paper and shell units",
          "[core]") {
  // the paper's units (densities per parameter area) and the shell's (per rest area, the rest
  // net a curved surface so that J0 varies)
  for (const SplineSpace& s : spaces()) {
    ControlNet restNet = deformedNet(s, 0.15);
    for (const ControlNet* rest : {static_cast<const ControlNet*>(nullptr), static_cast<const ControlNet*>(&restNet)}) {
      const std::string units = rest ? " (per rest area)" : " (per parameter area)";
      const ControlNet net = deformedNet(s, 0.3);
      ControlNet previous = net;
      previous.rowwise() -= 0.05 * Eigen::RowVector3d(0.3, -0.2, 1.5);
      const double dt = 0.05;
      struct Case {
        std::string name;
        std::shared_ptr<const Force> force;
        bool conservative;
      };
      const std::vector<Case> cases = {
          {"spring", std::make_shared<SpringForce>(0.37, 0.61, Eigen::Vector3d(0.2, 0.9, 0.5), 30.0), true},
          {"plane", std::make_shared<PlaneContactForce>(Eigen::Vector3d(0.0, 0.0, 0.12),
                                                        Eigen::Vector3d(0.1, 0.05, 1.0), 50.0), true},
          {"sphere", std::make_shared<SphereContactForce>(Eigen::Vector3d(0.45, 0.55, -0.4), 0.75, 80.0), true},
          {"drag", std::make_shared<DragForce>(4.0), true},  // the step's Rayleigh potential
          {"pressure", std::make_shared<PressureForce>(6.0), false},
      };
      for (const Case& k : cases) {
        REQUIRE(k.force->hasJacobian());
        ForceFieldCheck c = forForce(k.name + units + ", " + spaceName(s), *k.force, s, net, &previous, dt, rest);
        useOwnDerivatives(c, *k.force, s, net, &previous, dt, rest);
        CHECK(bool(c.energy) == k.conservative);
        // the energy check needs dL/dP symmetric: the drag's is (c/dt) G; pressure has none
        c.run();
      }
    }
  }
}

TEST_CASE("ForceField: a moving anchor's spring follows the anchor, and forces without derivatives say so", "[core]") {
  const SplineSpace s(3, 3, 4, 4);
  const ControlNet net = deformedNet(s, 0.2);
  auto anchor = std::make_shared<Eigen::Vector3d>(0.5, 0.5, 1.0);
  const SpringForce spring(0.5, 0.5, anchor, 10.0);
  const Eigen::Vector3d at = s.evaluate(net, 0.5, 0.5, 0).position;
  ControlNet load = ControlNet::Zero(s.numMoving(), 3);
  spring.addLoad(LoadContext{s, net, net, 0.1, 0.0}, load);
  const Eigen::Vector3d before = load.colwise().sum().transpose();
  *anchor = Eigen::Vector3d(0.5, 0.5, 3.0);
  load.setZero();
  spring.addLoad(LoadContext{s, net, net, 0.1, 0.0}, load);
  const Eigen::Vector3d after = load.colwise().sum().transpose();
  // interior point: the B-splines sum to one, so the loads sum to k (a - S)
  CHECK((before - 10.0 * (Eigen::Vector3d(0.5, 0.5, 1.0) - at)).norm() < 1e-12);
  CHECK((after - 10.0 * (Eigen::Vector3d(0.5, 0.5, 3.0) - at)).norm() < 1e-12);
  const DistributedForce expression([](const SurfaceSample& x) { return Eigen::Vector3d(x.position.z(), 0, 0); },
                                    kDependsOnPosition);
  CHECK_FALSE(expression.hasJacobian());
  double phi = 1.0;
  CHECK_FALSE(expression.potential(LoadContext{s, net, net, 0.1, 0.0}, phi));
}
