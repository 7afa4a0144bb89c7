// SPDX-License-Identifier: MIT
#include "Timeline.h"

#include <QUndoStack>
#include <algorithm>
#include <string>

#include "DiscardBranchCommand.h"
#include "bsdeform/dynamics/Simulation.h"

namespace bsdeform {

Timeline::Timeline(QUndoStack& undo, QObject* parent) : QObject(parent), m_undo(undo) {}

void Timeline::setSurfaces(const QVector<SoBSplineDeformSurface*>& surfaces) {
  if (surfaces == m_surfaces && !m_history.isEmpty()) return;
  m_surfaces = surfaces;
  restart();
}

void Timeline::surfaceEvent(SoBSplineDeformSurface*, SoBSplineDeformSurface::Event e) {
  if (m_restoring) return;
  if (e == SoBSplineDeformSurface::STEPPED) m_stepped = true;
  if (e == SoBSplineDeformSurface::STATE_CHANGED) m_restartPending = true;
}

void Timeline::capture() {
  if (m_restartPending) {
    restart();
    return;
  }
  if (!m_stepped || m_surfaces.isEmpty()) return;
  m_stepped = false;
  // stepping on from an earlier state: the later ones go, undoably
  if (!isAtEnd()) m_undo.push(new DiscardBranchCommand(*this));
  m_history.append(frameNow());
  m_position = m_history.size() - 1;
  emitChanged();
}

void Timeline::restart() {
  m_restartPending = m_stepped = false;
  ++m_generation;
  m_history.clear();
  if (!m_surfaces.isEmpty()) m_history.append(frameNow());
  // building a model while the frame was taken tells STATE_CHANGED: that is this start
  m_restartPending = false;
  m_position = m_history.size() - 1;
  emitChanged();
}

StateFrame Timeline::frameNow() {
  std::vector<SimulationState> states;
  for (SoBSplineDeformSurface* s : m_surfaces) states.push_back(s->state());
  return frameOf(std::move(states));
}

bool Timeline::showFrame(int index) {
  if (index < 0 || index >= m_history.size()) return false;
  if (!restore(m_history[index], tr("the kept state at t = %1").arg(m_history[index].time))) return false;
  m_position = index;
  emitChanged();
  return true;
}

bool Timeline::restore(const StateFrame& frame, const QString& source) {
  emit aboutToRestore();
  m_restoring = true;
  std::vector<SimulationState> before;
  for (SoBSplineDeformSurface* s : m_surfaces) before.push_back(s->state());
  std::string error;
  int k = 0;
  for (; k < m_surfaces.size(); ++k)
    if (!m_surfaces[k]->restoreState(frame.surfaces[std::size_t(k)], &error)) break;
  const bool ok = k == m_surfaces.size();
  if (!ok) {
    m_error = tr("%1 does not fit surface %2: %3").arg(source).arg(k + 1).arg(QString::fromStdString(error));
    for (int j = 0; j < k; ++j) m_surfaces[j]->restoreState(before[std::size_t(j)], nullptr);
  }
  m_restoring = false;
  m_stepped = false;
  return ok;
}

std::vector<std::pair<double, Diagnostics>> Timeline::diagnosticsAfter(int index, double time) {
  std::vector<std::pair<double, Diagnostics>> out;
  if (index < 0 || index >= m_surfaces.size()) return out;
  SoBSplineDeformSurface* s = m_surfaces[index];
  m_restoring = true;
  const SimulationState shown = s->state();
  for (int k = 0; k < m_history.size(); ++k) {
    const StateFrame& f = m_history[k];
    if (!(f.time > time) || !s->restoreState(f.surfaces[std::size_t(index)], nullptr)) continue;
    out.emplace_back(s->simulation().time(), s->simulation().diagnostics());
  }
  s->restoreState(shown, nullptr);
  m_restoring = false;
  return out;
}

bool Timeline::advanceReplay(double seconds) {
  if (m_history.isEmpty()) return false;
  m_replayTime = std::max(m_replayTime, m_history[m_position].time) + seconds;
  const int index = m_history.indexAt(m_replayTime);
  if (index > m_position) showFrame(index);
  return !isAtEnd();
}

void Timeline::setBudget(std::size_t bytes) {
  m_history.setBudget(bytes);
  m_position = std::min(m_position, m_history.size() - 1);
  emitChanged();
}

std::vector<StateFileSurface> Timeline::fileSurfaces() {
  std::vector<QString> names;
  for (SoBSplineDeformSurface* s : m_surfaces) names.push_back(QString::fromUtf8(s->getName().getString()));
  return fileSurfacesOf(names, frameNow());
}

bool Timeline::load(const QString& path, const StateFileContents& contents) {
  m_error = stateFileMismatch(path, contents.surfaces, fileSurfaces());
  if (!m_error.isEmpty()) return false;
  if (contents.frames.empty()) {
    m_error = tr("'%1' holds no states").arg(path);
    return false;
  }
  // every state is tried before any is kept (a held point moved, a NaN): nothing changes on a refusal
  const StateFrame now = frameNow();
  for (std::size_t f = 0; f < contents.frames.size(); ++f)
    if (!restore(contents.frames[f], tr("'%1': frame %2 (t = %3)").arg(path).arg(f + 1).arg(contents.frames[f].time))) {
      restore(now, QString());
      return false;
    }
  ++m_generation;
  m_history.clear();
  for (const StateFrame& f : contents.frames) m_history.append(f);
  m_position = m_history.size() - 1;
  emitChanged();
  return true;
}

void Timeline::emitChanged() {
  m_replayTime = m_history.isEmpty() ? 0.0 : m_history[m_position].time;
  emit changed(m_replayTime);
}

}  // namespace bsdeform
