// SPDX-License-Identifier: MIT
#pragma once
/// @file TimelinePanel.h
/// The timeline strip under the 3D view: a slider over the kept states (Timeline.h), dragging
/// it shows each state (the simulation pauses there); a Replay button plays the kept states
/// forward at the clock's speed without stepping; the label gives the time shown, the newest
/// time and the count, the slider's tool tip the memory they take against the budget.

#include <QElapsedTimer>
#include <QWidget>
#include <functional>

class QLabel;
class QSlider;
class QTimer;
class QToolButton;

namespace bsdeform {

class Timeline;

class TimelinePanel : public QWidget {
  Q_OBJECT
 public:
  /// `speed`: simulated seconds per wall-clock second of a replay (the clock's speed box).
  TimelinePanel(Timeline& timeline, std::function<double()> speed, QWidget* parent = nullptr);

  QSlider* slider() const { return m_slider; }
  /// "t = 1.25 s of 4 s · 40 states" (tests read it as the user does).
  QString label() const;
  /// The memory line of the tool tip: states kept, bytes against the budget, thinning.
  QString memoryText() const;
  bool isReplaying() const;
  /// Starts or stops the replay (a replay at the newest state starts from the first).
  void setReplaying(bool on);

 private:
  void refresh();
  void tick();
  Timeline& m_timeline;
  std::function<double()> m_speed;
  QSlider* m_slider = nullptr;
  QLabel* m_label = nullptr;
  QToolButton* m_replay = nullptr;
  QTimer* m_timer = nullptr;
  QElapsedTimer m_wall;
  bool m_refreshing = false;
};

}  // namespace bsdeform
