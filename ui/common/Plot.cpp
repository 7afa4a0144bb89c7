// SPDX-License-Identifier: MIT
#include "Plot.h"

#include "AtomicFile.h"
#include "PlotScale.h"

#include <QFileInfo>
#include <QGraphicsScene>
#include <QImage>
#include <QPainter>
#include <QtCharts/QChart>
#include <QtCharts/QLineSeries>
#include <QtCharts/QLogValueAxis>
#include <QtCharts/QValueAxis>
#include <algorithm>
#include <cmath>
#include <vector>

namespace bsdeform {

void applyTicks(QtCharts::QValueAxis* axis, const AxisTicks& ticks) {
  axis->setRange(ticks.min, ticks.max);
  axis->setTickCount(ticks.count);
  axis->setMinorTickCount(0);
  axis->setLabelFormat(QString::fromStdString(tickLabelFormat(ticks)));
}

QString fitEquation(double intercept, double slope, double r, const QString& x, const QString& y) {
  const QString sign = slope < 0.0 ? QStringLiteral(" - ") : QStringLiteral(" + ");
  return QStringLiteral("%1 = %2%3%4 %5, r = %6")
      .arg(y, QString::number(intercept, 'g', 4), sign, QString::number(std::abs(slope), 'g', 4), x,
           QString::number(r, 'f', 4));
}

namespace {
struct Range {
  double lo = INFINITY, hi = -INFINITY;
  void add(double v) {
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  bool empty() const { return !(lo <= hi); }
};
}  // namespace

QtCharts::QChart* makePlotChart(const QString& title, const QString& xLabel, const QString& yLabel,
                                const QVector<PlotSeries>& series, const PlotOptions& options) {
  using namespace QtCharts;
  std::vector<double> allX;
  for (const PlotSeries& s : series) allX.insert(allX.end(), s.x.begin(), s.x.end());
  const bool logX = options.logXWhenDecades && spansDecades(allX);

  auto* chart = new QChart;
  QString fullTitle = title;
  QAbstractAxis* ax = nullptr;
  QValueAxis* linearX = nullptr;
  QLogValueAxis* logAxis = nullptr;
  if (logX) {
    logAxis = new QLogValueAxis;
    logAxis->setBase(10.0);
    logAxis->setLabelFormat(QStringLiteral("%g"));
    logAxis->setMinorTickCount(8);
    ax = logAxis;
  } else {
    linearX = new QValueAxis;
    ax = linearX;
  }
  auto* ay = new QValueAxis;
  QValueAxis* ayRight = nullptr;
  ax->setTitleText(logX ? xLabel + QObject::tr(" (logarithmic)") : xLabel);
  ay->setTitleText(yLabel);
  chart->addAxis(ax, Qt::AlignBottom);
  chart->addAxis(ay, Qt::AlignLeft);
  Range rx, ry, ryRight;
  QStringList offAxis;  // x <= 0 on a log axis
  for (const PlotSeries& s : series) {
    QValueAxis* yAxis = ay;
    Range* yRange = &ry;
    if (s.rightAxis) {
      if (!ayRight) {
        ayRight = new QValueAxis;
        ayRight->setTitleText(options.rightLabel);
        chart->addAxis(ayRight, Qt::AlignRight);
      }
      yAxis = ayRight;
      yRange = &ryRight;
    }
    auto* line = new QLineSeries;
    line->setName(s.name);
    line->setPointsVisible(s.x.size() <= 60);
    std::vector<double> fx, fy;
    for (int i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      fx.push_back(s.x[i]);
      fy.push_back(s.y[i]);
      if (logX && s.x[i] <= 0.0) {
        offAxis << QStringLiteral("%1 at %2 = %3").arg(s.name).arg(s.x[i], 0, 'g', 4).arg(s.y[i], 0, 'g', 4);
        continue;
      }
      line->append(s.x[i], s.y[i]);
      rx.add(s.x[i]);
      yRange->add(s.y[i]);
    }
    chart->addSeries(line);
    line->attachAxis(ax);
    line->attachAxis(yAxis);
    if (options.fitLine) {
      const LinearFit fit = fitLine(fx, fy);
      if (fit.valid && !rx.empty()) {
        auto* fitted = new QLineSeries;
        fitted->setName(QObject::tr("least squares: %1").arg(fitEquation(fit.intercept, fit.slope, fit.r, xLabel, QStringLiteral("n"))));
        QPen pen = fitted->pen();
        pen.setStyle(Qt::DashLine);
        fitted->setPen(pen);
        // sampled densely: on a log axis the straight line is a curve
        const int n = 200;
        for (int k = 0; k < n; ++k) {
          const double f = double(k) / (n - 1);
          const double x = logX ? rx.lo * std::pow(rx.hi / rx.lo, f) : rx.lo + f * (rx.hi - rx.lo);
          fitted->append(x, fit.intercept + fit.slope * x);
          yRange->add(fit.intercept + fit.slope * x);
        }
        chart->addSeries(fitted);
        fitted->attachAxis(ax);
        fitted->attachAxis(yAxis);
      }
    }
  }
  if (!offAxis.isEmpty()) fullTitle += QStringLiteral("<br><small>") + QObject::tr("not on the log axis: ") + offAxis.join(QStringLiteral("; ")) + QStringLiteral("</small>");
  chart->setTitle(fullTitle);
  if (rx.empty()) rx.lo = 0.0, rx.hi = 1.0;
  if (logX) {
    logAxis->setRange(std::pow(10.0, std::floor(std::log10(rx.lo))), std::pow(10.0, std::ceil(std::log10(rx.hi))));
  } else {
    applyTicks(linearX, niceTicks(rx.lo, rx.hi, 8));
  }
  applyTicks(ay, niceTicks(ry.empty() ? 0.0 : ry.lo, ry.empty() ? 1.0 : ry.hi, 7, options.nonNegative));
  if (ayRight) applyTicks(ayRight, niceTicks(ryRight.empty() ? 0.0 : ryRight.lo, ryRight.empty() ? 1.0 : ryRight.hi, 7, options.nonNegative));
  chart->legend()->setVisible(series.size() > 1 || options.fitLine);
  chart->legend()->setAlignment(Qt::AlignBottom);
  return chart;
}

bool writePlotPng(const QString& path, const QString& title, const QString& xLabel, const QString& yLabel,
                  const QVector<PlotSeries>& series, int width, int height, QString& error, const PlotOptions& options) {
  QtCharts::QChart* chart = makePlotChart(title, xLabel, yLabel, series, options);
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
