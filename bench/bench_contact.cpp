// SPDX-License-Identifier: MIT
// Where a barrier-contact step's time goes (issue 35, "Speed": the cost split per step):
//   ContactSecond/<N>/<threads>  one simulated second of cloth_on_cube.iv's drop: a 1 m cotton
//                                cloth (SHELL, N x N biquadratic net, free sides, damping 1) falls
//                                from z = 0 onto a 0.6 m box (top at z = -0.1) under gravity,
//                                BACKWARD_EULER at dt 0.02 with Newton, barrier contact (offset
//                                0.01 m, d̂ 2 mm, 3 proxy samples per span) and friction 0.3;
//                                with <threads> kernel threads (BSDEFORM_THREADS).
//   PushedSheet/<N>              a plate pushing a resting sheet: the same cotton (N x N
//                                biquadratic net) lies on a 2 x 2 m plate, which an engine would
//                                raise by 2 cm a step (1 m/s at dt 0.02, ten times the barrier's
//                                reach); 25 steps, the plate swept into place each step
//                                (docs/math.md §18.4), the sheet carried along with it.
// Counters, per step (wall ms): elastic (energy, gradient, element Hessians and assembly), loads
// (the forces' loads, potentials and Jacobians: the contact's terms), collision checks (the line
// search's CCD), factorisation, solve, other; the contact's own parts (proxy, broad phase, pair
// terms, Jacobian push, CCD); Newton iterations per step; real time = simulated / wall seconds.
#include <benchmark/benchmark.h>

#include <memory>

#include "bsdeform/base/Parallel.h"
#include "bsdeform/contact/BarrierContact.h"
#include "bsdeform/contact/Contact.h"
#include "bsdeform/contact/TriangleTree.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/forces/ForceLaws.h"

namespace {

// An axis-aligned box [lo, hi], 12 triangles wound outward.
bsdeform::TriangleMesh box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  bsdeform::TriangleMesh m;
  for (int k = 0; k < 8; ++k)
    m.vertices.emplace_back(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(), k & 4 ? hi.z() : lo.z());
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    m.triangles.emplace_back(f[0], f[1], f[2]);
    m.triangles.emplace_back(f[0], f[2], f[3]);
  }
  return m;
}

/// A cotton sheet (N x N biquadratic net, free sides, SHELL) stepped by BACKWARD_EULER with
/// Newton at dt 0.02, as the contact scenes run it.
bsdeform::ModelParameters cottonSheet(int n) {
  bsdeform::ModelParameters p;
  p.numU = p.numV = n;
  p.degreeU = p.degreeV = 2;
  p.boundaries = {bsdeform::Boundary::Free, bsdeform::Boundary::Free, bsdeform::Boundary::Free,
                  bsdeform::Boundary::Free};
  p.energy = bsdeform::EnergyModel::Shell;
  p.material = bsdeform::ShellMaterial{0.821e6, 0.243, 0.318e-3, 472.6};
  p.damping = 1.0;
  p.timeStep = 0.02;
  p.integrator = bsdeform::Integrator::BackwardEuler;
  p.maxNewtonIterations = 200;
  return p;
}

/// Gravity on the sheet's own areal mass.
void addGravity(bsdeform::Simulation& sim) {
  const bsdeform::ShellMaterial& m = sim.parameters().material;
  sim.addForce(std::make_shared<bsdeform::GravityForce>(m.density * m.thickness, Eigen::Vector3d(0, 0, -9.81)));
}

