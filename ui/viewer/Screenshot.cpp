// SPDX-License-Identifier: MIT
#include "Screenshot.h"

#include <Inventor/Qt/viewers/SoQtExaminerViewer.h>
#include <Inventor/nodes/SoCamera.h>
#include <Inventor/nodes/SoSeparator.h>

#include <QDir>
#include <QFileDialog>
#include <QFileInfo>
#include <QGLWidget>
#include <QInputDialog>
#include <QPainter>
#include <string>

#include "DocumentActions.h"
#include "ImageSize.h"
#include "bsdeform/NodeRef.h"
#include "bsdeform/OffscreenRenderer.h"

namespace bsdeform {

QImage Screenshot::view(SoNode* scene, const QSize& size, QString& error) const {
  auto* gl = qobject_cast<QGLWidget*>(m_viewer->getGLWidget());
  const QSize viewSize = gl ? gl->size() : QSize();
  if (gl && (!size.isValid() || size == viewSize)) {
    m_viewer->render();
    return gl->grabFrameBuffer();
  }
  // another size: the same camera, rendered offscreen (EGL); renderOffscreen adds the one
  // headlight a viewer has (a second one here made the picture overexposed)
  const NodeRef<SoSeparator> root(new SoSeparator);
  if (SoCamera* cam = m_viewer->getCamera()) root->addChild(cam->copy());
  if (scene) root->addChild(scene);
  if (gl) gl->doneCurrent();  // EGL cannot make its context current while SoQt's GLX one is
  Image img;
  std::string why;
  const SbColor bg = m_viewer->getBackgroundColor();
  if (!renderOffscreen(root.get(), size.width(), size.height(), img, why, bg)) {
    error = QString::fromStdString(why);
    return QImage();
  }
  return QImage(img.rgb.data(), img.width, img.height, img.width * 3, QImage::Format_RGB888).copy();
}

QImage Screenshot::window(QWidget* window) const {
  QImage picture = window->grab().toImage();
  QWidget* glw = m_viewer->getGLWidget();
  if (auto* gl = qobject_cast<QGLWidget*>(glw)) {
    m_viewer->render();
    QPainter painter(&picture);
    painter.drawImage(glw->mapTo(window, QPoint(0, 0)), gl->grabFrameBuffer());
  }
  return picture;
}

bool Screenshot::ask(QWidget* parent, QString& path, QSize& size, QString& error) const {
  path = QFileDialog::getSaveFileName(parent, tr("Save screenshot"), QDir(DocumentActions::userFolder()).filePath(QStringLiteral("screenshot.png")),
                                      tr("PNG images (*.png)"));
  if (path.isEmpty()) return false;
  if (QFileInfo(path).suffix().isEmpty()) path += QStringLiteral(".png");
  const QSize view = m_viewer->getGLWidget()->size();
  bool ok = false;
  const QString text = QInputDialog::getText(parent, tr("Screenshot size"), tr("Width x height in pixels:"), QLineEdit::Normal,
                                             QStringLiteral("%1x%2").arg(view.width()).arg(view.height()), &ok);
  if (!ok) return false;
  if (!parseImageSize(text, size)) {
    error = tr("'%1' is not a size WxH within 1..%2").arg(text).arg(kMaxImageSide);
    return false;
  }
  return true;
}

}  // namespace bsdeform
