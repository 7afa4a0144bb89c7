// SPDX-License-Identifier: MIT
#pragma once
/// @file SurfaceListener.h
/// The window's ear on the surfaces (SoBSplineDeformSurface::addCallback): every event is passed
/// on at once (the plots take every step), and changed() follows once per turn of the event
/// loop, however many steps were taken in it (the rest of the window is brought up to date then).

#include <QObject>
#include <QVector>
#include <utility>
#include <vector>

#include "bsdeform/SoBSplineDeformSurface.h"

namespace bsdeform {

class SurfaceListener : public QObject {
  Q_OBJECT
 public:
  explicit SurfaceListener(QObject* parent = nullptr) : QObject(parent) {}
  ~SurfaceListener() override { stop(); }

  /// Listens to `surfaces` (ref'ed meanwhile) instead of the surfaces before.
  void listen(const QVector<SoBSplineDeformSurface*>& surfaces);
  /// Lets go of every surface.
  void stop();
  /// changed() at the next turn of the event loop; once, however often this is called before.
  void scheduleChanged();

 signals:
  /// What a surface told, as it tells it (on the thread that steps).
  void surfaceEvent(SoBSplineDeformSurface* surface, SoBSplineDeformSurface::Event e);
  /// The surfaces changed (or scheduleChanged() was called) since the last changed().
  void changed();

 private:
  std::vector<std::pair<SoBSplineDeformSurface*, int>> m_listening;  ///< ref'ed surfaces, callback ids
  bool m_pending = false;
};

}  // namespace bsdeform
