// SPDX-License-Identifier: MIT
#pragma once
/// @file WheelZoom.h
/// The mouse wheel in the 3D view as in Blender, FreeCAD and ParaView: turning it forward (away
/// from the user) zooms in, towards the point under the cursor, which stays under the cursor.
/// SoQt's own wheel zoom (the other way round, towards the view's centre) never sees the wheel.
/// View > Invert Wheel Zoom flips the direction; the choice is kept in QSettings.

#include <Inventor/SbVec2f.h>
#include <QObject>
#include <QPointer>

class QAction;
class QMenu;
class QWidget;
class SoQtViewer;

namespace bsdeform {

class WheelZoom : public QObject {
  Q_OBJECT
 public:
  /// The camera distance (perspective) or height (orthographic) is multiplied by this per
  /// notch of the wheel (120 eighths of a degree) towards the screen: 20 % closer.
  static constexpr float kNotchFactor = 0.8f;
  /// The QSettings key of the preference.
  static const char* const kInvertKey;

  /// Takes the wheel events of `viewer`'s GL widget.
  explicit WheelZoom(SoQtViewer* viewer, QObject* parent = nullptr);

  /// Adds "Invert Wheel Zoom" to `menu`.
  void addActions(QMenu* menu);
  /// Forward zooms out instead (the preference, saved at once).
  void setInverted(bool on);
  bool isInverted() const { return m_inverted; }
  /// Zooms by `notches` (positive: in) towards the scene point under `cursor` (normalized
  /// viewport coordinates, (0, 0) bottom left), or the point of the focal plane there when no
  /// shape is under it.
  void zoomAt(const SbVec2f& cursor, float notches);

 protected:
  bool eventFilter(QObject* watched, QEvent* e) override;

 private:
  SoQtViewer* m_viewer;
  QPointer<QWidget> m_gl;  // the viewer's GL widget, which outlives the viewer in ~MainWindow
  QAction* m_invertAction = nullptr;
  bool m_inverted = false;
};

}  // namespace bsdeform
