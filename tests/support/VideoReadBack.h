// SPDX-License-Identifier: MIT
#pragma once
// A video file read back with FFmpeg's libraries, for the tests of what the front ends record.
#include <string>
#include <vector>

namespace testsupport {

struct ReadBack {
  std::string codec;  ///< FFmpeg's name: "h264", "vp9"
  int width = 0, height = 0, frames = 0;  ///< frames: packets of the video stream
  double fps = 0.0;   ///< the stream's average frame rate
  std::vector<std::vector<unsigned char>> rgb;  ///< every decoded frame, RGB24 top-down
};

/// Reads and decodes every frame of the first video stream (the test fails when it cannot).
ReadBack readVideo(const std::string& path);

}  // namespace testsupport
