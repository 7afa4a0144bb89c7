// SPDX-License-Identifier: MIT
#pragma once
/// @file ClickSelect.h
/// A click in the 3D view selects what is under the cursor: a surface, or the COLLISION force
/// field whose obstacle the clicked shape is. A click is a left press and release no farther
/// apart than QApplication::startDragDistance() pixels; a longer move is a camera turn (viewing)
/// or a pull (drag mode) and selects nothing. The events still reach SoQt and the drag tool, so a
/// click in drag mode selects the surface as well as giving it a (zero-length) pull, and a click
/// in SoQt's seek mode seeks as well as selects. A click on the background or on a shape that is
/// not in the scene panel (an unlisted shape, the viewer's overlays) leaves the selection as it is.

#include <QObject>
#include <QPoint>
#include <QPointer>

class QMouseEvent;
class SoBase;
class SoPath;
class SoQtViewer;
class QWidget;

namespace bsdeform {

class SceneDocument;

class ClickSelect : public QObject {
  Q_OBJECT
 public:
  /// Watches the mouse on `viewer`'s GL widget; `doc` is the scene it shows.
  ClickSelect(SoQtViewer* viewer, const SceneDocument& doc, QObject* parent = nullptr);

  /// The surface or force field that a click at `pixel` (widget coordinates, y down) selects:
  /// the nearest shape of the scene there decides; nullptr when it stands for neither.
  SoBase* nodeAt(const QPoint& pixel) const;

 signals:
  /// A click picked `node` (a surface or force field of the document).
  void clicked(SoBase* node);

 protected:
  bool eventFilter(QObject* watched, QEvent* e) override;

 private:
  /// The node of the scene panel that `path` (from the viewer's root) stands for, or nullptr.
  SoBase* listedNodeOn(const SoPath* path) const;

  SoQtViewer* m_viewer;
  QPointer<QWidget> m_gl;  // the viewer's GL widget, which outlives the viewer in ~MainWindow
  const SceneDocument& m_doc;
  QPoint m_pressedAt;
  bool m_pressed = false;
};

}  // namespace bsdeform
