// SPDX-License-Identifier: MIT
#include "ViewOverlays.h"

#include <Inventor/Qt/viewers/SoQtViewer.h>
#include <Inventor/actions/SoGLRenderAction.h>
#include <Inventor/actions/SoRayPickAction.h>
#include <Inventor/nodes/SoCallback.h>
#include <Inventor/nodes/SoCamera.h>
#include <Inventor/nodes/SoSeparator.h>

namespace bsdeform {

ViewOverlays::ViewOverlays(SoQtViewer* viewer) : m_viewer(viewer) {
  m_root = new SoSeparator;
  m_root->ref();
  auto* camera = new SoCallback;
  camera->setCallback(&ViewOverlays::applyViewCamera, this);
  m_root->addChild(camera);
}

ViewOverlays::~ViewOverlays() { m_root->unref(); }

void ViewOverlays::add(SoNode* overlay) { m_root->addChild(overlay); }

void ViewOverlays::applyViewCamera(void* self, SoAction* action) {
  SoCamera* camera = static_cast<ViewOverlays*>(self)->m_viewer->getCamera();
  if (!camera) return;
  // drawing and picking need the view (a pick of the net's points sees them where they are drawn)
  if (action->isOfType(SoGLRenderAction::getClassTypeId()))
    camera->GLRender(static_cast<SoGLRenderAction*>(action));
  else if (action->isOfType(SoRayPickAction::getClassTypeId()))
    camera->rayPick(static_cast<SoRayPickAction*>(action));
}

}  // namespace bsdeform
