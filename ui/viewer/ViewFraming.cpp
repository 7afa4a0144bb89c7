// SPDX-License-Identifier: MIT
#include "ViewFraming.h"

#include <Inventor/Qt/viewers/SoQtViewer.h>
#include <Inventor/nodes/SoCamera.h>

#include <QAction>
#include <QMenu>

namespace bsdeform {

ViewFraming::ViewFraming(SoQtViewer* viewer, QObject* parent) : QObject(parent), m_viewer(viewer) {}

void ViewFraming::addActions(QMenu* menu) {
  QAction* a = menu->addAction(tr("View &All"), this, &ViewFraming::viewAll);
  a->setShortcut(QKeySequence(tr("A")));
  a->setToolTip(tr("Frame the whole scene keeping the direction of view (A)"));
  struct Entry {
    const char* text;
    const char* key;
    StandardView view;
  };
  const Entry entries[] = {{QT_TR_NOOP("&Default (three-quarter)"), "0", StandardView::Default},
                           {QT_TR_NOOP("&Front"), "1", StandardView::Front},
                           {QT_TR_NOOP("&Top"), "7", StandardView::Top},
                           {QT_TR_NOOP("&Side"), "3", StandardView::Side},
                           {QT_TR_NOOP("&Isometric"), "5", StandardView::Isometric}};
  QMenu* views = menu->addMenu(tr("&Standard Views"));
  for (const Entry& e : entries) {
    const StandardView view = e.view;
    views->addAction(tr(e.text), this, [this, view] { setView(view); })->setShortcut(QKeySequence(QLatin1String(e.key)));
  }
  m_followAction = menu->addAction(tr("&Follow"));
  m_followAction->setCheckable(true);
  m_followAction->setShortcut(QKeySequence(tr("F")));
  m_followAction->setToolTip(tr("Re-frame when the deforming scene leaves the view or becomes small in it (F)"));
  connect(m_followAction, &QAction::toggled, this, [this](bool on) {
    if (on) remember();
  });
}

void ViewFraming::sceneShown(SoNode* scene) {
  m_scene = scene;
  m_reframes = 0;
  m_framedCamera = CameraState();
  const bool ownCamera = findSceneCamera(scene) != nullptr;
  if (!ownCamera) setView(StandardView::Default);
  setFollowing(!ownCamera);
  remember();
}

void ViewFraming::setView(StandardView view) {
  SoCamera* camera = m_viewer->getCamera();
  if (!camera || !m_scene) return;
  frameView(camera, m_scene, m_viewer->getViewportRegion(), view);
  framed();
}

void ViewFraming::viewAll() {
  SoCamera* camera = m_viewer->getCamera();
  if (!camera || !m_scene) return;
  frameScene(camera, m_scene, m_viewer->getViewportRegion());
  framed();
}

void ViewFraming::setFollowing(bool on) {
  if (m_followAction) m_followAction->setChecked(on);
  remember();
}

bool ViewFraming::isFollowing() const { return m_followAction && m_followAction->isChecked(); }

SbBox2f ViewFraming::projectedSceneBox() const {
  SoCamera* camera = m_viewer->getCamera();
  if (!camera || !m_scene) return SbBox2f();
  return projectedBox(camera, sceneBoundingBox(m_scene, m_viewer->getViewportRegion()), m_viewer->getViewportRegion());
}

ViewFraming::CameraState ViewFraming::cameraState() const {
  CameraState s;
  if (SoCamera* camera = m_viewer->getCamera()) {
    s.position = camera->position.getValue();
    s.orientation = camera->orientation.getValue();
    s.focalDistance = camera->focalDistance.getValue();
  }
  return s;
}

bool ViewFraming::isInside(const SbBox2f& box) const {
  float x0, y0, x1, y1;
  box.getBounds(x0, y0, x1, y1);
  return x0 >= kEdgeMargin && y0 >= kEdgeMargin && x1 <= 1.0f - kEdgeMargin && y1 <= 1.0f - kEdgeMargin;
}

bool ViewFraming::isSmall(const SbBox2f& box) const {
  float w, h;
  box.getSize(w, h);
  return w < kSmallFraction && h < kSmallFraction;
}

void ViewFraming::remember() {
  const SbBox2f box = projectedSceneBox();
  m_wasInside = !box.isEmpty() && isInside(box);
  m_wasSmall = !box.isEmpty() && isSmall(box);
  m_lastCamera = cameraState();
}

void ViewFraming::framed() {
  remember();
  m_framedCamera = m_lastCamera;
  m_framedViewport = m_viewer->getViewportRegion().getWindowSize();
}

bool ViewFraming::follow() {
  if (!isFollowing() || !m_scene) return false;
  const SbBox2f box = projectedSceneBox();
  if (box.isEmpty()) return false;
  const CameraState now = cameraState();
  bool reframe;
  if (now == m_framedCamera) {
    reframe = !isInside(box) || isSmall(box) || m_viewer->getViewportRegion().getWindowSize() != m_framedViewport;
  } else {
    const bool userMoved = !(now == m_lastCamera);
    reframe = !userMoved && ((m_wasInside && !isInside(box)) || (!m_wasSmall && isSmall(box)));
  }
  if (reframe) {
    viewAll();
    ++m_reframes;
    return true;
  }
  m_wasInside = isInside(box);
  m_wasSmall = isSmall(box);
  m_lastCamera = cameraState();
  return false;
}

}  // namespace bsdeform
