// SPDX-License-Identifier: MIT
#include "DiscardBranchCommand.h"

#include "Timeline.h"

namespace bsdeform {

DiscardBranchCommand::DiscardBranchCommand(Timeline& timeline)
    : m_timeline(timeline), m_generation(timeline.m_generation) {
  const StateFrame& at = timeline.history()[timeline.position()];
  m_branchPoint.time = at.time;
  m_branchPoint.steps = at.steps;
  setText(QObject::tr("Discard Later States (from t = %1)").arg(at.time));
}

void DiscardBranchCommand::swapBranch() {
  StateHistory& h = m_timeline.m_history;
  std::vector<StateFrame> later = h.takeAfter(h.indexOf(m_branchPoint));
  h.appendAll(std::move(m_branch));
  m_branch = std::move(later);
}

void DiscardBranchCommand::undo() {
  if (m_generation != m_timeline.m_generation) return;
  swapBranch();
  emit m_timeline.branchSwapped(m_branchPoint.time);
  const int at = std::max(0, m_timeline.history().indexOf(m_branchPoint));
  if (!m_timeline.showFrame(at)) m_timeline.emitChanged();
}

void DiscardBranchCommand::redo() {
  if (m_generation != m_timeline.m_generation) return;
  swapBranch();
  if (!m_done) {  // the first time: the surfaces stepped on from the branch point (the plots too)
    m_done = true;
    return;
  }
  emit m_timeline.branchSwapped(m_branchPoint.time);
  if (!m_timeline.showFrame(m_timeline.history().size() - 1)) m_timeline.emitChanged();
}

}  // namespace bsdeform
