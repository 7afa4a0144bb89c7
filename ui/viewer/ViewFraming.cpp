// SPDX-License-Identifier: MIT
#include "ViewFraming.h"

#include <Inventor/Qt/viewers/SoQtViewer.h>
#include <Inventor/nodes/SoCamera.h>
#include <Inventor/nodes/SoOrthographicCamera.h>
#include <Inventor/nodes/SoPerspectiveCamera.h>

#include <QAction>
#include <QMenu>
#include <QTimer>

#include <algorithm>

namespace bsdeform {

ViewFraming::ViewFraming(SoQtViewer* viewer, QObject* parent) : QObject(parent), m_viewer(viewer) {
  m_glideTimer = new QTimer(this);
  m_glideTimer->setInterval(16);
  connect(m_glideTimer, &QTimer::timeout, this, &ViewFraming::glideStep);
}

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
  m_glideTimer->stop();
  m_scene = scene;
  m_reframes = 0;
  m_framedCamera = CameraState();
  const bool ownCamera = findSceneCamera(scene) != nullptr;
  if (!ownCamera) setView(StandardView::Default);
  setFollowing(!ownCamera);
  remember();
}

void ViewFraming::setView(StandardView view) {
  m_glideTimer->stop();
  SoCamera* camera = m_viewer->getCamera();
  if (!camera || !m_scene) return;
  frameView(camera, m_scene, m_viewer->getViewportRegion(), view);
  framed();
}

void ViewFraming::viewAll() {
  m_glideTimer->stop();
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
  if (!m_viewer->getCamera()) return CameraState();
  const Pose p = pose();
  CameraState s;
  s.position = p.position;
  s.orientation = p.orientation;
  s.focalDistance = p.focalDistance;
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
  if (!isFollowing() || !m_scene || isGliding()) return false;
  const CameraState now = cameraState();
  if (!(now == m_lastCamera)) {  // the user took the camera: it stays where they put it
    setFollowing(false);
    return false;
  }
  const SbBox2f box = projectedSceneBox();
  if (box.isEmpty()) return false;
  bool reframe;
  if (now == m_framedCamera)
    reframe = !isInside(box) || isSmall(box) || m_viewer->getViewportRegion().getWindowSize() != m_framedViewport;
  else
    reframe = (m_wasInside && !isInside(box)) || (!m_wasSmall && isSmall(box));
  if (reframe) {
    ++m_reframes;
    if (!(m_glideSeconds > 0.0)) {
      viewAll();
      return true;
    }
    // where View All would put the camera, then back: the glide goes there
    m_glideFrom = pose();
    viewAll();
    m_glideTo = pose();
    setPose(m_glideFrom);
    m_lastCamera = cameraState();
    m_glideClock.start();
    m_glideTimer->start();
    return true;
  }
  m_wasInside = isInside(box);
  m_wasSmall = isSmall(box);
  m_lastCamera = cameraState();
  return false;
}

}  // namespace bsdeform

namespace bsdeform {

bool ViewFraming::isGliding() const { return m_glideTimer->isActive(); }

void ViewFraming::hold() {
  if (!isGliding()) return;
  m_glideTimer->stop();
  setPose(m_glideTo);
  framed();
}

ViewFraming::Pose ViewFraming::pose() const {
  Pose p;
  if (SoCamera* c = m_viewer->getCamera()) {
    p.position = c->position.getValue();
    p.orientation = c->orientation.getValue();
    p.focalDistance = c->focalDistance.getValue();
    p.nearDistance = c->nearDistance.getValue();
    p.farDistance = c->farDistance.getValue();
    if (c->isOfType(SoOrthographicCamera::getClassTypeId())) p.height = static_cast<SoOrthographicCamera*>(c)->height.getValue();
  }
  return p;
}

void ViewFraming::setPose(const Pose& p) {
  SoCamera* c = m_viewer->getCamera();
  if (!c) return;
  c->position = p.position;
  c->orientation = p.orientation;
  c->focalDistance = p.focalDistance;
  c->nearDistance = p.nearDistance;
  c->farDistance = p.farDistance;
  if (c->isOfType(SoOrthographicCamera::getClassTypeId())) static_cast<SoOrthographicCamera*>(c)->height = p.height;
}

// One frame of a glide: smoothstep from where the camera was to where View All puts it. A camera
// moved by someone else on the way (the user) ends the glide and Follow.
void ViewFraming::glideStep() {
  if (!(cameraState() == m_lastCamera)) {
    m_glideTimer->stop();
    setFollowing(false);
    return;
  }
  const double s = std::min(1.0, m_glideClock.elapsed() / (1000.0 * m_glideSeconds));
  const float e = float(s * s * (3.0 - 2.0 * s));
  auto mix = [e](float a, float b) { return a + (b - a) * e; };
  Pose p;
  p.position = m_glideFrom.position + (m_glideTo.position - m_glideFrom.position) * e;
  p.orientation = SbRotation::slerp(m_glideFrom.orientation, m_glideTo.orientation, e);
  p.focalDistance = mix(m_glideFrom.focalDistance, m_glideTo.focalDistance);
  // the clipping planes wide enough for both ends all the way
  p.nearDistance = std::min(m_glideFrom.nearDistance, m_glideTo.nearDistance);
  p.farDistance = std::max(m_glideFrom.farDistance, m_glideTo.farDistance) +
                  (m_glideFrom.position - m_glideTo.position).length();
  p.height = mix(m_glideFrom.height, m_glideTo.height);
  if (s >= 1.0) {
    m_glideTimer->stop();
    setPose(m_glideTo);
    framed();
    return;
  }
  setPose(p);
  m_lastCamera = cameraState();
}

}  // namespace bsdeform
