// SPDX-License-Identifier: MIT
#include "RunSetup.h"

#include <Inventor/SoType.h>
#include <Inventor/fields/SoField.h>
#include <Inventor/fields/SoFieldContainer.h>
#include <Inventor/fields/SoSField.h>
#include <Inventor/nodes/SoSeparator.h>
#include <unistd.h>

#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QRegularExpression>
#include <QTemporaryFile>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

#include "RunOptions.h"
#include "bsdeform/SceneReader.h"

namespace bsdeform::run {

Failure loadScene(const QString& path, NodeRef<SoSeparator>& root) {
  const QFileInfo info(path);
  if (info.isDir()) return {kBadInput, QStringLiteral("cannot open scene '%1': it is a directory").arg(path)};
  if (!info.exists()) return {kBadInput, QStringLiteral("cannot open scene '%1': no such file").arg(path)};
  if (!info.isFile()) return {kBadInput, QStringLiteral("cannot open scene '%1': not a regular file").arg(path)};
  {
    QFile probe(path);  // Coin does not say why a file cannot be opened; the system does
    if (!probe.open(QIODevice::ReadOnly))
      return {kBadInput, QStringLiteral("cannot open scene '%1': %2").arg(path, probe.errorString())};
  }
  std::string error;  // the guarded reader (docs/reliability.md): FILE:LINE: reason, or Coin's errors
  root.reset(readSceneFile(QFile::encodeName(path).toStdString(), error));
  if (!root)
    return {kBadInput, QStringLiteral("cannot read scene: %1").arg(QString::fromStdString(error).replace(QLatin1Char('\n'), QStringLiteral("; ")))};
  return {kOk, {}};
}

Failure applySet(const QString& spec) {
  const int eq = spec.indexOf(QLatin1Char('='));
  const int dot = eq > 0 ? spec.lastIndexOf(QLatin1Char('.'), eq) : -1;
  if (eq <= 0 || dot <= 0 || dot + 1 >= eq)
    return {kBadInput, QStringLiteral("--set '%1': expected NAME.field=value").arg(spec)};
  const QString name = spec.left(dot), field = spec.mid(dot + 1, eq - dot - 1), value = spec.mid(eq + 1);
  SoBase* base = SoBase::getNamedBase(SbName(name.toUtf8().constData()), SoFieldContainer::getClassTypeId());
  if (!base) return {kBadInput, QStringLiteral("--set '%1': no node or engine is DEF'ed as '%2' in the scene").arg(spec, name)};
  auto* fc = static_cast<SoFieldContainer*>(base);
  SoField* f = fc->getField(SbName(field.toUtf8().constData()));
  if (!f) return {kBadInput, QStringLiteral("--set '%1': '%2' has no field '%3'").arg(spec, name, field)};
  // a vector may be written with commas, as lists are: 0,0,-1 (a single field of numbers)
  QString text = value;
  if (f->isOfType(SoSField::getClassTypeId()) && !text.contains(QLatin1Char('"')) && !text.contains(QLatin1Char('[')) &&
      QString::fromLatin1(f->getTypeId().getName().getString()).contains(QRegularExpression(QStringLiteral("Vec|Color|Rotation"))))
    text.replace(QLatin1Char(','), QLatin1Char(' '));
  if (!f->set(text.toUtf8().constData()))
    return {kBadInput, QStringLiteral("--set '%1': '%2' is not a valid value for field %3.%4 (%5)")
                           .arg(spec, value, name, field, QString::fromLatin1(f->getTypeId().getName().getString()))};
  return {kOk, {}};
}

Failure loadSceneWithSets(const RunOptions& o, NodeRef<SoSeparator>& root) {
  Failure f = loadScene(o.scene, root);
  for (int i = 0; f.ok() && i < o.sets.size(); ++i) f = applySet(o.sets[i]);
  return f;
}

Failure prepareOutDir(const RunOptions& o) {
  QDir dir(o.outDir);
  const QFileInfo info(o.outDir);
  if (info.exists() && !info.isDir()) return {kBadInput, QStringLiteral("output path '%1' is not a directory").arg(o.outDir)};
  // hidden files count: a directory holding only dot files is not empty
  const QDir::Filters everything = QDir::AllEntries | QDir::NoDotAndDotDot | QDir::Hidden | QDir::System;
  if (dir.exists() && !dir.isEmpty(everything) && !o.overwrite)
    return {kBadInput, QStringLiteral("output directory '%1' is not empty; nothing was written (use --overwrite to replace "
                                      "its files)").arg(o.outDir)};
  errno = 0;
  if (!QDir().mkpath(o.outDir)) {
    const QString why = errno ? QString::fromLocal8Bit(std::strerror(errno)) : QStringLiteral("unknown error");
    return {kBadInput, QStringLiteral("cannot create output directory '%1': %2").arg(o.outDir, why)};
  }
  // a uniquely named probe, removed again: never a name a user's file could have
  QTemporaryFile probe(dir.filePath(QStringLiteral(".bsdeform-write-test-XXXXXX")));
  if (!probe.open())
    return {kBadInput, QStringLiteral("output directory '%1' is not writable: %2").arg(o.outDir, probe.errorString())};
  return {kOk, {}};
}

ProgressBar::ProgressBar(const RunOptions& o) : m_visible(isatty(STDERR_FILENO) && !o.quiet && !o.resultOnly) {}

void ProgressBar::show(long done, long total, double t) {
  if (!m_visible || total <= 0) return;
  const int pct = int(100.0 * done / total);
  if (pct == m_last && done != total) return;
  m_last = pct;
  const int filled = pct / 4;
  std::fprintf(stderr, "\r[%s%s] %3d%%  t = %.4g", std::string(filled, '#').c_str(), std::string(25 - filled, '.').c_str(),
               pct, t);
  if (done == total) std::fprintf(stderr, "\n");
}

}  // namespace bsdeform::run
