// SPDX-License-Identifier: MIT
#include "MainWindow.h"

#include <Inventor/Qt/SoQt.h>
#include <Inventor/Qt/viewers/SoQtExaminerViewer.h>
#include <Inventor/nodes/SoSeparator.h>
#include <Inventor/nodes/SoSwitch.h>
#include <Inventor/nodes/SoTransformSeparator.h>

#include <QAction>
#include <QCloseEvent>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QFileDialog>
#include <QLabel>
#include <QMenuBar>
#include <QScrollArea>
#include <QSettings>
#include <QSplitter>
#include <QStatusBar>
#include <QToolBar>
#include <QUndoStack>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>

#include "Backlight.h"
#include "ClickSelect.h"
#include "ControlNetDisplay.h"
#include "DragTool.h"
#include "EditActions.h"
#include "EditCommands.h"
#include "ExaminerViewer.h"
#include "ExportActions.h"
#include "Feedback.h"
#include "FieldEditor.h"
#include "HelpDialogs.h"
#include "MaterialPresets.h"
#include "PlotPanel.h"
#include "RecordingControls.h"
#include "SceneDocument.h"
#include "ScenePanel.h"
#include "SceneProblems.h"
#include "SimulationControls.h"
#include "StatusPanel.h"
#include "SurfaceListener.h"
#include "Timeline.h"
#include "TimelinePanel.h"
#include "ViewDecorations.h"
#include "ViewFraming.h"
#include "ViewOverlays.h"
#include "ViewerClock.h"
#include "WheelZoom.h"
#include "bsdeform/SoForceField.h"

