// SPDX-License-Identifier: MIT
// Supports per component and symmetry sides (dynamics/SideSupports, issue 36): exact
// elimination, checked against the full model, against the space's own SIMPLY_SUPPORTED side,
// against held components at rest, and on the Scordelis-Lo roof against its thin-shell value.
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>

#include "bsdeform/dynamics/Reactions.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/forces/Force.h"
#include "bsdeform/forces/ForceLaws.h"

using namespace bsdeform;

namespace {
constexpr double kPi = 3.14159265358979323846;

ModelParameters shell(int spansU, int spansV, Boundaries b, ShellMaterial m) {
  ModelParameters p;
  p.degreeU = p.degreeV = 3;
  p.numU = spansU - 3;
  p.numV = spansV - 3;
  p.boundaries = b;
  p.energy = EnergyModel::Shell;
  p.material = m;
  return p;
}
SideSupport hinge(unsigned components) { return SideSupport{SideSupport::Kind::Hinge, components}; }
SideSupport symmetry() { return SideSupport{SideSupport::Kind::Symmetry, 7}; }

// The quarter of a cylindrical roof (radius R, half length halfL, half angle theta) at the
// Greville abscissae: u round the arc from the crown (x = 0) to the free edge, v along the axis
// from mid-span (y = 0) to the end (bicubic only).
ControlNet quarterRoof(const SplineSpace& s, double R, double halfL, double theta) {
  ControlNet net(s.netSize(), 3);
  for (int i = 0; i < s.netRows(); ++i)
    for (int j = 0; j < s.netCols(); ++j) {
      const double u = s.grevilleU(i - 3), v = s.grevilleV(j - 3), a = theta * u;
      net.row(Eigen::Index(i) * s.netCols() + j) << R * std::sin(a), halfL * v, R * std::cos(a);
    }
  return net;
}

// The Scordelis-Lo quarter's model on spans x spans bicubic elements (E 4.32e8, nu 0, t 0.25,
// the given density): the crown's plane x = 0 (umin) and the mid-span plane y = 0 (vmin)
// SYMMETRY sides, the end (vmax) on a rigid diaphragm holding x and z.
ModelParameters scordelisQuarter(int spans, double density) {
  ModelParameters p = shell(spans, spans, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free},
                            ShellMaterial{4.32e8, 0.0, 0.25, density});
  p.sideSupports[0] = symmetry();
  p.sideSupports[2] = symmetry();
  p.sideSupports[3] = hinge(1 | 4);
  return p;
}

// The quarter x, y >= 0 of a hemisphere of radius R with a hole at latitude `top` (the points
// at the Greville abscissae on the sphere: u round the equator, v up to the hole; bicubic only).
ControlNet openQuarterHemisphere(const SplineSpace& s, double R, double top) {
  ControlNet net(s.netSize(), 3);
  for (int i = 0; i < s.netRows(); ++i)
    for (int j = 0; j < s.netCols(); ++j) {
      const double u = s.grevilleU(i - 3), v = s.grevilleV(j - 3), phi = 0.5 * kPi * u, lat = top * v;
      net.row(Eigen::Index(i) * s.netCols() + j) << R * std::cos(lat) * std::cos(phi),
          R * std::cos(lat) * std::sin(phi), R * std::sin(lat);
    }
  return net;
}

// The quarter x, y, z >= 0 of the closed hemisphere of radius R (bicubic only), without a
// degenerate pole: the unit square maps onto the three-sided region by
// S(u, v) = R (sin a, sin b, cos a cos b) / |...|, a = pi u / 2, b = pi v / 2. Its sides u = 0 and
// v = 0 are the meridians in the planes x = 0 and y = 0, meeting at the pole at a right angle;
// u = 1 and v = 1 are the two halves of the equator, meeting at the 45 degree point, where the
// corner's angle is 180 degrees and S_u x S_v vanishes (that corner only, which no Gauss point
// touches). x is odd in u and y odd in v, so the net mirrors about both planes and the pole is a
// regular point of the mirrored surface. The control points are the cubic quasi-interpolant
// (1 - D_u^2 / 6)(1 - D_v^2 / 6) S at the Greville abscissae (D the central difference over one
// knot span; exact for cubics): on the sphere to 2.3e-6 of R at 32 spans, where S at the Greville
// abscissae alone lies 8e-4 of R inside it.
ControlNet closedQuarterHemisphere(const SplineSpace& s, double R) {
  auto S = [R](double u, double v) -> Eigen::Vector3d {
    const double a = 0.5 * kPi * u, b = 0.5 * kPi * v;
    return R * Eigen::Vector3d(std::sin(a), std::sin(b), std::cos(a) * std::cos(b)).normalized();
  };
  const double h = s.basisU().spacing(), k = s.basisV().spacing(), w[3] = {-1.0 / 6.0, 8.0 / 6.0, -1.0 / 6.0};
  ControlNet net(s.netSize(), 3);
  for (int i = 0; i < s.netRows(); ++i)
    for (int j = 0; j < s.netCols(); ++j) {
      const double u = s.grevilleU(i - 3), v = s.grevilleV(j - 3);
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (int a = -1; a <= 1; ++a)
        for (int b = -1; b <= 1; ++b) c += w[a + 1] * w[b + 1] * S(u + a * h, v + b * k);
      net.row(Eigen::Index(i) * s.netCols() + j) = c.transpose();
    }
  return net;
}
}  // namespace

