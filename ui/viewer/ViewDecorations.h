// SPDX-License-Identifier: MIT
#pragma once
/// @file ViewDecorations.h
/// The viewer's decorations of the 3D view: the ground grid (GroundGrid) and the axes gizmo
/// (AxesGizmo), with their View menu toggles. They belong to the viewer, not to the scene: the
/// grid sits beside the document's root (never under it), so it is never saved, never an
/// obstacle (obstacles are looked up in the document's scene) and never in the framing of View
/// All, Follow and the standard views (ViewFraming frames the document's root); it is
/// unpickable. The gizmo is a SoQt superimposition.
///
/// The grid is on by default for a scene without an environment of its own. A scene has its own
/// environment when it holds any shape besides its B-spline surfaces (a floor, a box, a rod,
/// terrain, an obstacle): the author built the setting, and a grid would cut through it. The
/// user's toggles are kept in QSettings: switching the grid off keeps it off for every scene
/// until it is switched on again; switching it on for a scene with its own environment shows it
/// for that scene only. The axes are on unless switched off.

#include <QObject>
#include <memory>

class QAction;
class QMenu;
class SoNode;
class SoSwitch;

namespace bsdeform {

class ExaminerViewer;
class AxesGizmo;
class GroundGrid;

class ViewDecorations : public QObject {
  Q_OBJECT
 public:
  /// QSettings keys of the user's toggles.
  static const char* const kGridKey;
  static const char* const kAxesKey;

  explicit ViewDecorations(ExaminerViewer* viewer, QObject* parent = nullptr);
  ~ViewDecorations() override;

  /// The grid's node: put it in the viewer's graph beside the scene, after it, under the view's
  /// camera (ViewOverlays).
  SoSwitch* gridNode() const { return m_gridSwitch; }
  /// Adds "Ground Grid" and "Axes" to `menu`.
  void addActions(QMenu* menu);
  /// A new scene is shown: the grid is fitted under it, and shown unless the scene has its own
  /// environment or the user switched the grid off.
  void sceneShown(SoNode* scene);
  /// Fits the grid to the scene again (a surface was inserted or removed).
  void refit();
  /// After the scene moved: a grid shown is lowered under a surface that fell below it.
  void follow();
  void setGridVisible(bool on);
  void setAxesVisible(bool on);
  bool isGridVisible() const;
  bool isAxesVisible() const;
  GroundGrid& grid() { return *m_grid; }
  AxesGizmo& axes() { return *m_axes; }

  /// Whether `scene` has an environment of its own: a shape that is not a
  /// SoBSplineDeformSurface.
  static bool hasOwnEnvironment(SoNode* scene);

 private:
  ExaminerViewer* m_viewer;
  SoNode* m_scene = nullptr;  // not owned: the document's root
  std::unique_ptr<GroundGrid> m_grid;
  std::unique_ptr<AxesGizmo> m_axes;
  SoSwitch* m_gridSwitch = nullptr;  // referenced
  QAction* m_gridAction = nullptr;
  QAction* m_axesAction = nullptr;
};

}  // namespace bsdeform
