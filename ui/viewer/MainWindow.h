// SPDX-License-Identifier: MIT
#pragma once
/// @file MainWindow.h
/// bsdeform-viewer's main window: an SoQtExaminerViewer with file handling, simulation
/// controls, a scene panel with a field editor, live plots and mouse dragging.

#include <QImage>
#include <QMainWindow>
#include <memory>

#include "Autosave.h"
#include "DocumentActions.h"
#include "SceneDocument.h"
#include "bsdeform/SoBSplineDeformSurface.h"

class QAction;
class QMenu;
class QUndoStack;
class SoBase;
class SoField;
class SoFieldContainer;
class SoQtExaminerViewer;
class SoSeparator;

namespace bsdeform {
class Backlight;
class ControlNetDisplay;
class DragTool;
class EditActions;
class ExportActions;
class Feedback;
class FieldEditor;
class PlotPanel;
class RecordingControls;
class ScenePanel;
class SimulationControls;
class StatusPanel;
class SurfaceListener;
class Timeline;
class TimelinePanel;
class ViewDecorations;
class ViewFraming;
class ViewOverlays;
class ViewerClock;
class WheelZoom;
class ClickSelect;
struct EditContext;
struct MaterialPreset;

/// The window: the 3D view, the menus, tool bar and docks, and the wiring between the parts
/// that do the work (DocumentActions, SimulationControls, RecordingControls, ExportActions,
/// StatusPanel, ScenePanel, FieldEditor, PlotPanel, ...). The public functions below are the
/// window's commands for main.cpp and the tests; most hand over to those parts.
class MainWindow : public QMainWindow {
  Q_OBJECT
 public:
  explicit MainWindow(QWidget* parent = nullptr);
  ~MainWindow() override;

  /// Opens a scene file; on failure reports Coin's reason and keeps the current scene.
  bool openScene(const QString& path);
  /// Shows the built-in default scene.
  void openDefaultScene();
  /// Writes the scene with its state (used by Save As); the file becomes the document's.
  bool saveSceneAs(const QString& path);
  /// Saves to the scene's own file (Save As for the built-in default scene and a template).
  bool saveScene();
  /// The open scene is one that comes with bsdeform: Save asks for a new name (DocumentActions).
  bool isTemplate() const;
  /// The edits since the scene was opened or saved: Edit > Undo / Redo, clean after a save.
  QUndoStack& undoStack() { return *m_undo; }
  /// Adds a force field of `type` (SoForceField::Type) to the selected surface, undoably.
  /// False when no surface is selected.
  bool insertForceField(int type);
  /// Adds a surface (default fields) beside the scene, undoably, and selects it.
  void insertSurface();
  /// Adds a SHELL surface of `preset`'s material (one of materialPresets(): Insert > Surface's
  /// presets) beside the scene, undoably, and selects it.
  void insertPresetSurface(const MaterialPreset& preset);
  /// Deletes the selected surface or force field, undoably. False when nothing is selected.
  bool deleteSelected();
  /// The selected surface or force field in the scene panel (nullptr: none).
  SoBase* selectedNode() const;
  /// Selects a surface or force field in the scene panel (false if it is not in the scene).
  bool selectNode(SoBase* node);
  /// With unsaved edits, asks whether to save them (interactive only: otherwise they are
  /// dropped). True when the caller may go on (saved or discarded), false on Cancel.
  bool maybeSave();
  /// The folder the Open dialog starts in: the last one used, scenes/ the first time.
  QString openFolder() const;
  /// Screenshot of the 3D view (see Screenshot.h); at the view's size from the frame buffer,
  /// otherwise rendered offscreen with the same camera.
  QImage screenshot(const QSize& size = QSize());
  bool saveScreenshot(const QString& path, const QSize& size = QSize());
  /// Records the 3D view at `fps` frames per simulated second into `path` (.mp4, .webm, or
  /// .png for a numbered sequence) until stopRecording(); see Recorder.h.
  bool startRecording(const QString& path, double fps);
  /// Finishes the recording; false (and the reason in lastError()) when the file could not be
  /// completed.
  bool stopRecording();
  bool isRecording() const;
  /// The whole window including the 3D view (QWidget::grab() leaves the GL area black).
  QImage windowScreenshot();
  /// The selected surface as a mesh (.obj, .stl) or its control net (.xyz, .obj); see SceneDocument.
  bool exportMesh(const QString& path);
  bool exportControlNet(const QString& path);
  /// Offers the recovery files of viewers that died (newest first). Returns true when one was
  /// restored.
  bool offerRecovery(RecoveryChoice choice);
  /// Opens a recovery file as the scene it came from; it becomes this viewer's recovery file.
  bool restoreRecovery(const RecoveryFile& file);

