// SPDX-License-Identifier: MIT
#pragma once
/// @file PlotPanel.h
/// Live plots of the deformation norm (eq. 15), kinetic and strain energy of one surface.

#include <QVector>
#include <QWidget>

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
  /// Appends a sample when the surface's time moved; restarts after a reset.
  void sample();
  /// Samples kept in the history (for export).
  int sampleCount() const { return m_t.size(); }
  /// At most `limit` samples are kept (default 100000, about 3 MB): when the history is full,
  /// every second sample is dropped and from then on only every second new one is kept, so a
  /// long run keeps its whole time span at a uniform, coarser spacing and memory stays flat.
  void setHistoryLimit(int limit);
  /// Keeps one sample in this many (1 until the history first filled up).
  int historyStride() const { return m_stride; }
  bool exportCsv(const QString& path, QString& error) const;
  bool exportPng(const QString& path, QString& error);

 signals:
  /// An export failed (message names the file).
  void failed(const QString& message);

 private:
  void clearHistory();
  void thinHistory();
  SoBSplineDeformSurface* m_surface = nullptr;
  QtCharts::QChartView* m_view = nullptr;
  QtCharts::QLineSeries* m_series[3] = {};
  QtCharts::QValueAxis* m_axisX = nullptr;
  QtCharts::QValueAxis* m_axisY = nullptr;
  QVector<double> m_t, m_norm, m_kinetic, m_strain;
  int m_historyLimit = 100000;
  int m_stride = 1;      // keep one sample in m_stride
  long m_skipped = 0;    // samples seen since the last one kept
};

}  // namespace bsdeform
