// SPDX-License-Identifier: MIT
#include "ViewerClock.h"

#include <Inventor/SoDB.h>
#include <Inventor/SoSceneManager.h>
#include <Inventor/fields/SoSFTime.h>

#include <QTimer>

#include "bsdeform/SceneRunner.h"
#include "bsdeform/SoBSplineDeformSurface.h"

namespace bsdeform {

ViewerClock::ViewerClock(QObject* parent) : QObject(parent) {
  m_sceneManagerUpdateWas = SoSceneManager::isRealTimeUpdateEnabled();
  SoSceneManager::enableRealTimeUpdate(FALSE);
  SoDB::enableRealTimeSensor(FALSE);
  // From 0, as in bsdeform-run: the time of day (1.7e9 s) would leave realTime's differences
  // only 4e-7 s exact, and a step could come a frame late.
  realTimeField()->setValue(SbTime(0.0));
  m_timer = new QTimer(this);
  m_timer->setTimerType(Qt::PreciseTimer);
  m_timer->setInterval(16);
  connect(m_timer, &QTimer::timeout, this, &ViewerClock::tick);
}

ViewerClock::~ViewerClock() {
  SoBSplineDeformSurface::setRealTimeCatchUp(false);
  SoSceneManager::enableRealTimeUpdate(m_sceneManagerUpdateWas);
  SoDB::enableRealTimeSensor(m_realTimeSensorWas);
}

void ViewerClock::setPlaying(bool on) {
  if (on == m_playing) return;
  m_playing = on;
  updateTimer();
  emit playingChanged(on);
}

void ViewerClock::setSpeed(double speed) {
  if (speed > 0.0) m_speed = speed;
}

void ViewerClock::setWallClock(bool on) {
  m_wallClock = on;
  // Wall time: a surface whose steps cannot keep up takes one per frame and falls behind. Off
  // (tests): realTime is simulated time, every step due is taken.
  SoBSplineDeformSurface::setRealTimeCatchUp(!on);
  updateTimer();
}

void ViewerClock::updateTimer() {
  if (m_playing && m_wallClock) {
    if (!m_timer->isActive()) {
      m_wall.start();
      m_timer->start();
    }
  } else {
    m_timer->stop();
  }
}

void ViewerClock::tick() {
  const double seconds = m_wall.nsecsElapsed() * 1e-9;
  m_wall.start();
  advance(seconds);
}

void ViewerClock::advance(double wallSeconds) {
  if (!m_playing || !(wallSeconds > 0.0)) return;
  SoSFTime* f = realTimeField();
  f->setValue(SbTime(f->getValue().getValue() + wallSeconds * m_speed));
}

double ViewerClock::realTime() { return realTimeField()->getValue().getValue(); }

}  // namespace bsdeform
