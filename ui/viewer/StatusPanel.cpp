// SPDX-License-Identifier: MIT
#include "StatusPanel.h"

#include <Inventor/actions/SoGLRenderAction.h>
#include <Inventor/nodes/SoCallback.h>

#include <QLabel>
#include <QStatusBar>
#include <algorithm>

#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/SoBSplineDeformSurface.h"

namespace bsdeform {

StatusPanel::StatusPanel(QStatusBar* bar)
    : m_timeLabel(new QLabel), m_rateLabel(new QLabel), m_modelLabel(new QLabel), m_stateLabel(new QLabel), m_frameCounter(new SoCallback) {
  for (QLabel* l : {m_timeLabel, m_rateLabel, m_modelLabel, m_stateLabel}) bar->addPermanentWidget(l);
  m_frameCounter->ref();
  m_frameCounter->setCallback(countFrame, this);
  m_rateClock.start();
}

StatusPanel::~StatusPanel() { m_frameCounter->unref(); }

SoNode* StatusPanel::frameCounter() const { return m_frameCounter; }

void StatusPanel::countFrame(void* data, SoAction* action) {
  if (action->isOfType(SoGLRenderAction::getClassTypeId())) ++static_cast<StatusPanel*>(data)->m_frames;
}

void StatusPanel::restart() {
  m_frames = m_lastFrames = 0;
  m_lastSteps = 0;
}

void StatusPanel::follow(SoBSplineDeformSurface* surface) { m_lastSteps = surface->simulation().stepCount(); }

void StatusPanel::update(SoBSplineDeformSurface* s, bool playing, SoBSplineDeformSurface* troubled,
                         const QStringList& refused, const QString& refusedDetails) {
  const double dt = m_rateClock.elapsed() / 1000.0;
  const long steps = s ? s->simulation().stepCount() : 0;
  if (dt >= 1.0) {
    m_fps = (m_frames - m_lastFrames) / dt;
    m_stepsPerSecond = std::max(0L, steps - m_lastSteps) / dt;
    m_lastFrames = m_frames;
    m_lastSteps = steps;
    m_rateClock.restart();
  }
  if (m_replaySpeed > 0.0)
    m_rateLabel->setText(tr("replay %1 x  %2 frames/s").arg(m_replaySpeed, 0, 'g', 3).arg(m_fps, 0, 'f', 1));
  else
    m_rateLabel->setText(tr("%1 steps/s  %2 frames/s").arg(m_stepsPerSecond, 0, 'f', 1).arg(m_fps, 0, 'f', 1));
  if (!s) {
    m_timeLabel->clear();
    m_modelLabel->clear();
    m_stateLabel->clear();
    return;
  }
  const Simulation& sim = s->simulation();
  const ModelParameters& p = sim.parameters();
  m_timeLabel->setText(tr("t = %1 s").arg(sim.time(), 0, 'f', 3));
  // moving points: N1 N2 when all sides are clamped, more with free or periodic sides, minus pins
  const qlonglong moving = qlonglong(sim.space().numMoving()) - qlonglong(sim.pinnedRows().size());
  m_modelLabel->setText(tr("%1 moving control points (%2 DOFs)  dt %3  limit %4  sub-steps %5")
                            .arg(moving)
                            .arg(3 * moving)
                            .arg(p.timeStep)
                            .arg(sim.stabilityLimit(), 0, 'g', 4)
                            .arg(sim.subSteps()));
  using Problem = SoBSplineDeformSurface::Problem;
  // the selected surface's problem, else another's: a refusal stays red until it is fixed
  SoBSplineDeformSurface* shown = s->problem().kind == Problem::NONE && troubled ? troubled : s;
  const Problem& problem = shown->problem();
  const SbName shownName = shown->getName();
  const QString who = shown == s ? QString()
                                 : (shownName.getLength() ? QString::fromUtf8(shownName.getString()) : tr("another surface")) +
                                       QLatin1Char('.');
  if (!refused.isEmpty()) {
    m_stateLabel->setText(tr("<b style='color:#c00'>refused: %1</b>").arg(refused.join(QStringLiteral(", ")).toHtmlEscaped()));
    m_stateLabel->setToolTip(refusedDetails);
  } else if (sim.status() != Status::Ok) {
    m_stateLabel->setText(tr("<b style='color:#c00'>STOPPED: blew up</b>"));
    m_stateLabel->setToolTip(QString::fromStdString(sim.statusMessage()));
  } else if (problem.kind == Problem::FIELD) {
    m_stateLabel->setText(tr("<b style='color:#c00'>refused: %1</b>").arg((who + QString::fromStdString(problem.field)).toHtmlEscaped()));
    m_stateLabel->setToolTip(QString::fromStdString(problem.message));
  } else if (problem.kind == Problem::FORCE_FIELD || problem.kind == Problem::STOPPED) {
    m_stateLabel->setText((problem.kind == Problem::STOPPED ? tr("<b style='color:#c00'>STOPPED: %1</b>")
                                                             : tr("<b style='color:#c00'>refused: %1</b>"))
                              .arg(QString::fromStdString(problem.node).toHtmlEscaped()));
    m_stateLabel->setToolTip(QString::fromStdString(problem.message));
  } else if (problem.kind != Problem::NONE) {
    m_stateLabel->setText(tr("<b style='color:#b60'>warning</b>"));
    m_stateLabel->setToolTip(QString::fromStdString(problem.message));
  } else {
    m_stateLabel->setText(playing ? tr("running") : tr("paused"));
    m_stateLabel->setToolTip(QString());
  }
}

}  // namespace bsdeform
