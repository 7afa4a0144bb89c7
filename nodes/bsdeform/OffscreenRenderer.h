// SPDX-License-Identifier: MIT
#pragma once
/// @file OffscreenRenderer.h
/// Headless rendering of a scene graph to an image and PNG, without X (coin-notes §5: Coin's
/// stock offscreen path needs GLX, fails under Xvfb and crashes without a display). Coin's
/// offscreen-context callbacks are implemented with Mesa's surfaceless EGL platform, so
/// SoOffscreenRenderer works with or without an X server.

#include <Inventor/SbColor.h>

#include <memory>
#include <string>
#include <vector>

class SoNode;
class SoOffscreenRenderer;

namespace bsdeform {

/// An 8-bit RGB image, rows top to bottom.
struct Image {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
};

/// Installs the EGL offscreen context callbacks in Coin (idempotent). Returns false with a
/// reason when no EGL display or context can be made.
bool installEglOffscreenContexts(std::string* error = nullptr);

/// The background of rendered images (the viewer's).
inline const SbColor kDefaultBackground(0.18f, 0.2f, 0.24f);

class OffscreenRenderer;

/// Renders `scene` at width x height with a headlight along the view direction (as a viewer
/// does). When the scene has no camera, a perspective camera with a three-quarter view from the
/// -y side that frames the whole scene is added. Returns false with a
/// reason on failure.
/// @param reuse a renderer kept across frames (faster), or null for a fresh one
bool renderOffscreen(SoNode* scene, int width, int height, Image& out, std::string& error,
                     const SbColor& background = kDefaultBackground, OffscreenRenderer* reuse = nullptr);

/// A renderer kept for many frames: one SoOffscreenRenderer, so one GL context and Coin's GL
/// caches (compiled shaders, display lists, textures) live across frames instead of being made
/// again per image (docs/benchmarks.md, "Why the code is as it is"). The images are the same as
/// from a fresh renderer. Frames of another size make a new context. Not for use from several
/// threads at once.
class OffscreenRenderer {
 public:
  OffscreenRenderer();
  ~OffscreenRenderer();
  OffscreenRenderer(const OffscreenRenderer&) = delete;
  OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;
  /// renderOffscreen() with this renderer
  bool render(SoNode* scene, int width, int height, Image& out, std::string& error,
              const SbColor& background = kDefaultBackground) {
    return renderOffscreen(scene, width, height, out, error, background, this);
  }

 private:
  friend bool renderOffscreen(SoNode*, int, int, Image&, std::string&, const SbColor&, OffscreenRenderer*);
  std::unique_ptr<SoOffscreenRenderer> m_renderer;
};

/// How PNG rows are compressed. The default: the SUB filter on every row and zlib level 3, faster
/// than libpng's defaults (adaptive filters, level 6) for files about twice as large: rendered
/// frames are smooth gradients, which SUB alone already flattens (docs/benchmarks.md, "Why the
/// code is as it is").
struct PngSettings {
  int zlibLevel = 3;  ///< 0 (stored) .. 9 (smallest, slowest); libpng's own default is 6
  bool subFilterOnly = true;  ///< every row SUB-filtered, else libpng's per-row choice of all five filters
};

/// Encodes `image` as PNG into `out` (replaced). False if libpng fails.
bool encodePng(const Image& image, std::vector<unsigned char>& out, const PngSettings& settings = PngSettings());

/// Writes `image` as PNG to `path` atomically (a temporary file in the same directory,
/// renamed over the target). Returns false with a message naming the file on failure.
/// @param syncToDisk fsync the file before the rename (about 4 ms on this project's VM); a
///        writer of many frames may pass false and sync the file system once at the end
bool writePng(const Image& image, const std::string& path, std::string& error, bool syncToDisk = true);

/// syncfs() of the file system holding `directory`: makes every file written there without
/// syncing durable. False with a message naming the directory on failure.
bool syncFileSystem(const std::string& directory, std::string& error);

}  // namespace bsdeform
