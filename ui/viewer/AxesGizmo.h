// SPDX-License-Identifier: MIT
#pragma once
/// @file AxesGizmo.h
/// The axes gizmo: an X (red), Y (green), Z (blue) triad with its letters in the bottom-left
/// corner of the 3D view, turned as the view's camera turns, the same size whatever the zoom.
/// It is a SoQt superimposition (drawn after the scene, over it, with its own camera and a
/// corner viewport), so it is in no bounding box, no pick and no saved file.

#include <Inventor/SbLinear.h>

class SoAction;
class SoRotation;
class SoSeparator;

namespace bsdeform {

class ExaminerViewer;
class AxesGizmo {
 public:
  /// Side of the gizmo's square in the corner, in pixels, and its distance from the edges.
  static constexpr int kSidePixels = 96;
  static constexpr int kMarginPixels = 4;

  /// Adds the gizmo to `viewer`'s superimpositions.
  explicit AxesGizmo(ExaminerViewer* viewer);
  ~AxesGizmo();
  AxesGizmo(const AxesGizmo&) = delete;
  AxesGizmo& operator=(const AxesGizmo&) = delete;

  void setVisible(bool on);
  bool isVisible() const { return m_visible; }
  /// The gizmo's graph (referenced by this object).
  SoSeparator* node() const { return m_root; }
  /// The turn the triad was last drawn with: the inverse of the view camera's orientation, so
  /// that the triad shows the world's axes as the camera sees them.
  SbRotation rotation() const;

 private:
  static void beforeDrawing(void* self, SoAction* action);

  ExaminerViewer* m_viewer;
  SoSeparator* m_root = nullptr;
  SoRotation* m_rotation = nullptr;
  bool m_visible = true;
};

}  // namespace bsdeform