  /// Tests and batch measurement: errors go to lastError() and the status bar, no dialogs.
  void setInteractive(bool on);
  const QString& lastError() const;
  SceneDocument& document() { return *m_doc; }
  SoQtExaminerViewer* viewer() const { return m_viewer; }
  DragTool& dragTool() { return *m_drag; }
  PlotPanel& plotPanel() { return *m_plots; }
  ViewFraming& framing() { return *m_framing; }
  ViewDecorations& decorations() { return *m_decorations; }
  WheelZoom& wheelZoom() { return *m_wheel; }
  ClickSelect& clickSelect() { return *m_clicks; }
  Backlight& backlight() { return *m_backlight; }
  ControlNetDisplay& netDisplay() { return *m_netDisplay; }
  /// The kept states and their strip under the view (Timeline.h, TimelinePanel.h).
  Timeline& timeline() { return *m_timeline; }
  TimelinePanel& timelinePanel() { return *m_timelinePanel; }
  /// Opens a bsdeform-run --keep-states file for the scene shown (Timeline::load); a file that
  /// does not fit is reported and changes nothing.
  bool openStates(const QString& path);
  FieldEditor& fieldEditor() { return *m_editor; }
  Autosave& autosave();
  /// The clock that drives realTime (tests: setWallClock(false), then advance()).
  ViewerClock& clock();
  /// Frames drawn since the scene was opened.
  long framesDrawn() const;
  void setPlaying(bool on);
  bool isPlaying() const;
  void setDragMode(bool on);
  void setSpeed(double speed);
  void selectSurface(int index);

 public slots:
  void open();
  void reload();
  void save();
  void saveAs();
  void openStatesDialog();
  void exportMeshDialog();
  void exportControlNetDialog();
  void screenshotDialog();
  /// Simulation > Record: asks for the file and the rate, or stops the recording.
  void recordToggled(bool on);
  /// Help > Field Reference: the fields of both nodes (bsdeform/FieldInfo.h).
  void showFieldReference();
  void play();
  void pause();
  void step();
  void reset();
  /// Simulation > Solve Static: every surface to the equilibrium of its loads (undoable); false
  /// and a reported error if one cannot be solved (nothing changes then).
  bool solveStatic();

 protected:
  void dragEnterEvent(QDragEnterEvent* e) override;
  void dropEvent(QDropEvent* e) override;
  void closeEvent(QCloseEvent* e) override;
  /// The 3D view's resize: the view is brought up to date (Follow fits the new size).
  bool eventFilter(QObject* watched, QEvent* e) override;

 private:
  void createActions();
  void createEditActions();
  void createHelpMenu();  ///< after the others: its shortcut list reads every menu
  void createDocks();
  /// The document's new scene in the view, the panels and the status; it plays when a surface
  /// of it is `on`.
  void showScene();
  /// The scene panel's selection: the field editor shows it, the plots follow a surface.
  void surfaceSelected(int index);
  void forceFieldSelected(int index);
  /// The surface the exports, a new force field and the status bar are about (nullptr: none).
  SoBSplineDeformSurface* selectedSurface() const;
  void fieldChanged(SoFieldContainer* owner, SoField* field);
  void structureChanged(SoBase* focus);
  /// The plots take every step of the surface they follow.
  void surfaceEvent(SoBSplineDeformSurface* surface, SoBSplineDeformSurface::Event e);
  /// Everything but the plots, after the surfaces changed (once per turn of the event loop).
  void refreshViews();
  void updateStatus();
  /// The window's geometry and dock layout (QSettings): saved on close, restored on start.
  void saveLayout();
  void restoreLayout();

  std::unique_ptr<SceneDocument> m_doc;
  std::unique_ptr<DragTool> m_drag;
  std::unique_ptr<Backlight> m_backlight;  ///< beside the scene: lights what the headlight misses
  std::unique_ptr<ViewOverlays> m_overlays;  ///< after the scene, under the view's camera
  std::unique_ptr<Feedback> m_feedback;
  std::unique_ptr<EditContext> m_edit;
  std::unique_ptr<StatusPanel> m_status;
  std::unique_ptr<EditActions> m_edits;
  SoQtExaminerViewer* m_viewer = nullptr;
  SoSeparator* m_wrapper = nullptr;
  QUndoStack* m_undo = nullptr;
  DocumentActions* m_files = nullptr;
  SimulationControls* m_simulation = nullptr;
  RecordingControls* m_recording = nullptr;
  ExportActions* m_exports = nullptr;
  ScenePanel* m_scenePanel = nullptr;
  FieldEditor* m_editor = nullptr;
  PlotPanel* m_plots = nullptr;
  ViewFraming* m_framing = nullptr;
  ViewDecorations* m_decorations = nullptr;
  WheelZoom* m_wheel = nullptr;
  ClickSelect* m_clicks = nullptr;
  ControlNetDisplay* m_netDisplay = nullptr;
  SurfaceListener* m_listener = nullptr;
  Timeline* m_timeline = nullptr;
  TimelinePanel* m_timelinePanel = nullptr;
  QAction* m_dragAction = nullptr;
  QMenu* m_simulationMenu = nullptr;
  SoBSplineDeformSurface* m_plotted = nullptr;  ///< the surface the plots follow
  int m_selectedSurface = -1;
};

}  // namespace bsdeform
