// SPDX-License-Identifier: MIT
#pragma once
/// @file SweepPool.h
/// bsdeform-run --sweep NAME.field=v1,v2,...: checks every value in this process, runs one
/// child process per value (a pool of QProcess, as many at once as there are cores, driven by
/// their signals), collects the children's RESULT lines and writes sweep.csv and sweep.png.

#include <QString>
#include <QStringList>
#include <QVector>

#include "RunFailure.h"
#include "RunOptions.h"

namespace bsdeform::run {

class SweepPool {
 public:
  explicit SweepPool(const RunOptions& options);
  Failure run();

 private:
  /// One surface's final state in one child run.
  struct Row {
    QString value, surface, norm, kinetic, strain, status;
    QStringList metrics;  ///< one per --metric, in order
  };

  /// sweep.csv's first line: the six columns, then one per --metric.
  QString csvHeader() const;
  Failure parseSweep();
  /// Names and every value are checked on the scene first: bad input is reported before any run.
  Failure validate();
  Failure runChildren();
  /// --sweep-rows: the rows of a sweep.csv another driver ran (bsdeform.sweep on Dask), in its order.
  Failure readRows();
  /// Reads a finished child's output into m_rows[i] and its failure into m_errors[i].
  void collect(int i, const QString& output, const QString& stderrText, int code, bool crashed);
  Failure writeResults();

  const RunOptions& m_options;
  QString m_target;  ///< NAME.field
  QStringList m_values;
  int m_parallel = 1;
  QVector<QVector<Row>> m_rows;
  QVector<QString> m_errors;
};

}  // namespace bsdeform::run
