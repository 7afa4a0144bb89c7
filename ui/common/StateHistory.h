// SPDX-License-Identifier: MIT
#pragma once
/// @file StateHistory.h
/// The states of a scene's surfaces at a series of common times, in bounded memory: the
/// viewer's timeline keeps what it has shown in one, bsdeform-run --keep-states what it writes.
///
/// The bound: bytes() never exceeds budget() once three frames are kept (a single frame larger
/// than a third of the budget is still kept, with the first and the newest). When an append
/// goes over it, the older half is thinned: every second frame between the first and the
/// middle is dropped, as often as needed. So the whole run stays reachable, the first state
/// exactly and the recent past at full resolution; the older a stretch, the coarser.

#include <cstddef>
#include <vector>

#include "bsdeform/dynamics/SimulationState.h"

namespace bsdeform {

/// The surfaces' states at one time (one per surface, in the scene's order).
struct StateFrame {
  double time = 0.0;  ///< the largest simulated time among the surfaces
  long steps = 0;     ///< the surfaces' steps, summed: with `time` it orders the frames (a
                      ///< Step of a scene whose time steps differ can leave the largest time as it was)
  std::vector<SimulationState> surfaces;
};

/// Whether `a` comes before `b`: an earlier time, or the same time and fewer steps.
inline bool comesBefore(const StateFrame& a, const StateFrame& b) {
  return a.time < b.time || (a.time == b.time && a.steps < b.steps);
}

/// The frame of `states` (one per surface, in order) at the largest of their times, with the
/// sum of their step counts.
StateFrame frameOf(std::vector<SimulationState> states);
/// Bytes a frame holds (its states and its own size).
std::size_t bytesOf(const StateFrame& frame);

class StateHistory {
 public:
  /// 256 MiB: at 60 frames per second, 11 minutes of a 20 × 20 net before any thinning.
  static constexpr std::size_t kDefaultBudget = std::size_t(256) << 20;

  explicit StateHistory(std::size_t budget = kDefaultBudget) : m_budget(budget) {}

  /// Appends `frame` (normally after the last one, comesBefore(); an earlier or equal frame
  /// replaces the frames from there on), then thins while over the budget.
  void append(StateFrame frame);
  /// Removes and returns the frames after `index` (a branch that is discarded).
  std::vector<StateFrame> takeAfter(int index);
  /// Appends `frames` after the last frame (a branch put back), thinning as append() does.
  void appendAll(std::vector<StateFrame> frames);
  void clear();

  /// Sets the byte budget (thins at once when the frames exceed it).
  void setBudget(std::size_t bytes);
  std::size_t budget() const { return m_budget; }
  std::size_t bytes() const { return m_bytes; }
  /// Times the older half was thinned since the last clear().
  int thinnings() const { return m_thinnings; }

  int size() const { return int(m_frames.size()); }
  bool isEmpty() const { return m_frames.empty(); }
  const StateFrame& operator[](int index) const { return m_frames[std::size_t(index)]; }
  const StateFrame& back() const { return m_frames.back(); }
  /// The last frame at or before `time` (-1 when every frame is later).
  int indexAt(double time) const;
  /// The last frame that is `frame` or comes before it (-1 when every frame comes after).
  int indexOf(const StateFrame& frame) const;

 private:
  void thinWhileOver();
  std::vector<StateFrame> m_frames;
  std::size_t m_budget;
  std::size_t m_bytes = 0;
  int m_thinnings = 0;
};

}  // namespace bsdeform