TEST_CASE("SYMMETRY: a quarter plate with two symmetry sides equals the full plate to the solver's tolerance",
          "[shell][supports]") {
  // a BUILT_IN square plate [0,1]² of 12 x 12 knot spans under a load large enough to be
  // nonlinear; the quarter [0, 0.5]² of 6 x 6 spans on the same knots, SYMMETRY at x = 0.5 and
  // y = 0.5: its equilibrium is the full one's there, point for point
  const ShellMaterial m{1e6, 0.3, 0.01, 1.0};
  const Eigen::Vector3d q(0, 0, -40.0);  // per rest area: deflection about 3 thicknesses
  ModelParameters full = shell(12, 12, Boundaries{Boundary::BuiltIn, Boundary::BuiltIn, Boundary::BuiltIn,
                                                  Boundary::BuiltIn}, m);
  Simulation a(full);
  a.addForce(std::make_shared<DistributedForce>(q));
  const StaticResult ra = a.solveStatic(1e-10, 100, LinearSolver::Automatic, 2);
  ModelParameters quarter = shell(6, 6, Boundaries{Boundary::BuiltIn, Boundary::Free, Boundary::BuiltIn, Boundary::Free}, m);
  quarter.sideSupports[1] = symmetry();
  quarter.sideSupports[3] = symmetry();
  const SplineSpace qs(3, 3, quarter.numU, quarter.numV, quarter.boundaries);
  ControlNet rest = qs.grevillePlane();
  rest.col(0) *= 0.5;
  rest.col(1) *= 0.5;
  Simulation b(quarter, rest);
  b.addForce(std::make_shared<DistributedForce>(q));
  const StaticResult rb = b.solveStatic(1e-10, 100, LinearSolver::Automatic, 2);
  const double centre = a.space().evaluate(ra.net, 0.5, 0.5, 0).position.z();
  CAPTURE(centre);
  CHECK(centre < -0.02);  // nonlinear: a few thicknesses
  for (double u : {0.1, 0.37, 0.8, 1.0})
    for (double v : {0.25, 0.6, 1.0}) {
      const Eigen::Vector3d pq = b.space().evaluate(rb.net, u, v, 0).position;
      const Eigen::Vector3d pf = a.space().evaluate(ra.net, 0.5 * u, 0.5 * v, 0).position;
      CAPTURE(u, v, pq.transpose(), pf.transpose());
      CHECK((pq - pf).norm() <= 1e-7 * std::abs(centre));
    }
  // the symmetry plane: the surface meets it at a right angle (S_u has no x component there)
  const SurfacePoint edge = b.space().evaluate(rb.net, 1.0, 0.4, 1);
  CHECK(std::abs(edge.du.y()) <= 1e-9 * edge.du.norm());
  CHECK(std::abs(edge.du.z()) <= 1e-9 * edge.du.norm());
  CHECK(std::abs(edge.position.x() - 0.5) <= 1e-12);
}

TEST_CASE("Supports per component: holding X, Y and Z is SIMPLY_SUPPORTED, a roller holds its component at rest and "
          "lets the others move",
          "[shell][supports][slow]") {  // [slow]: 41 s under the sanitizers (the Release suite runs it)
  const ShellMaterial m{1e6, 0.3, 0.01, 1.0};
  // all three components: the same equilibrium as the space's own SIMPLY_SUPPORTED sides
  ModelParameters ss = shell(8, 8, Boundaries{Boundary::SimplySupported, Boundary::SimplySupported, Boundary::Free,
                                              Boundary::Free}, m);
  Simulation a(ss);
  a.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, -20.0)));
  const StaticResult ra = a.solveStatic(1e-11, 100, LinearSolver::Automatic, 1);
  ModelParameters comp = ss;
  comp.boundaries.uMin = comp.boundaries.uMax = Boundary::Free;
  comp.sideSupports[0] = hinge(7);
  comp.sideSupports[1] = hinge(7);
  Simulation b(comp);
  b.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, -20.0)));
  const StaticResult rb = b.solveStatic(1e-11, 100, LinearSolver::Automatic, 1);
  for (double u : {0.0, 0.3, 0.5, 1.0})
    for (double v : {0.0, 0.5, 0.9}) {
      const Eigen::Vector3d pa = a.space().evaluate(ra.net, u, v, 0).position,
                            pb = b.space().evaluate(rb.net, u, v, 0).position;
      CAPTURE(u, v);
      CHECK((pa - pb).norm() <= 1e-9);
    }
  // a roller: z held on both u sides, x and y free; a load along x as well slides the sheet
  ModelParameters roller = comp;
  roller.sideSupports[0] = hinge(4);
  roller.sideSupports[1] = hinge(4 | 2);  // and y at u = 1: no rigid motion left but the x slide
  roller.pins = {};
  Simulation c(roller);
  c.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, -20.0)));
  // the x slide is free: balance it with a spring at one point so that the equilibrium exists
  c.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0.5, 0, 0)));
  c.addForce(std::make_shared<SpringForce>(0.5, 0.5, Eigen::Vector3d(0.5, 0.5, 0.0), 50.0));
  const StaticResult rc = c.solveStatic(1e-11, 100, LinearSolver::Automatic, 1);
  double slid = 0.0;
  for (double v : {0.0, 0.2, 0.5, 0.77, 1.0}) {
    const Eigen::Vector3d p0 = c.space().evaluate(rc.net, 0.0, v, 0).position;
    const Eigen::Vector3d p1 = c.space().evaluate(rc.net, 1.0, v, 0).position;
    const Eigen::Vector3d r0 = c.space().evaluate(c.rest(), 0.0, v, 0).position;
    const Eigen::Vector3d r1 = c.space().evaluate(c.rest(), 1.0, v, 0).position;
    CAPTURE(v);
    CHECK(std::abs(p0.z() - r0.z()) <= 1e-12);  // held components at rest, to rounding
    CHECK(std::abs(p1.z() - r1.z()) <= 1e-12);
    CHECK(std::abs(p1.y() - r1.y()) <= 1e-12);
    slid = std::max(slid, std::abs(p0.x() - r0.x()));
  }
  CHECK(slid > 1e-3);  // the free component moved
}

