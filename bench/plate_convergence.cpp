// SPDX-License-Identifier: MIT
// Convergence of the engineering edges (issue 23, docs/math.md §14): prints the Markdown tables
// of docs/math.md and the README. The paper's energy with w10 = w01 = 0 and w20 = w02 = w11 = D
// is the Kirchhoff plate D lap^2 w = q (Poisson's ratio 0), solved with Simulation::solveStatic:
//   - the clamped square plate (centre, against 0.0012653190878 q a^4 / D: Timoshenko's
//     0.00126532 to the ten digits of Taylor & Govindjee's series solution, which every
//     BUILT_IN degree >= 4 here reproduces to 1e-11),
//   - the simply supported one (centre, against Navier's series, summed here),
//   - the cantilever strip (tip, against the beam's q L^4 / (8 D)).
// Each cell: the relative error |w_N / w - 1| and, after the first column, the observed order
// log2(e_{N/2} / e_N). N free control points per side, degrees 2..5.
//   bsdeform-plate-convergence [maxN]   (default 128)
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <vector>

#include "bsdeform/dynamics/Simulation.h"

using namespace bsdeform;

namespace {
double navier() {
  const double pi = 3.14159265358979323846;
  double sum = 0.0;
  for (int m = 1; m < 2001; m += 2)
    for (int n = 1; n < 2001; n += 2)
      sum += (((m + n) / 2 - 1) % 2 ? -1.0 : 1.0) / (double(m) * n * std::pow(double(m) * m + double(n) * n, 2));
  return 16.0 / std::pow(pi, 6) * sum;
}

double deflection(Boundary side, int degree, int N, bool cantilever) {
  ModelParameters p;
  p.degreeU = p.degreeV = degree;
  p.numU = p.numV = N;
  p.weights = Weights{0.0, 0.0, 1.0, 1.0, 1.0};
  p.boundaries = cantilever ? Boundaries{side, Boundary::Free, Boundary::Free, Boundary::Free} : Boundaries{side, side, side, side};
  Simulation sim(p);
  sim.addForce(std::make_shared<DistributedForce>(Eigen::Vector3d(0, 0, 1)));
  const StaticResult r = sim.solveStatic();
  return sim.space().evaluate(r.net, cantilever ? 1.0 : 0.5, 0.5, 0).position.z();
}

void table(const char* title, Boundary side, bool cantilever, double exact, int maxN) {
  std::printf("\n%s (reference %.10g)\n\n| degree |", title, exact);
  std::vector<int> Ns;
  for (int N = 8; N <= maxN; N *= 2) Ns.push_back(N);
  for (int N : Ns) std::printf(" N = %d |", N);
  std::printf("\n|---|");
  for (size_t i = 0; i < Ns.size(); ++i) std::printf("---|");
  std::printf("\n");
  for (int n = 2; n <= 5; ++n) {
    std::printf("| %d |", n);
    double prev = 0.0;
    for (int N : Ns) {
      const double e = std::abs(deflection(side, n, N, cantilever) / exact - 1.0);
      if (prev > 0.0 && e > 0.0)
        std::printf(" %.2e (%.2f) |", e, std::log2(prev / e));
      else
        std::printf(" %.2e |", e);
      prev = e;
      std::fflush(stdout);
    }
    std::printf("\n");
  }
}
}  // namespace

int main(int argc, char** argv) {
  const int maxN = argc > 1 ? std::atoi(argv[1]) : 128;
  const double clamped = 0.0012653190878, supported = navier();
  table("Clamped square plate, paper's CLAMPED", Boundary::Clamped, false, clamped, maxN);
  table("Clamped square plate, BUILT_IN", Boundary::BuiltIn, false, clamped, maxN);
  table("Simply supported square plate, SIMPLY_SUPPORTED", Boundary::SimplySupported, false, supported, maxN);
  table("Cantilever tip, BUILT_IN", Boundary::BuiltIn, true, 0.125, maxN);
  table("Cantilever tip, paper's CLAMPED", Boundary::Clamped, true, 0.125, maxN);
  return 0;
}
