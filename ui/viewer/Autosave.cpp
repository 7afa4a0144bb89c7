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
#include <cstring>

#include "AtomicFile.h"
#include "SceneDocument.h"

namespace bsdeform {

namespace {
const char* kOriginPrefix = "# bsdeform-viewer recovery of: ";

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

QByteArray Autosave::currentHash() const {
  QCryptographicHash hash(QCryptographicHash::Sha1);
  const bool written = m_doc.writeTo([&hash](const char* data, std::size_t size) {
    hash.addData(data, int(size));  // pieces of about a megabyte
    return true;
  });
  return written ? hash.result() : QByteArray();
}

void Autosave::markClean() {
  m_lastHash = currentHash();
  discard();
}

bool Autosave::saveIfChanged(QString& error) {
  const QByteArray hash = currentHash();
  if (hash.isEmpty()) return true;
  if (hash == m_lastHash) return true;
  if (!write(error)) return false;
  m_lastHash = hash;
  return true;
}

bool Autosave::saveNow(QString& error) {
  if (!write(error)) return false;
  m_lastHash = currentHash();
  return true;
}

bool Autosave::write(QString& error) {
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
  // "#Inventor V2.1 ascii" must stay the first line; the origin goes on the second. The text is
  // streamed into the file, never held whole.
  const QByteArray origin = kOriginPrefix + QUrl::toPercentEncoding(m_doc.path()) + '\n';
  bool originWritten = false;
  auto writer = [&](QIODevice& device) {
    return m_doc.writeTo([&](const char* data, std::size_t size) {
      if (!originWritten) {
        if (const void* eol = std::memchr(data, '\n', size)) {
          const std::size_t head = std::size_t(static_cast<const char*>(eol) - data) + 1;
          if (device.write(data, qint64(head)) != qint64(head) || device.write(origin) != origin.size()) return false;
          originWritten = true;
          data += head;
          size -= head;
        }
      }
      return size == 0 || device.write(data, qint64(size)) == qint64(size);
    });
  };
  if (!saveFileAtomically(filePath(), writer, error)) return false;
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
