// SPDX-License-Identifier: MIT
#include "AxesGizmo.h"

#include "ExaminerViewer.h"

#include <Inventor/actions/SoGLRenderAction.h>
#include <Inventor/elements/SoViewportRegionElement.h>
#include <Inventor/nodes/SoBaseColor.h>
#include <Inventor/nodes/SoCallback.h>
#include <Inventor/nodes/SoCoordinate3.h>
#include <Inventor/nodes/SoDrawStyle.h>
#include <Inventor/nodes/SoFont.h>
#include <Inventor/nodes/SoLightModel.h>
#include <Inventor/nodes/SoLineSet.h>
#include <Inventor/nodes/SoOrthographicCamera.h>
#include <Inventor/nodes/SoRotation.h>
#include <Inventor/nodes/SoSeparator.h>
#include <Inventor/nodes/SoText2.h>
#include <Inventor/nodes/SoTranslation.h>

#include <algorithm>

namespace bsdeform {

namespace {
SoSeparator* axis(const SbVec3f& direction, const SbColor& color, const char* label) {
  auto* sep = new SoSeparator;
  auto* rgb = new SoBaseColor;
  rgb->rgb = color;
  auto* coords = new SoCoordinate3;
  coords->point.set1Value(0, SbVec3f(0, 0, 0));
  coords->point.set1Value(1, direction);
  auto* at = new SoTranslation;
  at->translation = direction * 1.2f;
  auto* text = new SoText2;
  text->string = label;
  text->justification = SoText2::CENTER;
  for (SoNode* n : {static_cast<SoNode*>(rgb), static_cast<SoNode*>(coords), static_cast<SoNode*>(new SoLineSet),
                    static_cast<SoNode*>(at), static_cast<SoNode*>(text)})
    sep->addChild(n);
  return sep;
}
}  // namespace

AxesGizmo::AxesGizmo(ExaminerViewer* viewer) : m_viewer(viewer) {
  m_root = new SoSeparator;
  m_root->ref();
  m_root->renderCaching = SoSeparator::OFF;  // the rotation is set while drawing
  auto* corner = new SoCallback;
  corner->setCallback(&AxesGizmo::beforeDrawing, this);
  auto* camera = new SoOrthographicCamera;  // looks along -z at the triad from +z
  camera->position.setValue(0, 0, 5);
  camera->height = 2.6f;  // unit axes and their letters, turned any way
  camera->nearDistance = 1.0f;
  camera->farDistance = 9.0f;
  auto* light = new SoLightModel;
  light->model = SoLightModel::BASE_COLOR;
  auto* style = new SoDrawStyle;
  style->lineWidth = 2.0f;
  auto* font = new SoFont;
  font->size = 14.0f;
  m_rotation = new SoRotation;
  for (SoNode* n : {static_cast<SoNode*>(corner), static_cast<SoNode*>(camera), static_cast<SoNode*>(light),
                    static_cast<SoNode*>(style), static_cast<SoNode*>(font), static_cast<SoNode*>(m_rotation)})
    m_root->addChild(n);
  m_root->addChild(axis(SbVec3f(1, 0, 0), SbColor(0.95f, 0.3f, 0.3f), "X"));
  m_root->addChild(axis(SbVec3f(0, 1, 0), SbColor(0.35f, 0.85f, 0.35f), "Y"));
  m_root->addChild(axis(SbVec3f(0, 0, 1), SbColor(0.4f, 0.55f, 1.0f), "Z"));
  m_viewer->addSuperimposition(m_root);
}

AxesGizmo::~AxesGizmo() {
  m_viewer->removeSuperimposition(m_root);
  m_root->unref();
}

void AxesGizmo::setVisible(bool on) {
  m_visible = on;
  m_viewer->setSuperimpositionEnabled(m_root, on);
  m_viewer->scheduleRedraw();
}

SbRotation AxesGizmo::rotation() const { return m_rotation->rotation.getValue(); }

void AxesGizmo::beforeDrawing(void* self, SoAction* action) {
  if (!action->isOfType(SoGLRenderAction::getClassTypeId())) return;
  auto* gizmo = static_cast<AxesGizmo*>(self);
  SoState* state = action->getState();
  // the corner square of the view
  SbViewportRegion corner = SoViewportRegionElement::get(state);
  const SbVec2s window = corner.getWindowSize();
  const short side = short(std::min<int>({AxesGizmo::kSidePixels, window[0], window[1]}));
  corner.setViewportPixels(SbVec2s(AxesGizmo::kMarginPixels, AxesGizmo::kMarginPixels), SbVec2s(side, side));
  SoViewportRegionElement::set(state, corner);
  // the world's axes as the view's camera sees them; not a change to draw again for
  if (SoCamera* camera = gizmo->m_viewer->getCamera()) {
    SoSFRotation& r = gizmo->m_rotation->rotation;
    const SbBool notifying = r.enableNotify(FALSE);
    r.setValue(camera->orientation.getValue().inverse());
    r.enableNotify(notifying);
  }
}

}  // namespace bsdeform
