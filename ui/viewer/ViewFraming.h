// SPDX-License-Identifier: MIT
#pragma once
/// @file ViewFraming.h
/// The 3D view's camera: the default three-quarter view of scenes without a camera (the same as
/// bsdeform-run's pictures, bsdeform/DefaultView.h), View All and the standard views of the View
/// menu, and "Follow", which re-frames when the scene leaves the view or shrinks to a small part
/// of it while it deforms.

#include <Inventor/SbBox2f.h>
#include <Inventor/SbRotation.h>
#include <Inventor/SbVec2s.h>
#include <Inventor/SbVec3f.h>
#include <QObject>

#include "bsdeform/DefaultView.h"

class QAction;
class QMenu;
class SoNode;
class SoQtViewer;

namespace bsdeform {

class ViewFraming : public QObject {
  Q_OBJECT
 public:
  /// Follow re-frames when the scene's projected bounding box comes closer than this to an edge
  /// of the view (fraction of the view)...
  static constexpr float kEdgeMargin = 0.02f;
  /// ... or when its larger side becomes smaller than this fraction of the view.
  static constexpr float kSmallFraction = 0.3f;

  ViewFraming(SoQtViewer* viewer, QObject* parent = nullptr);

  /// Adds View All, the standard views and Follow to `menu`.
  void addActions(QMenu* menu);
  /// A new scene is shown: without a camera of its own it gets the default view and Follow is
  /// turned on; a scene's own camera is left as the file has it and Follow is off.
  void sceneShown(SoNode* scene);
  /// Turns the camera to `view` and frames the scene.
  void setView(StandardView view);
  /// Frames the scene keeping the camera's direction (bsdeform::frameScene).
  void viewAll();
  void setFollowing(bool on);
  bool isFollowing() const;
  /// Follow's check, called periodically. While the camera is as this class last framed it,
  /// re-frames whenever the scene is outside the margins or small, or the view changed size.
  /// After the user moved the camera, re-frames only when the scene leaves the margins or
  /// becomes small between two checks without camera moves (the user's framing is respected
  /// until the scene moves out of it). Returns true when it re-framed.
  bool follow();
  /// The scene's bounding box projected on the view, (0, 0)-(1, 1) being the whole view.
  SbBox2f projectedSceneBox() const;
  /// Re-framings made by follow() since the scene was shown.
  int followReframes() const { return m_reframes; }

 private:
  struct CameraState {
    SbVec3f position;
    SbRotation orientation;
    float focalDistance = -1.0f;  // none yet
    bool operator==(const CameraState& o) const {
      return position == o.position && orientation == o.orientation && focalDistance == o.focalDistance;
    }
  };
  CameraState cameraState() const;
  bool isInside(const SbBox2f& box) const;
  bool isSmall(const SbBox2f& box) const;
  void remember();
  void framed();

  SoQtViewer* m_viewer;
  SoNode* m_scene = nullptr;  // not owned: the document's root, shown by the viewer
  QAction* m_followAction = nullptr;
  CameraState m_lastCamera;    // at the last check
  CameraState m_framedCamera;  // as the last framing by this class left it
  SbVec2s m_framedViewport;
  bool m_wasInside = false, m_wasSmall = false;
  int m_reframes = 0;
};

}  // namespace bsdeform
