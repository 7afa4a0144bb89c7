// SPDX-License-Identifier: MIT
#pragma once
/// @file Timeline.h
/// The states the viewer has shown, to scrub back to and replay: after every turn of the event
/// loop in which a surface stepped, the state of every surface of the scene (all at the clock's
/// common time) is kept in a StateHistory (bounded memory, older states thinned: StateHistory.h).
///
/// - showFrame() puts a kept state back into every surface (SoBSplineDeformSurface::restoreState:
///   the same bits, the models stay); the window pauses first (aboutToRestore()).
/// - Stepping on from an earlier state (Play, Step, a drag) discards the later states as one
///   command on the window's undo stack (DiscardBranchCommand): Undo brings them back and shows
///   the state they branched from, Redo swaps the branches again.
/// - A state replaced otherwise (Reset, Solve Static, a model rebuilt from rest, another scene,
///   a surface added or deleted) starts the timeline again from the state then.
/// - load() takes the states of a bsdeform-run --keep-states file (StateFile.h).

#include <QObject>
#include <QVector>
#include <utility>
#include <vector>

#include "StateFile.h"
#include "StateHistory.h"
#include "bsdeform/dynamics/Diagnostics.h"
#include "bsdeform/SoBSplineDeformSurface.h"

class QUndoStack;

namespace bsdeform {

class Timeline : public QObject {
  Q_OBJECT
 public:
  explicit Timeline(QUndoStack& undo, QObject* parent = nullptr);

  /// The scene's surfaces, in order (SceneDocument::surfaces()): a different list starts the
  /// timeline again from their state now.
  void setSurfaces(const QVector<SoBSplineDeformSurface*>& surfaces);
  /// What a surface told (SurfaceListener::surfaceEvent); nothing is kept here, see capture().
  void surfaceEvent(SoBSplineDeformSurface* surface, SoBSplineDeformSurface::Event e);
  /// Keeps the surfaces' state when they stepped since the last call (SurfaceListener::changed,
  /// once per turn of the event loop, after every surface has reached the clock's time).
  void capture();

  const StateHistory& history() const { return m_history; }
  /// The kept state shown (history().size() - 1 while the simulation runs at its newest state).
  int position() const { return m_position; }
  bool isAtEnd() const { return m_position == m_history.size() - 1; }
  /// Puts kept state `index` back into every surface. False (and `error()`) when a surface
  /// refuses it; nothing has changed then.
  bool showFrame(int index);
  /// While the timeline puts a state back (the surfaces tell STATE_CHANGED: not a reset).
  bool isRestoring() const { return m_restoring; }

  /// Replay: shows the kept states forward from the position, `seconds` of simulated time
  /// further on (the last state at or before that time). False once the last state is shown.
  bool advanceReplay(double seconds);

  /// The diagnostics of surface `index` (m_surfaces' order) in every kept state after `time`,
  /// with their times: what its plots show of the kept branch. Computed by putting each state
  /// back (as a scrub does, without telling a reset) and the shown state back at the end.
  std::vector<std::pair<double, Diagnostics>> diagnosticsAfter(int index, double time);

  /// Memory budget of the kept states, in bytes (StateHistory::kDefaultBudget unless set).
  void setBudget(std::size_t bytes);

  /// The surfaces as a state file names them (DEF names, net sizes), in order.
  std::vector<StateFileSurface> fileSurfaces();
  /// Replaces the kept states by those of a state file read from `path` and shows its last one.
  /// A file that does not fit the scene (surface names, order, net sizes, a state a surface
  /// refuses) changes nothing: false, and error() names the file, the entry and the value.
  bool load(const QString& path, const StateFileContents& contents);
  const QString& error() const { return m_error; }

 signals:
  /// Before a kept state is put back: the window pauses and lets go of a drag.
  void aboutToRestore();
  /// The kept states or the position changed; `time` is the position's.
  void changed(double time);
  /// Undo or Redo swapped the states after `time` for another branch (before the new
  /// position is shown): the plots take that branch's values (diagnosticsAfter()).
  void branchSwapped(double time);

 private:
  friend class DiscardBranchCommand;
  void restart();
  StateFrame frameNow();
  /// Puts `frame` back into every surface (all or none).
  bool restore(const StateFrame& frame, const QString& source);
  void emitChanged();

  QUndoStack& m_undo;
  QVector<SoBSplineDeformSurface*> m_surfaces;
  StateHistory m_history;
  int m_position = -1;
  bool m_stepped = false;         ///< a surface stepped since the last capture()
  bool m_restartPending = false;  ///< a state was replaced (not by the timeline)
  bool m_restoring = false;
  int m_generation = 0;           ///< counts restarts: a command of an older timeline does nothing
  double m_replayTime = 0.0;
  QString m_error;
};

}  // namespace bsdeform
