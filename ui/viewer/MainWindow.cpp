// SPDX-License-Identifier: MIT
#include "MainWindow.h"

#include <Inventor/Qt/SoQt.h>
#include <Inventor/Qt/viewers/SoQtExaminerViewer.h>
#include <Inventor/actions/SoGLRenderAction.h>
#include <Inventor/nodes/SoCallback.h>
#include <Inventor/nodes/SoSeparator.h>

#include <QAction>
#include <cstdio>
#include <QApplication>
#include <QCloseEvent>
#include <QDialog>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QDragEnterEvent>
#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QInputDialog>
#include <QSignalBlocker>
#include <QLabel>
#include <QLocale>
#include <QMenuBar>
#include <QMessageBox>
#include <QMimeData>
#include <QPushButton>
#include <QScrollArea>
#include <QSettings>
#include <QSplitter>
#include <QStatusBar>
#include <QTextBrowser>
#include <QTimer>
#include <QToolBar>
#include <QUndoStack>
#include <QVBoxLayout>

#include "AtomicFile.h"
#include "ControlNetDisplay.h"
#include "DragTool.h"
#include "EditCommands.h"
#include "FieldEditor.h"
#include "FieldWidgets.h"
#include "HelpDialogs.h"
#include "PlotPanel.h"
#include "Recorder.h"
#include "ScenePanel.h"
#include "Screenshot.h"
#include "ViewFraming.h"
#include "ViewerClock.h"
#include "bsdeform/FieldInfo.h"
#include "bsdeform/SceneRunner.h"
#include "bsdeform/Simulation.h"
#include "bsdeform/SoBSplineDeformSurface.h"
#include "bsdeform/SoForceField.h"

