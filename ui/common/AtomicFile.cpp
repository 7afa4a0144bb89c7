// SPDX-License-Identifier: MIT
#include "AtomicFile.h"

#include <unistd.h>

#include <QBuffer>
#include <QDir>
#include <QImage>
#include <QSaveFile>
#include <cerrno>
#include <cstring>

namespace bsdeform {

namespace {

// Qt's own message when it has one (it is strerror() of the failing call), else errno's.
QString reasonOf(const QFileDevice& file, int savedErrno) {
  const QString qt = file.errorString();
  if (file.error() != QFileDevice::NoError && !qt.isEmpty() && qt != QLatin1String("Unknown error")) return qt;
  if (savedErrno != 0) return QString::fromLocal8Bit(std::strerror(savedErrno));
  return QStringLiteral("unknown error");
}

}  // namespace

bool saveFileAtomically(const QString& path, const FileWriter& writer, QString& error) {
  QSaveFile file(path);
  // Leaving this function without commit() destroys `file` while open: QSaveFile then removes
  // its temporary file and the previous file stays as it was.
  auto fail = [&](const QString& reason) {
    error = QStringLiteral("cannot write '%1': %2").arg(QDir::toNativeSeparators(path), reason);
    file.cancelWriting();
    return false;
  };
  errno = 0;
  if (!file.open(QIODevice::WriteOnly)) return fail(reasonOf(file, errno));
  errno = 0;
  const bool written = writer(file);
  int savedErrno = errno;
  if (file.error() != QFileDevice::NoError) return fail(reasonOf(file, savedErrno));
  if (!written) return fail(savedErrno ? reasonOf(file, savedErrno) : QStringLiteral("the contents could not be encoded"));
  errno = 0;
  if (!file.flush()) return fail(reasonOf(file, errno));
  // commit() syncs too, but ignores the result; some file systems (NFS, quotas) report a full
  // disk only here. EINVAL / EROFS: the file cannot be synced at all, which is no data loss.
  if (::fsync(file.handle()) != 0 && errno != EINVAL && errno != EROFS) {
    savedErrno = errno;
    return fail(QString::fromLocal8Bit(std::strerror(savedErrno)));
  }
  errno = 0;
  if (!file.commit()) return fail(reasonOf(file, errno));
  return true;
}

bool saveFileAtomically(const QString& path, const QByteArray& contents, QString& error) {
  return saveFileAtomically(path, [&](QIODevice& device) { return device.write(contents) == contents.size(); }, error);
}

bool savePngAtomically(const QString& path, const QImage& image, QString& error) {
  QByteArray png;
  QBuffer buffer(&png);
  buffer.open(QIODevice::WriteOnly);
  if (!image.save(&buffer, "PNG")) {
    error = QStringLiteral("cannot write '%1': the image could not be encoded as PNG").arg(QDir::toNativeSeparators(path));
    return false;
  }
  return saveFileAtomically(path, png, error);
}

}  // namespace bsdeform
