// SPDX-License-Identifier: MIT
// Cost of a step with contact against an obstacle mesh (issue 9, item 4):
//   CollisionStep/<N>/<triangles>  one explicit update of an N^2 cloth (free edges, lumped mass)
//                                  lying on the top of a sphere mesh of about <triangles>
//                                  triangles (radius 0.5, the cloth 2 x 2, thickness 0.01);
//                                  <triangles> = 0 is the same step without the collision force
// One update per step (autoSubstep off, dt = 1e-5) in both, so the ratio is the cost of the
// contact load, not of the sub-steps its stiffness asks for. The cloth starts on the sphere with
// the apex inside the contact layer and gravity pulls it on; the state is put back every 200
// steps (untimed) so that every figure is of the same contact.
// CollisionStepApproach/<N>/<triangles>: the same cloth 10 thicknesses above the sphere.
// Counters: active = share of elements evaluated per load, refs/step = reference nets taken
// (clearances measured) per step, queries/step = quadrature points evaluated per step.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>

#include "bsdeform/contact/Contact.h"
#include "bsdeform/dynamics/Simulation.h"

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRadius = 0.5;
constexpr double kThickness = 0.01;

// A closed UV sphere with about `triangles` triangles, outward wound.
bsdeform::TriangleMesh sphere(int triangles) {
  const int rings = std::max(3, int(std::lround(std::sqrt(triangles / 4.0))));
  const int segments = 2 * rings;
  bsdeform::TriangleMesh m;
  m.vertices.emplace_back(0, 0, kRadius);
  for (int r = 1; r < rings; ++r) {
    const double th = kPi * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double ph = 2.0 * kPi * s / segments;
      m.vertices.emplace_back(kRadius * std::sin(th) * std::cos(ph), kRadius * std::sin(th) * std::sin(ph),
                              kRadius * std::cos(th));
    }
  }
  m.vertices.emplace_back(0, 0, -kRadius);
  const int south = int(m.vertices.size()) - 1;
  auto at = [&](int r, int s) { return 1 + (r - 1) * segments + (s % segments); };
  for (int s = 0; s < segments; ++s) m.triangles.emplace_back(0, at(1, s), at(1, s + 1));
  for (int r = 1; r + 1 < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      m.triangles.emplace_back(at(r, s), at(r + 1, s), at(r + 1, s + 1));
      m.triangles.emplace_back(at(r, s), at(r + 1, s + 1), at(r, s + 1));
    }
  for (int s = 0; s < segments; ++s) m.triangles.emplace_back(south, at(rings - 1, s + 1), at(rings - 1, s));
  return m;
}

void steps(benchmark::State& state, double gap) {
  const int N = static_cast<int>(state.range(0));
  const int triangles = static_cast<int>(state.range(1));
  bsdeform::ModelParameters p;
  p.numU = p.numV = N;
  p.boundaries = {bsdeform::Boundary::Free, bsdeform::Boundary::Free, bsdeform::Boundary::Free,
                  bsdeform::Boundary::Free};
  p.massModel = bsdeform::MassModel::Lumped;
  p.autoSubstep = false;
  p.timeStep = 1e-5;
  bsdeform::Simulation sim(p);
  // the cloth: [-1, 1]^2 at `gap` above the apex
  bsdeform::ControlNet start = sim.current();
  for (Eigen::Index i = 0; i < start.rows(); ++i)
    start.row(i) << 2.0 * start(i, 0) - 1.0, 2.0 * start(i, 1) - 1.0, kRadius + gap;
  sim.setState(start, start, 0.0, 0);
  sim.addForce(std::make_shared<bsdeform::DistributedForce>(Eigen::Vector3d(0, 0, -9.81)));
  std::shared_ptr<bsdeform::CollisionForce> contact;
  if (triangles > 0) {
    auto world = std::make_shared<bsdeform::ContactWorld>();
    const bsdeform::TriangleMesh mesh = sphere(triangles);
    world->obstacles.push_back({std::make_shared<bsdeform::TriangleTree>(mesh), bsdeform::isClosedMesh(mesh)});
    state.counters["triangles"] = double(world->obstacles[0].tree->triangleCount());
    bsdeform::ContactParameters cp;
    cp.thickness = kThickness;
    cp.stiffness = 1e4;
    cp.friction = 0.3;
    contact = std::make_shared<bsdeform::CollisionForce>(world, cp);
    sim.addForce(contact);
  }
  long steps = 0;
  double active = 0.0;
  for (auto _ : state) {
    if (++steps % 200 == 0) {
      state.PauseTiming();
      sim.setState(start, start, 0.0, 0);
      state.ResumeTiming();
    }
    sim.step();
    if (contact) active += double(contact->counters().activeElements) / contact->counters().elements;
    benchmark::DoNotOptimize(sim.current().data());
  }
  if (sim.status() != bsdeform::Status::Ok) state.SkipWithError("simulation diverged");
  if (contact) {
    const auto& c = contact->counters();
    state.counters["active"] = active / double(steps);
    state.counters["refs/step"] = double(c.references) / double(steps);
    state.counters["queries/step"] = double(c.pointQueries) / double(steps);
  }
}

// On the sphere: the apex half the thickness deep in the contact layer.
void CollisionStep(benchmark::State& state) { steps(state, 0.5 * kThickness); }
// Approaching: the cloth 10 thicknesses above the apex (no contact yet, the obstacle near).
void CollisionStepApproach(benchmark::State& state) { steps(state, 10.0 * kThickness); }

}  // namespace

BENCHMARK(CollisionStepApproach)->Args({64, 0})->Args({64, 100000})->Unit(benchmark::kMicrosecond);
BENCHMARK(CollisionStep)
    ->ArgsProduct({{64}, {0, 1000, 10000, 100000}})
    ->Args({128, 0})
    ->Args({128, 100000})
    ->Args({256, 0})
    ->Args({256, 1000})
    ->Args({256, 100000})
    ->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
