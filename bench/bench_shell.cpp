// SPDX-License-Identifier: MIT
// The SHELL energy (issue 24): the force evaluation (gradient of the Kirchhoff–Love energy) per
// control point, the explicit step's stability bound, and one implicit (Newton) step of a
// cotton sheet, for bicubic nets of N x N inner points.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>

#include "bsdeform/ForceLaws.h"
#include "bsdeform/Shell.h"
#include "bsdeform/Simulation.h"

using namespace bsdeform;

namespace {
const ShellMaterial kCotton{0.821e6, 0.243, 0.318e-3, 472.6};

// A gently waved state of the unit square (bending and membrane both at work).
ControlNet waved(const SplineSpace& s) {
  ControlNet net = s.grevillePlane();
  for (Eigen::Index r = 0; r < net.rows(); ++r)
    net(r, 2) = 0.02 * std::sin(6.0 * net(r, 0)) * std::cos(5.0 * net(r, 1));
  return net;
}

void ShellForces(benchmark::State& state) {
  const int n = int(state.range(0));
  const SplineSpace s(3, 3, n, n, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
  const ShellEnergy shell(s, s.grevillePlane(), kCotton);
  const ControlNet x = waved(s);
  ControlNet g;
  shell.gradient(x, g);
  for (auto _ : state) {
    shell.gradient(x, g);
    benchmark::DoNotOptimize(g.data());
  }
  state.counters["points/s"] = benchmark::Counter(double(s.netSize()), benchmark::Counter::kIsIterationInvariantRate);
}

void ShellBound(benchmark::State& state) {
  const int n = int(state.range(0));
  const SplineSpace s(3, 3, n, n, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
  const ShellEnergy shell(s, s.grevillePlane(), kCotton);
  const ControlNet x = waved(s);
  const Eigen::VectorXd mass = shell.lumpedMass();
  for (auto _ : state) benchmark::DoNotOptimize(shell.eigenvalueBound(x, mass));
  state.counters["points/s"] = benchmark::Counter(double(s.netSize()), benchmark::Counter::kIsIterationInvariantRate);
}

// A cotton curtain of N x N inner points hinged along v = 1, steps of 1/60 s, and its weight.
ModelParameters curtain(int n) {
  ModelParameters p;
  p.numU = p.numV = n;
  p.boundaries = Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::SimplySupported};
  p.energy = EnergyModel::Shell;
  p.material = kCotton;
  p.damping = 0.5;
  p.timeStep = 1.0 / 60.0;
  return p;
}
std::shared_ptr<const Force> gravity() {
  return std::make_shared<GravityForce>(kCotton.density * kCotton.thickness, Eigen::Vector3d(0, 0, -9.81));
}

// A cotton curtain hinged along v = 1 falling under gravity: one implicit step of 1/60 s each
// iteration, from the state the previous ones left (the first 5 steps untimed).
void ShellImplicitStep(benchmark::State& state) {
  ModelParameters p = curtain(int(state.range(0)));
  p.integrator = Integrator::Implicit;
  Simulation sim(p);
  sim.addForce(gravity());
  sim.advance(5);
  long newton = 0, steps = 0;
  for (auto _ : state) {
    if (sim.step() != Status::Ok) {
      state.SkipWithError(sim.statusMessage().c_str());
      break;
    }
    newton += sim.lastNewtonIterations();
    ++steps;
  }
  state.counters["newton/step"] = steps ? double(newton) / double(steps) : 0.0;
}

// The explicit counterpart: one step of 1/60 s of the same curtain (sub-stepped below the
// membrane's limit, the bound taken again every step).
void ShellExplicitStep(benchmark::State& state) {
  ModelParameters p = curtain(int(state.range(0)));
  p.maxSubSteps = 100000;
  Simulation sim(p);
  sim.addForce(gravity());
  sim.advance(5);
  for (auto _ : state)
    if (sim.step() != Status::Ok) {
      state.SkipWithError(sim.statusMessage().c_str());
      break;
    }
  state.counters["substeps"] = sim.subSteps();
}
}  // namespace

BENCHMARK(ShellForces)->RangeMultiplier(2)->Range(32, 512)->Unit(benchmark::kMillisecond);
BENCHMARK(ShellBound)->Arg(32)->Arg(128)->Unit(benchmark::kMillisecond);
BENCHMARK(ShellImplicitStep)->Arg(16)->Arg(32)->Arg(64)->Unit(benchmark::kMillisecond);
BENCHMARK(ShellExplicitStep)->Arg(16)->Arg(32)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
