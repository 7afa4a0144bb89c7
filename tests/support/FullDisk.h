// SPDX-License-Identifier: MIT
#pragma once
// A full disk under one directory for the lifetime of a FullDisk, through the preloaded
// tests/support/enospc_shim.c (set by CTest for the test executables that use it).
#include <catch2/catch.hpp>
#include <cstdlib>
#include <string>

namespace testsupport {

struct FullDisk {
  /// The disk under `dir` is full after `after` more bytes.
  explicit FullDisk(const std::string& dir, long after = 0) {
    const char* preload = std::getenv("LD_PRELOAD");
    INFO("tests/support/enospc_shim.c must be preloaded (LD_PRELOAD, set by CTest)");
    REQUIRE((preload && std::string(preload).find("enospc") != std::string::npos));
    setenv("BSDEFORM_ENOSPC_DIR", dir.c_str(), 1);
    setenv("BSDEFORM_ENOSPC_AFTER", std::to_string(after).c_str(), 1);
  }
  ~FullDisk() {
    unsetenv("BSDEFORM_ENOSPC_DIR");
    unsetenv("BSDEFORM_ENOSPC_AFTER");
  }
  FullDisk(const FullDisk&) = delete;
  FullDisk& operator=(const FullDisk&) = delete;
};

}  // namespace testsupport
