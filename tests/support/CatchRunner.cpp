// SPDX-License-Identifier: MIT
// Catch2's implementation, compiled once for every test program (the object library
// bsdeform_catch_runner): each program's copy took 17 s of a cold build. Each program's main is
// tests/main.cpp, which calls runCatch.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include "CatchRunner.h"

int bsdeform::test::runCatch(int argc, char* argv[]) { return Catch::Session().run(argc, argv); }