TEST_CASE("Scordelis-Lo roof as a quarter model: two SYMMETRY sides and a rigid diaphragm (X | Z)", "[shell][supports]") {
  // R = 25, L = 50, 80 degrees of arc, t = 0.25, E = 4.32e8, nu = 0, self-weight 90 per area;
  // the ends rest on rigid diaphragms (x and z held, the axial y free). Reference: the vertical
  // displacement at the middle of the free edge, 0.3006 for Kirchhoff-Love theory (Kiendl et
  // al. 2009; 0.3024 with transverse shear, MacNeal and Harder 1985). Quarter: u round the arc
  // from the crown (x = 0, SYMMETRY) to the free edge, v along the axis from mid-span (y = 0,
  // SYMMETRY) to the diaphragm.
  const double R = 25.0, halfL = 25.0, theta = 40.0 * kPi / 180.0;
  const int spans = 12;
  ModelParameters p = scordelisQuarter(spans, 1.0);
  const SplineSpace s(3, 3, p.numU, p.numV, p.boundaries);
  const ControlNet rest = quarterRoof(s, R, halfL, theta);
  Simulation roof(p, rest);
  // the reference is linear theory: the load scaled by 1e-4 and the deflection back by 1e4 (at
  // the full load the geometrically exact shell stiffens: w = 0.253, w/t = 1)
  const double scale = 1e-4;
  roof.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, -90.0 * scale)));
  const StaticResult r = roof.solveStatic(1e-10, 100, LinearSolver::Automatic, 1);
  const double w = (roof.space().evaluate(rest, 1.0, 0.0, 0).position.z() -
                    roof.space().evaluate(r.net, 1.0, 0.0, 0).position.z()) / scale;
  CAPTURE(w);
  CHECK(w == Approx(0.3006).epsilon(0.005));
  // the diaphragm: x and z of the end curve at rest, y free (it moves)
  double axial = 0.0;
  for (double u : {0.0, 0.3, 0.7, 1.0}) {
    const Eigen::Vector3d e = roof.space().evaluate(r.net, u, 1.0, 0).position, e0 = roof.space().evaluate(rest, u, 1.0, 0).position;
    CHECK(std::abs(e.x() - e0.x()) <= 1e-12 * R);
    CHECK(std::abs(e.z() - e0.z()) <= 1e-12 * R);
    axial = std::max(axial, std::abs(e.y() - e0.y()));
  }
  CHECK(axial > 1e-3 * w * scale);
  // the reactions: the diaphragm carries the weight (z) and nothing along the axis; the two
  // symmetry planes the forces across them; with the weight they balance
  const SupportReactions sr = supportReactions(roof, r.net);
  REQUIRE(sr.sides.size() == 3);
  CAPTURE(sr.imbalance().transpose(), sr.applied.transpose());
  CHECK(sr.imbalance().norm() <= 1e-6 * sr.applied.norm());
  for (const SupportReactions::Side& side : sr.sides)
    if (side.name == "vmax") {
      // the whole weight, but for what the corner it shares with the crown's band splits
      CHECK(side.force.z() == Approx(-sr.applied.z()).epsilon(0.01));
      CHECK(std::abs(side.force.y()) <= 0.01 * sr.applied.norm());  // the axial slide is free
    }
}

TEST_CASE("Diaphragms against fully held ends: the Scordelis-Lo roof on rigid diaphragms gives the thin-shell value, "
          "on ends held in all three components a stiffer roof",
          "[shell][supports]") {
  // the quarter of the test above (linear: 1e-4 of the weight), its end v = 1 once on a rigid
  // diaphragm (x and z held, the axial y free) and once SIMPLY_SUPPORTED in all three: holding
  // the axial slide too lets the ends carry the roof's bending as a thrust, and the free edge
  // deflects about half as much (0.51 of the reference, as issue 36 measured)
  const double R = 25.0, halfL = 25.0, theta = 40.0 * kPi / 180.0, scale = 1e-4;
  auto solve = [&](unsigned endHolds, double& axial) {
    ModelParameters p = shell(12, 12, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free},
                              ShellMaterial{4.32e8, 0.0, 0.25, 1.0});
    p.sideSupports[0] = symmetry();
    p.sideSupports[2] = symmetry();
    p.sideSupports[3] = hinge(endHolds);
    const SplineSpace s(3, 3, p.numU, p.numV, p.boundaries);
    const ControlNet rest = quarterRoof(s, R, halfL, theta);
    Simulation roof(p, rest);
    roof.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, -90.0 * scale)));
    const StaticResult r = roof.solveStatic(1e-10, 100, LinearSolver::Automatic, 1);
    axial = 0.0;  // the end curve's largest axial displacement
    for (double u : {0.0, 0.25, 0.5, 0.75, 1.0})
      axial = std::max(axial, std::abs(s.evaluate(r.net, u, 1.0, 0).position.y() - s.evaluate(rest, u, 1.0, 0).position.y()));
    return (s.evaluate(rest, 1.0, 0.0, 0).position.z() - s.evaluate(r.net, 1.0, 0.0, 0).position.z()) / scale;
  };
  double axialDiaphragm = 0.0, axialHeld = 0.0;
  const double diaphragm = solve(1 | 4, axialDiaphragm), held = solve(1 | 2 | 4, axialHeld);
  CAPTURE(diaphragm, held, held / diaphragm, axialDiaphragm, axialHeld);
  CHECK(diaphragm == Approx(0.3006).epsilon(0.005));
  CHECK(held / 0.3006 == Approx(0.51).epsilon(0.01));  // 0.1544, 0.514
  CHECK(axialDiaphragm > 1e-2 * diaphragm * scale);     // the end slides along the axis
  CHECK(axialHeld <= 1e-12 * halfL);                     // held: at rest to rounding
  // the pinched cylinder's octant (the test above, 32² spans) alike: 0.83 of 1.8248e-5 held
  const double Rc = 300.0;
  auto pinch = [&](unsigned endHolds, double& axial) {
    ModelParameters p = shell(32, 32, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free},
                              ShellMaterial{3e6, 0.3, 3.0, 1.0});
    p.sideSupports[0] = symmetry();
    p.sideSupports[1] = symmetry();
    p.sideSupports[2] = symmetry();
    p.sideSupports[3] = hinge(endHolds);
    const SplineSpace s(3, 3, p.numU, p.numV, p.boundaries);
    ControlNet rest(s.netSize(), 3);
    for (int i = 0; i < s.netRows(); ++i)
      for (int j = 0; j < s.netCols(); ++j) {
        const double u = s.grevilleU(i - 3), v = s.grevilleV(j - 3), a = 0.5 * kPi * u;
        rest.row(Eigen::Index(i) * s.netCols() + j) << Rc * std::sin(a), Rc * v, Rc * std::cos(a);
      }
    Simulation cyl(p, rest);
    cyl.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, -0.25), ParamRect{0.0, 0.0, 0.0, 0.0}));
    const StaticResult r = cyl.solveStatic(1e-10, 100, LinearSolver::Automatic, 1);
    axial = 0.0;
    for (double u : {0.0, 0.25, 0.5, 0.75, 1.0})
      axial = std::max(axial, std::abs(s.evaluate(r.net, u, 1.0, 0).position.y() - s.evaluate(rest, u, 1.0, 0).position.y()));
    return s.evaluate(rest, 0.0, 0.0, 0).position.z() - s.evaluate(r.net, 0.0, 0.0, 0).position.z();
  };
  const double pinchedDiaphragm = pinch(1 | 4, axialDiaphragm), pinchedHeld = pinch(1 | 2 | 4, axialHeld);
  CAPTURE(pinchedDiaphragm, pinchedHeld, pinchedHeld / 1.8248e-5, axialDiaphragm, axialHeld);
  CHECK(pinchedDiaphragm == Approx(1.8248e-5).epsilon(0.005));
  CHECK(pinchedHeld / 1.8248e-5 == Approx(0.83).epsilon(0.01));
  CHECK(axialDiaphragm > 1e-2 * pinchedDiaphragm);
  CHECK(axialHeld <= 1e-12 * Rc);
}

