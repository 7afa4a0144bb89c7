// SPDX-License-Identifier: MIT
#pragma once
/// @file KeptStates.h
/// bsdeform-run --keep-states: the states of every surface at the run's common times (the
/// first, every --record-every-th step of the smallest time step, the last), kept in a
/// StateHistory (older states thinned beyond its budget) and written as a state file
/// (StateFile.h) that bsdeform-viewer --states opens.

#include <QString>
#include <vector>

#include "StateFile.h"
#include "StateHistory.h"

class SoBSplineDeformSurface;

namespace bsdeform::run {

class KeptStates {
 public:
  /// The scene's surfaces in order (SceneRunner::surfaces()); a state every `every` frames.
  KeptStates(std::vector<SoBSplineDeformSurface*> surfaces, long every);
  /// After the surfaces reached frame `frame` of the run: keeps their states when it is due
  /// (`last`: the run's last frame, always kept).
  void frameReached(long frame, bool last);
  /// Writes the file atomically; false and `error` (naming the file) when it cannot.
  bool write(const QString& path, QString& error) const;
  const StateHistory& history() const { return m_history; }

 private:
  std::vector<SoBSplineDeformSurface*> m_surfaces;
  long m_every;
  StateHistory m_history;
};

}  // namespace bsdeform::run
