// SPDX-License-Identifier: MIT
#pragma once
#include <Inventor/SoDB.h>
#include <Inventor/SoInput.h>
#include <Inventor/actions/SoSearchAction.h>
#include <Inventor/errors/SoDebugError.h>
#include <Inventor/errors/SoReadError.h>
#include <Inventor/nodes/SoSeparator.h>

#include <string>
#include <vector>

#include "bsdeform/NodesInit.h"
#include "bsdeform/SceneReader.h"
#include "bsdeform/SceneText.h"
#include "bsdeform/SoBSplineDeformSurface.h"

namespace testutil {

/// Initialises Coin and our nodes once and collects Coin warnings and errors.
struct Coin {
  std::vector<std::string> messages;
  static Coin& get() {
    static Coin c;
    return c;
  }

 private:
  Coin() {
    bsdeform::disableDynamicNodeLoading();
    bsdeform::initNodes();
    SoDebugError::setHandlerCallback(
        [](const SoError* e, void* data) { static_cast<Coin*>(data)->messages.push_back(e->getDebugString().getString()); },
        this);
    SoReadError::setHandlerCallback(
        [](const SoError* e, void* data) { static_cast<Coin*>(data)->messages.push_back(e->getDebugString().getString()); },
        this);
  }
};

/// Reads a scene from a string (null on failure). The result is ref'ed.
inline SoSeparator* read(const std::string& text) {
  Coin::get();
  std::string error;  // the guarded reader our programs use; Coin's errors also reach `messages`
  SoSeparator* root = bsdeform::readSceneText(text.data(), text.size(), "test-scene", error);
  if (root) root->ref();
  else Coin::get().messages.push_back(error);
  return root;
}

inline std::string write(SoNode* root) { return bsdeform::sceneToText(root); }

/// The last object DEF'ed with `name` (engines included).
template <typename T>
T* named(const char* name) {
  return static_cast<T*>(SoBase::getNamedBase(SbName(name), T::getClassTypeId()));
}

template <typename T>
T* find(SoNode* root) {
  SoSearchAction sa;
  sa.setType(T::getClassTypeId());
  sa.setInterest(SoSearchAction::FIRST);
  sa.apply(root);
  return sa.getPath() ? static_cast<T*>(sa.getPath()->getTail()) : nullptr;
}

}  // namespace testutil
