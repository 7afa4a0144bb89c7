// SPDX-License-Identifier: MIT
#include "WheelZoom.h"

#include <Inventor/SoPickedPoint.h>
#include <Inventor/SoSceneManager.h>
#include <Inventor/Qt/viewers/SoQtViewer.h>
#include <Inventor/actions/SoRayPickAction.h>
#include <Inventor/nodes/SoCamera.h>
#include <Inventor/nodes/SoOrthographicCamera.h>

#include <QAction>
#include <QMenu>
#include <QSettings>
#include <QWheelEvent>
#include <QWidget>
#include <cmath>

#include "bsdeform/DefaultView.h"

namespace bsdeform {

const char* const WheelZoom::kInvertKey = "view/invertWheelZoom";

WheelZoom::WheelZoom(SoQtViewer* viewer, QObject* parent) : QObject(parent), m_viewer(viewer) {
  m_inverted = QSettings().value(kInvertKey, false).toBool();
  m_gl = m_viewer->getGLWidget();
  m_gl->installEventFilter(this);
}

void WheelZoom::addActions(QMenu* menu) {
  m_invertAction = menu->addAction(tr("&Invert Wheel Zoom"));
  m_invertAction->setCheckable(true);
  m_invertAction->setChecked(m_inverted);
  m_invertAction->setToolTip(tr("Off: the wheel turned forward zooms in, towards the cursor (as Blender, FreeCAD, ParaView)"));
  connect(m_invertAction, &QAction::toggled, this, &WheelZoom::setInverted);
}

void WheelZoom::setInverted(bool on) {
  m_inverted = on;
  QSettings().setValue(kInvertKey, on);
  if (m_invertAction && m_invertAction->isChecked() != on) m_invertAction->setChecked(on);
}

bool WheelZoom::eventFilter(QObject* watched, QEvent* e) {
  if (e->type() != QEvent::Wheel || watched != m_gl) return QObject::eventFilter(watched, e);
  auto* wheel = static_cast<QWheelEvent*>(e);
  const QWidget* gl = m_gl;
  const float notches = float(wheel->angleDelta().y()) / 120.0f;
  if (notches != 0.0f && gl->width() > 0 && gl->height() > 0) {
    const QPointF at = wheel->position();
    // the middle of the pixel under the cursor, as a pick there sees it
    const SbVec2f cursor(float((at.x() + 0.5) / gl->width()), float(1.0 - (at.y() + 0.5) / gl->height()));
    zoomAt(cursor, m_inverted ? -notches : notches);
  }
  return true;  // SoQt's own wheel zoom would move the camera a second time
}

void WheelZoom::zoomAt(const SbVec2f& cursor, float notches) {
  SoCamera* camera = m_viewer->getCamera();
  if (!camera || notches == 0.0f) return;
  const SbViewportRegion vp = m_viewer->getViewportRegion();
  // The point to zoom towards: the nearest shape under the cursor, else the focal plane there.
  SbVec3f target;
  SoRayPickAction pick(vp);
  pick.setNormalizedPoint(cursor);
  pick.apply(m_viewer->getSceneManager()->getSceneGraph());
  if (const SoPickedPoint* pp = pick.getPickedPoint()) {
    target = pp->getPoint();
  } else {
    const SbViewVolume vv = cameraViewVolume(camera, vp);
    SbLine ray;
    vv.projectPointToLine(cursor, ray);
    const SbVec3f eye = camera->position.getValue();
    const SbPlane focalPlane(-vv.getProjectionDirection(), eye + vv.getProjectionDirection() * camera->focalDistance.getValue());
    if (!focalPlane.intersect(ray, target)) return;
  }
  // The camera's frame scaled about the target by f: the target keeps its place on the screen.
  const float f = std::pow(kNotchFactor, notches);
  const SbVec3f eye = camera->position.getValue();
  if (camera->isOfType(SoOrthographicCamera::getClassTypeId())) {
    // Only across the view: the distance does not change the picture, and the camera must not
    // pass in front of the scene.
    auto* ortho = static_cast<SoOrthographicCamera*>(camera);
    SbVec3f along;
    camera->orientation.getValue().multVec(SbVec3f(0, 0, -1), along);
    SbVec3f across = target - eye;
    across -= along * across.dot(along);
    camera->position = eye + across * (1.0f - f);
    ortho->height = ortho->height.getValue() * f;
  } else {
    camera->position = target + (eye - target) * f;
    camera->focalDistance = camera->focalDistance.getValue() * f;
  }
}

}  // namespace bsdeform
