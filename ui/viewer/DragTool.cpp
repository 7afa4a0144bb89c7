// SPDX-License-Identifier: MIT
#include "bsdeform/DefaultView.h"
#include "DragTool.h"

#include <Inventor/SoPickedPoint.h>
#include <Inventor/actions/SoGetMatrixAction.h>
#include <Inventor/actions/SoHandleEventAction.h>
#include <Inventor/elements/SoViewVolumeElement.h>
#include <Inventor/nodes/SoCamera.h>
#include <Inventor/elements/SoViewportRegionElement.h>
#include <Inventor/events/SoLocation2Event.h>
#include <Inventor/events/SoMouseButtonEvent.h>
#include <Inventor/nodes/SoBaseColor.h>
#include <Inventor/nodes/SoCoordinate3.h>
#include <Inventor/nodes/SoDrawStyle.h>
#include <Inventor/nodes/SoEventCallback.h>
#include <Inventor/nodes/SoLightModel.h>
#include <Inventor/nodes/SoLineSet.h>
#include <Inventor/nodes/SoMarkerSet.h>
#include <Inventor/nodes/SoPickStyle.h>
#include <Inventor/nodes/SoSeparator.h>
#include <Inventor/nodes/SoSwitch.h>

#include "bsdeform/forces/ForceLaws.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/SoBSplineDeformSurface.h"

namespace bsdeform {

DragTool::DragTool() {
  m_root = new SoSeparator;
  m_root->ref();
  m_events = new SoEventCallback;
  m_events->addEventCallback(SoMouseButtonEvent::getClassTypeId(), eventCallback, this);
  m_events->addEventCallback(SoLocation2Event::getClassTypeId(), eventCallback, this);
  m_root->addChild(m_events);
  m_lineSwitch = new SoSwitch;
  m_lineSwitch->whichChild = SO_SWITCH_NONE;
  auto* line = new SoSeparator;
  auto* pick = new SoPickStyle;
  pick->style = SoPickStyle::UNPICKABLE;  // the line never hides the surface from the pick
  auto* lm = new SoLightModel;
  lm->model = SoLightModel::BASE_COLOR;
  auto* color = new SoBaseColor;
  color->rgb.setValue(1.0f, 0.9f, 0.1f);
  auto* style = new SoDrawStyle;
  style->lineWidth = 3.0f;
  style->pointSize = 8.0f;
  m_lineCoords = new SoCoordinate3;
  m_lineCoords->point.setNum(2);
  auto* markers = new SoMarkerSet;
  markers->markerIndex = SoMarkerSet::CIRCLE_FILLED_7_7;
  for (SoNode* n : {static_cast<SoNode*>(pick), static_cast<SoNode*>(lm), static_cast<SoNode*>(color),
                    static_cast<SoNode*>(style), static_cast<SoNode*>(m_lineCoords), static_cast<SoNode*>(new SoLineSet),
                    static_cast<SoNode*>(markers)})
    line->addChild(n);
  m_lineSwitch->addChild(line);
  m_root->addChild(m_lineSwitch);
}

DragTool::~DragTool() {
  release();
  setCamera(nullptr);
  m_root->unref();
}

void DragTool::setEnabled(bool on) {
  m_enabled = on;
  if (!on) release();
}

void DragTool::setCamera(SoCamera* camera) {
  if (camera) camera->ref();
  if (m_camera) m_camera->unref();
  m_camera = camera;
}

SbViewVolume DragTool::viewVolume(SoState* state, const SbViewportRegion& vp) const {
  return m_camera ? cameraViewVolume(m_camera, vp) : SoViewVolumeElement::get(state);
}

void DragTool::eventCallback(void* data, SoEventCallback* cb) { static_cast<DragTool*>(data)->handle(cb); }

void DragTool::handle(SoEventCallback* cb) {
  if (!m_enabled) return;
  const SoEvent* ev = cb->getEvent();
  SoState* state = cb->getAction()->getState();
  const SbViewportRegion& vp = SoViewportRegionElement::get(state);
  if (SO_MOUSE_PRESS_EVENT(ev, BUTTON1)) {
    const SoPickedPoint* pp = cb->getPickedPoint();
    float u = 0, v = 0;
    if (!pp || !SoBSplineDeformSurface::pickedParameter(pp, u, v)) return;
    release();
    m_surface = static_cast<SoBSplineDeformSurface*>(pp->getPath()->getTail());
    m_surface->ref();
    SoGetMatrixAction gma(vp);
    gma.apply(pp->getPath());
    m_toWorld = gma.getMatrix();
    m_toLocal = gma.getInverse();
    m_u = u;
    m_v = v;
    m_anchorWorld = pp->getPoint();
    const SbViewVolume vv = viewVolume(state, vp);
    m_plane = SbPlane(-vv.getProjectionDirection(), m_anchorWorld);
    SbVec3f local;
    m_toLocal.multVecMatrix(m_anchorWorld, local);
    m_anchorLocal = std::make_shared<Eigen::Vector3d>(local[0], local[1], local[2]);
    // Stiff enough to dominate the surface's own stiffness at that point (the stability
    // estimate includes it, so the explicit scheme sub-steps accordingly).
    // SpringForce: with its Jacobian, inside an implicit step's Newton system
    m_force = std::make_shared<SpringForce>(u, v, m_anchorLocal, m_surface->simulation().dragStiffness());
    m_surface->addTransientForce(m_force);
    m_lineSwitch->whichChild = 0;
    update();
    cb->setHandled();
  } else if (SO_MOUSE_RELEASE_EVENT(ev, BUTTON1)) {
    if (isDragging()) {
      release();
      cb->setHandled();
    }
  } else if (ev->isOfType(SoLocation2Event::getClassTypeId()) && isDragging()) {
    const SbViewVolume vv = viewVolume(state, vp);
    SbLine ray;
    vv.projectPointToLine(ev->getNormalizedPosition(vp), ray);
    SbVec3f hit;
    if (m_plane.intersect(ray, hit)) {
      m_anchorWorld = hit;
      SbVec3f local;
      m_toLocal.multVecMatrix(hit, local);
      *m_anchorLocal = Eigen::Vector3d(local[0], local[1], local[2]);
      update();
    }
    cb->setHandled();
  }
}

void DragTool::update() {
  if (!isDragging()) return;
  const Eigen::Vector3d p = m_surface->simulation().evaluate(m_u, m_v, 0).position;
  SbVec3f world;
  m_toWorld.multVecMatrix(SbVec3f(float(p.x()), float(p.y()), float(p.z())), world);
  m_lineCoords->point.set1Value(0, world);
  m_lineCoords->point.set1Value(1, m_anchorWorld);
}

void DragTool::release() {
  if (!m_surface) return;
  m_surface->removeTransientForce(m_force.get());
  m_surface->unref();
  m_surface = nullptr;
  m_force.reset();
  m_lineSwitch->whichChild = SO_SWITCH_NONE;
}

}  // namespace bsdeform
