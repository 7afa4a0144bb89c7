// SPDX-License-Identifier: MIT
#pragma once
/// @file ViewerClock.h
/// The viewer drives Coin's realTime, and through it every surface (and every engine) of the
/// scene, as SoElapsedTime reads it: Play / Pause and the speed box are this clock's controls,
/// never the surfaces' fields (`on` and `speed` stay as the file has them).
///
/// Coin's own real-time sensor and the scene manager's update of realTime before each render
/// are switched off while a ViewerClock lives; realTime starts at 0 and advances by speed × wall-clock seconds
/// while playing, at the rate of the screen (a 60 Hz timer), and stands still while paused.
/// Tests switch the wall clock off (setWallClock(false)) and advance() by hand: time passes
/// without waiting.

#include <QElapsedTimer>
#include <QObject>

class QTimer;

namespace bsdeform {

class ViewerClock : public QObject {
  Q_OBJECT
 public:
  explicit ViewerClock(QObject* parent = nullptr);
  ~ViewerClock() override;

  bool isPlaying() const { return m_playing; }
  void setPlaying(bool on);
  /// realTime seconds per wall-clock second (> 0).
  double speed() const { return m_speed; }
  void setSpeed(double speed);
  /// Whether a timer advances the clock with the wall clock while playing (default true).
  void setWallClock(bool on);
  /// Moves realTime on by `wallSeconds` × speed while playing (nothing while paused). The
  /// surfaces follow when Coin processes its sensor queue (the event loop, or
  /// SoDB::getSensorManager()->processDelayQueue()).
  void advance(double wallSeconds);
  /// Coin's realTime now, in seconds.
  static double realTime();

 signals:
  void playingChanged(bool playing);

 private:
  void tick();
  void updateTimer();
  bool m_playing = false;
  bool m_wallClock = true;
  double m_speed = 1.0;
  QTimer* m_timer = nullptr;
  QElapsedTimer m_wall;
  bool m_realTimeSensorWas = true;
  bool m_sceneManagerUpdateWas = true;
};

}  // namespace bsdeform