TEST_CASE("Supports per component refuse what they cannot do, naming it", "[shell][supports]") {
  ModelParameters p = shell(6, 6, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free},
                            ShellMaterial{1e6, 0.3, 0.01, 1.0});
  // the Greville plane is symmetric about x = 0 at u = 0? No: u = 0 is x = 0 and the layers
  // beyond it are at negative x, mirrors of those inside: it is. A sheared net is not.
  p.sideSupports[0] = symmetry();
  const SplineSpace s(3, 3, p.numU, p.numV, p.boundaries);
  ControlNet sheared = s.grevillePlane();
  sheared.col(0) += 0.3 * sheared.col(1);
  CHECK_THROWS_WITH(Simulation(p, sheared), Catch::Contains("boundaryUMin SYMMETRY") &&
                                                Catch::Contains("not mirror-symmetric"));
  CHECK_NOTHROW(Simulation(p, s.grevillePlane()));
  p.sideSupports[0] = hinge(0);
  CHECK_THROWS_WITH(Simulation(p), Catch::Contains("holding no component"));
  p.sideSupports[0] = hinge(4);
  p.energy = EnergyModel::Paper;
  CHECK_THROWS_WITH(Simulation(p), Catch::Contains("only the SHELL energy"));
  p.energy = EnergyModel::Shell;
  Simulation sim(p);
  CHECK(sim.step() == Status::Refused);
  CHECK(sim.statusMessage().find("not yet by EXPLICIT") != std::string::npos);
}


TEST_CASE("Pinched cylinder as an octant: three SYMMETRY sides and a rigid diaphragm converge to 1.8248e-5",
          "[shell][supports]") {
  // R = 300, L = 600, t = 3, E = 3e6, nu = 0.3, rigid diaphragms at the ends (x, z held), two
  // opposite unit loads at mid-length pinching it (Belytschko et al. 1985; the thin-shell value
  // 1.8248e-5 under the load). The octant: u round a quarter of the section from the loaded
  // point (x = 0, SYMMETRY) to the side (z = 0, SYMMETRY), v from mid-length (y = 0, SYMMETRY) to
  // the diaphragm; a quarter of one load at its corner. Bicubic: 16 spans 0.973, 32 0.998,
  // 48 1.0003 of the reference.
  const double R = 300.0, halfL = 300.0;
  const int spans = 32;
  ModelParameters p = shell(spans, spans, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free},
                            ShellMaterial{3e6, 0.3, 3.0, 1.0});
  p.sideSupports[0] = symmetry();
  p.sideSupports[1] = symmetry();
  p.sideSupports[2] = symmetry();
  p.sideSupports[3] = hinge(1 | 4);
  const SplineSpace s(3, 3, p.numU, p.numV, p.boundaries);
  ControlNet rest(s.netSize(), 3);
  for (int i = 0; i < s.netRows(); ++i)
    for (int j = 0; j < s.netCols(); ++j) {
      const double u = s.grevilleU(i - 3), v = s.grevilleV(j - 3), a = 0.5 * kPi * u;
      rest.row(Eigen::Index(i) * s.netCols() + j) << R * std::sin(a), halfL * v, R * std::cos(a);
    }
  Simulation cyl(p, rest);
  cyl.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, -0.25), ParamRect{0.0, 0.0, 0.0, 0.0}));
  const StaticResult r = cyl.solveStatic(1e-10, 100, LinearSolver::Automatic, 1);
  const double w =
      cyl.space().evaluate(rest, 0.0, 0.0, 0).position.z() - cyl.space().evaluate(r.net, 0.0, 0.0, 0).position.z();
  CAPTURE(w);
  CHECK(w == Approx(1.8248e-5).epsilon(0.005));
  // the side plane z = 0 keeps its z, the section's quarter meets it at a right angle
  const SurfacePoint side = cyl.space().evaluate(r.net, 1.0, 0.3, 1);
  CHECK(std::abs(side.position.z()) <= 1e-12 * R);
  CHECK(std::abs(side.du.x()) <= 1e-9 * side.du.norm());
}

