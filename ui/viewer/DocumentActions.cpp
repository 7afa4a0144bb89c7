// SPDX-License-Identifier: MIT
#include "DocumentActions.h"

#include "SceneProblems.h"

#include <QCoreApplication>
#include <QDragEnterEvent>
#include <QDir>
#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QLocale>
#include <QMainWindow>
#include <QMenu>
#include <QMessageBox>
#include <QMimeData>
#include <QPushButton>
#include <QSettings>
#include <QStandardPaths>
#include <QUndoStack>
#include <memory>

#include "DragTool.h"
#include "Feedback.h"
#include "SceneDocument.h"
#include "SceneProblems.h"

namespace bsdeform {

namespace {
constexpr int kMaxRecent = 8;
const char* kRecentKey = "recentFiles";
const char* kFolderKey = "lastFolder";
}  // namespace

DocumentActions::DocumentActions(SceneDocument& doc, QUndoStack& undo, DragTool& drag, Feedback& feedback, QMainWindow& window)
    : QObject(&window), m_doc(doc), m_undo(undo), m_drag(drag), m_feedback(feedback), m_window(window) {
  connect(&m_undo, &QUndoStack::cleanChanged, this, [this](bool clean) { m_window.setWindowModified(!clean || m_restoredUnsaved); });
  m_autosave = new Autosave(m_doc, this);
  connect(m_autosave, &Autosave::failed, this, [this](const QString& message) {
    // set first: the timer keeps running while the dialog is open, and must not stack dialogs
    const bool first = !m_autosaveFailing;
    m_autosaveFailing = true;
    if (first)
      m_feedback.error(tr("Autosave failed"), message);
    else
      m_feedback.show(tr("Autosave failed: %1").arg(message), 10000);
  });
  connect(m_autosave, &Autosave::saved, this, [this] { m_autosaveFailing = false; });
}

void DocumentActions::setRecentMenu(QMenu* menu) {
  m_recentMenu = menu;
  updateRecentMenu();
}

// ---------------------------------------------------------------------------------------------
// Open, reload

bool DocumentActions::openScene(const QString& path) {
  QString error;
  m_drag.release();
  if (!m_doc.load(path, error)) {
    m_feedback.error(tr("Cannot open scene"), error);
    return false;
  }
  m_feedback.clearError();
  addRecent(QFileInfo(path).absoluteFilePath());
  const QString folder = QFileInfo(path).canonicalPath();
  m_template = shippedSceneFolders().contains(folder);
  if (!m_template) rememberFolder(path);  // Save As starts in the user's folder, not in the shipped scenes
  loaded();
  m_autosave->markClean();
  reportProblems();
  return true;
}

// Values the nodes refuse are listed when the scene opens, all of them in one box; the scene
// stays paused until they are fixed (SimulationControls::setPlaying).
void DocumentActions::reportProblems() {
  const QVector<SceneProblem> problems = sceneProblems(m_doc);
  if (problems.isEmpty()) return;
  QStringList lines;
  for (const SceneProblem& p : problems) lines << QStringLiteral("- ") + p.text();
  m_feedback.error(tr("Values refused in %1").arg(QFileInfo(m_doc.path()).fileName()),
                   tr("%1 has %n value(s) the simulation does not take. Nothing runs until they are changed; the "
                      "Field Editor shows each refused value as the file has it, in red with its reason.\n\n%2",
                      "", problems.size())
                       .arg(m_doc.path(), lines.join(QLatin1Char('\n'))));
}

void DocumentActions::openDefaultScene() {
  QFile f(QStringLiteral(":/default.iv"));
  QString error;
  if (!f.open(QIODevice::ReadOnly) || !m_doc.loadFromText(f.readAll(), tr("default scene"), error)) {
    m_feedback.error(tr("Cannot open the default scene"), error);
    return;
  }
  m_template = false;
  loaded();
  m_autosave->markClean();
}

void DocumentActions::loaded() {
  m_undo.clear();  // the edits belong to the scene that was shown
  m_restoredUnsaved = false;
  setTitle();
  m_window.setWindowModified(false);
  emit sceneLoaded();
}

void DocumentActions::setTitle() {
  const QString name = m_doc.path().isEmpty() ? tr("default scene") : QFileInfo(m_doc.path()).fileName();
  m_window.setWindowTitle(m_template ? tr("%1 (template)[*] - bsdeform viewer").arg(name) : tr("%1[*] - bsdeform viewer").arg(name));
}

QStringList DocumentActions::shippedSceneFolders() {
  QStringList out;  // in this order: the installed scenes, then the source tree's
  for (const QString& dir : {QCoreApplication::applicationDirPath() + QStringLiteral("/../share/bsdeform/scenes"),
                             QStringLiteral(BSDEFORM_SOURCE_SCENES_DIR)}) {
    const QString canonical = QFileInfo(dir).canonicalFilePath();
    if (!canonical.isEmpty() && !out.contains(canonical)) out << canonical;
  }
  return out;
}

void DocumentActions::open() {
  if (!maybeSave()) return;
  const QString path = QFileDialog::getOpenFileName(&m_window, tr("Open scene"), openFolder(), tr("Inventor scenes (*.iv);;All files (*)"));
  if (!path.isEmpty()) openScene(path);
}

void DocumentActions::openAfterAsking(const QString& path) {
  if (maybeSave()) openScene(path);
}

QString DocumentActions::openFolder() {
  const QString last = QSettings().value(kFolderKey).toString();
  if (!last.isEmpty() && QFileInfo(last).isDir()) return last;
  // the installed scenes, then the source tree's (a build that is run where it was built)
  const QStringList shipped = shippedSceneFolders();
  return shipped.isEmpty() ? QString() : shipped.front();
}

QString DocumentActions::userFolder() {
  const QString remembered = QSettings().value(kFolderKey).toString();
  if (!remembered.isEmpty() && QFileInfo(remembered).isDir() &&
      !shippedSceneFolders().contains(QFileInfo(remembered).canonicalFilePath()))
    return remembered;
  // writableLocation names ~/Documents whether or not it exists; a dialog given a folder that
  // does not exist opens in the working directory (a source tree, say)
  const QString documents = QStandardPaths::writableLocation(QStandardPaths::DocumentsLocation);
  if (!documents.isEmpty() && QFileInfo(documents).isDir()) return documents;
  return QDir::homePath();
}

void DocumentActions::rememberFolder(const QString& path) {
  QSettings().setValue(kFolderKey, QFileInfo(path).absolutePath());
}

void DocumentActions::reload() {
  if (!maybeSave()) return;
  if (m_doc.path().isEmpty())
    openDefaultScene();
  else
    openScene(m_doc.path());
}

// ---------------------------------------------------------------------------------------------
// Save

bool DocumentActions::maybeSave() {
  if ((m_undo.isClean() && !m_restoredUnsaved) || !m_feedback.isInteractive()) return true;
  const QString name = m_doc.path().isEmpty() ? tr("the default scene") : QFileInfo(m_doc.path()).fileName();
  std::unique_ptr<QMessageBox> box(unsavedChangesBox(&m_window, name));
  const int answer = box->exec();
  if (answer == QMessageBox::Cancel) return false;
  if (answer == QMessageBox::Save) return saveScene();
  return true;
}

QMessageBox* DocumentActions::unsavedChangesBox(QWidget* parent, const QString& name) {
  auto* box = new QMessageBox(QMessageBox::Warning, tr("Unsaved changes"), tr("Save the changes to %1?").arg(name),
                              QMessageBox::Save | QMessageBox::Discard | QMessageBox::Cancel, parent);
  box->setDefaultButton(QMessageBox::Cancel);
  box->setEscapeButton(QMessageBox::Cancel);
  return box;
}

bool DocumentActions::saveSceneAs(const QString& path) {
  QString error;
  if (!m_doc.save(path, error)) {
    m_feedback.error(tr("Cannot save scene"), error);
    return false;
  }
  addRecent(QFileInfo(path).absoluteFilePath());
  rememberFolder(path);
  m_template = shippedSceneFolders().contains(QFileInfo(path).canonicalPath());
  m_doc.setPath(path);
  setTitle();
  m_undo.setClean();
  m_restoredUnsaved = false;
  m_window.setWindowModified(false);
  m_autosave->markClean();  // saved: the recovery file is no longer needed
  m_feedback.show(tr("Saved %1").arg(path), 5000);
  return true;
}

bool DocumentActions::saveScene() {
  if (m_template && !m_feedback.isInteractive()) {
    m_feedback.error(tr("Cannot save scene"), tr("%1 is a scene that comes with bsdeform, opened as a template: Save As "
                                                 "gives your version a name of its own")
                                                  .arg(m_doc.path()));
    return false;
  }
  if (m_doc.path().isEmpty() || m_template) {
    saveAs();
    return m_undo.isClean() && !m_restoredUnsaved;
  }
  return saveSceneAs(m_doc.path());
}

void DocumentActions::saveAs() {
  // QFileDialog asks before replacing an existing file; the file is written atomically. A
  // template is offered under its name in the user's folder, not where it came from.
  QString start = m_doc.path().isEmpty() ? openFolder() : m_doc.path();
  if (m_template) start = QDir(userFolder()).filePath(QFileInfo(m_doc.path()).fileName());
  QString path = QFileDialog::getSaveFileName(&m_window, tr("Save scene as"), start, tr("Inventor scenes (*.iv)"));
  if (path.isEmpty()) return;
  if (QFileInfo(path).suffix().isEmpty()) path += QStringLiteral(".iv");
  saveSceneAs(path);
}

// ---------------------------------------------------------------------------------------------
// Recent files, drag and drop

void DocumentActions::addRecent(const QString& path) {
  QSettings settings;
  QStringList recent = settings.value(kRecentKey).toStringList();
  recent.removeAll(path);
  recent.prepend(path);
  while (recent.size() > kMaxRecent) recent.removeLast();
  settings.setValue(kRecentKey, recent);
  updateRecentMenu();
}

void DocumentActions::updateRecentMenu() {
  m_recentMenu->clear();
  const QStringList recent = QSettings().value(kRecentKey).toStringList();
  for (const QString& path : recent)
    m_recentMenu->addAction(QFileInfo(path).fileName(), this, [this, path] { openAfterAsking(path); })->setToolTip(path);
  m_recentMenu->setEnabled(!recent.isEmpty());
}

void DocumentActions::dragEnter(QDragEnterEvent* e) {
  for (const QUrl& url : e->mimeData()->urls())
    if (url.isLocalFile() && url.toLocalFile().endsWith(QLatin1String(".iv"), Qt::CaseInsensitive)) {
      e->acceptProposedAction();
      return;
    }
}

void DocumentActions::drop(QDropEvent* e) {
  for (const QUrl& url : e->mimeData()->urls())
    if (url.isLocalFile()) {
      openAfterAsking(url.toLocalFile());
      return;
    }
}

// ---------------------------------------------------------------------------------------------
// Recovery

bool DocumentActions::offerRecovery(RecoveryChoice choice) {
  const QVector<RecoveryFile> files = m_autosave->orphans();
  if (files.isEmpty()) return false;
  const RecoveryFile& newest = files.first();
  const QString what = newest.originalPath.isEmpty() ? tr("the default scene") : newest.originalPath;
  if (choice == RecoveryChoice::Ask && !m_feedback.isInteractive()) choice = RecoveryChoice::Keep;
  if (choice == RecoveryChoice::Ask) {
    QMessageBox box(QMessageBox::Question, tr("Restore unsaved work?"),
                    tr("bsdeform-viewer did not quit cleanly. Its autosave of %1 from %2 can be restored.")
                        .arg(what, QLocale().toString(newest.saved, QLocale::ShortFormat)),
                    QMessageBox::NoButton, &m_window);
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
      m_feedback.show(tr("Discarded %n recovery file(s)", "", files.size()), 5000);
      return false;
    case RecoveryChoice::Ask:
    case RecoveryChoice::Keep:
      break;
  }
  m_feedback.report(tr("%n recovery file(s) kept in %1 (newest: autosave of %2); start with --restore-recovery or "
                       "--discard-recovery", "", files.size())
                        .arg(m_autosave->directory(), what),
                    10000);
  return false;
}

bool DocumentActions::restoreRecovery(const RecoveryFile& file) {
  QString error;
  m_drag.release();
  if (!m_doc.load(file.path, error)) {
    m_feedback.error(tr("Cannot restore the autosave"), error);  // the recovery file stays
    return false;
  }
  m_doc.setPath(file.originalPath);
  m_template = !file.originalPath.isEmpty() && shippedSceneFolders().contains(QFileInfo(file.originalPath).canonicalPath());
  loaded();
  m_restoredUnsaved = true;  // the restored work is not in the scene's file yet
  m_window.setWindowModified(true);
  // this viewer's own copy first, then the old file goes: the work is on disk all the time
  if (!m_autosave->saveNow(error)) {
    m_feedback.error(tr("Autosave failed"), error);
  } else {
    Autosave::remove(file);
  }
  m_feedback.report(tr("Restored the autosave of %1").arg(file.originalPath.isEmpty() ? tr("the default scene") : file.originalPath),
                    10000);
  return true;
}

}  // namespace bsdeform
