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

/// Catch2 2.13's console reporter indents the wrapped lines of a test case's name by the offset
/// of its first ": " plus 2, within 79 columns: from an offset of 76 the text column is one
/// character wide or less and the reporter loops for ever when the case fails (it printed a
/// line of one word without end, and under ctest, which keeps every line, took 24 GB before the
/// kernel killed it). Such a name is refused: every run of the program fails, naming it, before
/// any case runs (listing the cases, as CTest does at build time, and --help still work, so
/// that every case stays a CTest entry). The limit, 58, leaves room to spare and keeps the
/// wrapped lines readable; SECTION names (indented 2 more) are not checked.
constexpr std::size_t kLastColonColumn = 58;

bool namesFitTheReporter() {
  bool ok = true;
  for (const Catch::TestCase& t : Catch::getRegistryHub().getTestCaseRegistry().getAllTests()) {
    const std::size_t colon = t.name.find(": ");
    if (colon != std::string::npos && colon > kLastColonColumn) {
      std::cerr << t.lineInfo << ": the test case name \"" << t.name << "\" has its first \": \" at offset "
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
  for (int i = 1; i < argc; ++i)
    listing = listing || std::strncmp(argv[i], "--list", 6) == 0 || std::strcmp(argv[i], "--help") == 0 ||
              std::strcmp(argv[i], "-h") == 0 || std::strcmp(argv[i], "-?") == 0;
  if (!listing && !namesFitTheReporter()) return 2;
  return Catch::Session().run(argc, argv);
}
