// SPDX-License-Identifier: MIT
#include "Backlight.h"

#include <Inventor/actions/SoGLRenderAction.h>
#include <Inventor/elements/SoViewingMatrixElement.h>
#include <Inventor/nodes/SoCallback.h>
#include <Inventor/nodes/SoDirectionalLight.h>
#include <Inventor/nodes/SoRotation.h>
#include <Inventor/nodes/SoTransformSeparator.h>

namespace bsdeform {

Backlight::Backlight() {
  m_root = new SoTransformSeparator;  // the turn stays inside, the light shines on the scene after it
  m_root->ref();
  auto* turnNow = new SoCallback;
  turnNow->setCallback(&Backlight::beforeDrawing, this);
  m_turn = new SoRotation;
  m_light = new SoDirectionalLight;
  m_light->direction.setValue(-1.0f, 1.0f, 10.0f);  // SoQt's headlight has (1, -1, -10), in camera space
  m_light->intensity = kIntensity;
  m_root->addChild(turnNow);
  m_root->addChild(m_turn);
  m_root->addChild(m_light);
}

Backlight::~Backlight() { m_root->unref(); }

void Backlight::beforeDrawing(void* self, SoAction* action) {
  if (!action->isOfType(SoGLRenderAction::getClassTypeId())) return;
  // the viewing matrix turns world into camera space (identity before any camera): its inverse
  // turn takes the light's camera-space direction to where the light is drawn
  SbVec3f translation, scale;
  SbRotation turn, scaleOrientation;
  SoViewingMatrixElement::get(action->getState()).getTransform(translation, turn, scale, scaleOrientation);
  SoSFRotation& r = static_cast<Backlight*>(self)->m_turn->rotation;
  const SbBool notifying = r.enableNotify(FALSE);  // set while drawing: not a change to draw again for
  r.setValue(turn.inverse());
  r.enableNotify(notifying);
}

}  // namespace bsdeform