TEST_CASE("A roof on two diaphragms: its free axial slide is named when loaded, and one pin holding Y takes it out",
          "[shell][supports]") {
  // the whole Scordelis-Lo roof, both ends on diaphragms (X | Z): free to slide along its axis y
  const double R = 25.0, halfL = 25.0, theta = 40.0 * kPi / 180.0;
  ModelParameters p = shell(12, 12, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free},
                            ShellMaterial{4.32e8, 0.0, 0.25, 1.0});
  p.sideSupports[2] = hinge(1 | 4);
  p.sideSupports[3] = hinge(1 | 4);
  const SplineSpace s(3, 3, p.numU, p.numV, p.boundaries);
  ControlNet rest(s.netSize(), 3);
  for (int i = 0; i < s.netRows(); ++i)
    for (int j = 0; j < s.netCols(); ++j) {
      const double u = s.grevilleU(i - 3), v = s.grevilleV(j - 3), a = theta * (2 * u - 1);
      rest.row(Eigen::Index(i) * s.netCols() + j) << R * std::sin(a), halfL * (2 * v - 1), R * std::cos(a);
    }
  {
    Simulation roof(p, rest);
    roof.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 1.0, -90.0)));
    CHECK_THROWS_WITH(roof.solveStatic(1e-10, 100, LinearSolver::Automatic, 1),
                      Catch::Contains("translation along y is free"));
  }
  // one pin at the middle holding Y only: it holds the y of its knot span's 16 control points
  // (not of one point), which the symmetric equilibrium moves a little, so the roof is a little
  // stiffer than on the ideal supports: 0.2980 (-0.9 %) against 0.3006
  p.pins = {Eigen::Vector2d(0.5, 0.5)};
  p.pinComponents = 2;
  Simulation roof(p, rest);
  const double scale = 1e-4;
  roof.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, -90.0 * scale)));
  const StaticResult r = roof.solveStatic(1e-10, 100, LinearSolver::Automatic, 1);
  const double w = (roof.space().evaluate(rest, 1.0, 0.5, 0).position.z() -
                    roof.space().evaluate(r.net, 1.0, 0.5, 0).position.z()) / scale;
  CAPTURE(w);
  CHECK(w == Approx(0.3006).epsilon(0.012));
  CHECK(w < 0.3006);
  // the pin holds y only: its point moved in z
  const Eigen::Vector3d pin = roof.space().evaluate(r.net, 0.5, 0.5, 0).position, pin0 = roof.space().evaluate(rest, 0.5, 0.5, 0).position;
  CHECK(std::abs(pin.y() - pin0.y()) <= 1e-12 * R);
  CHECK(std::abs(pin.z() - pin0.z()) > 1e-3 * w * scale);
  CHECK(roof.step() == Status::Refused);  // pins holding some components: not with EXPLICIT
}

TEST_CASE("A pin holding some components: setState checks and restores the held ones, the free ones are state",
          "[shell][supports]") {
  // a sheet on a CLAMPED side, one pin holding z only: its 16 control points may move in x and y
  ModelParameters p = shell(6, 6, Boundaries{Boundary::Clamped, Boundary::Free, Boundary::Free, Boundary::Free},
                            ShellMaterial{1e6, 0.3, 0.01, 1.0});
  p.pins = {Eigen::Vector2d(0.6, 0.5)};
  p.pinComponents = 4;
  Simulation sim(p);
  sim.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(2.0, 1.0, -5.0)));
  // the static solve's equilibrium moves the pinned points in x and y: a state setState takes
  // as it is (the runner and Python set it on the node, and a saved final.iv reads it back)
  const StaticResult r = sim.solveStatic(1e-10, 100, LinearSolver::Automatic, 1);
  const SplineSpace& s = sim.space();
  const int su = s.basisU().span(0.6), sv = s.basisV().span(0.5);
  const Eigen::Index pinned = s.movingToNet(s.movingIndex(su, sv));
  REQUIRE(std::abs(r.net(pinned, 0) - sim.rest()(pinned, 0)) > 1e-6);
  REQUIRE(r.net(pinned, 2) == sim.rest()(pinned, 2));
  CHECK_NOTHROW(sim.setState(r.net, 0.0, 0));
  CHECK(sim.current() == r.net);
  // a held component moved is refused, naming it; Reset puts that one back and keeps the others
  ControlNet moved = r.net;
  moved(pinned, 2) += 1e-3;
  moved(pinned, 1) += 2e-3;
  CHECK_THROWS_WITH(sim.setState(moved, 0.0, 0), Catch::Contains("pinned control point") && Catch::Contains("in z"));
  sim.setState(moved, 0.0, 0, HeldPoints::Reset);
  CHECK(sim.current()(pinned, 2) == sim.rest()(pinned, 2));
  CHECK(sim.current()(pinned, 1) == moved(pinned, 1));
  CHECK(sim.current()(pinned, 0) == r.net(pinned, 0));
}

