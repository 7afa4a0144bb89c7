// SPDX-License-Identifier: MIT
#pragma once
/// @file Plot.h
/// Line plots rendered to PNG with Qt Charts (needs a QApplication; headless programs use the
/// offscreen platform), and the axis set-up shared with the viewer's live plots: round ticks
/// (PlotScale.h), y >= 0 for non-negative quantities, a logarithmic x axis when the
/// values span decades, a least-squares line with its equation and r.

#include <QString>
#include <QVector>

namespace QtCharts {
class QChart;
class QValueAxis;
}

namespace bsdeform {

struct AxisTicks;

struct PlotSeries {
  QString name;
  QVector<double> x, y;
  /// Drawn against a second y axis on the right (e.g. energies beside a norm).
  bool rightAxis = false;
};

struct PlotOptions {
  QString rightLabel;        ///< title of the right y axis (used when a series asks for it)
  bool nonNegative = false;  ///< the y values cannot be negative: axes start at or above 0
  /// x axis: logarithmic when the positive x values span two decades or more (x <= 0 cannot be
  /// shown on it: their values are listed under the title instead).
  bool logXWhenDecades = false;
  /// Adds the least-squares line of each series with its equation and r in the legend.
  bool fitLine = false;
};

/// Sets `axis` to the round ticks `ticks` (range, tick count, label decimals).
void applyTicks(QtCharts::QValueAxis* axis, const AxisTicks& ticks);

/// "y = a + b x, r = c" with four significant digits.
QString fitEquation(double intercept, double slope, double r, const QString& x = QStringLiteral("x"),
                    const QString& y = QStringLiteral("y"));

/// The chart writePlotPng draws (the caller owns it): one line per series, the fitted lines
/// when asked, axes as PlotOptions say.
QtCharts::QChart* makePlotChart(const QString& title, const QString& xLabel, const QString& yLabel,
                                const QVector<PlotSeries>& series, const PlotOptions& options = PlotOptions());

/// Draws the series as lines with points and writes a PNG (atomically). Returns false with a
/// message naming the file on failure.
bool writePlotPng(const QString& path, const QString& title, const QString& xLabel, const QString& yLabel,
                  const QVector<PlotSeries>& series, int width, int height, QString& error,
                  const PlotOptions& options = PlotOptions());

}  // namespace bsdeform
