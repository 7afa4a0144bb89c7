// SPDX-License-Identifier: MIT
#include "SurfaceListener.h"

#include <QTimer>

namespace bsdeform {

void SurfaceListener::listen(const QVector<SoBSplineDeformSurface*>& surfaces) {
  stop();
  for (SoBSplineDeformSurface* s : surfaces) {
    s->ref();
    m_listening.emplace_back(s, s->addCallback([this](SoBSplineDeformSurface* surface, SoBSplineDeformSurface::Event e) {
      emit surfaceEvent(surface, e);
      scheduleChanged();
    }));
  }
}

void SurfaceListener::stop() {
  for (auto& l : m_listening) {
    l.first->removeCallback(l.second);
    l.first->unref();
  }
  m_listening.clear();
}

void SurfaceListener::scheduleChanged() {
  if (m_pending) return;
  m_pending = true;
  QTimer::singleShot(0, this, [this] {
    m_pending = false;
    emit changed();
  });
}

}  // namespace bsdeform
