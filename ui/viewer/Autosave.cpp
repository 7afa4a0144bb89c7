// SPDX-License-Identifier: MIT
#include "Autosave.h"

#include <unistd.h>

#include <QCryptographicHash>
#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QLockFile>
#include <QStandardPaths>
#include <QTimer>
#include <QUrl>
#include <algorithm>

#include "AtomicFile.h"
#include "SceneDocument.h"

namespace bsdeform {

namespace {
const char* kOriginPrefix = "# bsdeform-viewer recovery of: ";

QByteArray hashOf(const QByteArray& text) { return QCryptographicHash::hash(text, QCryptographicHash::Sha1); }

QString lockPathOf(const QString& ivPath) { return ivPath.left(ivPath.size() - 3) + QStringLiteral(".lock"); }
}  // namespace

Autosave::Autosave(const SceneDocument& doc, QObject* parent)
    : QObject(parent),
      m_doc(doc),
      m_dir(defaultDirectory()),
      m_name(QStringLiteral("recovery-%1-%2").arg(::getpid()).arg(QDateTime::currentMSecsSinceEpoch())) {
  m_timer = new QTimer(this);
  connect(m_timer, &QTimer::timeout, this, [this] {
    QString error;
    if (!saveIfChanged(error)) emit failed(error);
  });
  m_timer->start(kDefaultIntervalMs);
}

Autosave::~Autosave() { discard(); }

QString Autosave::defaultDirectory() {
  return QStandardPaths::writableLocation(QStandardPaths::AppDataLocation) + QStringLiteral("/recovery");
}

void Autosave::setDirectory(const QString& dir) {
  if (dir == m_dir) return;
  const bool had = QFile::exists(filePath());
  discard();
  m_dir = dir;
  if (had) m_lastHash.clear();  // the new place has no copy yet: write at the next tick
}

void Autosave::setInterval(int ms) {
  if (ms > 0)
    m_timer->start(ms);
  else
    m_timer->stop();
}

int Autosave::interval() const { return m_timer->isActive() ? m_timer->interval() : 0; }

QString Autosave::filePath() const { return QDir(m_dir).filePath(m_name + QStringLiteral(".iv")); }

void Autosave::markClean() {
  m_lastHash = hashOf(m_doc.toText());
  discard();
}

bool Autosave::saveIfChanged(QString& error) {
  const QByteArray text = m_doc.toText();
  if (text.isEmpty()) return true;
  const QByteArray hash = hashOf(text);
  if (hash == m_lastHash) return true;
  if (!write(text, error)) return false;
  m_lastHash = hash;
  return true;
}

bool Autosave::saveNow(QString& error) {
  const QByteArray text = m_doc.toText();
  if (!write(text, error)) return false;
  m_lastHash = hashOf(text);
  return true;
}

bool Autosave::write(const QByteArray& text, QString& error) {
  if (!QDir().mkpath(m_dir)) {
    error = QStringLiteral("cannot create the recovery directory '%1'").arg(m_dir);
    return false;
  }
  if (!m_lock) {
    // held while this viewer runs: other viewers leave this recovery file alone
    auto lock = std::make_unique<QLockFile>(lockPathOf(filePath()));
    lock->setStaleLockTime(0);  // stale only when the process is gone, however long it runs
    if (!lock->tryLock(0)) {
      const QString why = lock->error() == QLockFile::PermissionError ? QStringLiteral("permission denied")
                          : lock->error() == QLockFile::LockFailedError ? QStringLiteral("another process holds it")
                                                                        : QStringLiteral("unknown error");
      error = QStringLiteral("cannot lock '%1': %2").arg(lockPathOf(filePath()), why);
      return false;
    }
    m_lock = std::move(lock);
  }
  // "#Inventor V2.1 ascii" must stay the first line; the origin goes on the second
  const int eol = text.indexOf('\n');
  QByteArray out = text.left(eol + 1);
  out += kOriginPrefix + QUrl::toPercentEncoding(m_doc.path()) + '\n';
  out += text.mid(eol + 1);
  if (!saveFileAtomically(filePath(), out, error)) return false;
  emit saved(filePath());
  return true;
}

void Autosave::discard() {
  QFile::remove(filePath());
  if (m_lock) {
    m_lock->unlock();  // removes the lock file
    m_lock.reset();
  }
}

QVector<RecoveryFile> Autosave::orphans() const {
  QVector<RecoveryFile> out;
  const QDir dir(m_dir);
  for (const QFileInfo& info : dir.entryInfoList({QStringLiteral("recovery-*.iv")}, QDir::Files | QDir::Hidden)) {
    if (info.absoluteFilePath() == QFileInfo(filePath()).absoluteFilePath()) continue;  // ours
    QLockFile lock(lockPathOf(info.absoluteFilePath()));
    lock.setStaleLockTime(0);
    if (!lock.tryLock(0)) continue;  // its viewer still runs
    lock.unlock();
    RecoveryFile f{info.absoluteFilePath(), QString(), info.lastModified()};
    QFile file(f.path);
    if (file.open(QIODevice::ReadOnly)) {
      file.readLine();
      const QByteArray second = file.readLine().trimmed();
      if (second.startsWith(kOriginPrefix))
        f.originalPath = QUrl::fromPercentEncoding(second.mid(int(qstrlen(kOriginPrefix))));
    }
    out << f;
  }
  std::sort(out.begin(), out.end(), [](const RecoveryFile& a, const RecoveryFile& b) { return a.saved > b.saved; });
  return out;
}

bool Autosave::remove(const RecoveryFile& file) { return QFile::remove(file.path); }

}  // namespace bsdeform
