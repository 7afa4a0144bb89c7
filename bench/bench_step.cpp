// SPDX-License-Identifier: MIT
// Cost of one explicit central-difference step (design.md §4):
//   ExplicitStep/<N>/<T>  the product: the fused stencil kernel of bsdeform::Simulation, on T
//                         threads (issue 11 item 6; split at every size, wall time)
//   ExplicitStepSides/<N>/<K> the paper's step with all four sides CLAMPED (K = 0),
//                         SIMPLY_SUPPORTED (1) or BUILT_IN (2) (issue 23)
//   SparseMatrixStep/<N>  the baseline a user would write: the same update with an Eigen
//                         SparseMatrix product A_II P_I + A_IB P_B
//   StreamBound/<N>       the same memory traffic without the stencil: the bandwidth bound
//   Build/<N>             construction of a model with a whole-domain constant force (issue 11
//                         item 7): Simulation + addForce, as a node builds it
//   Diagnostics/<N>/<T>   what the runner records per history row: eq. 15 norm, kinetic energy
//                         and the five strain-energy terms in one pass (issue 11 item 1)
//   DiagnosticsPerTerm/<N> the same from deformationNorm(), kineticEnergy(), strainEnergy()
//   RecordedStep/<N>/<R>  one step of the runner's region-load scene (auto sub-steps: 2 at 128^2)
//                         with R = 0 no history row, 1 a row computed on the stepping thread
//                         (diagnostics()), 2 a row computed beside the step
//                         (DiagnosticsBeside, issue 11 item 1); wall time
// N is the number of free control points per side (N^2 in all), bicubic, paper weights.
// Counters: points/s = free control points updated per second.
#include <benchmark/benchmark.h>

#include <Eigen/Sparse>
#include <memory>

#include "bsdeform/base/Parallel.h"
#include "bsdeform/spline/RestShape.h"
#include "bsdeform/dynamics/DiagnosticsBeside.h"
#include "bsdeform/dynamics/Simulation.h"

namespace {

bsdeform::ModelParameters params(int N) {
  bsdeform::ModelParameters p;
  p.numU = p.numV = N;
  p.autoSubstep = false;  // measure exactly one update per step
  p.timeStep = 1e-4;
  return p;
}

// Runs a benchmark with `threads` kernel threads, splitting at every size (issue 11 item 6), and
// puts back one thread, the setting of every other benchmark here.
class KernelThreads {
 public:
  explicit KernelThreads(int threads) {
    bsdeform::setKernelThreads(threads);
    bsdeform::setExplicitParallelMinPoints(0);
  }
  ~KernelThreads() {
    bsdeform::setKernelThreads(1);
    bsdeform::setExplicitParallelMinPoints(m_minPoints);
  }

