// SPDX-License-Identifier: MIT
#pragma once
/// @file ViewFraming.h
/// The 3D view's camera: the default three-quarter view of scenes without a camera (the same as
/// bsdeform-run's pictures, bsdeform/DefaultView.h), View All and the standard views of the View
/// menu, and "Follow", which re-frames when the scene leaves the view or shrinks to a small part
/// of it while it deforms: gliding there (a third of a second), never while the window holds
/// the camera (a drag, a recording: hold()), and turned off as soon as the user moves the camera.

#include <Inventor/SbBox2f.h>
#include <Inventor/SbRotation.h>
#include <Inventor/SbVec2s.h>
#include <Inventor/SbVec3f.h>
#include <QElapsedTimer>
#include <QObject>

#include "bsdeform/DefaultView.h"

class QAction;
class QMenu;
class QTimer;
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
  /// Follow's check, called after the scene changed. A camera moved since the last check (by
  /// the user: this class's own moves are remembered) turns Follow off. While the camera is as
  /// this class last framed it, re-frames whenever the scene is outside the margins or small, or
  /// the view changed size. When Follow was turned on for a camera placed by the user,
  /// re-frames only when the scene leaves the margins or becomes small between two checks.
  /// A re-framing glides there (glideSeconds()); returns true when one began.
  bool follow();
  /// The camera is the window's to keep (a drag, a recording): a glide under way ends where it
  /// was going, and follow() is not called until the hold ends.
  void hold();
  /// How long a re-framing by Follow takes (wall seconds; 0: at once, as tests want it).
  void setGlideSeconds(double seconds) { m_glideSeconds = seconds; }
  double glideSeconds() const { return m_glideSeconds; }
  bool isGliding() const;
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
  /// Every camera field a framing sets, for a glide between two framings.
  struct Pose {
    SbVec3f position;
    SbRotation orientation;
    float focalDistance = 1.0f, nearDistance = 0.1f, farDistance = 10.0f, height = 2.0f;
  };
  Pose pose() const;
  void setPose(const Pose& p);
  void glideStep();
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
  double m_glideSeconds = 0.3;
  QTimer* m_glideTimer = nullptr;
  QElapsedTimer m_glideClock;
  Pose m_glideFrom, m_glideTo;
};

}  // namespace bsdeform
