// SPDX-License-Identifier: MIT
#include "bsdeform/SceneRunner.h"

#include <Inventor/SoDB.h>
#include <Inventor/fields/SoSFTime.h>
#include <Inventor/nodes/SoNode.h>

#include <algorithm>
#include <cmath>

#include "bsdeform/SceneReader.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/SoBSplineDeformSurface.h"

namespace bsdeform {

SoSFTime* realTimeField() { return static_cast<SoSFTime*>(SoDB::getGlobalField(SbName("realTime"))); }

SceneRunner::SceneRunner(SoNode* root, Clock clock) : m_clock(clock) {
  if (m_clock == Clock::Simulated) SoDB::enableRealTimeSensor(FALSE);
  if (root) m_surfaces = sceneSurfaces(root);
  m_start = m_surfaces.empty() ? 0.0 : INFINITY;
  for (SoBSplineDeformSurface* s : m_surfaces) {
    s->ref();
    ++s->m_drivers;
    s->updateClock();
    s->setScene(root);
    m_start = std::min(m_start, s->simulation().time());
  }
  m_time = m_start;
}

SceneRunner::~SceneRunner() {
  for (SoBSplineDeformSurface* s : m_surfaces) {
    --s->m_drivers;
    s->updateClock();
    s->unref();
  }
}

double SceneRunner::timeStep() const {
  double dt = INFINITY;
  for (SoBSplineDeformSurface* s : m_surfaces) dt = std::min(dt, s->simulation().parameters().timeStep);
  return m_surfaces.empty() ? 0.0 : dt;
}

bool SceneRunner::advanceTo(double t) {
  if (m_clock == Clock::Simulated)
    realTimeField()->setValue(SbTime(t));
  bool ok = true;
  for (SoBSplineDeformSurface* s : m_surfaces) {
    // simulation() each time: a step callback may change a field and so rebuild the model
    auto due = [s, t] {
      const Simulation& sim = s->simulation();
      return sim.status() == Status::Ok && sim.time() + 0.5 * sim.parameters().timeStep <= t;
    };
    while (due()) s->stepSimulation(1);
    ok &= s->simulation().status() == Status::Ok;
  }
  m_time = std::max(m_time, t);
  return ok;
}

bool SceneRunner::step() { return advanceTo(m_time + timeStep()); }

std::vector<SoBSplineDeformSurface*> SceneRunner::failed() const {
  std::vector<SoBSplineDeformSurface*> out;
  for (SoBSplineDeformSurface* s : m_surfaces)
    if (s->simulation().status() != Status::Ok) out.push_back(s);
  return out;
}

}  // namespace bsdeform
