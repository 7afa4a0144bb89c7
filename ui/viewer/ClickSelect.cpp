// SPDX-License-Identifier: MIT
#include "ClickSelect.h"

#include <Inventor/SoPath.h>
#include <Inventor/SoPickedPoint.h>
#include <Inventor/SoSceneManager.h>
#include <Inventor/Qt/viewers/SoQtViewer.h>
#include <Inventor/actions/SoRayPickAction.h>
#include <Inventor/nodes/SoSeparator.h>
#include <Inventor/lists/SoPickedPointList.h>

#include <QApplication>
#include <QMouseEvent>
#include <QWidget>

#include "SceneDocument.h"
#include "bsdeform/SoBSplineDeformSurface.h"
#include "bsdeform/SoForceField.h"

namespace bsdeform {

ClickSelect::ClickSelect(SoQtViewer* viewer, const SceneDocument& doc, QObject* parent)
    : QObject(parent), m_viewer(viewer), m_doc(doc) {
  m_gl = m_viewer->getGLWidget();
  m_gl->installEventFilter(this);
}

bool ClickSelect::eventFilter(QObject* watched, QEvent* e) {
  if (watched == m_gl) {
    if (e->type() == QEvent::MouseButtonPress) {
      auto* m = static_cast<QMouseEvent*>(e);
      m_pressed = m->button() == Qt::LeftButton;
      m_pressedAt = m->pos();
    } else if (e->type() == QEvent::MouseMove && m_pressed) {
      auto* m = static_cast<QMouseEvent*>(e);
      if ((m->pos() - m_pressedAt).manhattanLength() > QApplication::startDragDistance()) m_pressed = false;
    } else if (e->type() == QEvent::MouseButtonRelease && m_pressed) {
      auto* m = static_cast<QMouseEvent*>(e);
      m_pressed = false;
      if (m->button() == Qt::LeftButton && (m->pos() - m_pressedAt).manhattanLength() <= QApplication::startDragDistance())
        if (SoBase* node = nodeAt(m->pos())) emit clicked(node);
    }
  }
  return QObject::eventFilter(watched, e);  // SoQt and the drag tool get every event too
}

SoBase* ClickSelect::nodeAt(const QPoint& pixel) const {
  const QWidget* gl = m_gl;
  if (!gl || !m_doc.root() || gl->width() <= 0 || gl->height() <= 0) return nullptr;
  SoRayPickAction pick(m_viewer->getViewportRegion());
  pick.setNormalizedPoint(SbVec2f(float(pixel.x() + 0.5) / gl->width(), 1.0f - float(pixel.y() + 0.5) / gl->height()));
  pick.setPickAll(TRUE);
  pick.apply(m_viewer->getSceneManager()->getSceneGraph());
  const SoPickedPointList& hits = pick.getPickedPointList();
  for (int i = 0; i < hits.getLength(); ++i) {
    const SoPath* path = hits[i]->getPath();
    if (path->containsNode(m_doc.root())) return listedNodeOn(path);  // the scene's nearest shape decides
  }
  return nullptr;  // the background, or only the viewer's overlays
}

SoBase* ClickSelect::listedNodeOn(const SoPath* path) const {
  for (int k = path->getLength() - 1; k >= 0; --k) {
    SoNode* node = path->getNode(k);
    if (node == m_doc.root()) break;
    for (SoBSplineDeformSurface* s : m_doc.surfaces())
      if (s == node) return s;
    for (SoForceField* f : m_doc.forceFields()) {
      if (f->type.getValue() != SoForceField::COLLISION) continue;
      if (f->obstacles.find(node) >= 0) return f;
      const SbName name = node->getName();
      if (name.getLength() && f->obstacleNames.find(SbString(name.getString())) >= 0) return f;
    }
  }
  return nullptr;
}

}  // namespace bsdeform
