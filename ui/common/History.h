// SPDX-License-Identifier: MIT
#pragma once
/// @file History.h
/// The time series of one surface's diagnostics (norm eq. 15, kinetic and strain energy) that
/// both front ends keep: bsdeform-run's history CSV and plot, the viewer's live plots and their
/// CSV export. Numbers are written in the shortest text that reads back exactly (historyNumber),
/// times at their 15-digit value (decimalNumber).

#include <QByteArray>
#include <QLocale>
#include <QString>
#include <QVector>
#include <cmath>

#include "Plot.h"

namespace bsdeform {

struct Diagnostics;

class History {
 public:
  /// Appends one sample at simulated `time`.
  void append(double time, const Diagnostics& d);
  void clear();
  /// Drops every second sample (the first one is kept): the span stays, the spacing doubles.
  void thin();
  /// Drops the samples at `time` and after (a branch of the run that is replaced).
  void dropFrom(double time);

  int size() const { return m_time.size(); }
  bool isEmpty() const { return m_time.isEmpty(); }
  const QVector<double>& time() const { return m_time; }
  const QVector<double>& norm() const { return m_norm; }
  const QVector<double>& kinetic() const { return m_kinetic; }
  const QVector<double>& strain() const { return m_strain; }

  /// The norm against time, and the kinetic and strain energies on the right axis.
  QVector<PlotSeries> plotSeries() const;
  /// "time,norm,kinetic,strain" and one line per sample.
  QByteArray csv() const;

  /// bsdeform-run's history CSV: the header line (with its newline) and the line of a state at
  /// `time` after `steps` steps of `subSteps` sub-steps, with its diagnostics `d` (time, step,
  /// norm, kinetic, strain and its terms w10 w01 w11 w20 w02, sub-steps, the membrane and
  /// bending energies). `shell`: a SHELL surface's, without the paper's five weight terms
  /// (always 0 for it).
  static QString detailedCsvHeader(bool shell = false);
  static QString detailedCsvRow(double time, long steps, int subSteps, const Diagnostics& d, bool shell = false);

 private:
  QVector<double> m_time, m_norm, m_kinetic, m_strain;
};

/// A number as the history files write it: the shortest text that reads back to the same
/// double (17 digits only where they are needed).
inline QString historyNumber(double x) { return QString::number(x, 'g', QLocale::FloatingPointShortest); }

/// A simulated time or a load factor, a sum of steps (0.1 + 0.1 + 0.1 = 0.30000000000000004):
/// its 15-significant-digit value (the step as a person wrote it, as the scene files snap their
/// doubles), in the shortest text: "0.3". Non-finite values as historyNumber.
inline QString decimalNumber(double x) {
  return std::isfinite(x) ? historyNumber(QString::number(x, 'g', 15).toDouble()) : historyNumber(x);
}

}  // namespace bsdeform
