// SPDX-License-Identifier: MIT
// The SHELL energy (issue 24): the force evaluation (gradient of the Kirchhoff–Love energy) per
// control point, the explicit step's stability bound, and one implicit (Newton) step of a
// cotton sheet, for bicubic nets of N x N inner points.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <memory>

#include "bsdeform/base/Parallel.h"
#include "bsdeform/energy/ElasticEnergy.h"
#include "bsdeform/forces/ForceLaws.h"
#include "bsdeform/spline/RestShape.h"
#include "bsdeform/dynamics/MassMatrix.h"
#include "bsdeform/dynamics/SparseCholesky.h"
#include "bsdeform/dynamics/TangentMatrix.h"
#include "bsdeform/energy/Shell.h"
#include "bsdeform/dynamics/Simulation.h"

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

// Steps of the curtain `p` falling under gravity, each iteration one step from the state the
// previous ones left (the first 5 steps untimed); Newton iterations per step as a counter.
void implicitSteps(benchmark::State& state, const ModelParameters& p) {
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

// A cotton curtain hinged along v = 1 falling under gravity: one implicit (Newmark) step of
// 1/60 s each iteration.
void ShellImplicitStep(benchmark::State& state) {
  ModelParameters p = curtain(int(state.range(0)));
  p.integrator = Integrator::Implicit;
  implicitSteps(state, p);
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
// One Newton iteration of the implicit step of a cotton curtain (N x N inner points, bicubic or
// biquadratic, hinged
// at v = 1) at a waved state: the tangent M/h^2 + H (element Hessians projected, assembled in
// place into the fixed pattern), its numeric Cholesky factorisation (CHOLMOD supernodal, the
// symbolic analysis done once before the loop, as the steppers keep it) and one solve.
// Counters: the parts' times per iteration. NewtonIterationExact: the exact element Hessians,
// the tangent backward Euler factorises first (and, with more of the mass, after a failure).
void newtonIteration(benchmark::State& state, HessianMode mode) {
  const int n = int(state.range(0)), degree = int(state.range(1));
  const SplineSpace s(degree, degree, n, n, Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::SimplySupported});
  const ShellModelEnergy energy(s, s.grevillePlane(), kCotton);
  ControlNet x = waved(s);
  s.completeNet(x, nullptr);
  TangentMatrix K(s, energy.foldStart(), energy.foldEntries());
  // the mass T^T W T, as the SHELL model builds it
  const Eigen::SparseMatrix<double> M =
      MassMatrix::folded(s, energy.netMass(), std::vector<char>(size_t(s.numMoving()), 0))->matrix();
  const double h = 0.02;
  auto assemble = [&] {
    K.setZero();
    energy.shell().elementHessians(x, mode, false,
                                   [&](int e1, int e2, const double* Ke) { K.addElement(e1, e2, Ke, 1.0); });
    K.addScalarMatrix(M, 1.0 / (h * h));
  };
  assemble();
  // the fill-reducing ordering: 0 CHOLMOD's default (AMD, METIS only when AMD's fill is high),
  // 1 METIS, 2 CHOLMOD's nested dissection (NESDIS); the symbolic analysis is made at the first
  // factorisation, before the loop
  const int ordering = int(state.range(2));
  SparseCholesky llt(ordering == 0   ? SparseCholesky::Ordering::Default
                     : ordering == 1 ? SparseCholesky::Ordering::Metis
                                     : SparseCholesky::Ordering::NestedDissection);
  llt.factor(K.matrix());
  const Eigen::VectorXd rhs = Eigen::VectorXd::Ones(K.matrix().rows());
  double tAssemble = 0.0, tFactor = 0.0, tSolve = 0.0;
  using Clock = std::chrono::steady_clock;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    assemble();
    const auto t1 = Clock::now();
    if (!llt.factor(K.matrix())) {  // an indefinite tangent stops early: no timing
      state.SkipWithError("the tangent is not positive definite");
      break;
    }
    const auto t2 = Clock::now();
    Eigen::VectorXd d = llt.solve(rhs);
    benchmark::DoNotOptimize(d.data());
    const auto t3 = Clock::now();
    tAssemble += std::chrono::duration<double>(t1 - t0).count();
    tFactor += std::chrono::duration<double>(t2 - t1).count();
    tSolve += std::chrono::duration<double>(t3 - t2).count();
  }
  const double iters = double(state.iterations());
  state.counters["assembly_ms"] = 1e3 * tAssemble / iters;
  state.counters["factor_ms"] = 1e3 * tFactor / iters;
  state.counters["solve_ms"] = 1e3 * tSolve / iters;
  state.counters["unknowns"] = double(K.matrix().rows());
  state.counters["nnz_L"] = llt.factorNonZeros();
  state.counters["Mflop"] = llt.factorFlops() * 1e-6;
}
void NewtonIteration(benchmark::State& state) { newtonIteration(state, HessianMode::Projected); }
void NewtonIterationExact(benchmark::State& state) { newtonIteration(state, HessianMode::Exact); }

