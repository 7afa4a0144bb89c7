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
  int sampleCount() const { return m_t.size(); }
  bool exportCsv(const QString& path, QString& error) const;
  bool exportPng(const QString& path, QString& error);

 signals:
  /// An export failed (message names the file).
  void failed(const QString& message);

 private:
  void clearHistory();
  SoBSplineDeformSurface* m_surface = nullptr;
  QtCharts::QChartView* m_view = nullptr;
  QtCharts::QLineSeries* m_series[3] = {};
  QtCharts::QValueAxis* m_axisX = nullptr;
  QtCharts::QValueAxis* m_axisY = nullptr;
  QVector<double> m_t, m_norm, m_kinetic, m_strain;
};

}  // namespace bsdeform
