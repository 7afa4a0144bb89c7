// SPDX-License-Identifier: MIT
#include "Plot.h"

#include "AtomicFile.h"

#include <QFileInfo>
#include <QGraphicsScene>
#include <QImage>
#include <QPainter>
#include <QtCharts/QChart>
#include <QtCharts/QLineSeries>
#include <QtCharts/QValueAxis>
#include <algorithm>
#include <cmath>

namespace bsdeform {

bool writePlotPng(const QString& path, const QString& title, const QString& xLabel, const QString& yLabel,
                  const QVector<PlotSeries>& series, int width, int height, QString& error) {
  using namespace QtCharts;
  auto* chart = new QChart;
  chart->setTitle(title);
  auto* ax = new QValueAxis;
  auto* ay = new QValueAxis;
  ax->setTitleText(xLabel);
  ay->setTitleText(yLabel);
  chart->addAxis(ax, Qt::AlignBottom);
  chart->addAxis(ay, Qt::AlignLeft);
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (const PlotSeries& s : series) {
    auto* line = new QLineSeries;
    line->setName(s.name);
    line->setPointsVisible(s.x.size() <= 60);
    for (int i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      line->append(s.x[i], s.y[i]);
      x0 = std::min(x0, s.x[i]);
      x1 = std::max(x1, s.x[i]);
      y0 = std::min(y0, s.y[i]);
      y1 = std::max(y1, s.y[i]);
    }
    chart->addSeries(line);
    line->attachAxis(ax);
    line->attachAxis(ay);
  }
  if (!(x0 <= x1)) x0 = 0, x1 = 1;
  if (!(y0 <= y1)) y0 = 0, y1 = 1;
  if (x0 == x1) x0 -= 0.5, x1 += 0.5;
  const double pad = (y1 > y0) ? 0.05 * (y1 - y0) : std::max(1e-12, 0.05 * std::abs(y0));
  ax->setRange(x0, x1);
  ay->setRange(y0 - pad, y1 + pad);
  chart->legend()->setVisible(series.size() > 1);

  // A hidden QChartView never lays the chart out; size the chart in its own scene instead.
  QGraphicsScene scene;
  scene.addItem(chart);  // the scene owns the chart
  chart->setGeometry(0, 0, width, height);
  scene.setSceneRect(0, 0, width, height);
  QImage image(width, height, QImage::Format_RGB32);
  image.fill(Qt::white);
  {
    QPainter painter(&image);
    painter.setRenderHint(QPainter::Antialiasing);
    scene.render(&painter, QRectF(0, 0, width, height), QRectF(0, 0, width, height));
  }
  return savePngAtomically(path, image, error);
}

}  // namespace bsdeform
