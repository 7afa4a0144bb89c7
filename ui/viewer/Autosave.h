// SPDX-License-Identifier: MIT
#pragma once
/// @file Autosave.h
/// Crash recovery for bsdeform-viewer: the scene with its running state is written to a
/// recovery file at a fixed interval, but only when it changed since the last autosave, open
/// or save. The file is removed on a clean quit and after a successful save, so a recovery file
/// found at start-up was left by a viewer that died (docs/reliability.md).
///
/// Each viewer writes its own file, `recovery-<pid>-<start time>.iv`, and holds a lock file
/// next to it (QLockFile) while it runs: a recovery file whose lock is free or stale belongs
/// to a viewer that is gone. The second line of a recovery file names the scene file it came
/// from: `# bsdeform-viewer recovery of: <percent-encoded path>`.

#include <QByteArray>
#include <QDateTime>
#include <QObject>
#include <QString>
#include <QVector>
#include <memory>

class QLockFile;
class QTimer;

namespace bsdeform {

class SceneDocument;

/// A recovery file left by a viewer that did not quit cleanly.
struct RecoveryFile {
  QString path;          ///< the autosaved scene (.iv)
  QString originalPath;  ///< the scene file it was opened from; empty for the built-in scene
  QDateTime saved;       ///< when it was last written
};

class Autosave : public QObject {
  Q_OBJECT
 public:
  static constexpr int kDefaultIntervalMs = 60 * 1000;

  explicit Autosave(const SceneDocument& doc, QObject* parent = nullptr);
  /// An orderly end: removes this viewer's recovery file.
  ~Autosave() override;

  /// `$XDG_DATA_HOME/<organization>/<application>/recovery` (QStandardPaths::AppDataLocation),
  /// ~/.local/share/bsdeform/bsdeform-viewer/recovery for the viewer.
  static QString defaultDirectory();
  void setDirectory(const QString& dir);
  const QString& directory() const { return m_dir; }
  /// Milliseconds between autosaves; 0 turns autosave off.
  void setInterval(int ms);
  int interval() const;
  /// This viewer's recovery file (it exists only while there are unsaved changes).
  QString filePath() const;

  /// The document as it is now is saved (or freshly opened): no autosave until it changes, and
  /// this viewer's recovery file is removed.
  void markClean();
  /// Writes the recovery file if the document changed since the last autosave or markClean().
  /// Returns false with `error` when writing failed (the previous recovery file is kept).
  bool saveIfChanged(QString& error);
  /// Writes the recovery file now, changed or not.
  bool saveNow(QString& error);
  /// Removes this viewer's recovery file and its lock (a clean quit).
  void discard();

  /// Recovery files of viewers that are gone, newest first.
  QVector<RecoveryFile> orphans() const;
  /// Deletes a recovery file (restored elsewhere or discarded by the user).
  static bool remove(const RecoveryFile& file);

 signals:
  /// An autosave could not be written; the message names the file and the reason.
  void failed(const QString& message);
  /// The recovery file was written.
  void saved(const QString& path);

 private:
  bool write(QString& error);  // streams the scene with its origin line
  QByteArray currentHash() const;  // of the scene text, streamed; empty without a scene

  const SceneDocument& m_doc;
  QString m_dir;
  QString m_name;  // recovery-<pid>-<start time>
  QTimer* m_timer = nullptr;
  QByteArray m_lastHash;  // of the text last autosaved, opened or saved
  std::unique_ptr<QLockFile> m_lock;
};

}  // namespace bsdeform
