// SPDX-License-Identifier: MIT
#pragma once
/// @file VideoWriter.h
/// Frames of the 3D view into a video file through FFmpeg's libraries (libavformat,
/// libavcodec, libswscale): H.264 in MP4 or VP9 in WebM, chosen by the file's extension.
/// All or nothing, like every file the front ends write: the video is encoded into a temporary
/// file beside the target and renamed over it only when the whole file was written and synced;
/// on any failure (a full disk included) the previous file is untouched.

#include <memory>
#include <string>

namespace bsdeform {

class VideoWriter {
 public:
  /// Opens a video of `width` x `height` pixels at `fps` frames per second. The container and
  /// codec follow the extension: ".mp4" (H.264, libx264, CRF 18, yuv420p) or ".webm" (VP9,
  /// libvpx, realtime). H.264 and VP9 in 4:2:0 need even sizes: an odd width or height drops
  /// the last column or row of each frame. Returns null and sets `error` (naming the file) when
  /// the extension, the size, the rate or the encoder is not usable.
  static std::unique_ptr<VideoWriter> open(const std::string& path, int width, int height, double fps,
                                           std::string& error);
  ~VideoWriter();  ///< removes the temporary file unless finish() succeeded
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  /// Encodes one frame: `rgb` holds width x height pixels, 3 bytes each, rows top-down, each
  /// row `rowBytes` after the previous (0: packed, 3 x the width given to open()).
  bool addFrame(const unsigned char* rgb, std::string& error, int rowBytes = 0);
  /// Flushes the encoder, writes the trailer, syncs and renames into place. The writer cannot
  /// be used afterwards.
  bool finish(std::string& error);

  int width() const;   ///< of the encoded frames (even)
  int height() const;
  long long frames() const;  ///< added so far
  const std::string& path() const;

 private:
  VideoWriter();
  struct Impl;
  std::unique_ptr<Impl> m;
};

}  // namespace bsdeform
