// SPDX-License-Identifier: MIT
#pragma once

namespace bsdeform::test {
/// Runs Catch2's session on the command line (support/CatchRunner.cpp, compiled once).
int runCatch(int argc, char* argv[]);
}  // namespace bsdeform::test
