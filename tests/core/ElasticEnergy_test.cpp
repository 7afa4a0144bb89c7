// SPDX-License-Identifier: MIT
// The energy interface (ElasticEnergy.h), one fixture for both implementations, the paper's
// eq. 7 and the Kirchhoff–Love shell: on random states of every side kind its gradient is the
// finite difference of its energy, its Hessian–vector product the finite difference of its
// gradient and symmetric (the force-law fixture, support/ForceFieldCheck.h), the rest net has
// zero energy and force, and its stability bound lies above
// lambda_max(M^-1 H) as power iteration finds it (and not absurdly far above).
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "../support/ForceFieldCheck.h"
#include "bsdeform/energy/ElasticEnergy.h"
#include "bsdeform/dynamics/Simulation.h"

using namespace bsdeform;
using namespace bsdeform::test;

namespace {

ControlNet withUnknowns(const Simulation& sim, const ControlNet& x) {
  ControlNet net = sim.rest();
  sim.space().scatterMoving(x, net);
  sim.space().completeNet(net, &sim.rest());
  return net;
}

struct Setup {
  EnergyModel energy;
  Boundaries sides;
  ElasticReference reference;
};

ModelParameters params(const Setup& s) {
  ModelParameters p;
  p.numU = 5;
  p.numV = 4;
  p.boundaries = s.sides;
  p.energy = s.energy;
  p.reference = s.reference;
  p.massModel = MassModel::Lumped;
  p.material.youngsModulus = 1.0e4;
  p.material.thickness = 0.02;
  p.material.density = 50.0;
  return p;
}

// A curved rest net (so the reference matters and the shell is curved at rest).
ControlNet curvedRest(const ModelParameters& p) {
  const SplineSpace s(p.degreeU, p.degreeV, p.numU, p.numV, p.boundaries);
  ControlNet rest = s.grevillePlane();
  for (Eigen::Index r = 0; r < rest.rows(); ++r) rest(r, 2) = 0.2 * std::sin(2.0 * rest(r, 0)) * rest(r, 1);
  return rest;
}

}  // namespace

TEST_CASE("ElasticEnergy: gradient and Hessian product are the derivatives of the energy, paper and shell",
          "[core][shell]") {
  using B = Boundary;
  const Boundaries sideSets[] = {Boundaries{}, Boundaries{B::Free, B::Free, B::Free, B::Clamped},
                                 Boundaries{B::SimplySupported, B::BuiltIn, B::Free, B::Free},
                                 Boundaries{B::BuiltIn, B::Free, B::SimplySupported, B::Clamped}};
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (EnergyModel model : {EnergyModel::Paper, EnergyModel::Shell})
    for (ElasticReference reference : {ElasticReference::Rest, ElasticReference::Absolute})
      for (const Boundaries& sides : sideSets) {
        if (model == EnergyModel::Shell && reference == ElasticReference::Absolute) continue;  // paper only
        const Setup setup{model, sides, reference};
        const ModelParameters p = params(setup);
        CAPTURE(int(model), int(reference), boundaryName(sides.uMin), boundaryName(sides.uMax),
                boundaryName(sides.vMin), boundaryName(sides.vMax));
        Simulation sim(p, curvedRest(p));
        const ElasticEnergy& E = sim.energy();
        CHECK(E.isLinear() == (model == EnergyModel::Paper));
        const Eigen::Index n = sim.space().numMoving();
        const ControlNet x0 = sim.space().gatherMoving(sim.rest());
        // at rest: zero energy, and zero gradient for the Rest reference
        ControlNet g;
        CHECK(E.energy(sim.rest()) == Approx(0.0).margin(1e-12));
        E.gradient(sim.rest(), g);
        if (reference == ElasticReference::Rest) CHECK(g.cwiseAbs().maxCoeff() < 1e-9 * (1.0 + E.eigenvalueBound(sim.rest())));
        // the elastic force -g through the force-law fixture: -g = -dW/dx, -H d its derivative,
        // H symmetric, at a random state
        ForceFieldCheck check;
        check.P = ControlNet(n, 3);
        for (Eigen::Index i = 0; i < check.P.size(); ++i) check.P.data()[i] = x0.data()[i] + 0.05 * u(rng);
        check.netOf = [&](const ControlNet& x) { return withUnknowns(sim, x); };
        check.load = [&](const ControlNet& net) {
          ControlNet gt;
          E.gradient(net, gt);
          return ControlNet(-gt);
        };
        check.energy = [&](const ControlNet& net) { return E.energy(net); };
        const ControlNet net = withUnknowns(sim, check.P);
        check.jacobianProduct = [&](const ControlNet& d) {
          ControlNet Hd;
          E.hessianProduct(net, d, Hd);
          return ControlNet(-Hd);
        };
        check.step = 1e-5;
        check.absoluteTolerance = 1e-9;
        check.seed = unsigned(rng());
        check.directions = 2;
        check.run();
      }
}

TEST_CASE("ElasticEnergy: the stability bound lies above lambda_max(M^-1 H) found by power iteration", "[core][shell]") {
  // Clamped and free sides only: the unknowns' mass is then diagonal (massAt of each point).
  using B = Boundary;
  for (EnergyModel model : {EnergyModel::Paper, EnergyModel::Shell})
    for (const Boundaries& sides : {Boundaries{}, Boundaries{B::Free, B::Free, B::Free, B::Clamped}}) {
      CAPTURE(int(model), boundaryName(sides.uMin));
      const ModelParameters p = params(Setup{model, sides, ElasticReference::Rest});
      Simulation sim(p, curvedRest(p));
      const ElasticEnergy& E = sim.energy();
      const Eigen::Index n = sim.space().numMoving();
      ControlNet x = sim.space().gatherMoving(sim.rest());
      x.col(2).array() += 0.03;  // a deformed state (the shell's bound depends on it)
      x.col(0) *= 1.05;
      const ControlNet net = withUnknowns(sim, x);
      Eigen::VectorXd rootMass(n);
      for (Eigen::Index f = 0; f < n; ++f) {
        const Eigen::Index r = sim.space().movingToNet(f);
        rootMass[f] = std::sqrt(sim.massAt(int(r / sim.space().netCols()), int(r % sim.space().netCols())));
      }
      // power iteration on M^-1/2 H M^-1/2 (symmetric): its Rayleigh quotients rise to lambda_max
      ControlNet y = ControlNet::Ones(n, 3), Hy;
      double lambda = 0.0;
      for (int k = 0; k < 300; ++k) {
        y /= y.norm();
        const ControlNet z = rootMass.cwiseInverse().asDiagonal() * y;
        E.hessianProduct(net, z, Hy);
        const ControlNet w = rootMass.cwiseInverse().asDiagonal() * Hy;
        lambda = (w.array() * y.array()).sum();
        y = w;
      }
      const double bound = E.eigenvalueBound(net);
      CAPTURE(lambda, bound);
      CHECK(lambda > 0.0);
      CHECK(bound >= lambda * (1.0 - 1e-9));
      CHECK(bound < 50.0 * lambda);  // a bound, not a blanket
    }
}
