// SPDX-License-Identifier: MIT
#pragma once
/// @file SimulationControls.h
/// The Simulation menu's commands with their actions and the tool bar's speed box: Play /
/// Pause and the speed drive the ViewerClock, and through Coin's realTime every surface, never
/// the surfaces' `on` or `speed`; Step (SceneRunner: every surface to the time of the smallest
/// step), Reset and Solve Static (undoable).

#include <QObject>

class QAction;
class QDoubleSpinBox;
class QUndoStack;

namespace bsdeform {

class DragTool;
class Feedback;
class ViewerClock;
struct EditContext;

class SimulationControls : public QObject {
  Q_OBJECT
 public:
  /// `edit` and `undo`: where Solve Static's command goes.
  SimulationControls(EditContext& edit, QUndoStack& undo, DragTool& drag, Feedback& feedback, QObject* parent = nullptr);

  /// The clock that drives realTime.
  ViewerClock& clock() { return *m_clock; }

  /// The actions, for the window's menu and tool bar. Play / Pause (Space) is checked while
  /// playing, its text the command it would give.
  QAction* playAction() const { return m_playAction; }
  QAction* stepAction() const { return m_stepAction; }
  QAction* resetAction() const { return m_resetAction; }
  QAction* solveStaticAction() const { return m_solveStaticAction; }
  /// Simulated seconds per real second (the clock's speed, not written to the scene file); a
  /// widget without a parent for the tool bar to take.
  QDoubleSpinBox* speedBox() const { return m_speed; }

  bool isPlaying() const;
  void setPlaying(bool on);
  /// Sets the speed box, and through it the clock.
  void setSpeed(double speed);
  /// Pauses, then one step of the smallest time step, every surface to that common time.
  void step();
  /// Every surface back to its rest state (the clock keeps playing or not).
  void reset();
  /// Every surface to the equilibrium of its loads (undoable); false and a reported error if
  /// one cannot be solved (nothing changes then).
  bool solveStatic();

 signals:
  /// After setPlaying(), also when it did not change.
  void playingSet(bool playing);

 private:
  void createActions();

  EditContext& m_edit;
  QUndoStack& m_undo;
  DragTool& m_drag;
  Feedback& m_feedback;
  /// True (and says so in the status bar) while a node of the scene refuses a value.
  bool refusesToRun();
  ViewerClock* m_clock;
  QAction* m_playAction = nullptr;
  QAction* m_stepAction = nullptr;
  QAction* m_resetAction = nullptr;
  QAction* m_solveStaticAction = nullptr;
  QDoubleSpinBox* m_speed = nullptr;
};

}  // namespace bsdeform