namespace bsdeform {

namespace {
const char* kGeometryKey = "window/geometry";  // size and place of the window
const char* kLayoutKey = "window/layout";      // docks and tool bar (QMainWindow::saveState)
}  // namespace

MainWindow::MainWindow(QWidget* parent)
    : QMainWindow(parent), m_doc(new SceneDocument), m_drag(new DragTool), m_backlight(new Backlight), m_feedback(new Feedback(*this)) {
  setWindowTitle(tr("bsdeform viewer"));
  setAcceptDrops(true);
  m_undo = new QUndoStack(this);
  m_edit.reset(new EditContext{*m_doc, [this](SoFieldContainer* o, SoField* f) { fieldChanged(o, f); },
                               [this](SoBase* focus) { structureChanged(focus); }});
  m_simulation = new SimulationControls(*m_edit, *m_undo, *m_drag, *m_feedback, this);  // drives realTime from now on
  connect(m_simulation, &SimulationControls::playingSet, this, &MainWindow::updateStatus);
  m_files = new DocumentActions(*m_doc, *m_undo, *m_drag, *m_feedback, *this);
  connect(m_files, &DocumentActions::sceneLoaded, this, &MainWindow::showScene);
  m_listener = new SurfaceListener(this);
  connect(m_listener, &SurfaceListener::surfaceEvent, this, &MainWindow::surfaceEvent);
  connect(m_listener, &SurfaceListener::changed, this, &MainWindow::refreshViews);
  m_timeline = new Timeline(*m_undo, this);
  connect(m_listener, &SurfaceListener::surfaceEvent, m_timeline, &Timeline::surfaceEvent);
  connect(m_listener, &SurfaceListener::changed, m_timeline, &Timeline::capture);
  connect(m_timeline, &Timeline::aboutToRestore, this, [this] {
    setPlaying(false);
    m_drag->release();
  });
  m_wrapper = new SoSeparator;
  m_wrapper->ref();

  auto* central = new QWidget(this);
  auto* layout = new QVBoxLayout(central);
  layout->setContentsMargins(0, 0, 0, 0);
  setCentralWidget(central);
  auto* examiner = new ExaminerViewer(central);  // SoQt's, with the view decorations' needs
  m_viewer = examiner;
  layout->addWidget(m_viewer->getWidget());
  m_viewer->setBackgroundColor(SbColor(0.18f, 0.2f, 0.24f));
  m_viewer->setSceneGraph(m_wrapper);
  m_framing = new ViewFraming(m_viewer, this);
  m_viewer->getGLWidget()->installEventFilter(this);
  m_wheel = new WheelZoom(m_viewer, this);
  m_decorations = new ViewDecorations(examiner, this);
  m_clicks = new ClickSelect(m_viewer, *m_doc, this);
  connect(m_clicks, &ClickSelect::clicked, this, [this](SoBase* node) { selectNode(node); });
  m_netDisplay = new ControlNetDisplay(this);
  m_overlays = std::make_unique<ViewOverlays>(m_viewer);
  m_overlays->add(m_drag->node());  // its spring line
  m_overlays->add(m_netDisplay->node());
  m_overlays->add(m_decorations->gridNode());
  m_exports = new ExportActions(*m_doc, m_viewer, [this] { return selectedSurface(); }, *m_feedback, *this);
  m_recording = new RecordingControls(*m_doc, m_viewer, [this] { return screenshot(); }, *m_feedback, this);

  createActions();
  createEditActions();
  createHelpMenu();
  createDocks();
  m_edits = std::make_unique<EditActions>(*m_edit, *m_undo, *m_scenePanel, [this] { return selectedSurface(); }, *m_feedback);
  m_status = std::make_unique<StatusPanel>(statusBar());
  resize(1200, 800);
  restoreLayout();
}

MainWindow::~MainWindow() {
  m_listener->stop();
  m_undo->clear();  // the commands hold nodes of the scene
  m_drag->release();
  delete m_decorations;  // it leaves the viewer's superimpositions
  m_viewer->setSceneGraph(nullptr);
  delete m_viewer;
  m_viewer = nullptr;  // eventFilter() may still see the GL widget's last events
  m_wrapper->unref();
}

// ---------------------------------------------------------------------------------------------
// Menus, tool bar, docks

void MainWindow::createActions() {
  QMenu* file = menuBar()->addMenu(tr("&File"));
  QAction* a = file->addAction(tr("&Open..."), this, &MainWindow::open);
  a->setShortcut(QKeySequence::Open);
  m_files->setRecentMenu(file->addMenu(tr("Open &Recent")));
  a = file->addAction(tr("Re&load"), this, &MainWindow::reload);
  a->setShortcut(QKeySequence::Refresh);
  a = file->addAction(tr("&Save"), this, &MainWindow::save);
  a->setShortcut(QKeySequence::Save);
  a = file->addAction(tr("Save &As..."), this, &MainWindow::saveAs);
  a->setShortcut(QKeySequence(tr("Ctrl+Shift+S")));  // QKeySequence::SaveAs is empty without a desktop theme
  file->addAction(tr("Open S&tates..."), this, &MainWindow::openStatesDialog)
      ->setToolTip(tr("Scrub through the states a bsdeform-run --keep-states run of this scene wrote"));
  file->addSeparator();
  file->addAction(tr("&Export Mesh (OBJ, STL)..."), this, &MainWindow::exportMeshDialog);
  file->addAction(tr("Export &Control Net (XYZ, OBJ)..."), this, &MainWindow::exportControlNetDialog);
  a = file->addAction(tr("Save &Screenshot..."), this, &MainWindow::screenshotDialog);
  a->setShortcut(QKeySequence(tr("Ctrl+P")));
  file->addSeparator();
  a = file->addAction(tr("&Quit"), this, &QWidget::close);
  a->setShortcut(QKeySequence::Quit);

  QMenu* sim = menuBar()->addMenu(tr("&Simulation"));
  m_simulationMenu = sim;
  QToolBar* bar = addToolBar(tr("Simulation"));
  bar->setObjectName(QStringLiteral("simulationToolBar"));
  m_dragAction = new QAction(tr("Drag"), this);
  m_dragAction->setCheckable(true);
  m_dragAction->setShortcut(QKeySequence(tr("D")));
  m_dragAction->setToolTip(tr("Drag mode: press on a surface and pull (D); off: camera mode"));
  connect(m_dragAction, &QAction::toggled, this, &MainWindow::setDragMode);
  for (QAction* act : {m_simulation->playAction(), m_simulation->stepAction(), m_simulation->resetAction(), m_dragAction,
                       m_recording->action()}) {
    sim->addAction(act);
    bar->addAction(act);
  }
  sim->addSeparator();
  sim->addAction(m_simulation->solveStaticAction());
  bar->addSeparator();
  bar->addWidget(new QLabel(tr(" speed ")));
  bar->addWidget(m_simulation->speedBox());

  QMenu* view = menuBar()->addMenu(tr("&View"));
  m_framing->addActions(view);
  view->addSeparator();
  m_netDisplay->addActions(view);
  view->addSeparator();
  m_decorations->addActions(view);
  m_wheel->addActions(view);
}

void MainWindow::createHelpMenu() {
  QMenu* help = menuBar()->addMenu(tr("&Help"));
  QAction* a = help->addAction(tr("&Keyboard Shortcuts"), this, [this] { showShortcuts(this, menuBar()); });
  a->setShortcut(QKeySequence::HelpContents);
  help->addAction(tr("&Field Reference"), this, &MainWindow::showFieldReference);
  help->addSeparator();
  help->addAction(tr("&About bsdeform-viewer"), this, [this] { showAbout(this); });
}

void MainWindow::createEditActions() {
  // File, Edit, Insert, Simulation, View, Help
  QMenu* edit = new QMenu(tr("&Edit"), this);
  menuBar()->insertMenu(m_simulationMenu->menuAction(), edit);
  QAction* undo = m_undo->createUndoAction(this, tr("&Undo"));
  undo->setShortcut(QKeySequence::Undo);
  QAction* redo = m_undo->createRedoAction(this, tr("&Redo"));
  QList<QKeySequence> redoKeys = QKeySequence::keyBindings(QKeySequence::Redo);
  if (!redoKeys.contains(QKeySequence(tr("Ctrl+Shift+Z")))) redoKeys.prepend(QKeySequence(tr("Ctrl+Shift+Z")));
  redo->setShortcuts(redoKeys);
  edit->addAction(undo);
  edit->addAction(redo);
  edit->addSeparator();
  QAction* del = edit->addAction(tr("&Delete"), this, &MainWindow::deleteSelected);
  del->setShortcut(QKeySequence::Delete);
  del->setToolTip(tr("Delete the selected surface or force field"));

  QMenu* insert = new QMenu(tr("&Insert"), this);
  menuBar()->insertMenu(m_simulationMenu->menuAction(), insert);
  QMenu* forces = insert->addMenu(tr("&Force Field"));
  forces->setToolTipsVisible(true);
  SoForceField* probe = new SoForceField;  // for the names of its types
  probe->ref();
  for (int k = 0; k < probe->type.getNumEnums(); ++k) {
    SbName name;
    const int type = probe->type.getEnum(k, name);
    QAction* a = forces->addAction(QString::fromLatin1(name.getString()), this, [this, type] { insertForceField(type); });
    a->setToolTip(tr("Add a %1 force field to the selected surface").arg(QString::fromLatin1(name.getString())));
  }
  probe->unref();
  // Insert > Surface: the plain surface (the node's defaults: the paper's energy), then one
  // SHELL surface per named material
  QMenu* surfaces = insert->addMenu(tr("&Surface"));
  surfaces->setToolTipsVisible(true);
  QAction* plain = surfaces->addAction(tr("&Plain (default fields)"), this, &MainWindow::insertSurface);
  plain->setToolTip(tr("Add a surface with the node's default fields (the paper's energy)"));
  surfaces->addSection(tr("SHELL materials"));
  for (const MaterialPreset& preset : materialPresets()) {
    QAction* a = surfaces->addAction(QString::fromUtf8(preset.name), this,
                                     [this, &preset] { insertPresetSurface(preset); });
    a->setToolTip(tr("Add a SHELL surface: E %1 Pa, ν %2, t %3 m, ρ %4 kg/m³ (%5)")
                      .arg(preset.youngsModulus).arg(preset.poissonRatio).arg(preset.thickness)
                      .arg(preset.density).arg(QString::fromUtf8(preset.source)));
  }
}

void MainWindow::createDocks() {
  auto* sceneDock = new QDockWidget(tr("Scene"), this);
  sceneDock->setObjectName(QStringLiteral("sceneDock"));
  auto* split = new QSplitter(Qt::Vertical);
  m_scenePanel = new ScenePanel(*m_doc);
  connect(m_scenePanel, &ScenePanel::surfaceSelected, this, &MainWindow::surfaceSelected);
  connect(m_scenePanel, &ScenePanel::forceFieldSelected, this, &MainWindow::forceFieldSelected);
  m_editor = new FieldEditor;
  m_editor->setChecker(refusalOf);
  m_editor->setRefusedFields([](SoFieldContainer* owner) {
    FieldEditor::Refusals out;
    for (const RefusedField& r : refusedFieldsOf(owner)) out.emplace_back(r.field, r.reason);
    return out;
  });
  connect(m_editor, &FieldEditor::notice, this, [this](const QString& m) { m_feedback->show(m, 8000); });
  // after an edit the keyboard goes back to the 3D view, where Space, S, R, D act
  connect(m_editor, &FieldEditor::done, this, [this] { m_viewer->getGLWidget()->setFocus(Qt::OtherFocusReason); });
  m_editor->setChangeHandler([this](SoFieldContainer* owner, SoField* field, const SoField& before, bool beforeIsDefault) {
    m_undo->push(new SetFieldCommand(*m_edit, owner, field, before, beforeIsDefault, *field, true));
  });
  connect(m_editor, &FieldEditor::rejected, this, [this](const QString& m) { m_feedback->show(m, 5000); });
  auto* scroll = new QScrollArea;
  scroll->setObjectName(QStringLiteral("fieldEditorScroll"));
  scroll->setWidget(m_editor);
  scroll->setWidgetResizable(true);
  // the rows fit the dock's width (reasons wrap): no sideways scrolling
  scroll->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
  split->addWidget(m_scenePanel);
  split->addWidget(scroll);
  split->setStretchFactor(0, 1);
  split->setStretchFactor(1, 4);
  split->setSizes({160, 640});
  // the scene and the editor take the window's whole height; the plots go under the 3D view
  setCorner(Qt::TopRightCorner, Qt::RightDockWidgetArea);
  setCorner(Qt::BottomRightCorner, Qt::RightDockWidgetArea);
  sceneDock->setWidget(split);
  addDockWidget(Qt::RightDockWidgetArea, sceneDock);
  resizeDocks({sceneDock}, {420}, Qt::Horizontal);  // the field editor's labels and spin boxes side by side

  auto* plotDock = new QDockWidget(tr("Plots"), this);
  plotDock->setObjectName(QStringLiteral("plotDock"));
  m_plots = new PlotPanel;
  connect(m_plots, &PlotPanel::failed, this, [this](const QString& m) { m_feedback->error(tr("Export failed"), m); });
  plotDock->setWidget(m_plots);
  addDockWidget(Qt::BottomDockWidgetArea, plotDock);
  connect(m_timeline, &Timeline::branchSwapped, m_plots, [this](double t) {
    m_plots->replaceAfter(t, m_timeline->diagnosticsAfter(m_doc->surfaces().indexOf(m_plotted), t));
  });
  connect(m_timeline, &Timeline::changed, m_plots, [this](double t) { m_plots->showUntil(m_timeline->isAtEnd() ? INFINITY : t); });

  auto* timelineDock = new QDockWidget(tr("Timeline"), this);
  timelineDock->setObjectName(QStringLiteral("timelineDock"));
  m_timelinePanel = new TimelinePanel(*m_timeline, [this] { return clock().speed(); });
  timelineDock->setWidget(m_timelinePanel);
  addDockWidget(Qt::BottomDockWidgetArea, timelineDock);
  splitDockWidget(timelineDock, plotDock, Qt::Vertical);  // the strip right under the view
}

void MainWindow::saveLayout() {
  QSettings settings;
  settings.setValue(kGeometryKey, saveGeometry());
  settings.setValue(kLayoutKey, saveState());
}

void MainWindow::restoreLayout() {
  // nothing saved yet (or unreadable): the default size and docks stay
  const QSettings settings;
  restoreGeometry(settings.value(kGeometryKey).toByteArray());
  restoreState(settings.value(kLayoutKey).toByteArray());
}

// ---------------------------------------------------------------------------------------------
// The window's events

void MainWindow::dragEnterEvent(QDragEnterEvent* e) { m_files->dragEnter(e); }

void MainWindow::dropEvent(QDropEvent* e) { m_files->drop(e); }

void MainWindow::closeEvent(QCloseEvent* e) {
  if (!maybeSave()) {
    e->ignore();
    return;
  }
  clock().setPlaying(false);
  if (isRecording()) stopRecording();  // a finished video rather than a lost one
  autosave().discard();  // a clean quit
  autosave().setInterval(0);
  saveLayout();
  QMainWindow::closeEvent(e);
}

bool MainWindow::eventFilter(QObject* watched, QEvent* e) {
  if (e->type() == QEvent::Resize && m_viewer && watched == m_viewer->getGLWidget()) m_listener->scheduleChanged();
  return QMainWindow::eventFilter(watched, e);
}

// ---------------------------------------------------------------------------------------------
// The scene in the view and the panels

void MainWindow::showScene() {
  if (isRecording()) stopRecording();  // its surfaces leave the view
  m_wrapper->removeAllChildren();
  m_wrapper->addChild(m_status->frameCounter());
  m_wrapper->addChild(m_backlight->node());
  m_wrapper->addChild(m_doc->root());
  m_wrapper->addChild(m_overlays->node());  // the drag tool, the net display and the grid
  m_netDisplay->setScene(m_doc->root());
  // SoQt looks for a camera only when it gets a new graph: with the same root it kept its own
  // camera, which the scene's camera overrode in rendering while the mouse moved SoQt's
  m_viewer->setSceneGraph(nullptr);
  m_viewer->setSceneGraph(m_wrapper);
  m_drag->setCamera(m_viewer->getCamera());
  m_framing->sceneShown(m_doc->root());
  m_decorations->sceneShown(m_doc->root());
  m_listener->listen(m_doc->surfaces());
  m_timeline->setSurfaces(m_doc->surfaces());
  m_status->restart();
  m_selectedSurface = -1;
  m_plotted = nullptr;
  m_scenePanel->populate();
  m_listener->scheduleChanged();
  // a scene opens playing when its author let a surface follow the clock (`on`, read, not set)
  bool authoredOn = false;
  for (SoBSplineDeformSurface* s : m_doc->surfaces()) authoredOn |= bool(s->on.getValue());
  setPlaying(authoredOn);
}

SoBSplineDeformSurface* MainWindow::selectedSurface() const {
  const QVector<SoBSplineDeformSurface*>& surfaces = m_doc->surfaces();
  return surfaces.isEmpty() ? nullptr : surfaces[std::max(0, std::min(m_selectedSurface, int(surfaces.size()) - 1))];
}

void MainWindow::fieldChanged(SoFieldContainer* owner, SoField* field) {
  if (owner->isOfType(SoForceField::getClassTypeId()) && field == &static_cast<SoForceField*>(owner)->type) {
    structureChanged(owner);  // its label in the panel and the fields it shows change
    return;
  }
  if (m_editor->container() != owner) selectNode(owner);  // an undo shows what it changed
  m_editor->refresh();
}

void MainWindow::structureChanged(SoBase* focus) {
  m_drag->release();
  m_listener->listen(m_doc->surfaces());  // surfaces that came in (they follow the same realTime as the others)
  m_timeline->setSurfaces(m_doc->surfaces());
  m_scenePanel->populate();  // selects the first surface, if any
  m_decorations->refit();
  if ((!focus || !selectNode(focus)) && m_doc->surfaces().isEmpty()) {
    m_editor->setContainer(nullptr, QString());
    m_plots->setSurface(nullptr, QString());
    m_plotted = nullptr;
  }
}

void MainWindow::surfaceSelected(int index) {
  SoBSplineDeformSurface* s = m_doc->surfaces()[index];
  m_selectedSurface = index;
  m_editor->setContainer(s, m_doc->nameOf(s));
  if (s != m_plotted) m_plots->setSurface(s, m_doc->nameOf(s));  // the same one again (a panel rebuild): its history stays
  m_plotted = s;
  m_status->follow(s);
  updateStatus();
}

void MainWindow::forceFieldSelected(int index) {
  SoForceField* f = m_doc->forceFields()[index];
  m_editor->setContainer(f, m_doc->nameOf(f));
}

// ---------------------------------------------------------------------------------------------
// What the surfaces tell (SurfaceListener): the plots take every step; the rest of the window
// (drag line, framing, control net, editor, status, recording) is brought up to date once per
// turn of the event loop, however many steps were taken in it.

void MainWindow::surfaceEvent(SoBSplineDeformSurface* surface, SoBSplineDeformSurface::Event e) {
  if (surface != m_plotted) return;
  if (e == SoBSplineDeformSurface::STEPPED) m_plots->sample();
  if (e == SoBSplineDeformSurface::STATE_CHANGED && !m_timeline->isRestoring()) m_plots->restart();
}

void MainWindow::refreshViews() {
  // a live edit the scene refuses (or a refused force field) stops the clock: nothing runs on
  // values the scene refuses
  if (isPlaying() && sceneRefused(*m_doc)) setPlaying(false);
  m_drag->update();
  // the camera stays put under a drag and through a recording (one camera for the whole video)
  if (m_drag->isDragging() || isRecording())
    m_framing->hold();
  else
    m_framing->follow();
  m_netDisplay->update();
  m_decorations->follow();  // a cloth that falls below the grid does not hang through it
  m_plots->updateAxes();
  m_editor->refresh();  // live values (time, steps) included
  updateStatus();
  m_recording->recordFrames();
}

void MainWindow::updateStatus() {
  SoBSplineDeformSurface* troubled = nullptr;
  for (SoBSplineDeformSurface* s : m_doc->surfaces())
    if (!troubled && s->problem().kind != SoBSplineDeformSurface::Problem::NONE) troubled = s;
  QStringList refused;
  QStringList details;
  if (sceneRefused(*m_doc)) {
    for (const SceneProblem& p : sceneProblems(*m_doc)) {
      const QString what = p.field.isEmpty() ? p.node : p.node + QLatin1Char('.') + p.field;
      if (!refused.contains(what)) refused << what;
      details << p.text();
    }
  }
  m_status->setReplaySpeed(m_timelinePanel && m_timelinePanel->isReplaying() ? clock().speed() : 0.0);
  m_status->update(selectedSurface(), isPlaying(), troubled, refused, details.join(QLatin1Char('\n')));
}

// ---------------------------------------------------------------------------------------------
// Commands handed over to the parts that do them

bool MainWindow::openScene(const QString& path) { return m_files->openScene(path); }
void MainWindow::openDefaultScene() { m_files->openDefaultScene(); }
bool MainWindow::saveSceneAs(const QString& path) { return m_files->saveSceneAs(path); }
bool MainWindow::saveScene() { return m_files->saveScene(); }
bool MainWindow::isTemplate() const { return m_files->isTemplate(); }
bool MainWindow::maybeSave() { return m_files->maybeSave(); }
QString MainWindow::openFolder() const { return DocumentActions::openFolder(); }
bool MainWindow::offerRecovery(RecoveryChoice choice) { return m_files->offerRecovery(choice); }
bool MainWindow::restoreRecovery(const RecoveryFile& file) { return m_files->restoreRecovery(file); }
Autosave& MainWindow::autosave() { return m_files->autosave(); }
void MainWindow::open() { m_files->open(); }
void MainWindow::reload() { m_files->reload(); }
void MainWindow::save() { m_files->saveScene(); }
void MainWindow::saveAs() { m_files->saveAs(); }

bool MainWindow::openStates(const QString& path) {
  StateFileContents contents;
  QString error;
  if (readStateFile(path, contents, error) && m_timeline->load(path, contents)) {
    // the plots show the whole kept run, not only the state opened (one point draws no line)
    m_plots->restart();
    m_plots->replaceAfter(-INFINITY, m_timeline->diagnosticsAfter(m_doc->surfaces().indexOf(m_plotted), -INFINITY));
    return true;
  }
  m_feedback->error(tr("Open States"), error.isEmpty() ? m_timeline->error() : error);
  return false;
}

void MainWindow::openStatesDialog() {
  const QString path = QFileDialog::getOpenFileName(this, tr("Open States"), QString(), tr("State files (*.states);;All files (*)"));
  if (!path.isEmpty()) openStates(path);
}

QImage MainWindow::screenshot(const QSize& size) { return m_exports->screenshot(size); }
bool MainWindow::saveScreenshot(const QString& path, const QSize& size) { return m_exports->saveScreenshot(path, size); }
QImage MainWindow::windowScreenshot() { return m_exports->windowScreenshot(); }
void MainWindow::screenshotDialog() { m_exports->screenshotDialog(); }
bool MainWindow::exportMesh(const QString& path) { return m_exports->exportMesh(path); }
bool MainWindow::exportControlNet(const QString& path) { return m_exports->exportControlNet(path); }
void MainWindow::exportMeshDialog() { m_exports->exportMeshDialog(); }
void MainWindow::exportControlNetDialog() { m_exports->exportControlNetDialog(); }

bool MainWindow::startRecording(const QString& path, double fps) { return m_recording->start(path, fps); }
bool MainWindow::stopRecording() { return m_recording->stop(); }
bool MainWindow::isRecording() const { return m_recording->isRecording(); }
void MainWindow::recordToggled(bool on) { m_recording->toggled(on); }

ViewerClock& MainWindow::clock() { return m_simulation->clock(); }
bool MainWindow::isPlaying() const { return m_simulation->isPlaying(); }
void MainWindow::setPlaying(bool on) { m_simulation->setPlaying(on); }
void MainWindow::setSpeed(double speed) { m_simulation->setSpeed(speed); }
void MainWindow::play() { setPlaying(true); }
void MainWindow::pause() { setPlaying(false); }
void MainWindow::step() { m_simulation->step(); }
void MainWindow::reset() { m_simulation->reset(); }
bool MainWindow::solveStatic() { return m_simulation->solveStatic(); }

bool MainWindow::insertForceField(int type) { return m_edits->insertForceField(type); }
void MainWindow::insertSurface() { m_edits->insertSurface(); }
void MainWindow::insertPresetSurface(const MaterialPreset& preset) { m_edits->insertSurface(preset); }
bool MainWindow::deleteSelected() { return m_edits->deleteSelected(); }
long MainWindow::framesDrawn() const { return m_status->framesDrawn(); }

void MainWindow::setDragMode(bool on) {
  m_drag->setEnabled(on);
  m_viewer->setViewing(!on);  // in drag mode mouse events reach the scene, not the camera
  if (m_dragAction->isChecked() != on) m_dragAction->setChecked(on);
}

SoBase* MainWindow::selectedNode() const { return m_scenePanel->selectedNode(); }
bool MainWindow::selectNode(SoBase* node) { return m_scenePanel->selectNode(node); }
void MainWindow::selectSurface(int index) { m_scenePanel->selectSurface(index); }
void MainWindow::showFieldReference() { bsdeform::showFieldReference(this); }
void MainWindow::setInteractive(bool on) { m_feedback->setInteractive(on); }
const QString& MainWindow::lastError() const { return m_feedback->lastError(); }

}  // namespace bsdeform
