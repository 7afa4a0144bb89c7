// SPDX-License-Identifier: MIT
#pragma once
/// @file DiscardBranchCommand.h
/// Stepping on from an earlier kept state discards the later ones (Timeline.h); this command on
/// the window's undo stack holds them. undo() puts them back in place of the states kept since
/// and shows the state they branched from; redo() swaps the branches again and shows the newest.
/// A command from before the timeline started again (Reset, another scene) does nothing.

#include <QUndoCommand>
#include <vector>

#include "StateHistory.h"

namespace bsdeform {

class Timeline;

class DiscardBranchCommand : public QUndoCommand {
 public:
  /// Discards the states after the timeline's position when first done (redo()).
  explicit DiscardBranchCommand(Timeline& timeline);
  void undo() override;
  void redo() override;

 private:
  /// Exchanges the kept states after m_branchPoint with m_branch.
  void swapBranch();
  Timeline& m_timeline;
  int m_generation;
  StateFrame m_branchPoint;  ///< the frame branched from (its time and steps, no states)
  std::vector<StateFrame> m_branch;
  bool m_done = false;
};

}  // namespace bsdeform
