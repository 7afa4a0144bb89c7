// SPDX-License-Identifier: MIT
#pragma once
// Checks shared by the front ends' full-disk tests (bsdeform_io_tests): the writers of
// ui/common (AtomicFile_test.cpp) and of the viewer (viewer/AtomicWrite_test.cpp).
#include <QByteArray>
#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QString>
#include <QStringList>
#include <catch2/catch.hpp>

#include "../../support/FullDisk.h"

namespace testsupport {

/// The disk under `dir` is full while this lives (after `after` more bytes).
struct QtFullDisk : FullDisk {
  explicit QtFullDisk(const QString& dir, long after = 0) : FullDisk(QFile::encodeName(dir).toStdString(), after) {}
};

inline QByteArray slurp(const QString& path) {
  QFile f(path);
  return f.open(QIODevice::ReadOnly) ? f.readAll() : QByteArray();
}

inline QStringList entries(const QString& dir) {
  return QDir(dir).entryList(QDir::AllEntries | QDir::NoDotAndDotDot | QDir::Hidden | QDir::System, QDir::Name);
}

/// A failed write kept `path` as `before`, left no temporary file and gave the reason in `error`.
inline void checkKept(const QString& path, const QByteArray& before, const QString& error) {
  INFO(error.toStdString());
  CHECK(error.contains(QStringLiteral("No space left on device")));
  CHECK(error.contains(QFileInfo(path).fileName()));
  CHECK(slurp(path) == before);
  CHECK(entries(QFileInfo(path).path()) == QStringList{QFileInfo(path).fileName()});  // no temporary file left
}

}  // namespace testsupport