namespace bsdeform {

namespace {
constexpr int kMaxRecent = 8;
const char* kRecentKey = "recentFiles";
const char* kFolderKey = "lastFolder";
const char* kGeometryKey = "window/geometry";  // size and place of the window
const char* kLayoutKey = "window/layout";      // docks and tool bar (QMainWindow::saveState)
}  // namespace

MainWindow::MainWindow(QWidget* parent) : QMainWindow(parent), m_doc(new SceneDocument), m_drag(new DragTool) {
  setWindowTitle(tr("bsdeform viewer"));
  setAcceptDrops(true);
  m_clock = new ViewerClock(this);
  m_undo = new QUndoStack(this);
  m_edit.reset(new EditContext{*m_doc, [this](SoFieldContainer* o, SoField* f) { fieldChanged(o, f); },
                               [this](SoBase* focus) { structureChanged(focus); }});
  connect(m_undo, &QUndoStack::cleanChanged, this, [this](bool clean) { setWindowModified(!clean || m_restoredUnsaved); });
  m_wrapper = new SoSeparator;
  m_wrapper->ref();
  m_frameCounter = new SoCallback;
  m_frameCounter->ref();  // it outlives every scene shown in the wrapper
  m_frameCounter->setCallback(countFrame, this);

  auto* central = new QWidget(this);
  auto* layout = new QVBoxLayout(central);
  layout->setContentsMargins(0, 0, 0, 0);
  setCentralWidget(central);
  m_viewer = new SoQtExaminerViewer(central);
  layout->addWidget(m_viewer->getWidget());
  m_viewer->setBackgroundColor(SbColor(0.18f, 0.2f, 0.24f));
  m_viewer->setSceneGraph(m_wrapper);
  m_framing = new ViewFraming(m_viewer, this);
  m_viewer->getGLWidget()->installEventFilter(this);
  m_netDisplay = new ControlNetDisplay(this);

  createActions();
  createEditActions();
  createHelpMenu();
  createDocks();
  createStatusBar();
  updateRecentMenu();
  resize(1200, 800);
  restoreLayout();

  m_recorder = std::make_unique<Recorder>();
  m_rateClock.start();

  m_autosave = new Autosave(*m_doc, this);
  connect(m_autosave, &Autosave::failed, this, [this](const QString& message) {
    // set first: the timer keeps running while the dialog is open, and must not stack dialogs
    const bool first = !m_autosaveFailing;
    m_autosaveFailing = true;
    if (first)
      reportError(tr("Autosave failed"), message);
    else
      statusBar()->showMessage(tr("Autosave failed: %1").arg(message), 10000);
  });
  connect(m_autosave, &Autosave::saved, this, [this] { m_autosaveFailing = false; });
}

MainWindow::~MainWindow() {
  listenToSurfaces(false);
  m_undo->clear();  // the commands hold nodes of the scene
  m_drag->release();
  m_viewer->setSceneGraph(nullptr);
  delete m_viewer;
  m_wrapper->unref();
  m_frameCounter->unref();
}

void MainWindow::countFrame(void* data, SoAction* action) {
  if (action->isOfType(SoGLRenderAction::getClassTypeId())) ++static_cast<MainWindow*>(data)->m_frames;
}

// ---------------------------------------------------------------------------------------------

void MainWindow::createActions() {
  QMenu* file = menuBar()->addMenu(tr("&File"));
  QAction* a = file->addAction(tr("&Open..."), this, &MainWindow::open);
  a->setShortcut(QKeySequence::Open);
  m_recentMenu = file->addMenu(tr("Open &Recent"));
  a = file->addAction(tr("Re&load"), this, &MainWindow::reload);
  a->setShortcut(QKeySequence::Refresh);
  a = file->addAction(tr("&Save"), this, &MainWindow::save);
  a->setShortcut(QKeySequence::Save);
  a = file->addAction(tr("Save &As..."), this, &MainWindow::saveAs);
  a->setShortcut(QKeySequence::SaveAs);
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
  m_playAction = new QAction(tr("Play"), this);
  m_playAction->setCheckable(true);
  m_playAction->setShortcut(QKeySequence(Qt::Key_Space));
  m_playAction->setShortcutContext(Qt::ApplicationShortcut);
  m_playAction->setToolTip(tr("Play / pause (Space)"));
  connect(m_playAction, &QAction::triggered, this, [this](bool on) { setPlaying(on); });
  QAction* stepAction = new QAction(tr("Step"), this);
  stepAction->setShortcut(QKeySequence(tr("S")));
  stepAction->setToolTip(tr("One time step (S)"));
  connect(stepAction, &QAction::triggered, this, &MainWindow::step);
  QAction* resetAction = new QAction(tr("Reset"), this);
  resetAction->setShortcut(QKeySequence(tr("R")));
  resetAction->setToolTip(tr("Back to the rest state (R)"));
  connect(resetAction, &QAction::triggered, this, &MainWindow::reset);
  m_dragAction = new QAction(tr("Drag"), this);
  m_dragAction->setCheckable(true);
  m_dragAction->setShortcut(QKeySequence(tr("D")));
  m_dragAction->setToolTip(tr("Drag mode: press on a surface and pull (D); off: camera mode"));
  connect(m_dragAction, &QAction::toggled, this, &MainWindow::setDragMode);
  m_recordAction = new QAction(tr("Record"), this);
  m_recordAction->setCheckable(true);
  m_recordAction->setToolTip(tr("Record the 3D view into a video (MP4, WebM) or PNG images, at a rate in simulated time"));
  connect(m_recordAction, &QAction::toggled, this, &MainWindow::recordToggled);
  for (QAction* act : {m_playAction, stepAction, resetAction, m_dragAction, m_recordAction}) {
    sim->addAction(act);
    bar->addAction(act);
  }
  sim->addSeparator();
  QAction* staticAction = sim->addAction(tr("Solve S&tatic"), this, &MainWindow::solveStatic);
  staticAction->setShortcut(QKeySequence(tr("Ctrl+E")));
  staticAction->setToolTip(tr("Every surface to the equilibrium of its loads at t = 0, at rest (the paper's A P = L); "
                              "undo brings the state back (Ctrl+E)"));
  bar->addSeparator();
  bar->addWidget(new QLabel(tr(" speed ")));
  m_speed = new QDoubleSpinBox;
  m_speed->setRange(0.01, 100.0);
  m_speed->setDecimals(2);
  m_speed->setValue(1.0);
  m_speed->setSuffix(tr(" x"));
  m_speed->setToolTip(tr("Simulated seconds per real second (not written to the scene file)"));
  m_speed->installEventFilter(new SimulationKeysPassThrough(m_speed));
  connect(m_speed, QOverload<double>::of(&QDoubleSpinBox::valueChanged), m_clock, &ViewerClock::setSpeed);
  bar->addWidget(m_speed);

  QMenu* view = menuBar()->addMenu(tr("&View"));
  m_framing->addActions(view);
  view->addSeparator();
  m_netDisplay->addActions(view);

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
  insert->addAction(tr("&Surface"), this, &MainWindow::insertSurface);
}

void MainWindow::showFieldReference() {
  if (!m_fieldReference) {
    m_fieldReference = new QDialog(this);
    m_fieldReference->setWindowTitle(tr("Field reference"));
    auto* text = new QTextBrowser;
    text->setMarkdown(QString::fromStdString(fieldReferenceMarkdown()));
    auto* layout = new QVBoxLayout(m_fieldReference);
    layout->addWidget(text);
    m_fieldReference->resize(1000, 700);
  }
  m_fieldReference->show();
  m_fieldReference->raise();
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
  connect(m_editor, &FieldEditor::notice, this, [this](const QString& m) { statusBar()->showMessage(m, 8000); });
  // after an edit the keyboard goes back to the 3D view, where Space, S, R, D act
  connect(m_editor, &FieldEditor::done, this, [this] { m_viewer->getGLWidget()->setFocus(Qt::OtherFocusReason); });
  m_editor->setChangeHandler([this](SoFieldContainer* owner, SoField* field, const SoField& before, bool beforeIsDefault) {
    m_undo->push(new SetFieldCommand(*m_edit, owner, field, before, beforeIsDefault, *field, true));
  });
  connect(m_editor, &FieldEditor::rejected, this, [this](const QString& m) { statusBar()->showMessage(m, 5000); });
  auto* scroll = new QScrollArea;
  scroll->setWidget(m_editor);
  scroll->setWidgetResizable(true);
  split->addWidget(m_scenePanel);
  split->addWidget(scroll);
  split->setStretchFactor(1, 3);
  sceneDock->setWidget(split);
  addDockWidget(Qt::RightDockWidgetArea, sceneDock);
  resizeDocks({sceneDock}, {420}, Qt::Horizontal);  // the field editor's labels and spin boxes side by side

  auto* plotDock = new QDockWidget(tr("Plots"), this);
  plotDock->setObjectName(QStringLiteral("plotDock"));
  m_plots = new PlotPanel;
  connect(m_plots, &PlotPanel::failed, this, [this](const QString& m) { reportError(tr("Export failed"), m); });
  plotDock->setWidget(m_plots);
  addDockWidget(Qt::BottomDockWidgetArea, plotDock);
}

void MainWindow::createStatusBar() {
  m_timeLabel = new QLabel;
  m_rateLabel = new QLabel;
  m_modelLabel = new QLabel;
  m_stateLabel = new QLabel;
  for (QLabel* l : {m_timeLabel, m_rateLabel, m_modelLabel, m_stateLabel}) statusBar()->addPermanentWidget(l);
}

// ---------------------------------------------------------------------------------------------
// Files

void MainWindow::reportError(const QString& title, const QString& message) {
  m_lastError = message;
  statusBar()->showMessage(title + QStringLiteral(": ") + message.section(QLatin1Char('\n'), 0, 0), 10000);
  if (m_interactive)
    QMessageBox::warning(this, title, message);
  else
    std::fprintf(stderr, "bsdeform-viewer: %s: %s\n", title.toUtf8().constData(), message.toUtf8().constData());
}

bool MainWindow::openScene(const QString& path) {
  QString error;
  m_drag->release();
  if (!m_doc->load(path, error)) {
    reportError(tr("Cannot open scene"), error);
    return false;
  }
  m_lastError.clear();
  addRecent(QFileInfo(path).absoluteFilePath());
  rememberFolder(path);
  showScene();
  m_autosave->markClean();
  return true;
}

void MainWindow::openDefaultScene() {
  QFile f(QStringLiteral(":/default.iv"));
  QString error;
  if (!f.open(QIODevice::ReadOnly) || !m_doc->loadFromText(f.readAll(), tr("default scene"), error)) {
    reportError(tr("Cannot open the default scene"), error);
    return;
  }
  showScene();
  m_autosave->markClean();
}

void MainWindow::showScene() {
  if (m_recorder && m_recorder->active()) stopRecording();  // its surfaces leave the view
  m_undo->clear();  // the edits belong to the scene that was shown
  m_restoredUnsaved = false;
  m_wrapper->removeAllChildren();
  m_wrapper->addChild(m_frameCounter);
  m_wrapper->addChild(m_drag->node());
  m_wrapper->addChild(m_doc->root());
  m_wrapper->addChild(m_netDisplay->node());
  m_netDisplay->setScene(m_doc->root());
  // SoQt looks for a camera only when it gets a new graph: with the same root it kept its own
  // camera, which the scene's camera overrode in rendering while the mouse moved SoQt's
  m_viewer->setSceneGraph(nullptr);
  m_viewer->setSceneGraph(m_wrapper);
  m_drag->setCamera(m_viewer->getCamera());
  m_framing->sceneShown(m_doc->root());
  setWindowTitle(tr("%1[*] - bsdeform viewer").arg(m_doc->path().isEmpty() ? tr("default scene") : QFileInfo(m_doc->path()).fileName()));
  setWindowModified(false);
  listenToSurfaces(true);
  m_frames = m_lastFrames = 0;
  m_lastSteps = 0;
  m_selectedSurface = -1;
  m_plotted = nullptr;
  m_scenePanel->populate();
  scheduleRefresh();
  // a scene opens playing when its author let a surface follow the clock (`on`, read, not set)
  bool authoredOn = false;
  for (SoBSplineDeformSurface* s : m_doc->surfaces()) authoredOn |= bool(s->on.getValue());
  setPlaying(authoredOn);
}

void MainWindow::open() {
  if (!maybeSave()) return;
  const QString path = QFileDialog::getOpenFileName(this, tr("Open scene"), openFolder(), tr("Inventor scenes (*.iv);;All files (*)"));
  if (!path.isEmpty()) openScene(path);
}

void MainWindow::openAfterAsking(const QString& path) {
  if (maybeSave()) openScene(path);
}

QString MainWindow::openFolder() const {
  const QString last = QSettings().value(kFolderKey).toString();
  if (!last.isEmpty() && QFileInfo(last).isDir()) return last;
  // the installed scenes, then the source tree's (a build that is run where it was built)
  for (const QString& dir : {QCoreApplication::applicationDirPath() + QStringLiteral("/../share/bsdeform/scenes"),
                             QStringLiteral(BSDEFORM_SOURCE_SCENES_DIR)})
    if (QFileInfo(dir).isDir()) return QFileInfo(dir).canonicalFilePath();
  return QString();
}

void MainWindow::rememberFolder(const QString& path) {
  QSettings().setValue(kFolderKey, QFileInfo(path).absolutePath());
}

bool MainWindow::maybeSave() {
  if ((m_undo->isClean() && !m_restoredUnsaved) || !m_interactive) return true;
  const QString name = m_doc->path().isEmpty() ? tr("the default scene") : QFileInfo(m_doc->path()).fileName();
  const auto answer = QMessageBox::warning(this, tr("Unsaved changes"), tr("Save the changes to %1?").arg(name),
                                           QMessageBox::Save | QMessageBox::Discard | QMessageBox::Cancel, QMessageBox::Save);
  if (answer == QMessageBox::Cancel) return false;
  if (answer == QMessageBox::Save) return saveScene();
  return true;
}

void MainWindow::reload() {
  if (!maybeSave()) return;
  if (m_doc->path().isEmpty())
    openDefaultScene();
  else
    openScene(m_doc->path());
}

bool MainWindow::saveSceneAs(const QString& path) {
  QString error;
  if (!m_doc->save(path, error)) {
    reportError(tr("Cannot save scene"), error);
    return false;
  }
  addRecent(QFileInfo(path).absoluteFilePath());
  rememberFolder(path);
  if (m_doc->path() != path) {
    m_doc->setPath(path);
    setWindowTitle(tr("%1[*] - bsdeform viewer").arg(QFileInfo(path).fileName()));
  }
  m_undo->setClean();
  m_restoredUnsaved = false;
  setWindowModified(false);
  m_autosave->markClean();  // saved: the recovery file is no longer needed
  statusBar()->showMessage(tr("Saved %1").arg(path), 5000);
  return true;
}

bool MainWindow::saveScene() {
  if (m_doc->path().isEmpty()) {
    saveAs();
    return m_undo->isClean() && !m_restoredUnsaved;
  }
  return saveSceneAs(m_doc->path());
}

void MainWindow::save() { saveScene(); }

void MainWindow::saveAs() {
  // QFileDialog asks before replacing an existing file; the file is written atomically.
  QString path = QFileDialog::getSaveFileName(this, tr("Save scene as"), m_doc->path().isEmpty() ? openFolder() : m_doc->path(),
                                              tr("Inventor scenes (*.iv)"));
  if (path.isEmpty()) return;
  if (QFileInfo(path).suffix().isEmpty()) path += QStringLiteral(".iv");
  saveSceneAs(path);
}

bool MainWindow::exportSurface(const QString& path, bool controlNet) {
  if (m_doc->surfaces().isEmpty()) {
    reportError(tr("Export failed"), tr("the scene has no surface"));
    return false;
  }
  SoBSplineDeformSurface* s = m_doc->surfaces()[std::max(0, std::min(m_selectedSurface, int(m_doc->surfaces().size()) - 1))];
  QString error;
  if (!(controlNet ? m_doc->exportControlNet(s, path, error) : m_doc->exportMesh(s, path, error))) {
    reportError(tr("Export failed"), error);
    return false;
  }
  statusBar()->showMessage(tr("Exported %1 to %2").arg(m_doc->nameOf(s), path), 5000);
  return true;
}

bool MainWindow::exportMesh(const QString& path) { return exportSurface(path, false); }

bool MainWindow::exportControlNet(const QString& path) { return exportSurface(path, true); }

void MainWindow::exportMeshDialog() { exportDialog(false); }

void MainWindow::exportControlNetDialog() { exportDialog(true); }

void MainWindow::exportDialog(bool controlNet) {
  const QStringList filters = controlNet ? QStringList{tr("Points, x y z per line (*.xyz)"), tr("Wavefront OBJ, points and net lines (*.obj)")}
                                         : QStringList{tr("Wavefront OBJ (*.obj)"), tr("STL (*.stl)")};
  QString filter;
  QString path = QFileDialog::getSaveFileName(this, controlNet ? tr("Export the control net of the selected surface")
                                                               : tr("Export mesh of the selected surface"),
                                              m_doc->path().isEmpty() ? openFolder() : QFileInfo(m_doc->path()).absolutePath(),
                                              filters.join(QStringLiteral(";;")), &filter);
  if (path.isEmpty()) return;
  if (QFileInfo(path).suffix().isEmpty()) path += QLatin1Char('.') + filter.section(QStringLiteral("(*."), 1).chopped(1);
  exportSurface(path, controlNet);
}

QImage MainWindow::screenshot(const QSize& size) {
  QString error;
  const QImage img = Screenshot(m_viewer).view(m_doc->root(), size, error);
  if (!error.isEmpty()) reportError(tr("Screenshot failed"), error);
  return img;
}

QImage MainWindow::windowScreenshot() { return Screenshot(m_viewer).window(this); }

bool MainWindow::saveScreenshot(const QString& path, const QSize& size) {
  const QImage img = screenshot(size);
  if (img.isNull()) return false;
  QString error;
  if (!savePngAtomically(path, img, error)) {
    reportError(tr("Screenshot failed"), error);
    return false;
  }
  statusBar()->showMessage(tr("Saved %1 (%2 x %3)").arg(path).arg(img.width()).arg(img.height()), 5000);
  return true;
}

void MainWindow::screenshotDialog() {
  QString path, error;
  QSize size;
  if (Screenshot(m_viewer).ask(this, path, size, error))
    saveScreenshot(path, size);
  else if (!error.isEmpty())
    reportError(tr("Screenshot"), error);
}

bool MainWindow::isRecording() const { return m_recorder->active(); }

bool MainWindow::startRecording(const QString& path, double fps) {
  if (m_doc->surfaces().isEmpty()) {
    reportError(tr("Record"), tr("the scene has no surface: recording follows a surface's simulated time"));
    return false;
  }
  QString error;
  const double t = m_doc->surfaces().first()->simulation().time();
  if (!m_recorder->start(path, fps, m_viewer->getGLWidget()->size(), t, error)) {
    reportError(tr("Record"), error);
    return false;
  }
  const QSignalBlocker block(m_recordAction);
  m_recordAction->setChecked(true);
  recordFrames();  // the first frame: the state when the recording starts
  return true;
}

bool MainWindow::stopRecording() {
  const QSignalBlocker block(m_recordAction);
  m_recordAction->setChecked(false);
  if (!m_recorder->active()) return true;
  const long long frames = m_recorder->frames();
  QString error;
  if (!m_recorder->stop(error)) {
    reportError(tr("Record"), error);
    return false;
  }
  statusBar()->showMessage(tr("Recorded %1 frames to %2").arg(frames).arg(m_recorder->path()), 8000);
  return true;
}

void MainWindow::recordFrames() {
  if (!m_recorder->active() || m_doc->surfaces().isEmpty()) return;
  QString error;
  const double t = m_doc->surfaces().first()->simulation().time();
  if (!m_recorder->capture(t, [this] { return screenshot(); }, error)) {
    const QSignalBlocker block(m_recordAction);
    m_recordAction->setChecked(false);
    reportError(tr("Record"), error);
    return;
  }
  statusBar()->showMessage(tr("Recording %1: %2 frames, t = %3 s").arg(QFileInfo(m_recorder->path()).fileName())
                               .arg(m_recorder->frames()).arg(t, 0, 'f', 2));
}

void MainWindow::recordToggled(bool on) {
  if (!on) {
    stopRecording();
    return;
  }
  QString path = QFileDialog::getSaveFileName(this, tr("Record the 3D view"), QString(),
                                              tr("Videos (*.mp4 *.webm);;PNG images, numbered (*.png)"));
  bool ok = !path.isEmpty();
  if (ok && QFileInfo(path).suffix().isEmpty()) path += QStringLiteral(".mp4");
  const double fps = ok ? QInputDialog::getDouble(this, tr("Record"), tr("Frames per simulated second:"), 25.0, 1.0,
                                                  240.0, 1, &ok)
                        : 0.0;
  if (!ok || !startRecording(path, fps)) {
    const QSignalBlocker block(m_recordAction);
    m_recordAction->setChecked(false);
  }
}

void MainWindow::addRecent(const QString& path) {
  QSettings settings;
  QStringList recent = settings.value(kRecentKey).toStringList();
  recent.removeAll(path);
  recent.prepend(path);
  while (recent.size() > kMaxRecent) recent.removeLast();
  settings.setValue(kRecentKey, recent);
  updateRecentMenu();
}

void MainWindow::updateRecentMenu() {
  m_recentMenu->clear();
  const QStringList recent = QSettings().value(kRecentKey).toStringList();
  for (const QString& path : recent)
    m_recentMenu->addAction(QFileInfo(path).fileName(), this, [this, path] { openAfterAsking(path); })->setToolTip(path);
  m_recentMenu->setEnabled(!recent.isEmpty());
}

void MainWindow::dragEnterEvent(QDragEnterEvent* e) {
  for (const QUrl& url : e->mimeData()->urls())
    if (url.isLocalFile() && url.toLocalFile().endsWith(QLatin1String(".iv"), Qt::CaseInsensitive)) {
      e->acceptProposedAction();
      return;
    }
}

void MainWindow::dropEvent(QDropEvent* e) {
  for (const QUrl& url : e->mimeData()->urls())
    if (url.isLocalFile()) {
      openAfterAsking(url.toLocalFile());
      return;
    }
}

void MainWindow::closeEvent(QCloseEvent* e) {
  if (!maybeSave()) {
    e->ignore();
    return;
  }
  m_clock->setPlaying(false);
  if (isRecording()) stopRecording();  // a finished video rather than a lost one
  m_autosave->discard();  // a clean quit
  m_autosave->setInterval(0);
  saveLayout();
  QMainWindow::closeEvent(e);
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

bool MainWindow::offerRecovery(RecoveryChoice choice) {
  const QVector<RecoveryFile> files = m_autosave->orphans();
  if (files.isEmpty()) return false;
  const RecoveryFile& newest = files.first();
  const QString what = newest.originalPath.isEmpty() ? tr("the default scene") : newest.originalPath;
  if (choice == RecoveryChoice::Ask && !m_interactive) choice = RecoveryChoice::Keep;
  if (choice == RecoveryChoice::Ask) {
    QMessageBox box(QMessageBox::Question, tr("Restore unsaved work?"),
                    tr("bsdeform-viewer did not quit cleanly. Its autosave of %1 from %2 can be restored.")
                        .arg(what, QLocale().toString(newest.saved, QLocale::ShortFormat)),
                    QMessageBox::NoButton, this);
    if (files.size() > 1) box.setInformativeText(tr("%n older recovery file(s) are in %1.", "", files.size() - 1).arg(m_autosave->directory()));
    QPushButton* restore = box.addButton(tr("Restore"), QMessageBox::AcceptRole);
    QPushButton* discard = box.addButton(tr("Discard"), QMessageBox::DestructiveRole);
    box.addButton(tr("Decide Later"), QMessageBox::RejectRole);
    box.setDefaultButton(restore);
    box.exec();
    choice = box.clickedButton() == restore   ? RecoveryChoice::Restore
             : box.clickedButton() == discard ? RecoveryChoice::Discard
                                              : RecoveryChoice::Keep;
  }
  switch (choice) {
    case RecoveryChoice::Restore:
      return restoreRecovery(newest);
    case RecoveryChoice::Discard:
      for (const RecoveryFile& f : files) Autosave::remove(f);
      statusBar()->showMessage(tr("Discarded %n recovery file(s)", "", files.size()), 5000);
      return false;
    case RecoveryChoice::Ask:
    case RecoveryChoice::Keep:
      break;
  }
  const QString kept = tr("%n recovery file(s) kept in %1 (newest: autosave of %2); start with --restore-recovery or "
                          "--discard-recovery", "", files.size())
                           .arg(m_autosave->directory(), what);
  statusBar()->showMessage(kept, 10000);
  if (!m_interactive) std::fprintf(stderr, "bsdeform-viewer: %s\n", kept.toUtf8().constData());
  return false;
}

bool MainWindow::restoreRecovery(const RecoveryFile& file) {
  QString error;
  m_drag->release();
  if (!m_doc->load(file.path, error)) {
    reportError(tr("Cannot restore the autosave"), error);  // the recovery file stays
    return false;
  }
  m_doc->setPath(file.originalPath);
  showScene();
  m_restoredUnsaved = true;  // the restored work is not in the scene's file yet
  setWindowModified(true);
  // this viewer's own copy first, then the old file goes: the work is on disk all the time
  if (!m_autosave->saveNow(error)) {
    reportError(tr("Autosave failed"), error);
  } else {
    Autosave::remove(file);
  }
  const QString message = tr("Restored the autosave of %1").arg(file.originalPath.isEmpty() ? tr("the default scene") : file.originalPath);
  statusBar()->showMessage(message, 10000);
  if (!m_interactive) std::fprintf(stderr, "bsdeform-viewer: %s\n", message.toUtf8().constData());
  return true;
}

// ---------------------------------------------------------------------------------------------
// Simulation controls

bool MainWindow::isPlaying() const { return m_clock->isPlaying(); }

void MainWindow::setPlaying(bool on) {
  m_clock->setPlaying(on);
  m_playAction->setChecked(on);
  m_playAction->setText(on ? tr("Pause") : tr("Play"));
  updateStatus();
}

void MainWindow::setSpeed(double speed) { m_speed->setValue(speed); }

void MainWindow::play() { setPlaying(true); }
void MainWindow::pause() { setPlaying(false); }

void MainWindow::step() {
  setPlaying(false);
  if (!m_doc->root()) return;
  // one step of the smallest time step, every surface to that common time (realTime is the
  // paused clock's: it stays)
  SceneRunner(m_doc->root(), SceneRunner::Clock::Untouched).step();
}

void MainWindow::reset() {
  m_drag->release();
  for (SoBSplineDeformSurface* s : m_doc->surfaces()) s->resetSimulation();
}

bool MainWindow::solveStatic() {
  setPlaying(false);
  m_drag->release();
  const QVector<SoBSplineDeformSurface*> surfaces = m_doc->surfaces();
  auto* command = new SolveStaticCommand(*m_edit, std::vector<SoBSplineDeformSurface*>(surfaces.begin(), surfaces.end()));
  if (!command->error().isEmpty()) {
    const QString error = command->error();
    delete command;
    reportError(tr("Solve Static"), error);
    return false;
  }
  const QString report = command->report();
  m_undo->push(command);
  statusBar()->showMessage(report, 10000);
  if (!m_interactive) std::fprintf(stderr, "bsdeform-viewer: %s\n", report.toUtf8().constData());
  return true;
}

void MainWindow::setDragMode(bool on) {
  m_drag->setEnabled(on);
  m_viewer->setViewing(!on);  // in drag mode mouse events reach the scene, not the camera
  if (m_dragAction->isChecked() != on) m_dragAction->setChecked(on);
}

// ---------------------------------------------------------------------------------------------
// Scene panel

SoBase* MainWindow::selectedNode() const { return m_scenePanel->selectedNode(); }

bool MainWindow::selectNode(SoBase* node) { return m_scenePanel->selectNode(node); }

bool MainWindow::insertForceField(int type) {
  SoBase* sel = selectedNode();
  SoBSplineDeformSurface* surface = nullptr;
  if (sel && sel->isOfType(SoBSplineDeformSurface::getClassTypeId()))
    surface = static_cast<SoBSplineDeformSurface*>(sel);
  else if (!m_doc->surfaces().isEmpty())
    surface = m_doc->surfaces()[std::max(0, std::min(m_selectedSurface, int(m_doc->surfaces().size()) - 1))];
  if (!surface) {
    reportError(tr("Insert force field"), tr("the scene has no surface to add a force field to"));
    return false;
  }
  m_undo->push(new InsertForceCommand(*m_edit, surface, type));
  return true;
}

void MainWindow::insertSurface() {
  if (!m_doc->root()) return;
  m_undo->push(new InsertSurfaceCommand(*m_edit, m_doc->root()));
}

bool MainWindow::deleteSelected() {
  SoBase* sel = selectedNode();
  if (!sel) return false;
  if (sel->isOfType(SoBSplineDeformSurface::getClassTypeId()))
    m_undo->push(new DeleteCommand(*m_edit, static_cast<SoBSplineDeformSurface*>(sel)));
  else
    m_undo->push(new DeleteCommand(*m_edit, static_cast<SoForceField*>(sel)));
  return true;
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
  listenToSurfaces(true);  // surfaces that came in (they follow the same realTime as the others)
  m_scenePanel->populate();  // selects the first surface, if any
  if ((!focus || !selectNode(focus)) && m_doc->surfaces().isEmpty()) {
    m_editor->setContainer(nullptr, QString());
    m_plots->setSurface(nullptr, QString());
    m_plotted = nullptr;
  }
}

void MainWindow::selectSurface(int index) { m_scenePanel->selectSurface(index); }

void MainWindow::surfaceSelected(int index) {
  SoBSplineDeformSurface* s = m_doc->surfaces()[index];
  m_selectedSurface = index;
  m_editor->setContainer(s, m_doc->nameOf(s));
  if (s != m_plotted) m_plots->setSurface(s, m_doc->nameOf(s));  // the same one again (a panel rebuild): its history stays
  m_plotted = s;
  m_lastSteps = s->simulation().stepCount();
}

void MainWindow::forceFieldSelected(int index) {
  SoForceField* f = m_doc->forceFields()[index];
  m_editor->setContainer(f, m_doc->nameOf(f));
}

// ---------------------------------------------------------------------------------------------
// What the surfaces tell (SoBSplineDeformSurface::addCallback): the plots take every step; the
// rest of the window (drag line, framing, control net, editor, status, recording) is brought up
// to date once per turn of the event loop, however many steps were taken in it.

void MainWindow::listenToSurfaces(bool on) {
  for (auto& l : m_listening) {
    l.first->removeCallback(l.second);
    l.first->unref();
  }
  m_listening.clear();
  if (!on) return;
  for (SoBSplineDeformSurface* s : m_doc->surfaces()) {
    s->ref();
    m_listening.emplace_back(s, s->addCallback([this](SoBSplineDeformSurface* surface, SoBSplineDeformSurface::Event e) {
      surfaceEvent(surface, e);
    }));
  }
}

void MainWindow::surfaceEvent(SoBSplineDeformSurface* surface, SoBSplineDeformSurface::Event e) {
  if (surface == m_plotted) {
    if (e == SoBSplineDeformSurface::STEPPED) m_plots->sample();
    if (e == SoBSplineDeformSurface::STATE_CHANGED) m_plots->restart();
  }
  scheduleRefresh();
}

void MainWindow::scheduleRefresh() {
  if (m_refreshPending) return;
  m_refreshPending = true;
  QTimer::singleShot(0, this, &MainWindow::refreshViews);
}

bool MainWindow::eventFilter(QObject* watched, QEvent* e) {
  if (e->type() == QEvent::Resize && m_viewer && watched == m_viewer->getGLWidget()) scheduleRefresh();
  return QMainWindow::eventFilter(watched, e);
}

void MainWindow::refreshViews() {
  m_refreshPending = false;
  m_drag->update();
  m_framing->follow();
  m_netDisplay->update();
  m_plots->updateAxes();
  m_editor->refresh();  // live values (time, steps) included
  updateStatus();
  recordFrames();
}

void MainWindow::updateStatus() {
  const double dt = m_rateClock.elapsed() / 1000.0;
  SoBSplineDeformSurface* s = m_doc->surfaces().isEmpty() ? nullptr : m_doc->surfaces()[std::max(0, m_selectedSurface)];
  const long steps = s ? s->simulation().stepCount() : 0;
  if (dt >= 1.0) {
    m_fps = (m_frames - m_lastFrames) / dt;
    m_stepsPerSecond = std::max(0L, steps - m_lastSteps) / dt;
    m_lastFrames = m_frames;
    m_lastSteps = steps;
    m_rateClock.restart();
  }
  m_rateLabel->setText(tr("%1 steps/s  %2 frames/s").arg(m_stepsPerSecond, 0, 'f', 1).arg(m_fps, 0, 'f', 1));
  if (!s) {
    m_timeLabel->clear();
    m_modelLabel->clear();
    m_stateLabel->clear();
    return;
  }
  const Simulation& sim = s->simulation();
  const ModelParameters& p = sim.parameters();
  m_timeLabel->setText(tr("t = %1 s").arg(sim.time(), 0, 'f', 3));
  // moving points: N1 N2 when all sides are clamped, more with free or periodic sides, minus pins
  const qlonglong moving = qlonglong(sim.space().numMoving()) - qlonglong(sim.pinnedRows().size());
  m_modelLabel->setText(tr("%1 moving control points (%2 DOFs)  dt %3  limit %4  sub-steps %5")
                            .arg(moving)
                            .arg(3 * moving)
                            .arg(p.timeStep)
                            .arg(sim.stabilityLimit(), 0, 'g', 4)
                            .arg(sim.subSteps()));
  const SoBSplineDeformSurface::Problem& problem = s->problem();
  if (sim.status() != Status::Ok) {
    m_stateLabel->setText(tr("<b style='color:#c00'>STOPPED: blew up</b>"));
    m_stateLabel->setToolTip(QString::fromStdString(sim.statusMessage()));
  } else if (problem.kind == SoBSplineDeformSurface::Problem::FIELD) {
    m_stateLabel->setText(tr("<b style='color:#c00'>refused: %1</b>").arg(QString::fromStdString(problem.field)));
    m_stateLabel->setToolTip(QString::fromStdString(problem.message));
  } else if (problem.kind != SoBSplineDeformSurface::Problem::NONE) {
    m_stateLabel->setText(tr("<b style='color:#b60'>warning</b>"));
    m_stateLabel->setToolTip(QString::fromStdString(problem.message));
  } else {
    m_stateLabel->setText(isPlaying() ? tr("running") : tr("paused"));
    m_stateLabel->setToolTip(QString());
  }
}

}  // namespace bsdeform
