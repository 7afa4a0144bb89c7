// SPDX-License-Identifier: MIT
#pragma once
// A PNG file read back with libpng, for the tests of the pictures the front ends write.
#include <string>
#include <vector>

namespace testsupport {

struct Picture {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;  ///< RGB24, rows top to bottom
};

/// Reads `path` as 8-bit RGB (the test fails when it cannot).
Picture readPng(const std::string& path);

}  // namespace testsupport
