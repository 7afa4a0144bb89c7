// SPDX-License-Identifier: MIT
// The core tests run with floating-point traps on in Debug builds (tests/main.cpp), so a NaN or a
// division by zero in our numerics stops the test where it happens.
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <csignal>
#include <memory>

#include "bsdeform/dynamics/Simulation.h"
#include "../support/FpTraps.h"

using namespace bsdeform;
using bsdeform::test::enabledFpTraps;
using bsdeform::test::kTrappedFpExceptions;

TEST_CASE("FP traps: the core steps with invalid and divide-by-zero trapping (Debug builds)", "[core]") {
  ModelParameters p;
  p.numU = p.numV = 6;
  Simulation sim(p);
  // a force called by the core inside every (sub-)step records the trap mask it runs under
  auto seen = std::make_shared<int>(-1);
  sim.addForce(std::make_shared<PointForce>(
      0.5, 0.5,
      [seen](const SurfaceSample&) {
        *seen = enabledFpTraps();
        return Eigen::Vector3d(0, 0, 1);
      },
      kDependsOnTime));
  sim.advance(3);
  CHECK(sim.status() == Status::Ok);
  CHECK(*seen == kTrappedFpExceptions);
}

TEST_CASE("FP traps: 0/0 in the core test process raises SIGFPE (Debug builds)", "[core]") {
  const pid_t pid = fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    volatile double zero = 0.0;
    volatile double nan = zero / zero;
    (void)nan;
    _exit(0);
  }
  int status = 0;
  REQUIRE(waitpid(pid, &status, 0) == pid);
  if (kTrappedFpExceptions != 0) {
    CHECK(WIFSIGNALED(status));
    CHECK(WTERMSIG(status) == SIGFPE);
  } else {
    // release builds: no traps, the NaN is just a value
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 0);
  }
}
