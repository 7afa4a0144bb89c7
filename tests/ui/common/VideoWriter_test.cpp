// SPDX-License-Identifier: MIT
// VideoWriter: the files read back with libavformat/libavcodec (container, codec, size, frame
// count, the pictures themselves), atomic replacement, and a full disk (enospc_shim preloaded).
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <unistd.h>
#include <fstream>
#include <iterator>
#include <vector>

#include "../../support/FullDisk.h"
#include "../../support/VideoReadBack.h"
#include "VideoWriter.h"

namespace fs = std::filesystem;
using bsdeform::VideoWriter;
using testsupport::readVideo;
using testsupport::ReadBack;

namespace {

/// A smooth picture that moves with `k`: a colour gradient and a bright disc.
std::vector<unsigned char> picture(int w, int h, int k) {
  std::vector<unsigned char> rgb(size_t(w) * h * 3);
  const double cx = w * (0.2 + 0.6 * (k % 10) / 10.0), cy = h * 0.5, r = h * 0.25;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      unsigned char* p = &rgb[(size_t(y) * w + x) * 3];
      const bool disc = (x - cx) * (x - cx) + (y - cy) * (y - cy) < r * r;
      p[0] = disc ? 240 : (unsigned char)(40 + 150 * x / w);
      p[1] = disc ? 220 : (unsigned char)(60 + 120 * y / h);
      p[2] = disc ? 60 : 130;
    }
  return rgb;
}

/// Mean absolute difference per channel over the w x h pixels of a (row length aw) and b.
double meanDifference(const std::vector<unsigned char>& a, int aw, const std::vector<unsigned char>& b, int w, int h) {
  double sum = 0.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < 3 * w; ++x) sum += std::abs(int(a[size_t(y) * aw * 3 + x]) - int(b[size_t(y) * w * 3 + x]));
  return sum / (3.0 * w * h);
}

std::vector<std::string> entries(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  return names;
}

struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("bsdeform_video_" + std::to_string(::getpid()) + "_" + std::to_string(counter()++));
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  static int& counter() {
    static int n = 0;
    return n;
  }
};

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

}  // namespace

TEST_CASE("VideoWriter: MP4 (H.264) and WebM (VP9) read back with every frame, the size, the rate and the pictures", "[ui]") {
  for (const char* ext : {".mp4", ".webm"}) {
    TempDir dir;
    const std::string path = (dir.path / (std::string("run") + ext)).string();
    // an odd size: the last column and row are dropped
    const int w = 97, h = 63, frames = 25;
    std::string error;
    auto video = VideoWriter::open(path, w, h, 12.5, error);
    INFO(ext << ": " << error);
    REQUIRE(video);
    CHECK(video->width() == 96);
    CHECK(video->height() == 62);
    for (int k = 0; k < frames; ++k) REQUIRE(video->addFrame(picture(w, h, k).data(), error));
    REQUIRE(video->finish(error));
    CHECK(entries(dir.path) == std::vector<std::string>{std::string("run") + ext});  // no temporary file
    const ReadBack back = readVideo(path);
    CHECK(back.codec == (std::string(ext) == ".mp4" ? "h264" : "vp9"));
    CHECK(back.width == 96);
    CHECK(back.height == 62);
    CHECK(back.frames == frames);
    CHECK(back.fps == Approx(12.5));
    REQUIRE(back.rgb.size() == size_t(frames));
    // each decoded frame is its own picture (4:2:0 and lossy coding: a few levels), not another
    for (int k : {0, 7, frames - 1}) {
      CHECK(meanDifference(picture(w, h, k), w, back.rgb[size_t(k)], 96, 62) < 4.0);
      CHECK(meanDifference(picture(w, h, k + 3), w, back.rgb[size_t(k)], 96, 62) > 8.0);
    }
  }
}

TEST_CASE("VideoWriter: bad requests are refused with the file and the reason, nothing written", "[ui]") {
  TempDir dir;
  std::string error;
  CHECK_FALSE(VideoWriter::open((dir.path / "clip.avi").string(), 64, 48, 30, error));
  CHECK(error.find("clip.avi") != std::string::npos);
  CHECK(error.find(".avi") != std::string::npos);
  CHECK_FALSE(VideoWriter::open((dir.path / "clip.mp4").string(), 1, 48, 30, error));
  CHECK(error.find("1 x 48") != std::string::npos);
  CHECK_FALSE(VideoWriter::open((dir.path / "clip.mp4").string(), 64, 48, 0.0, error));
  CHECK(error.find("frame rate") != std::string::npos);
  CHECK_FALSE(VideoWriter::open((dir.path / "no" / "such" / "clip.mp4").string(), 64, 48, 30, error));
  CHECK(error.find("clip.mp4") != std::string::npos);
  CHECK(entries(dir.path).empty());
}

TEST_CASE("VideoWriter: the previous video stays until the new one is complete", "[ui]") {
  TempDir dir;
  const fs::path path = dir.path / "take.mp4";
  { std::ofstream(path) << "the user's previous video"; }
  std::string error;
  {
    auto video = VideoWriter::open(path.string(), 64, 48, 30, error);
    REQUIRE(video);
    for (int k = 0; k < 5; ++k) REQUIRE(video->addFrame(picture(64, 48, k).data(), error));
    CHECK(slurp(path) == "the user's previous video");  // while recording
  }  // abandoned without finish(): nothing replaced, no temporary file left
  CHECK(slurp(path) == "the user's previous video");
  CHECK(entries(dir.path) == std::vector<std::string>{"take.mp4"});

  // a full disk part way: an error naming the file and the reason, the old file kept
  {
    testsupport::FullDisk full(dir.path.string(), 2000);
    auto video = VideoWriter::open(path.string(), 64, 48, 30, error);
    bool ok = static_cast<bool>(video);
    for (int k = 0; ok && k < 60; ++k) ok = video->addFrame(picture(64, 48, k).data(), error);
    if (ok) ok = video->finish(error);
    CHECK_FALSE(ok);
    INFO(error);
    CHECK(error.find("take.mp4") != std::string::npos);
    CHECK(error.find("No space left on device") != std::string::npos);
  }
  CHECK(slurp(path) == "the user's previous video");
  CHECK(entries(dir.path) == std::vector<std::string>{"take.mp4"});
}