 private:
  long m_minPoints = bsdeform::explicitParallelMinPoints();
};

void ExplicitStep(benchmark::State& state) {
  const int N = static_cast<int>(state.range(0));
  const KernelThreads threads(static_cast<int>(state.range(1)));
  bsdeform::Simulation sim(params(N));
  sim.addForce(std::make_shared<bsdeform::DistributedForce>(Eigen::Vector3d(0, 0, 1)));
  for (auto _ : state) {
    sim.step();
    benchmark::DoNotOptimize(sim.current().data());
  }
  if (sim.status() != bsdeform::Status::Ok) state.SkipWithError("simulation diverged");
  state.counters["points/s"] = benchmark::Counter(double(N) * N, benchmark::Counter::kIsIterationInvariantRate);
}

// The same step with other boundary conditions (issue 8): all four sides FREE with lumped mass
// (the band of truncated edge rows, smaller edge masses), and a tube periodic in u with its v
// sides clamped (wrapped rows). points/s counts the moving control points.
void steppedModel(benchmark::State& state, const bsdeform::Boundaries& bc, bool closedRest) {
  const int N = static_cast<int>(state.range(0));
  bsdeform::ModelParameters p = params(N);
  p.boundaries = bc;
  p.massModel = bsdeform::MassModel::Lumped;
  p.timeStep = 1e-6;
  std::unique_ptr<bsdeform::Simulation> sim;
  if (closedRest) {
    const bsdeform::SplineSpace s(p.degreeU, p.degreeV, p.numU, p.numV, bc);
    sim = std::make_unique<bsdeform::Simulation>(
        p, bsdeform::shapeRestNet(bsdeform::ShapeKind::Cylinder, bsdeform::ShapeSize(), s));
  } else {
    sim = std::make_unique<bsdeform::Simulation>(p);
  }
  sim->addForce(std::make_shared<bsdeform::DistributedForce>(Eigen::Vector3d(0, 0, 1)));
  for (auto _ : state) {
    sim->step();
    benchmark::DoNotOptimize(sim->current().data());
  }
  if (sim->status() != bsdeform::Status::Ok) state.SkipWithError("simulation diverged");
  state.counters["points/s"] =
      benchmark::Counter(double(sim->space().numMoving()), benchmark::Counter::kIsIterationInvariantRate);
}

void ExplicitStepFree(benchmark::State& state) {
  using bsdeform::Boundary;
  steppedModel(state, {Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free}, false);
}

void ExplicitStepPeriodic(benchmark::State& state) {
  using bsdeform::Boundary;
  steppedModel(state, {Boundary::Periodic, Boundary::Periodic, Boundary::Clamped, Boundary::Clamped}, true);
}

// The paper's step with every side of one kind (issue 23): K = 0 CLAMPED (the paper), 1
// SIMPLY_SUPPORTED, 2 BUILT_IN. Nodal mass as the paper; points/s counts the moving points.
void ExplicitStepSides(benchmark::State& state) {
  using bsdeform::Boundary;
  const int N = static_cast<int>(state.range(0));
  const Boundary kinds[] = {Boundary::Clamped, Boundary::SimplySupported, Boundary::BuiltIn};
  const Boundary k = kinds[state.range(1)];
  bsdeform::ModelParameters p = params(N);
  p.boundaries = {k, k, k, k};
  bsdeform::Simulation sim(p);
  sim.addForce(std::make_shared<bsdeform::DistributedForce>(Eigen::Vector3d(0, 0, 1)));
  for (auto _ : state) {
    sim.step();
    benchmark::DoNotOptimize(sim.current().data());
  }
  if (sim.status() != bsdeform::Status::Ok) state.SkipWithError("simulation diverged");
  state.counters["points/s"] =
      benchmark::Counter(double(sim.space().numMoving()), benchmark::Counter::kIsIterationInvariantRate);
}

// The same step with an assembled sparse matrix: A = [A_II A_IB] over all net points, so one
// sparse product gives (A P)_free, then the diagonal central-difference update.
void SparseMatrixStep(benchmark::State& state) {
  const int N = static_cast<int>(state.range(0));
  const bsdeform::ModelParameters p = params(N);
  bsdeform::Simulation sim(p);
  const bsdeform::SplineSpace& s = sim.space();
  const int n1 = s.degreeU(), n2 = s.degreeV();
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(size_t(s.numMoving()) * (2 * n1 + 1) * (2 * n2 + 1));
  for (int a = 0; a < N; ++a)
    for (int b = 0; b < N; ++b)
      for (int d1 = -n1; d1 <= n1; ++d1)
        for (int d2 = -n2; d2 <= n2; ++d2)
          t.emplace_back(a * N + b, int(s.netIndex(a + d1, b + d2)), sim.stencil().coefficient(d1, d2));
  Eigen::SparseMatrix<double, Eigen::RowMajor> A(s.numMoving(), s.netSize());
  A.setFromTriplets(t.begin(), t.end());
  t.clear();
  t.shrink_to_fit();
  Eigen::MatrixXd net = sim.rest();  // all points, column-major N x 3
  Eigen::MatrixXd P = s.gatherMoving(sim.rest()), Pold = P, Pnew(P.rows(), 3);
  const Eigen::MatrixXd L = sim.loadVector();
  const double dt = p.timeStep, m = p.mass, c = p.damping, g = 2 * m + dt * c;
  const double alpha = 2 * dt * dt / g, beta = 4 * m / g, gamma = (2 * m - dt * c) / g;
  std::vector<Eigen::Index> freeRows(s.numMoving());
  for (Eigen::Index f = 0; f < s.numMoving(); ++f) freeRows[f] = s.movingToNet(f);
  for (auto _ : state) {
    Pnew.noalias() = alpha * (L - A * net) + beta * P - gamma * Pold;
    Pold.swap(P);
    P.swap(Pnew);
    for (Eigen::Index f = 0; f < s.numMoving(); ++f) net.row(freeRows[f]) = P.row(f);
    benchmark::DoNotOptimize(net.data());
  }
  state.counters["points/s"] = benchmark::Counter(double(N) * N, benchmark::Counter::kIsIterationInvariantRate);
}

// The memory traffic of ExplicitStep without its arithmetic: the same arrays (current net,
// previous net rewritten in place, load) streamed once with the update minus the stencil.
// Its time is this machine's bandwidth bound for the explicit step.
void StreamBound(benchmark::State& state) {
  const int N = static_cast<int>(state.range(0));
  bsdeform::Simulation sim(params(N));
  const bsdeform::SplineSpace& s = sim.space();
  Eigen::Matrix<double, Eigen::Dynamic, 1> P = Eigen::Map<const Eigen::VectorXd>(sim.rest().data(), sim.rest().size());
  Eigen::Matrix<double, Eigen::Dynamic, 1> Pold = P;
  const Eigen::VectorXd L = Eigen::VectorXd::Constant(3 * s.numMoving(), 1e-9);
  const long cols3 = 3L * s.netCols(), free3 = 3L * s.numV();
  for (auto _ : state) {
    for (int a = 0; a < N; ++a) {
      const long row = (a + s.degreeU()) * cols3 + 3L * s.degreeV();
      Pold.segment(row, free3) = P.segment(row, free3) + 1e-3 * (L.segment(3L * a * N, free3)) +
                                 0.5 * (P.segment(row, free3) - Pold.segment(row, free3));
    }
    P.swap(Pold);
    benchmark::DoNotOptimize(P.data());
  }
  state.counters["points/s"] = benchmark::Counter(double(N) * N, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["bytes/s"] = benchmark::Counter(4.0 * 24.0 * N * N, benchmark::Counter::kIsIterationInvariantRate,
                                                 benchmark::Counter::kIs1024);
}

void Build(benchmark::State& state) {
  const int N = static_cast<int>(state.range(0));
  bsdeform::ModelParameters p;
  p.numU = p.numV = N;
  for (auto _ : state) {
    bsdeform::Simulation sim(p);
    sim.addForce(std::make_shared<bsdeform::DistributedForce>(Eigen::Vector3d(0, 0, 60)));
    benchmark::DoNotOptimize(sim.current().data());
  }
  state.counters["points/s"] = benchmark::Counter(double(N) * N, benchmark::Counter::kIsIterationInvariantRate);
}

// A deformed, moving state: a few steps of a region load, as bsdeform-run records it.
std::unique_ptr<bsdeform::Simulation> deformedModel(int N) {
  bsdeform::ModelParameters p;
  p.numU = p.numV = N;
  p.damping = 1.0;
  auto sim = std::make_unique<bsdeform::Simulation>(p);
  sim->addForce(std::make_shared<bsdeform::DistributedForce>(Eigen::Vector3d(0, 0, 60),
                                                             bsdeform::ParamRect{0.3, 0.7, 0.3, 0.7}));
  sim->advance(3);
  return sim;
}

void Diagnostics(benchmark::State& state) {
  const int N = static_cast<int>(state.range(0));
  const auto sim = deformedModel(N);
  const KernelThreads threads(static_cast<int>(state.range(1)));
  for (auto _ : state) {
    const bsdeform::Diagnostics d = sim->diagnostics();
    benchmark::DoNotOptimize(d.strain.total + d.norm + d.kinetic);
  }
  state.counters["points/s"] = benchmark::Counter(double(N) * N, benchmark::Counter::kIsIterationInvariantRate);
}

// The same values from the functions that compute one each (five stencils built and applied
// for the strain energy): what bsdeform-run called per row before issue 11.
void DiagnosticsPerTerm(benchmark::State& state) {
  const int N = static_cast<int>(state.range(0));
  const auto sim = deformedModel(N);
  for (auto _ : state) {
    const bsdeform::StrainEnergy e = sim->strainEnergy();
    benchmark::DoNotOptimize(e.total + sim->deformationNorm() + sim->kineticEnergy());
  }
  state.counters["points/s"] = benchmark::Counter(double(N) * N, benchmark::Counter::kIsIterationInvariantRate);
}

// The runner's loop: a step, then the history row of the new state (none, on this thread, or
// beside the next step, collected after it).
void RecordedStep(benchmark::State& state) {
  const int N = static_cast<int>(state.range(0));
  const int rows = static_cast<int>(state.range(1));
  bsdeform::ModelParameters p;
  p.numU = p.numV = N;
  p.damping = 1.0;  // the scene of docs/benchmarks.md, "Runner history (item 1)"
  bsdeform::Simulation sim(p);
  sim.addForce(std::make_shared<bsdeform::DistributedForce>(Eigen::Vector3d(0, 0, 60),
                                                            bsdeform::ParamRect{0.3, 0.7, 0.3, 0.7}));
  bsdeform::DiagnosticsBeside beside;
  bsdeform::PendingDiagnostics row;
  double sum = 0.0;
  for (auto _ : state) {
    sim.step();
    if (rows == 1) sum += sim.diagnostics().norm;
    if (rows == 2) {
      if (row.valid()) sum += row.get().norm;
      row = beside.begin(sim);
    }
  }
  if (row.valid()) sum += row.get().norm;
  benchmark::DoNotOptimize(sum);
  if (sim.status() != bsdeform::Status::Ok) state.SkipWithError("simulation diverged");
  state.counters["sub-steps"] = sim.subSteps();
}

}  // namespace

// <N>/<threads>: wall time (UseRealTime), since the second thread's time is not the caller's CPU time
BENCHMARK(ExplicitStep)
    ->ArgsProduct({{32, 48, 64, 96, 128, 256, 512, 1024}, {1, 2}})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();
BENCHMARK(ExplicitStepSides)->ArgsProduct({{64, 256, 1024}, {0, 1, 2}})->Unit(benchmark::kMicrosecond);
BENCHMARK(ExplicitStepFree)->RangeMultiplier(2)->Range(32, 1024)->Unit(benchmark::kMicrosecond);
BENCHMARK(ExplicitStepPeriodic)->RangeMultiplier(2)->Range(32, 1024)->Unit(benchmark::kMicrosecond);
BENCHMARK(SparseMatrixStep)->RangeMultiplier(2)->Range(32, 1024)->Unit(benchmark::kMicrosecond);
BENCHMARK(StreamBound)->Arg(256)->Arg(1024)->Unit(benchmark::kMicrosecond);
BENCHMARK(Build)->RangeMultiplier(2)->Range(128, 2048)->Unit(benchmark::kMillisecond);
BENCHMARK(Diagnostics)
    ->ArgsProduct({{32, 48, 64, 96, 128, 256, 512, 1024}, {1, 2}})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();
BENCHMARK(DiagnosticsPerTerm)->RangeMultiplier(2)->Range(32, 1024)->Unit(benchmark::kMicrosecond);
BENCHMARK(RecordedStep)->ArgsProduct({{64, 128, 256}, {0, 1, 2}})->Unit(benchmark::kMicrosecond)->UseRealTime();

int main(int argc, char** argv) {
  bsdeform::setKernelThreads(1);  // one thread unless a benchmark asks for more
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
