// SPDX-License-Identifier: MIT
#pragma once
/// @file DocumentActions.h
/// The viewer's File jobs on its SceneDocument: Open (the dialog, Open Recent, a dropped file),
/// Reload, Save, Save As, the question about unsaved edits, the window's title and its
/// modified mark, and the autosave with the offer to restore a recovery file left by a viewer
/// that died.

#include <QObject>
#include <QString>

#include "Autosave.h"

class QDragEnterEvent;
class QDropEvent;
class QMainWindow;
class QMenu;
class QMessageBox;
class QWidget;
class QUndoStack;

namespace bsdeform {

class DragTool;
class Feedback;
class SceneDocument;

/// What to do with a recovery file left by a viewer that died.
enum class RecoveryChoice {
  Ask,      ///< a question box; when not interactive: Keep
  Restore,  ///< open the newest recovery file (its scene keeps its original file name)
  Discard,  ///< delete every recovery file
  Keep,     ///< leave them for the next start
};

class DocumentActions : public QObject {
  Q_OBJECT
 public:
  /// `undo`: the edits, clean after a save; `window`: the dialogs' parent, its title and
  /// modified mark.
  DocumentActions(SceneDocument& doc, QUndoStack& undo, DragTool& drag, Feedback& feedback, QMainWindow& window);

  Autosave& autosave() { return *m_autosave; }
  /// The menu Open Recent fills with the recent files.
  void setRecentMenu(QMenu* menu);

  /// Opens a scene file; on failure reports Coin's reason and keeps the current scene.
  bool openScene(const QString& path);
  /// Shows the built-in default scene.
  void openDefaultScene();
  /// Writes the scene with its state; the file becomes the document's.
  bool saveSceneAs(const QString& path);
  /// Saves to the scene's own file (Save As for the built-in default scene and for a
  /// template: a shipped scene is never overwritten by Save; when not interactive that is an
  /// error and nothing is written).
  bool saveScene();
  /// With unsaved edits, asks whether to save them (interactive only: otherwise they are
  /// dropped). True when the caller may go on (saved or discarded), false on Cancel.
  bool maybeSave();
  /// The question maybeSave() asks about `name`: Save, Discard, Cancel, Cancel the default
  /// (Return neither writes over a file nor throws work away).
  static QMessageBox* unsavedChangesBox(QWidget* parent, const QString& name);
  /// The folder the Open dialog starts in: the last one used, scenes/ the first time.
  static QString openFolder();
  /// The folder a dialog that writes the user's work starts in (Save As of a template, Record,
  /// Save Screenshot): the last folder used when it exists and holds no shipped scenes, else
  /// ~/Documents when it exists, else the home folder; never the folder the viewer was started in.
  static QString userFolder();
  /// The folders of the scenes that come with bsdeform (installed, and the source tree's for a
  /// build run where it was built), canonical.
  static QStringList shippedSceneFolders();
  /// The open scene is one of those: a template, which Save does not overwrite.
  bool isTemplate() const { return m_template; }

  /// Offers the recovery files of viewers that died (newest first). Returns true when one was
  /// restored.
  bool offerRecovery(RecoveryChoice choice);
  /// Opens a recovery file as the scene it came from; it becomes this viewer's recovery file.
  bool restoreRecovery(const RecoveryFile& file);

  /// The menu's commands (with their dialogs).
  void open();
  void reload();
  void saveAs();

  /// The window's drag and drop: an .iv file is accepted, and opened after maybeSave().
  void dragEnter(QDragEnterEvent* e);
  void drop(QDropEvent* e);

 signals:
  /// The document holds another scene (opened, reloaded or restored): the window shows it.
  void sceneLoaded();

 private:
  /// After a scene opened: every value its nodes refuse, in one warning box (SceneProblems.h).
  void reportProblems();
  /// Opens `path` after maybeSave() (recent files, a dropped file).
  void openAfterAsking(const QString& path);
  /// The document's new scene: no edits, the title names it, then sceneLoaded().
  void loaded();
  void setTitle();
  void rememberFolder(const QString& path);
  void addRecent(const QString& path);
  void updateRecentMenu();

  SceneDocument& m_doc;
  QUndoStack& m_undo;
  DragTool& m_drag;
  Feedback& m_feedback;
  QMainWindow& m_window;
  Autosave* m_autosave;
  bool m_autosaveFailing = false;  // report the first failure in a dialog, later ones in the status bar
  bool m_restoredUnsaved = false;  ///< a restored autosave: unsaved although there is nothing to undo
  bool m_template = false;         ///< the scene came from shippedSceneFolders()
  QMenu* m_recentMenu = nullptr;
};

}  // namespace bsdeform
