// SPDX-License-Identifier: MIT
#pragma once
/// @file FrameClock.h
/// Which frames of a recording fall due: one at the start time and one at every 1/fps of
/// simulated time after it (bsdeform-run's --video and the viewer's Record). A step that
/// crosses several frame times makes several frames due (the same picture repeats: the
/// video's clock is the simulation's); time going back (a Reset) starts over from the new time.

namespace bsdeform {

class FrameClock {
 public:
  FrameClock() = default;
  /// A clock whose first frame falls due at `startTime`. `fps` > 0.
  FrameClock(double fps, double startTime);

  /// The frames due by `time` that were not counted before (at most `maxFrames`: after a jump
  /// longer than that the clock skips ahead, the next frame falls due 1/fps after `time`).
  /// Frame times are start + k / fps; a time within 1e-9 relative of one counts as reaching it.
  long due(double time, long maxFrames = kUnlimited);

  /// Frames counted since the clock was made.
  long long frames() const { return m_frames; }
  /// The time at which the next frame falls due.
  double nextTime() const;

  static constexpr long kUnlimited = 0x7fffffffL;

 private:
  double m_fps = 1.0;
  double m_origin = 0.0;   ///< frame times since the last start or reset: m_origin + k / m_fps
  long long m_sinceOrigin = 0;
  double m_last = 0.0;     ///< the latest time asked about (a smaller one is a reset)
  long long m_frames = 0;
};

}  // namespace bsdeform
