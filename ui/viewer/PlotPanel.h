// SPDX-License-Identifier: MIT
#pragma once
/// @file PlotPanel.h
/// Live plots of one surface: the deformation norm (eq. 15) in one chart, the kinetic and strain
/// energies in another (their scales differ by orders of magnitude), with round ticks, y >= 0.

#include <QWidget>
#include <utility>
#include <vector>
#include <cmath>

#include "History.h"

class SoBSplineDeformSurface;
namespace QtCharts {
class QChartView;
class QLineSeries;
class QValueAxis;
}  // namespace QtCharts

namespace bsdeform {

class PlotPanel : public QWidget {
  Q_OBJECT
 public:
  explicit PlotPanel(QWidget* parent = nullptr);
  /// Follows `surface` (nullptr: none); the history restarts.
  void setSurface(SoBSplineDeformSurface* surface, const QString& name);
  /// Appends a sample of the surface's state when its time moved (the window calls it after
  /// every step, SoBSplineDeformSurface::STEPPED).
  void sample();
  /// The state was replaced (a reset, a static solve): the history starts again from it.
  void restart();
  /// Shows the history up to simulated time `time` only (the timeline's position, Timeline.h);
  /// INFINITY: all of it. A sample earlier than the newest kept (stepping on from a scrubbed
  /// state) drops the later ones and shows all again.
  void showUntil(double time);
  /// The samples after `time` replaced by `samples` (time, diagnostics), in order: another
  /// branch of the timeline.
  void replaceAfter(double time, const std::vector<std::pair<double, Diagnostics>>& samples);
  /// The time of the last sample the charts show (NaN: none).
  double lastShownTime() const;
  /// Fits the axes to what the series show (once per batch of samples).
  void updateAxes();
  /// Samples kept in the history (for export).
  int sampleCount() const { return m_history.size(); }
  /// Whether the curves mark their points (so that a single sample is seen, as after Solve Static).
  bool marksPoints() const;
  /// The samples kept (also those after the timeline's position).
  const History& history() const { return m_history; }
  /// At most `limit` samples are kept (default 100000, about 3 MB): when the history is full,
  /// every second sample is dropped and from then on only every second new one is kept, so a
  /// long run keeps its whole time span at a uniform, coarser spacing and memory stays flat.
  void setHistoryLimit(int limit);
  /// Keeps one sample in this many (1 until the history first filled up).
  int historyStride() const { return m_stride; }
  bool exportCsv(const QString& path, QString& error) const;
  bool exportPng(const QString& path, QString& error);
  /// The axes (tests): time (both charts share the range), norm, energies.
  enum class Axis { Time, Norm, Energy };
  const QtCharts::QValueAxis* axis(Axis which) const;

 signals:
  /// An export failed (message names the file).
  void failed(const QString& message);

 private:
  void clearHistory();
  void thinHistory();
  /// The series from the history, up to m_until.
  void rebuildSeries();
  SoBSplineDeformSurface* m_surface = nullptr;
  QWidget* m_charts = nullptr;                     // both chart views (exported as one picture)
  QtCharts::QChartView* m_views[2] = {};           // norm, energies
  QtCharts::QLineSeries* m_series[3] = {};         // norm, kinetic, strain
  QtCharts::QValueAxis* m_axisX[2] = {};           // time axis of each chart
  QtCharts::QValueAxis* m_axisY[2] = {};           // norm, energy
  History m_history;
  int m_historyLimit = 100000;
  int m_stride = 1;      // keep one sample in m_stride
  long m_skipped = 0;    // samples seen since the last one kept
  double m_until = INFINITY;  // the series show the history up to this time
};

}  // namespace bsdeform
