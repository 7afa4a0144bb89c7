// SPDX-License-Identifier: MIT
// The implicit scheme at scale (issue 11 item 5): bicubic, paper weights and mass (nodal, m = 1,
// c = 0.5, dt = 0.1), all sides clamped, a region load; N x N free control points.
//   ImplicitFactor/<N>      building the model with its linear system as shipped
//                           (LinearSolver::Automatic): for the direct solver this is the
//                           CHOLMOD factorisation
//   ImplicitStep/<N>        one implicit step of that model (a moving state)
//   ImplicitFactorDirect/<N>, ImplicitStepDirect/<N>  the same with LinearSolver::Direct
//   ImplicitFactorCG/<N>,     ImplicitStepCG/<N>      the same with LinearSolver::ConjugateGradient
//   ImplicitFactorMG/<N>,     ImplicitStepMG/<N>      the same with LinearSolver::Multigrid
// Large N take seconds to minutes per iteration: those run one iteration (Iterations(1)); peak
// memory is measured from outside (/usr/bin/time -v on one filtered benchmark, docs/benchmarks.md).
#include <benchmark/benchmark.h>

#include <memory>

#include "bsdeform/dynamics/Simulation.h"

namespace {

using bsdeform::LinearSolver;

std::unique_ptr<bsdeform::Simulation> implicitModel(int N, LinearSolver solver) {
  bsdeform::ModelParameters p;
  p.numU = p.numV = N;
  p.integrator = bsdeform::Integrator::Implicit;
  p.implicitSolver = solver;
  auto sim = std::make_unique<bsdeform::Simulation>(p);
  sim->addForce(std::make_shared<bsdeform::DistributedForce>(Eigen::Vector3d(0, 0, 60),
                                                             bsdeform::ParamRect{0.3, 0.7, 0.3, 0.7}));
  return sim;
}

void reportSystem(benchmark::State& state, const bsdeform::Simulation& sim) {
  const bsdeform::ImplicitSystem& sys = *sim.implicitSystem();
  state.counters["direct"] = sys.method() == LinearSolver::Direct ? 1 : 0;
  state.counters["factorNnz"] = sys.factorNonZeros();
  state.counters["kappaBound"] = sys.conditionBound();
}

void factor(benchmark::State& state, LinearSolver solver) {
  const int N = static_cast<int>(state.range(0));
  std::unique_ptr<bsdeform::Simulation> sim;
  for (auto _ : state) {
    state.PauseTiming();
    sim.reset();  // one model at a time: peak memory is one model's
    state.ResumeTiming();
    sim = implicitModel(N, solver);
    benchmark::DoNotOptimize(sim->current().data());
  }
  reportSystem(state, *sim);
}

void step(benchmark::State& state, LinearSolver solver) {
  const int N = static_cast<int>(state.range(0));
  const auto sim = implicitModel(N, solver);
  sim->advance(2);  // started and moving
  long iterations = 0, steps = 0;
  for (auto _ : state) {
    sim->step();
    iterations += sim->implicitSystem()->lastIterations();
    ++steps;
    benchmark::DoNotOptimize(sim->current().data());
  }
  if (sim->status() != bsdeform::Status::Ok) state.SkipWithError(sim->statusMessage().c_str());
  reportSystem(state, *sim);
  state.counters["cgIterations"] = steps ? double(iterations) / double(steps) : 0.0;
}

void ImplicitFactor(benchmark::State& s) { factor(s, LinearSolver::Automatic); }
void ImplicitStep(benchmark::State& s) { step(s, LinearSolver::Automatic); }
void ImplicitFactorDirect(benchmark::State& s) { factor(s, LinearSolver::Direct); }
void ImplicitStepDirect(benchmark::State& s) { step(s, LinearSolver::Direct); }
void ImplicitFactorCG(benchmark::State& s) { factor(s, LinearSolver::ConjugateGradient); }
void ImplicitStepCG(benchmark::State& s) { step(s, LinearSolver::ConjugateGradient); }
void ImplicitFactorMG(benchmark::State& s) { factor(s, LinearSolver::Multigrid); }
void ImplicitStepMG(benchmark::State& s) { step(s, LinearSolver::Multigrid); }

// Issue 23: ImplicitStepSides/<N>/<K>, the implicit step with all four sides CLAMPED (K = 0),
// SIMPLY_SUPPORTED (1) or BUILT_IN (2); StaticSolve/<N>/<K>, Simulation::solveStatic of the
// Kirchhoff plate (w10 = w01 = 0, the others 1) under a uniform load with those sides: what
// bsdeform-run --static does per surface.
bsdeform::Boundary sideKind(int k) {
  const bsdeform::Boundary kinds[] = {bsdeform::Boundary::Clamped, bsdeform::Boundary::SimplySupported,
                                      bsdeform::Boundary::BuiltIn};
  return kinds[k];
}

void ImplicitStepSides(benchmark::State& state) {
  const int N = static_cast<int>(state.range(0));
  const bsdeform::Boundary k = sideKind(int(state.range(1)));
  bsdeform::ModelParameters p;
  p.numU = p.numV = N;
  p.integrator = bsdeform::Integrator::Implicit;
  p.boundaries = {k, k, k, k};
  bsdeform::Simulation sim(p);
  sim.addForce(std::make_shared<bsdeform::DistributedForce>(Eigen::Vector3d(0, 0, 60), bsdeform::ParamRect{0.3, 0.7, 0.3, 0.7}));
  sim.advance(2);
  long iterations = 0, steps = 0;
  for (auto _ : state) {
    sim.step();
    iterations += sim.implicitSystem()->lastIterations();
    ++steps;
    benchmark::DoNotOptimize(sim.current().data());
  }
  if (sim.status() != bsdeform::Status::Ok) state.SkipWithError(sim.statusMessage().c_str());
  reportSystem(state, sim);
  state.counters["cgIterations"] = steps ? double(iterations) / double(steps) : 0.0;
}

void StaticSolve(benchmark::State& state) {
  const int N = static_cast<int>(state.range(0));
  const bsdeform::Boundary k = sideKind(int(state.range(1)));
  bsdeform::ModelParameters p;
  p.numU = p.numV = N;
  p.weights = bsdeform::Weights{0, 0, 1, 1, 1};
  p.boundaries = {k, k, k, k};
  bsdeform::Simulation sim(p);
  sim.addForce(std::make_shared<bsdeform::DistributedForce>(Eigen::Vector3d(0, 0, 1)));
  double residual = 0.0;
  for (auto _ : state) {
    const bsdeform::StaticResult r = sim.solveStatic();
    residual = r.residual;
    benchmark::DoNotOptimize(r.net.data());
  }
  state.counters["residual"] = residual;
}

}  // namespace