TEST_CASE("Reactions of the Scordelis-Lo quarter: a SYMMETRY plane carries no force along itself, and the reactions "
          "balance the weight",
          "[shell][supports]") {
  // the quarter of "Scordelis-Lo roof as a quarter model" under its full weight: the crown's
  // plane x = 0 (umin) and the mid-span plane y = 0 (vmin) meet the diaphragm (vmax, x and z)
  // at corners; a corner point's component goes only to the sides that hold it
  const double R = 25.0, halfL = 25.0, theta = 40.0 * kPi / 180.0;
  ModelParameters p = scordelisQuarter(8, 1.0);
  const SplineSpace s(3, 3, p.numU, p.numV, p.boundaries);
  const ControlNet rest = quarterRoof(s, R, halfL, theta);
  Simulation roof(p, rest);
  roof.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, -90.0)));
  const StaticResult r = roof.solveStatic(1e-10, 100, LinearSolver::Automatic, 1);
  const SupportReactions sr = supportReactions(roof, r.net);
  REQUIRE(sr.sides.size() == 3);
  const double size = sr.applied.norm();
  CAPTURE(sr.applied.transpose(), sr.imbalance().transpose(), sr.elsewhere.transpose());
  CHECK(sr.imbalance().norm() <= 1e-6 * size);
  for (const SupportReactions::Side& side : sr.sides) {
    CAPTURE(side.name, side.force.transpose());
    if (side.name == "umin") {  // the plane x = 0: the thrust across the crown (x) only
      CHECK(std::abs(side.force.y()) <= 1e-8 * size);
      CHECK(std::abs(side.force.z()) <= 1e-8 * size);
      CHECK(std::abs(side.force.x()) > 0.1 * size);
    } else if (side.name == "vmin") {  // the plane y = 0: the axial force across mid-span only
      CHECK(std::abs(side.force.x()) <= 1e-8 * size);
      CHECK(std::abs(side.force.z()) <= 1e-8 * size);
    } else {  // the diaphragm: the whole weight, nothing along the axis it leaves free
      CHECK(side.name == "vmax");
      CHECK(side.force.z() == Approx(-sr.applied.z()).epsilon(1e-6));
      CHECK(std::abs(side.force.y()) <= 1e-8 * size);
    }
  }
}

TEST_CASE("Pinched hemisphere with an 18 degree hole: 0.094 as a quarter with two SYMMETRY sides", "[shell][supports]") {
  // MacNeal and Harder 1985: R = 10, t = 0.04, E = 6.825e7, nu = 0.3, open 18 degrees round the
  // pole, free equator; loads of 2 at the equator, outward along x, inward along y (and the
  // opposite ones); the linear radial displacement under a load is 0.094 (Kirchhoff-Love). The
  // quarter: u round 90 degrees between the planes y = 0 and x = 0 (SYMMETRY, each through a
  // load: half of it here), v from the equator to the hole. The loads have no z resultant and
  // nothing else holds z: the z of one control point is held (net layers (1, 1), on the plane
  // y = 0 at the equator), as the static solve asks. Bicubic: 8 spans 0.0880, 16 0.09297, 32
  // 0.09342.
  const double R = 10.0, top = 72.0 * kPi / 180.0;
  const int spans = 32;
  ModelParameters p = shell(spans, spans, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free},
                            ShellMaterial{6.825e7, 0.3, 0.04, 1.0});
  p.sideSupports[0] = symmetry();
  p.sideSupports[1] = symmetry();
  const SplineSpace s(3, 3, p.numU, p.numV, p.boundaries);
  const ControlNet rest = openQuarterHemisphere(s, R, top);
  p.heldCoordinates.push_back({Eigen::Index(1) * s.netCols() + 1, 2});
  Simulation h(p, rest);
  const double scale = 1e-3;  // linear
  h.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(1.0 * scale, 0, 0), ParamRect{0.0, 0.0, 0.0, 0.0}));
  h.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, -1.0 * scale, 0), ParamRect{1.0, 1.0, 0.0, 0.0}));
  const StaticResult r = h.solveStatic(1e-10, 100, LinearSolver::Automatic, 1);
  const double out = (h.space().evaluate(r.net, 0.0, 0.0, 0).position.x() - h.space().evaluate(rest, 0.0, 0.0, 0).position.x()) / scale;
  const double in = -(h.space().evaluate(r.net, 1.0, 0.0, 0).position.y() - h.space().evaluate(rest, 1.0, 0.0, 0).position.y()) / scale;
  CAPTURE(out, in);
  CHECK(out == Approx(0.094).epsilon(0.01));
  CHECK(in == Approx(out).epsilon(1e-3));  // the two loads alike, as the linear theory has it
}

TEST_CASE("Closed pinched hemisphere: 0.0924 as a quarter whose pole is the corner of two SYMMETRY sides, and "
          "Newton's convergence does not depend on the load's size",
          "[shell][supports]") {
  // the hemisphere above without its hole: the radial displacement under a load is 0.0924 (the
  // value used since Belytschko et al. 1985; MacNeal and Harder's 0.094 was computed for this
  // closed shell, not for the one with the hole). The quarter of
  // closedQuarterHemisphere: u = 0 (plane x = 0) and v = 0 (plane y = 0) SYMMETRY, the equator
  // FREE; half a load at each of the corners (1, 0) = (R, 0, 0), outward, and (0, 1) = (0, R, 0),
  // inward. The loads have no z resultant and z translation is free: the pole's control point
  // keeps its z (a gauge without reaction; by the loads' antisymmetry about the diagonal plane
  // x = y the pole does not move in z). Left free, that singular direction drifts in rounding and
  // Newton takes up to 17 iterations; held, 2 at every net. Bicubic: 8 spans 0.08441, 16 0.09208,
  // 24 0.09236, 32 0.092395, 48 0.092408, 64 0.092411 (a lat-long quarter whose last net row
  // collapses into the pole, x, y and z held there, gives the same from 32 spans: docs/math.md).
  const double R = 10.0;
  const int spans = 32;
  ModelParameters p = shell(spans, spans, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free},
                            ShellMaterial{6.825e7, 0.3, 0.04, 1.0});
  p.sideSupports[0] = symmetry();
  p.sideSupports[2] = symmetry();
  const SplineSpace s(3, 3, p.numU, p.numV, p.boundaries);
  const ControlNet rest = closedQuarterHemisphere(s, R);
  p.heldCoordinates.push_back({Eigen::Index(1) * s.netCols() + 1, 2});  // net layers (1, 1): on both planes
  double onSphere = 0.0;
  for (int a = 0; a <= 40; ++a)
    for (int b = 0; b <= 40; ++b)
      onSphere = std::max(onSphere, std::abs(s.evaluate(rest, a / 40.0, b / 40.0, 0).position.norm() - R));
  CHECK(onSphere <= 1e-5 * R);
  double first = 0.0;
  for (double scale : {1e-6, 1e-4}) {
    Simulation h(p, rest);
    h.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(scale, 0, 0), ParamRect{1.0, 1.0, 0.0, 0.0}));
    h.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, -scale, 0), ParamRect{0.0, 0.0, 1.0, 1.0}));
    const StaticResult r = h.solveStatic(1e-8, 100, LinearSolver::Automatic, 1);
    auto move = [&](double u, double v) {
      return Eigen::Vector3d(h.space().evaluate(r.net, u, v, 0).position - h.space().evaluate(rest, u, v, 0).position);
    };
    const double out = move(1.0, 0.0).x() / scale, in = -move(0.0, 1.0).y() / scale;
    CAPTURE(scale, out, in, r.loadIterations, r.residual);
    CHECK(r.loadIterations <= 4);
    CHECK(in == Approx(out).epsilon(1e-4));
    CHECK(move(0.0, 0.0).norm() <= 1e-6 * out * scale);  // the pole stays
    if (first == 0.0) first = out;
    CHECK(out == Approx(first).epsilon(1e-5));
  }
  // 0.99995 of the reference at 32 spans, which is given to three figures; 16 spans (0.9966)
  // would fail
  CHECK(first == Approx(0.0924).epsilon(1e-3));
}

