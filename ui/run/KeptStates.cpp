// SPDX-License-Identifier: MIT
#include "KeptStates.h"

#include "bsdeform/Simulation.h"
#include "bsdeform/SoBSplineDeformSurface.h"

namespace bsdeform::run {

KeptStates::KeptStates(std::vector<SoBSplineDeformSurface*> surfaces, long every)
    : m_surfaces(std::move(surfaces)), m_every(every) {}

void KeptStates::frameReached(long frame, bool last) {
  if (frame % m_every != 0 && !last) return;
  std::vector<SimulationState> states;
  for (SoBSplineDeformSurface* s : m_surfaces) states.push_back(s->state());
  m_history.append(frameOf(std::move(states)));
}

bool KeptStates::write(const QString& path, QString& error) const {
  std::vector<StateFileSurface> surfaces;
  for (SoBSplineDeformSurface* s : m_surfaces)
    surfaces.push_back({QString::fromUtf8(s->getName().getString()), int(s->simulation().current().rows())});
  return writeStateFile(path, surfaces, m_history, error);
}

}  // namespace bsdeform::run