BENCHMARK(ImplicitStepSides)->ArgsProduct({{64, 128, 256}, {0, 1, 2}})->Unit(benchmark::kMillisecond);
BENCHMARK(StaticSolve)->ArgsProduct({{64, 256}, {0, 1, 2}})->Unit(benchmark::kMillisecond);
BENCHMARK(StaticSolve)->ArgsProduct({{1024}, {0, 1, 2}})->Iterations(1)->Unit(benchmark::kMillisecond);

// 64..256 repeat as Google Benchmark decides; 512 and 1024 once (seconds to minutes each).
#define BSDEFORM_IMPLICIT_BENCH(name)                                                   \
  BENCHMARK(name)->Arg(64)->Arg(128)->Arg(256)->Unit(benchmark::kMillisecond);         \
  BENCHMARK(name)->Arg(512)->Arg(1024)->Iterations(1)->Unit(benchmark::kMillisecond)

BSDEFORM_IMPLICIT_BENCH(ImplicitFactor);
BSDEFORM_IMPLICIT_BENCH(ImplicitStep);
BSDEFORM_IMPLICIT_BENCH(ImplicitFactorDirect);
BSDEFORM_IMPLICIT_BENCH(ImplicitStepDirect);
BSDEFORM_IMPLICIT_BENCH(ImplicitFactorCG);
BSDEFORM_IMPLICIT_BENCH(ImplicitStepCG);
BSDEFORM_IMPLICIT_BENCH(ImplicitFactorMG);
BSDEFORM_IMPLICIT_BENCH(ImplicitStepMG);

BENCHMARK_MAIN();
