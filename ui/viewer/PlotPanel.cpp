// SPDX-License-Identifier: MIT
#include "PlotPanel.h"

#include <QFileDialog>
#include <QHBoxLayout>
#include <QPushButton>
#include <QVBoxLayout>
#include <QtCharts/QChart>
#include <QtCharts/QChartView>
#include <QtCharts/QLineSeries>
#include <QtCharts/QValueAxis>
#include <algorithm>
#include <cmath>

#include "AtomicFile.h"
#include "Plot.h"
#include "PlotScale.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/SoBSplineDeformSurface.h"

namespace bsdeform {

namespace {
constexpr int kMaxSamples = 4000;  // older samples are dropped so plotting stays cheap
}

PlotPanel::PlotPanel(QWidget* parent) : QWidget(parent) {
  using namespace QtCharts;
  m_charts = new QWidget;
  auto* row = new QHBoxLayout(m_charts);
  row->setContentsMargins(0, 0, 0, 0);
  const char* titles[2] = {QT_TR_NOOP("norm (eq. 15)"), QT_TR_NOOP("energy")};
  for (int c = 0; c < 2; ++c) {
    auto* chart = new QChart;
    m_axisX[c] = new QValueAxis;
    m_axisY[c] = new QValueAxis;
    m_axisX[c]->setTitleText(tr("time"));
    m_axisY[c]->setTitleText(tr(titles[c]));
    chart->addAxis(m_axisX[c], Qt::AlignBottom);
    chart->addAxis(m_axisY[c], Qt::AlignLeft);
    chart->setMargins(QMargins(2, 2, 2, 2));
    chart->legend()->setAlignment(Qt::AlignTop);
    m_views[c] = new QChartView(chart);
    m_views[c]->setRenderHint(QPainter::Antialiasing);
    m_views[c]->setMinimumHeight(220);
    row->addWidget(m_views[c]);
  }
  const char* names[3] = {QT_TR_NOOP("norm (eq. 15)"), QT_TR_NOOP("kinetic energy"), QT_TR_NOOP("strain energy")};
  for (int i = 0; i < 3; ++i) {
    const int c = i == 0 ? 0 : 1;
    m_series[i] = new QLineSeries;
    m_series[i]->setName(tr(names[i]));
    m_views[c]->chart()->addSeries(m_series[i]);
    m_series[i]->attachAxis(m_axisX[c]);
    m_series[i]->attachAxis(m_axisY[c]);
  }
  m_views[0]->chart()->legend()->setVisible(false);  // one series: the axis title says it
  updateAxes();
  auto* png = new QPushButton(tr("Export PNG..."));
  auto* csv = new QPushButton(tr("Export CSV..."));
  auto* buttons = new QHBoxLayout;
  buttons->addStretch();
  buttons->addWidget(png);
  buttons->addWidget(csv);
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(m_charts);
  layout->addLayout(buttons);
  connect(png, &QPushButton::clicked, this, [this] {
    const QString path = QFileDialog::getSaveFileName(this, tr("Export plot"), QString(), tr("PNG images (*.png)"));
    QString error;
    if (!path.isEmpty() && !exportPng(path, error)) emit failed(error);
  });
  connect(csv, &QPushButton::clicked, this, [this] {
    const QString path = QFileDialog::getSaveFileName(this, tr("Export history"), QString(), tr("CSV files (*.csv)"));
    QString error;
    if (!path.isEmpty() && !exportCsv(path, error)) emit failed(error);
  });
}

void PlotPanel::clearHistory() {
  m_history.clear();
  m_until = INFINITY;
  m_stride = 1;
  m_skipped = 0;
  for (auto* s : m_series) s->clear();
  updateAxes();
}

void PlotPanel::setHistoryLimit(int limit) {
  m_historyLimit = std::max(4, limit + (limit & 1));  // even: thinning keeps the spacing uniform
  while (m_history.size() >= m_historyLimit) thinHistory();
}

// Drops every second sample and halves the rate of new ones.
void PlotPanel::thinHistory() {
  m_history.thin();
  m_stride *= 2;
  m_skipped = 0;
}

void PlotPanel::setSurface(SoBSplineDeformSurface* surface, const QString& name) {
  m_surface = surface;
  m_views[0]->chart()->setTitle(surface ? name : QString());
  restart();
}

void PlotPanel::restart() {
  clearHistory();
  sample();
  updateAxes();
}

void PlotPanel::sample() {
  if (!m_surface) return;
  const Simulation& sim = m_surface->simulation();
  const double t = sim.time();
  if (!m_history.isEmpty() && t == m_history.time().back() && t <= m_until) return;
  if (!m_history.isEmpty() && t <= m_history.time().back()) m_history.dropFrom(t);  // stepping on from an earlier state
  if (t > m_until) showUntil(INFINITY);
  const bsdeform::Diagnostics d = sim.diagnostics();  // one pass over the nets
  const double values[3] = {d.norm, d.kinetic, d.strain.total};
  if (m_history.isEmpty() || ++m_skipped >= m_stride) {
    if (m_history.size() >= m_historyLimit) thinHistory();
    m_history.append(t, d);
    m_skipped = 0;
  }
  for (int i = 0; i < 3; ++i) {
    if (m_series[i]->count() >= kMaxSamples) m_series[i]->removePoints(0, m_series[i]->count() - kMaxSamples + 1);
    m_series[i]->append(t, values[i]);
  }
}

void PlotPanel::replaceAfter(double time, const std::vector<std::pair<double, Diagnostics>>& samples) {
  // dropFrom(t) drops the samples at t and after; the one at the branch point stays
  const QVector<double>& times = m_history.time();
  auto after = std::upper_bound(times.begin(), times.end(), time);
  if (after != times.end()) m_history.dropFrom(*after);
  for (const auto& [t, d] : samples) {
    if (m_history.size() >= m_historyLimit) thinHistory();
    m_history.append(t, d);
  }
  m_skipped = 0;
  rebuildSeries();
}

void PlotPanel::showUntil(double time) {
  if (time == m_until) return;
  m_until = time;
  rebuildSeries();
}

bool PlotPanel::marksPoints() const { return m_series[0]->pointsVisible(); }

double PlotPanel::lastShownTime() const {
  const int n = m_series[0]->count();
  return n ? m_series[0]->at(n - 1).x() : NAN;
}

void PlotPanel::rebuildSeries() {
  const QVector<double>& t = m_history.time();
  const int end = int(std::upper_bound(t.begin(), t.end(), m_until) - t.begin());
  const QVector<double>* values[3] = {&m_history.norm(), &m_history.kinetic(), &m_history.strain()};
  for (int i = 0; i < 3; ++i) {
    QVector<QPointF> points;
    for (int k = std::max(0, end - kMaxSamples); k < end; ++k) points << QPointF(t[k], (*values[i])[k]);
    m_series[i]->replace(points);
  }
  updateAxes();
}

// Round ticks over what the series show (the latest kMaxSamples samples); y >= 0: norms and
// energies are non-negative. One sample or none (after Reset) still gives a real range.
void PlotPanel::updateAxes() {
  // a single sample (after Solve Static, Reset, a state opened) draws no line: mark it
  for (auto* series : m_series) series->setPointsVisible(series->count() == 1);
  const bool any = m_series[0]->count() > 0;
  const double t0 = any ? m_series[0]->at(0).x() : 0.0, t1 = any ? m_series[0]->at(m_series[0]->count() - 1).x() : 0.0;
  const AxisTicks time = niceTicks(t0, t1, 6);
  for (QtCharts::QValueAxis* a : m_axisX) applyTicks(a, time);
  for (int c = 0; c < 2; ++c) {
    double lo = INFINITY, hi = -INFINITY;
    for (int i = c == 0 ? 0 : 1; i < (c == 0 ? 1 : 3); ++i)
      for (int k = 0; k < m_series[i]->count(); ++k) {
        lo = std::min(lo, m_series[i]->at(k).y());
        hi = std::max(hi, m_series[i]->at(k).y());
      }
    if (!(lo <= hi)) lo = hi = 0.0;
    applyTicks(m_axisY[c], niceTicks(lo, hi, 6, true));
  }
}

const QtCharts::QValueAxis* PlotPanel::axis(Axis which) const {
  return which == Axis::Time ? m_axisX[0] : which == Axis::Norm ? m_axisY[0] : m_axisY[1];
}

bool PlotPanel::exportCsv(const QString& path, QString& error) const {
  return saveFileAtomically(path, m_history.csv(), error);
}

bool PlotPanel::exportPng(const QString& path, QString& error) {
  return savePngAtomically(path, m_charts->grab().toImage(), error);
}

}  // namespace bsdeform
