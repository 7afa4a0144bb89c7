// SPDX-License-Identifier: MIT
#pragma once
/// @file Screenshot.h
/// Pictures of the viewer: the 3D view at its own size (its frame buffer) or at any other size
/// (the same camera rendered offscreen), the whole window, and the Save Screenshot dialog.

#include <QCoreApplication>
#include <QImage>
#include <QSize>
#include <QString>

class QWidget;
class SoNode;
class SoQtExaminerViewer;

namespace bsdeform {

class Screenshot {
  Q_DECLARE_TR_FUNCTIONS(Screenshot)

 public:
  explicit Screenshot(SoQtExaminerViewer* viewer) : m_viewer(viewer) {}

  /// The 3D view at `size` (invalid: the view's size); at another size, `scene` (the
  /// document's root) under a copy of the viewer's camera, rendered offscreen. A null image,
  /// and `error`, when that failed.
  QImage view(SoNode* scene, const QSize& size, QString& error) const;
  /// The whole window including the 3D view (QWidget::grab() leaves the GL area black).
  QImage window(QWidget* window) const;

  /// The Save Screenshot dialog: the file (".png" added when it has no suffix), then the size
  /// (the view's by default). False when cancelled or, with `error`, when the size is not WxH
  /// within 1..8192.
  bool ask(QWidget* parent, QString& path, QSize& size, QString& error) const;

 private:
  SoQtExaminerViewer* m_viewer;
};

}  // namespace bsdeform