TEST_CASE("Damped quarter roof with SYMMETRY sides: BACKWARD_EULER and IMPLICIT settle on the static "
          "equilibrium (supports per component)",
          "[shell][supports][slow]") {
  const double R = 25.0, halfL = 25.0, theta = 40.0 * kPi / 180.0;
  ModelParameters p = scordelisQuarter(8, 100.0);
  p.integrator = GENERATE(Integrator::BackwardEuler, Integrator::Implicit);
  p.timeStep = 0.01;
  p.damping = 8.0;  // about critical: the roof's first mode is near 3.8 rad/s here
  p.newtonVelocityTolerance = 1e-9;
  const SplineSpace s(3, 3, p.numU, p.numV, p.boundaries);
  const ControlNet rest = quarterRoof(s, R, halfL, theta);
  Simulation roof(p, rest);
  roof.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, -90.0)));
  const StaticResult st = roof.solveStatic(1e-10, 100, LinearSolver::Automatic, 1);
  CAPTURE(int(p.integrator));
  REQUIRE(roof.refusal().empty());
  roof.advance(600);
  CAPTURE(roof.statusMessage());
  REQUIRE(roof.status() == Status::Ok);
  const double wStatic = roof.space().evaluate(rest, 1.0, 0.0, 0).position.z() - roof.space().evaluate(st.net, 1.0, 0.0, 0).position.z();
  CHECK(wStatic > 0.2);
  for (double u : {0.0, 0.5, 1.0})
    for (double v : {0.0, 0.5, 1.0}) {
      const Eigen::Vector3d a = roof.evaluate(u, v).position, b = roof.space().evaluate(st.net, u, v, 0).position;
      CAPTURE(u, v, a.transpose(), b.transpose());
      CHECK((a - b).norm() <= 1e-4 * std::abs(wStatic) + 1e-9);
    }
  // the constraints hold at every state: the diaphragm's x and z, the symmetry planes' normals
  for (double u : {0.0, 0.4, 1.0}) {
    const Eigen::Vector3d e = roof.evaluate(u, 1.0).position, e0 = roof.space().evaluate(rest, u, 1.0, 0).position;
    CHECK(std::abs(e.x() - e0.x()) <= 1e-12 * R);
    CHECK(std::abs(e.z() - e0.z()) <= 1e-12 * R);
  }
  CHECK(std::abs(roof.evaluate(0.0, 0.3).position.x()) <= 1e-12 * R);
  CHECK(std::abs(roof.evaluate(0.6, 0.0).position.y()) <= 1e-12 * R);
  // EXPLICIT does not take them yet (its mass inverse would need the fold), and says so
  ModelParameters q = p;
  q.integrator = Integrator::Explicit;
  Simulation explicitRoof(q, rest);
  CHECK(explicitRoof.step() == Status::Refused);
  CHECK(explicitRoof.statusMessage().find("not yet by EXPLICIT") != std::string::npos);
}

