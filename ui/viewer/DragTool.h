// SPDX-License-Identifier: MIT
#pragma once
/// @file DragTool.h
/// Pulling a surface with the mouse: pressing on a surface picks the (u, v) under the cursor,
/// dragging pulls that point towards the cursor with a spring (a transient force of the node),
/// a line shows the spring, releasing lets go. The cursor moves on the plane through the picked
/// point facing the camera.

#include <Inventor/SbLinear.h>
#include <Eigen/Core>
#include <memory>

class SoCamera;
class SoSeparator;
class SoState;
class SbViewportRegion;
class SoEventCallback;
class SoCoordinate3;
class SoSwitch;
class SoBSplineDeformSurface;

namespace bsdeform {
class PointForce;

class DragTool {
 public:
  DragTool();
  ~DragTool();
  /// The node to put at the top of the rendered scene (event handling and the spring line).
  SoSeparator* node() const { return m_root; }
  /// Only in drag mode are mouse events used.
  void setEnabled(bool on);
  bool isEnabled() const { return m_enabled; }
  bool isDragging() const { return m_surface != nullptr; }
  SoBSplineDeformSurface* surface() const { return m_surface; }
  /// Where the spring pulls to (world coordinates) and the picked (u, v), while dragging.
  const SbVec3f& anchorWorld() const { return m_anchorWorld; }
  SbVec2f pickedParameter() const { return SbVec2f(float(m_u), float(m_v)); }
  /// Moves the line's ends to the current surface point and the anchor.
  void update();
  /// Lets go (also done on release, and before the scene is replaced).
  void release();
  /// The camera the view shows (referenced; nullptr: none). The tool's node comes before a
  /// scene's own camera, so the view volume it needs is taken from the camera, not the state.
  void setCamera(SoCamera* camera);

 private:
  static void eventCallback(void* data, SoEventCallback* cb);
  void handle(SoEventCallback* cb);

  SbViewVolume viewVolume(SoState* state, const SbViewportRegion& vp) const;

  SoSeparator* m_root = nullptr;
  SoCamera* m_camera = nullptr;
  SoEventCallback* m_events = nullptr;
  SoSwitch* m_lineSwitch = nullptr;
  SoCoordinate3* m_lineCoords = nullptr;
  bool m_enabled = false;
  SoBSplineDeformSurface* m_surface = nullptr;
  std::shared_ptr<PointForce> m_force;
  std::shared_ptr<Eigen::Vector3d> m_anchorLocal;
  double m_u = 0, m_v = 0;
  SbMatrix m_toWorld, m_toLocal;
  SbVec3f m_anchorWorld;
  SbPlane m_plane;
};

}  // namespace bsdeform
