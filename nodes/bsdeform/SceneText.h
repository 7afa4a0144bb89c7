// SPDX-License-Identifier: MIT
#pragma once
/// @file SceneText.h
/// A scene graph as .iv text (what SoWriteAction writes), e.g. to save it atomically.

#include <string>

class SoNode;

namespace bsdeform {

/// Writes `root` (with every surface's current state) as ASCII Inventor text.
std::string sceneToText(SoNode* root);

}  // namespace bsdeform
