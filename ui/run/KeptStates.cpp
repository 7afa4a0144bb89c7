// SPDX-License-Identifier: MIT
#include "KeptStates.h"

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
  std::vector<QString> names;
  for (SoBSplineDeformSurface* s : m_surfaces) names.push_back(QString::fromUtf8(s->getName().getString()));
  return writeStateFile(path, fileSurfacesOf(names, m_history.isEmpty() ? StateFrame() : m_history.back()), m_history, error);
}

}  // namespace bsdeform::run
