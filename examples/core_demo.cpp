// SPDX-License-Identifier: MIT
// A deformation run of the core engine, printed as a table: the paper's Figure 5 setting
// (bicubic, 6 x 6 free control points, weights 0.1/0.1/0.01/0.01/0.01, Delta t = 0.1) with a
// uniform force density (0, 0, 20) normal to the plane, compared with the static solution.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>

#include "bsdeform/dynamics/Simulation.h"

int main(int argc, char** argv) {
  try {
    bsdeform::ModelParameters p;
    p.numU = p.numV = 6;
    p.damping = 1.0;
    if (argc > 1) p.numU = p.numV = std::atoi(argv[1]);
    bsdeform::Simulation sim(p);
    sim.addForce(std::make_shared<bsdeform::DistributedForce>(Eigen::Vector3d(0, 0, 20)));
    const bsdeform::ControlNet equilibrium = sim.staticSolution();
    const double zStatic = sim.space().evaluate(equilibrium, 0.5, 0.5).position.z();
    std::printf("bsdeform core demo: %dx%d free control points, degree (%d,%d), dt %.3g\n", p.numU, p.numV,
                p.degreeU, p.degreeV, p.timeStep);
    std::printf("stability limit %.4g, %d sub-step(s) per step\n", sim.stabilityLimit(), sim.subSteps());
    std::printf("%8s %12s %12s %12s %12s\n", "t", "z(0.5,0.5)", "norm(15)", "kinetic", "strain");
    for (int i = 0; i <= 300; ++i) {
      if (i % 25 == 0) {
        std::printf("%8.2f %12.6f %12.6f %12.6f %12.6f\n", sim.time(), sim.evaluate(0.5, 0.5).position.z(),
                    sim.deformationNorm(), sim.kineticEnergy(), sim.strainEnergy().total);
      }
      if (sim.step() != bsdeform::Status::Ok) {
        std::fprintf(stderr, "simulation stopped: %s\n", sim.statusMessage().c_str());
        return 2;
      }
    }
    std::printf("static solution z(0.5,0.5) = %.6f\n", zStatic);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bsdeform-core-demo: %s\n", e.what());
    return 1;
  }
}