void ContactSecond(benchmark::State& state) {
  const int n = int(state.range(0));
  const int threads = int(state.range(1));
  const int before = bsdeform::kernelThreads();
  bsdeform::setKernelThreads(threads);  // before the obstacle's Embree device, which takes it
  const bsdeform::ModelParameters p = cottonSheet(n);
  auto world = std::make_shared<bsdeform::ContactWorld>();
  const bsdeform::TriangleMesh cube = box(Eigen::Vector3d(0.2, 0.2, -0.7), Eigen::Vector3d(0.8, 0.8, -0.1));
  world->obstacles.push_back({std::make_shared<bsdeform::TriangleTree>(cube), bsdeform::isClosedMesh(cube)});
  bsdeform::BarrierContactParameters bp;
  bp.offset = 0.01;
  bp.dhat = 0.002;
  bp.samplesPerSpan = 3;
  bp.friction = 0.3;
  bp.modelMass = true;
  bsdeform::StepCosts costs;
  bsdeform::BarrierContactForce::Costs contactCosts;
  double iterations = 0.0;
  long steps = 0;
  for (auto _ : state) {
    state.PauseTiming();
    bsdeform::Simulation sim(p);
    addGravity(sim);
    auto contact = std::make_shared<bsdeform::BarrierContactForce>(world, bp);
    sim.addForce(contact);
    state.ResumeTiming();
    for (int k = 0; k < 50; ++k)
      if (sim.step() != bsdeform::Status::Ok) {
        state.SkipWithError(sim.statusMessage().c_str());
        break;
      }
    const bsdeform::StepCosts& c = sim.stepCosts();
    costs.total += c.total;
    costs.elastic += c.elastic;
    costs.loads += c.loads;
    costs.collisionChecks += c.collisionChecks;
    costs.factorisation += c.factorisation;
    costs.solve += c.solve;
    iterations += double(c.iterations);
    steps += c.steps;
    const bsdeform::BarrierContactForce::Costs& b = contact->costs();
    contactCosts.proxy += b.proxy;
    contactCosts.broadPhase += b.broadPhase;
    contactCosts.pairs += b.pairs;
    contactCosts.push += b.push;
    contactCosts.ccd += b.ccd;
  }
  bsdeform::setKernelThreads(before);
  if (steps == 0) return;
  const double perStep = 1e3 / double(steps);  // seconds in all → ms a step
  state.counters["real time"] = double(steps) * p.timeStep / costs.total;
  state.counters["Newton/step"] = iterations / double(steps);
  state.counters["elastic ms"] = costs.elastic * perStep;
  state.counters["loads ms"] = costs.loads * perStep;
  state.counters["CCD ms"] = costs.collisionChecks * perStep;
  state.counters["factor ms"] = costs.factorisation * perStep;
  state.counters["solve ms"] = costs.solve * perStep;
  state.counters["other ms"] = costs.other() * perStep;
  state.counters["c.proxy ms"] = contactCosts.proxy * perStep;
  state.counters["c.broad ms"] = contactCosts.broadPhase * perStep;
  state.counters["c.pairs ms"] = contactCosts.pairs * perStep;
  state.counters["c.push ms"] = contactCosts.push * perStep;
  state.counters["c.ccd ms"] = contactCosts.ccd * perStep;
}

void PushedSheet(benchmark::State& state) {
  const int n = int(state.range(0));
  const bsdeform::ModelParameters p = cottonSheet(n);
  bsdeform::BarrierContactParameters bp;
  bp.offset = 0.005;
  bp.dhat = 0.002;
  bp.samplesPerSpan = 3;
  bp.modelMass = true;
  double iterations = 0.0, seconds = 0.0;
  long steps = 0;
  for (auto _ : state) {
    state.PauseTiming();
    const double top0 = -0.0065;  // the sheet (z = 0) 1.5 mm beyond the offset
    bsdeform::TriangleMesh plate = box(Eigen::Vector3d(-0.5, -0.5, top0 - 0.05), Eigen::Vector3d(1.5, 1.5, top0));
    auto tree = std::make_shared<bsdeform::TriangleTree>(plate);
    auto world = std::make_shared<bsdeform::ContactWorld>();
    world->obstacles.push_back({tree, true});
    bsdeform::Simulation sim(p);
    addGravity(sim);
    sim.addForce(std::make_shared<bsdeform::BarrierContactForce>(world, bp));
    state.ResumeTiming();
    for (int k = 0; k < 25; ++k) {
      for (Eigen::Vector3d& v : plate.vertices) v.z() += 0.02;
      tree->update(plate.vertices);
      if (sim.step() != bsdeform::Status::Ok) {
        state.SkipWithError(sim.statusMessage().c_str());
        break;
      }
    }
    iterations += double(sim.stepCosts().iterations);
    seconds += sim.stepCosts().total;
    steps += sim.stepCosts().steps;
  }
  if (steps == 0) return;
  state.counters["Newton/step"] = iterations / double(steps);
  state.counters["ms/step"] = 1e3 * seconds / double(steps);
}

}  // namespace

BENCHMARK(PushedSheet)->Arg(8)->Arg(16)->Iterations(1)->Unit(benchmark::kSecond);
BENCHMARK(ContactSecond)->Args({16, 1})->Args({16, 2})->Args({32, 1})->Args({32, 2})->Iterations(1)->Unit(benchmark::kSecond);

BENCHMARK_MAIN();
