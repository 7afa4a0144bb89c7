// SPDX-License-Identifier: MIT
// Catch2's implementation, compiled once for every test program (the object library
// bsdeform_catch_runner): each program's copy took 17 s of a cold build. Each program's main is
// tests/main.cpp, which calls runCatch.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include <cstring>
#include <iostream>

#include "CatchRunner.h"

namespace {

/// Catch2 2.13's console reporter indents the lines of a test case's name after its first ": "
/// by that colon's column. A name whose first ": " is near the console's width (79) sends the
/// reporter into an endless loop when the case fails: it printed a line of one word for ever,
/// and under ctest, which keeps every line, took 24 GB before the kernel killed it. Such a name
/// is refused: every run of the program fails, naming it, before any case runs (listing the
/// cases, as CTest does at build time, still works, so that every case stays a CTest entry).
constexpr std::size_t kLastColonColumn = 58;

bool namesFitTheReporter() {
  bool ok = true;
  for (const Catch::TestCase& t : Catch::getRegistryHub().getTestCaseRegistry().getAllTests()) {
    const std::size_t colon = t.name.find(": ");
    if (colon != std::string::npos && colon > kLastColonColumn) {
      std::cerr << t.lineInfo << ": the test case name \"" << t.name << "\" has its first \": \" at column "
                << colon << ", beyond " << kLastColonColumn
                << " (Catch2's reporter loops without end on it when the case fails): move it earlier\n";
      ok = false;
    }
  }
  return ok;
}

}  // namespace

int bsdeform::test::runCatch(int argc, char* argv[]) {
  bool listing = false;
  for (int i = 1; i < argc; ++i) listing = listing || std::strncmp(argv[i], "--list", 6) == 0;
  if (!listing && !namesFitTheReporter()) return 2;
  return Catch::Session().run(argc, argv);
}
