// SPDX-License-Identifier: MIT
#include "FrameClock.h"

#include <algorithm>
#include <cmath>

namespace bsdeform {

FrameClock::FrameClock(double fps, double startTime) : m_fps(fps), m_origin(startTime), m_last(startTime) {}

double FrameClock::nextTime() const { return m_origin + double(m_sinceOrigin) / m_fps; }

long FrameClock::due(double time, long maxFrames) {
  if (time < m_last) {  // a reset: go on from the new time
    m_origin = time;
    m_sinceOrigin = 0;
  }
  m_last = time;
  const double tolerance = 1e-9 * std::max(1.0, std::abs(time));
  long n = 0;
  while (n < maxFrames && nextTime() <= time + tolerance) {
    ++n;
    ++m_sinceOrigin;
  }
  if (nextTime() <= time) {  // more than maxFrames: skip ahead
    m_origin = time;
    m_sinceOrigin = 1;
  }
  m_frames += n;
  return n;
}

}  // namespace bsdeform
