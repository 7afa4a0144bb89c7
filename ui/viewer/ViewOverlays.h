// SPDX-License-Identifier: MIT
#pragma once
/// @file ViewOverlays.h
/// The group of the viewer's overlays drawn after the scene (the control net and ghost, the
/// ground grid), under the camera the view shows. A scene's own camera sits under the scene's
/// root, so after that root it is no longer in effect and an overlay would be drawn in camera
/// space (a net floating in a corner); the group applies the view's camera again first. With
/// SoQt's own camera (scenes without one) that is the camera already in effect.

class SoAction;
class SoNode;
class SoQtViewer;
class SoSeparator;

namespace bsdeform {

class ViewOverlays {
 public:
  explicit ViewOverlays(SoQtViewer* viewer);
  ~ViewOverlays();
  ViewOverlays(const ViewOverlays&) = delete;
  ViewOverlays& operator=(const ViewOverlays&) = delete;

  /// The group: put it in the viewer's graph after the scene's root.
  SoSeparator* node() const { return m_root; }
  /// Adds an overlay to the group (drawn in the order added).
  void add(SoNode* overlay);

 private:
  static void applyViewCamera(void* self, SoAction* action);

  SoQtViewer* m_viewer;
  SoSeparator* m_root = nullptr;
};

}  // namespace bsdeform