// The cotton curtain with the integrator the docs recommend for cloth: one BACKWARD_EULER step
// of 0.02 s each iteration (the first 5 untimed).
void ShellBackwardEulerStep(benchmark::State& state) {
  ModelParameters p = curtain(int(state.range(0)));
  p.integrator = Integrator::BackwardEuler;
  p.timeStep = 0.02;
  p.newtonVelocityTolerance = 1e-4;
  if (state.range(1) == 1) {
    p.nonlinearSolver = NonlinearSolver::LBFGS;
    p.maxNewtonIterations = int(state.range(2));
  }
  implicitSteps(state, p);
}

// The curtain released horizontal and falling for one simulated second (50 BACKWARD_EULER steps
// of 0.02 s) per iteration, by Newton (solver 0) or L-BFGS (1), newtonVelocityTolerance
// 10^-tolerance m/s, bicubic or biquadratic (degree): wall seconds per simulated second, the
// same states for every repetition.
void CurtainSecond(benchmark::State& state) {
  ModelParameters p = curtain(int(state.range(0)));
  p.degreeU = p.degreeV = int(state.range(3));
  p.integrator = Integrator::BackwardEuler;
  p.timeStep = 0.02;
  p.newtonVelocityTolerance = std::pow(10.0, -double(state.range(2)));
  if (state.range(1) == 1) {
    p.nonlinearSolver = NonlinearSolver::LBFGS;
    p.maxNewtonIterations = 400;
  }
  long newton = 0, steps = 0;
  for (auto _ : state) {
    Simulation sim(p);
    sim.addForce(gravity());
    for (int k = 0; k < 50; ++k) {
      if (sim.step() != Status::Ok) {
        state.SkipWithError(sim.statusMessage().c_str());
        return;
      }
      newton += sim.lastNewtonIterations();
      ++steps;
    }
  }
  state.counters["iterations/step"] = steps ? double(newton) / double(steps) : 0.0;
}

// The linear static solve of a pinched cylinder of S x S knot spans (R = 300, L = 600, t = 3,
// E = 3e6, nu = 0.3; both ends BUILT_IN, a stand-in for rigid diaphragms; two opposite unit point
// loads at mid-length): Newton's two iterations on the fixed-pattern tangent, CHOLMOD. Peak
// memory is the process's (`/usr/bin/time -f %M` around a run of one size).
void StaticPinchedCylinder(benchmark::State& state) {
  const int spans = int(state.range(0));
  ModelParameters p;
  p.numU = p.numV = spans - 3;
  p.boundaries = shapeBoundaries(ShapeKind::Cylinder,
                                 Boundaries{Boundary::Periodic, Boundary::Periodic, Boundary::BuiltIn, Boundary::BuiltIn});
  p.energy = EnergyModel::Shell;
  p.material = ShellMaterial{3e6, 0.3, 3.0, 1.0};
  ShapeSize size;
  size.radius = 300;
  size.height = 600;
  const SplineSpace space(3, 3, p.numU, p.numV, p.boundaries);
  Simulation sim(p, shapeRestNet(ShapeKind::Cylinder, size, space));
  for (double u : {0.0, 0.5}) {
    const Eigen::Vector3d x = sim.evaluate(u, 0.5).position;
    sim.addForce(std::make_shared<PointForce>(u, 0.5, Eigen::Vector3d(-x.x(), -x.y(), 0.0).normalized()));
  }
  for (auto _ : state) benchmark::DoNotOptimize(sim.solveStatic(1e-8, 100, LinearSolver::Automatic, 1).residual);
  state.counters["unknowns"] = double(3 * sim.space().numMoving());
}
}  // namespace

BENCHMARK(StaticPinchedCylinder)->Arg(64)->Arg(186)->Iterations(1)->Unit(benchmark::kSecond);
BENCHMARK(ShellForces)->RangeMultiplier(2)->Range(32, 512)->Unit(benchmark::kMillisecond);
BENCHMARK(ShellBound)->Arg(32)->Arg(128)->Unit(benchmark::kMillisecond);
BENCHMARK(ShellImplicitStep)->Arg(16)->Arg(32)->Arg(64)->Unit(benchmark::kMillisecond);
BENCHMARK(NewtonIteration)
    ->ArgsProduct({{16, 32, 64, 128}, {3, 2}, {0, 1, 2}})
    ->ArgNames({"N", "degree", "ordering"})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(NewtonIterationExact)
    ->ArgsProduct({{16, 32, 64, 128}, {3, 2}, {0}})
    ->ArgNames({"N", "degree", "ordering"})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(ShellBackwardEulerStep)
    ->Args({16, 0, 30})
    ->Args({32, 0, 30})
    ->Args({64, 0, 30})
    ->Args({16, 1, 300})
    ->Args({32, 1, 300})
    ->Args({64, 1, 300})
    ->ArgNames({"N", "lbfgs", "maxIterations"})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(CurtainSecond)
    ->ArgsProduct({{16, 32, 64}, {0, 1}, {2, 3, 4}, {3, 2}})
    ->ArgNames({"N", "lbfgs", "tolerance", "degree"})
    ->Iterations(1)
    ->Unit(benchmark::kSecond);
BENCHMARK(ShellExplicitStep)->Arg(16)->Arg(32)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
