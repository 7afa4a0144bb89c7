// SPDX-License-Identifier: MIT
#include "SimulationControls.h"

#include <Inventor/nodes/SoSeparator.h>

#include <QAction>
#include <QDoubleSpinBox>
#include <QUndoStack>
#include <vector>

#include "DragTool.h"
#include "EditCommands.h"
#include "Feedback.h"
#include "FieldWidgets.h"
#include "SceneDocument.h"
#include "SceneProblems.h"
#include "ViewerClock.h"
#include "bsdeform/SceneRunner.h"
#include "bsdeform/SoBSplineDeformSurface.h"

namespace bsdeform {

SimulationControls::SimulationControls(EditContext& edit, QUndoStack& undo, DragTool& drag, Feedback& feedback, QObject* parent)
    : QObject(parent), m_edit(edit), m_undo(undo), m_drag(drag), m_feedback(feedback), m_clock(new ViewerClock(this)) {
  createActions();
}

void SimulationControls::createActions() {
  m_playAction = new QAction(tr("Play"), this);
  m_playAction->setCheckable(true);
  m_playAction->setShortcut(QKeySequence(Qt::Key_Space));
  m_playAction->setShortcutContext(Qt::ApplicationShortcut);
  m_playAction->setToolTip(tr("Play / pause (Space)"));
  connect(m_playAction, &QAction::triggered, this, [this](bool on) { setPlaying(on); });
  m_stepAction = new QAction(tr("Step"), this);
  m_stepAction->setShortcut(QKeySequence(tr("S")));
  m_stepAction->setToolTip(tr("One time step (S)"));
  connect(m_stepAction, &QAction::triggered, this, &SimulationControls::step);
  m_resetAction = new QAction(tr("Reset"), this);
  m_resetAction->setShortcut(QKeySequence(tr("R")));
  m_resetAction->setToolTip(tr("Back to the rest state (R)"));
  connect(m_resetAction, &QAction::triggered, this, &SimulationControls::reset);
  m_solveStaticAction = new QAction(tr("Solve S&tatic"), this);
  m_solveStaticAction->setShortcut(QKeySequence(tr("Ctrl+E")));
  m_solveStaticAction->setToolTip(tr("Every surface to the equilibrium of its loads at t = 0, at rest (the paper's A P = L); "
                                     "undo brings the state back (Ctrl+E)"));
  connect(m_solveStaticAction, &QAction::triggered, this, &SimulationControls::solveStatic);
  m_speed = new QDoubleSpinBox;
  m_speed->setRange(0.01, 100.0);
  m_speed->setDecimals(2);
  m_speed->setValue(1.0);
  m_speed->setSuffix(tr(" x"));
  m_speed->setToolTip(tr("Simulated seconds per real second (not written to the scene file)"));
  m_speed->installEventFilter(new SimulationKeysPassThrough(m_speed));
  connect(m_speed, QOverload<double>::of(&QDoubleSpinBox::valueChanged), m_clock, &ViewerClock::setSpeed);
}

bool SimulationControls::isPlaying() const { return m_clock->isPlaying(); }

bool SimulationControls::refusesToRun() {
  if (!m_edit.doc.root() || !sceneRefused(m_edit.doc)) return false;
  m_feedback.show(tr("Not running: %1 refuse(s) a value (red in the Field Editor); the last valid state is kept")
                      .arg(refusedNodes(m_edit.doc).join(QStringLiteral(", "))),
                  5000);
  return true;
}

void SimulationControls::setPlaying(bool on) {
  // nothing runs on values the scene refuses (a model on other values would be a different scene)
  if (on && refusesToRun()) on = false;
  m_clock->setPlaying(on);
  m_playAction->setChecked(on);
  m_playAction->setText(on ? tr("Pause") : tr("Play"));
  emit playingSet(on);
}

void SimulationControls::setSpeed(double speed) { m_speed->setValue(speed); }

void SimulationControls::step() {
  setPlaying(false);
  if (!m_edit.doc.root() || refusesToRun()) return;
  // one step of the smallest time step, every surface to that common time (realTime is the
  // paused clock's: it stays)
  SceneRunner(m_edit.doc.root(), SceneRunner::Clock::Untouched).step();
}

void SimulationControls::reset() {
  m_drag.release();
  for (SoBSplineDeformSurface* s : m_edit.doc.surfaces()) s->resetSimulation();
}

bool SimulationControls::solveStatic() {
  setPlaying(false);
  m_drag.release();
  const QVector<SoBSplineDeformSurface*> surfaces = m_edit.doc.surfaces();
  auto* command = new SolveStaticCommand(m_edit, std::vector<SoBSplineDeformSurface*>(surfaces.begin(), surfaces.end()));
  if (!command->error().isEmpty()) {
    const QString error = command->error();
    delete command;
    m_feedback.error(tr("Solve Static"), error);
    return false;
  }
  const QString report = command->report();
  m_undo.push(command);
  m_feedback.report(report, 10000);
  return true;
}

}  // namespace bsdeform
