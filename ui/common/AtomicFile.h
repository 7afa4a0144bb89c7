// SPDX-License-Identifier: MIT
#pragma once
/// @file AtomicFile.h
/// The one way the front ends write a file: all or nothing, with the real reason on failure.

#include <QByteArray>
#include <QString>
#include <functional>

class QIODevice;
class QImage;

namespace bsdeform {

/// Writes the file's contents into the device; returns false when it could not (an encoder
/// failure, or a write error the device reports).
using FileWriter = std::function<bool(QIODevice& device)>;

/// Writes `path` atomically: `writer` fills a temporary file in the same directory
/// (QSaveFile), which is flushed, checked, synced to disk and renamed over `path` only when
/// every step succeeded. On failure the previous file is untouched, the temporary file is
/// removed and `error` names the file and the system's reason, e.g. "cannot write
/// 'out/final.iv': No space left on device".
///
/// Why not QSaveFile::commit() alone: in Qt 5.15 commit() flushes the write buffer itself and
/// ignores a failure of that flush, so on a full disk it renames a truncated (often empty)
/// file over the old one and returns true. An explicit flush() reports it.
bool saveFileAtomically(const QString& path, const FileWriter& writer, QString& error);

/// The same for contents already in memory.
bool saveFileAtomically(const QString& path, const QByteArray& contents, QString& error);

/// Writes `image` as a PNG file, atomically. The PNG is encoded in memory first: Qt 5.15's PNG
/// writer leaks its converted copy of the image when the device fails a write (libpng's error
/// handler longjmps past the copy's destructor; LeakSanitizer saw it on a full disk), so the
/// encoder never writes to the file itself.
bool savePngAtomically(const QString& path, const QImage& image, QString& error);

}  // namespace bsdeform
