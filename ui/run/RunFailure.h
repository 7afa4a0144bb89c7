// SPDX-License-Identifier: MIT
#pragma once
/// @file RunFailure.h
/// bsdeform-run's outcome: the exit code and the message printed for it.

#include <QString>
#include <QStringList>

namespace bsdeform::run {

/// The exit codes README.md and `--help` list.
enum ExitCode { kOk = 0, kInternal = 1, kBadInput = 2, kBlowUp = 3, kWriteFailed = 4 };

struct Failure {
  ExitCode code = kOk;
  QString message;
  bool ok() const { return code == kOk; }
};

/// A write failure after the run: which file, why, and which files were already replaced.
inline Failure writeFailure(const QString& error, const QStringList& written) {
  if (written.isEmpty()) return {kWriteFailed, error};
  return {kWriteFailed, QStringLiteral("%1 (already written: %2)").arg(error, written.join(QStringLiteral(", ")))};
}

}  // namespace bsdeform::run
