// SPDX-License-Identifier: MIT
#include "bsdeform/SceneText.h"

#include <Inventor/SoOutput.h>
#include <Inventor/actions/SoWriteAction.h>

#include <cstdlib>

namespace bsdeform {

std::string sceneToText(SoNode* root) {
  SoOutput out;
  out.setBuffer(nullptr, 0, [](void* p, size_t n) { return std::realloc(p, n); });
  SoWriteAction wa(&out);
  wa.apply(root);
  void* buf = nullptr;
  size_t size = 0;
  out.getBuffer(buf, size);
  return std::string(static_cast<const char*>(buf), size);
}

}  // namespace bsdeform