TEST_CASE("Supports per component on BUILT_IN sides: all three are BUILT_IN, Z alone keeps the edge's height and "
          "slope at rest",
          "[shell][supports][slow]") {  // 76 s under the sanitizers
  const ShellMaterial m{1e6, 0.3, 0.01, 1.0};
  ModelParameters bi = shell(8, 8, Boundaries{Boundary::BuiltIn, Boundary::Free, Boundary::Free, Boundary::Free}, m);
  Simulation a(bi);
  a.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, -2.0)));
  const StaticResult ra = a.solveStatic(1e-11, 100, LinearSolver::Automatic, 2);
  ModelParameters comp = bi;
  comp.boundaries.uMin = Boundary::Free;
  comp.sideSupports[0] = SideSupport{SideSupport::Kind::Clamp, 7};
  Simulation b(comp);
  b.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, -2.0)));
  const StaticResult rb = b.solveStatic(1e-11, 100, LinearSolver::Automatic, 2);
  for (double u : {0.0, 0.4, 1.0})
    for (double v : {0.0, 0.5, 1.0}) {
      CAPTURE(u, v);
      CHECK((a.space().evaluate(ra.net, u, v, 0).position - b.space().evaluate(rb.net, u, v, 0).position).norm() <= 1e-9);
    }
  // Z only on both u sides (x, y free: a sheet on two clamping rails it may slide along; the
  // slides and the turn about z held at two control points of the middle row, x and y at one, x
  // at the other, as the static solve asks)
  ModelParameters z = comp;
  z.boundaries.uMax = Boundary::Free;
  z.sideSupports[0] = SideSupport{SideSupport::Kind::Clamp, 4};
  z.sideSupports[1] = SideSupport{SideSupport::Kind::Clamp, 4};
  {
    const SplineSpace zs(3, 3, z.numU, z.numV, z.boundaries);
    const Eigen::Index a = Eigen::Index(zs.netRows() / 2) * zs.netCols() + 3, b = a + zs.netCols() - 6;
    z.heldCoordinates = {{a, 0}, {a, 1}, {b, 0}};
  }
  Simulation c(z);
  c.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, -2.0)));
  const StaticResult rc = c.solveStatic(1e-11, 100, LinearSolver::Automatic, 2);
  double sag = 0.0;
  for (double v : {0.0, 0.3, 0.5, 1.0}) {
    for (double u : {0.0, 1.0}) {
      const SurfacePoint p = c.space().evaluate(rc.net, u, v, 1), r0 = c.space().evaluate(c.rest(), u, v, 1);
      CAPTURE(u, v);
      CHECK(std::abs(p.position.z() - r0.position.z()) <= 1e-12);
      CHECK(std::abs(p.du.z() - r0.du.z()) <= 1e-10);  // clamped: no slope across the edge
    }
    sag = std::max(sag, -c.space().evaluate(rc.net, 0.5, v, 0).position.z());
  }
  CHECK(sag > 1e-3);
}

TEST_CASE("Static Newton independent of the load's size: a thin hemisphere under 1e-6 and 1e-4 "
          "of its load",
          "[shell][supports]") {
  // the quarter hemisphere with an 18 degree hole (t/R = 0.004): the relative residual of a thin
  // shell under a small load sits on a rounding floor (7e-3 at 1e-6 of the load: a solve judged
  // by it never ends); the update, judged against the displacement, does not, so each load
  // converges in a few iterations and the scaled displacements agree (at 1e-2 of the load the
  // geometric nonlinearity shows, 5e-5); z held at one control point, as in the test above
  const double R = 10.0, top = 72.0 * kPi / 180.0;
  ModelParameters p = shell(16, 16, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free},
                            ShellMaterial{6.825e7, 0.3, 0.04, 1.0});
  p.sideSupports[0] = symmetry();
  p.sideSupports[1] = symmetry();
  const SplineSpace s(3, 3, p.numU, p.numV, p.boundaries);
  const ControlNet rest = openQuarterHemisphere(s, R, top);
  p.heldCoordinates.push_back({Eigen::Index(1) * s.netCols() + 1, 2});
  double first = 0.0;
  for (double scale : {1e-6, 1e-4}) {
    Simulation h(p, rest);
    h.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(scale, 0, 0), ParamRect{0.0, 0.0, 0.0, 0.0}));
    h.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, -scale, 0), ParamRect{1.0, 1.0, 0.0, 0.0}));
    const StaticResult r = h.solveStatic(1e-8, 100, LinearSolver::Automatic, 1);
    const double out =
        (h.space().evaluate(r.net, 0.0, 0.0, 0).position.x() - h.space().evaluate(rest, 0.0, 0.0, 0).position.x()) / scale;
    CAPTURE(scale, out, r.loadIterations, r.residual);
    CHECK(r.loadIterations <= 4);
    if (first == 0.0) first = out;
    CHECK(out == Approx(first).epsilon(1e-5));
  }
  CHECK(first == Approx(0.093).epsilon(0.01));
}

TEST_CASE("A plate on one edge holding Z only: its free x slide is refused by name, pushed or not, and its free "
          "rotation about the edge is named when Newton fails",
          "[shell][supports]") {
  // a sheet in the plane z = 0, its side u = 0 (the line x = 0) holding z: it may slide in x and
  // y, turn about z, and turn about the edge itself
  ModelParameters p = shell(6, 6, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free},
                            ShellMaterial{1e6, 0.3, 0.01, 1.0});
  p.sideSupports[0] = hinge(4);
  // a push along the free x slide: refused at once
  Simulation pushed(p);
  pushed.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(1.0, 0, 0)));
  CHECK_THROWS_WITH(pushed.solveStatic(1e-10, 100, LinearSolver::Automatic, 1),
                    Catch::Contains("the translation along x is free"));
  // a downward load alone does no work on the slides, but they leave the equilibrium undecided:
  // refused as well, naming one
  Simulation unpushed(p);
  unpushed.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, -1.0)));
  CHECK_THROWS_WITH(unpushed.solveStatic(1e-10, 100, LinearSolver::Automatic, 1),
                    Catch::Contains("the translation along x is free") && Catch::Contains("the loads do no work on it"));
  // held as an engineer would (x and y of one control point, y of another: the slides and the
  // turn about z), the load turns it about the edge: no equilibrium, and the failure says which
  const SplineSpace s(3, 3, p.numU, p.numV, p.boundaries);
  const Eigen::Index a = Eigen::Index(3) * s.netCols() + 3, b = Eigen::Index(6) * s.netCols() + 3;
  p.heldCoordinates = {{a, 0}, {a, 1}, {b, 1}};
  Simulation sheet(p);
  sheet.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, -1.0)));
  CHECK(sheet.freeRigidMotionLoaded(sheet.loadVector(), false).empty());  // no translation
  CHECK_THAT(sheet.freeRigidMotionLoaded(sheet.loadVector(), true),
             Catch::Contains("the rotation about the axis (0, 1, 0) through (0, ") && Catch::Contains(", 0) is free"));
  CHECK_THROWS_WITH(sheet.solveStatic(1e-10, 20, LinearSolver::Automatic, 1),
                    Catch::Contains("perhaps because the rotation about the axis (0, 1, 0)"));
}
