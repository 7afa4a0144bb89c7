// SPDX-License-Identifier: MIT
#pragma once
/// @file OffscreenRenderer.h
/// Headless rendering of a scene graph to an image and PNG, without X (coin-notes §5: Coin's
/// stock offscreen path needs GLX, fails under Xvfb and crashes without a display). Coin's
/// offscreen-context callbacks are implemented with Mesa's surfaceless EGL platform, so
/// SoOffscreenRenderer works with or without an X server.

#include <Inventor/SbColor.h>

#include <string>
#include <vector>

class SoNode;

namespace bsdeform {

/// An 8-bit RGB image, rows top to bottom.
struct Image {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
};

/// Installs the EGL offscreen context callbacks in Coin (idempotent). Returns false with a
/// reason when no EGL display or context can be made.
bool installEglOffscreenContexts(std::string* error = nullptr);

/// Renders `scene` at width x height with a headlight along the view direction (as a viewer
/// does). When the scene has no camera, a perspective camera with a three-quarter view from the
/// -y side that frames the whole scene is added. Returns false with a
/// reason on failure.
bool renderOffscreen(SoNode* scene, int width, int height, Image& out, std::string& error,
                     const SbColor& background = SbColor(0.18f, 0.2f, 0.24f));

/// Writes `image` as PNG to `path` atomically (a temporary file in the same directory,
/// renamed over the target). Returns false with a message naming the file on failure.
bool writePng(const Image& image, const std::string& path, std::string& error);

}  // namespace bsdeform
