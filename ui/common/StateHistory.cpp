// SPDX-License-Identifier: MIT
#include "StateHistory.h"

#include <algorithm>
#include <iterator>

namespace bsdeform {

StateFrame frameOf(std::vector<SimulationState> states) {
  StateFrame frame{states.empty() ? 0.0 : states.front().time, 0, std::move(states)};
  for (const SimulationState& s : frame.surfaces) {
    frame.time = std::max(frame.time, s.time);
    frame.steps += s.steps;
  }
  return frame;
}

std::size_t bytesOf(const StateFrame& frame) {
  std::size_t bytes = sizeof(StateFrame);
  for (const SimulationState& s : frame.surfaces) bytes += bytesOf(s);
  return bytes;
}

void StateHistory::append(StateFrame frame) {
  if (!m_frames.empty() && !comesBefore(m_frames.back(), frame)) {  // the frames from it on are replaced
    const auto from = std::lower_bound(m_frames.begin(), m_frames.end(), frame, comesBefore);
    takeAfter(int(from - m_frames.begin()) - 1);
  }
  m_bytes += bytesOf(frame);
  m_frames.push_back(std::move(frame));
  thinWhileOver();
}

std::vector<StateFrame> StateHistory::takeAfter(int index) {
  const auto first = m_frames.begin() + std::max(0, std::min(index + 1, size()));
  std::vector<StateFrame> taken(std::make_move_iterator(first), std::make_move_iterator(m_frames.end()));
  m_frames.erase(first, m_frames.end());
  for (const StateFrame& f : taken) m_bytes -= bytesOf(f);
  return taken;
}

void StateHistory::appendAll(std::vector<StateFrame> frames) {
  for (StateFrame& f : frames) append(std::move(f));
}

void StateHistory::clear() {
  m_frames.clear();
  m_bytes = 0;
  m_thinnings = 0;
}

void StateHistory::setBudget(std::size_t bytes) {
  m_budget = bytes;
  thinWhileOver();
}

int StateHistory::indexAt(double time) const {
  const auto after = std::upper_bound(m_frames.begin(), m_frames.end(), time,
                                      [](double t, const StateFrame& f) { return t < f.time; });
  return int(after - m_frames.begin()) - 1;
}

int StateHistory::indexOf(const StateFrame& frame) const {
  return int(std::upper_bound(m_frames.begin(), m_frames.end(), frame, comesBefore) - m_frames.begin()) - 1;
}

// Every second frame of the older half goes, the first one stays: frames 1, 3, 5, ... below
// size() / 2. The newer half is untouched, so the recent past keeps every frame.
void StateHistory::thinWhileOver() {
  while (m_bytes > m_budget && m_frames.size() >= 3) {
    const std::size_t half = std::max<std::size_t>(2, m_frames.size() / 2);
    std::size_t kept = 1;
    for (std::size_t i = 1; i < m_frames.size(); ++i) {
      if (i < half && i % 2 == 1) {
        m_bytes -= bytesOf(m_frames[i]);
        continue;
      }
      if (kept != i) m_frames[kept] = std::move(m_frames[i]);
      ++kept;
    }
    m_frames.resize(kept);
    ++m_thinnings;
  }
}

}  // namespace bsdeform
