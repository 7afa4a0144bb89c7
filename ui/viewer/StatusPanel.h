// SPDX-License-Identifier: MIT
#pragma once
/// @file StatusPanel.h
/// The viewer's status bar: simulated time, steps and frames per second, the model's size and
/// time step, and the simulation's state (running, paused, a refused field, STOPPED when it
/// blew up; SoBSplineDeformSurface::problem() and Simulation::status()). It counts the frames
/// drawn through a node put into the rendered graph.

#include <QCoreApplication>
#include <QElapsedTimer>
#include <QStringList>

class QLabel;
class QStatusBar;
class SoAction;
class SoBSplineDeformSurface;
class SoCallback;
class SoNode;

namespace bsdeform {

class StatusPanel {
  Q_DECLARE_TR_FUNCTIONS(StatusPanel)

 public:
  /// Adds the labels to `bar` as permanent widgets.
  explicit StatusPanel(QStatusBar* bar);
  ~StatusPanel();
  StatusPanel(const StatusPanel&) = delete;
  StatusPanel& operator=(const StatusPanel&) = delete;

  /// Counts a frame each time it is rendered: part of the graph the viewer shows.
  SoNode* frameCounter() const;
  /// Frames drawn since restart().
  long framesDrawn() const { return m_frames; }
  /// A new scene: frames and steps count from 0.
  void restart();
  /// While the timeline replays kept states (speed > 0, simulated seconds per second) the rate
  /// reads "replay N x": no step is taken then, and "0.0 steps/s" said nothing; 0: not replaying.
  void setReplaySpeed(double speed) { m_replaySpeed = speed; }
  /// The steps per second count `surface`'s steps from now (another surface is shown).
  void follow(SoBSplineDeformSurface* surface);
  /// The labels for `surface` (nullptr: only the rates) and the clock's `playing`.
  /// `troubled`: a surface of the scene with a problem when `surface` (the selected one) has
  /// none: the state shows it, red while a value is refused, until it is fixed.
  /// `refused`: every refused value of the scene as "node.field" (or "node" when no one field
  /// is at fault), all named, red, before anything else; `refusedDetails` their reasons.
  void update(SoBSplineDeformSurface* surface, bool playing, SoBSplineDeformSurface* troubled = nullptr,
              const QStringList& refused = QStringList(), const QString& refusedDetails = QString());

 private:
  static void countFrame(void* data, SoAction* action);

  QLabel* m_timeLabel;
  QLabel* m_rateLabel;
  QLabel* m_modelLabel;
  QLabel* m_stateLabel;
  double m_replaySpeed = 0.0;
  SoCallback* m_frameCounter;  ///< ref'ed: it outlives every scene shown
  long m_frames = 0;
  long m_lastFrames = 0, m_lastSteps = 0;
  QElapsedTimer m_rateClock;
  double m_fps = 0.0, m_stepsPerSecond = 0.0;
};

}  // namespace bsdeform
