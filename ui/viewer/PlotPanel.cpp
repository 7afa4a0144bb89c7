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

#include "AtomicFile.h"
#include "bsdeform/Simulation.h"
#include "bsdeform/SoBSplineDeformSurface.h"

namespace bsdeform {

namespace {
constexpr int kMaxSamples = 4000;  // older samples are dropped so plotting stays cheap
}

PlotPanel::PlotPanel(QWidget* parent) : QWidget(parent) {
  using namespace QtCharts;
  auto* chart = new QChart;
  m_axisX = new QValueAxis;
  m_axisY = new QValueAxis;
  m_axisX->setTitleText(tr("time"));
  m_axisX->setLabelFormat(QStringLiteral("%.3g"));
  m_axisY->setLabelFormat(QStringLiteral("%.3g"));
  chart->addAxis(m_axisX, Qt::AlignBottom);
  chart->addAxis(m_axisY, Qt::AlignLeft);
  const char* names[3] = {"norm (eq. 15)", "kinetic energy", "strain energy"};
  for (int i = 0; i < 3; ++i) {
    m_series[i] = new QLineSeries;
    m_series[i]->setName(tr(names[i]));
    chart->addSeries(m_series[i]);
    m_series[i]->attachAxis(m_axisX);
    m_series[i]->attachAxis(m_axisY);
  }
  chart->setMargins(QMargins(2, 2, 2, 2));
  m_view = new QChartView(chart);
  m_view->setRenderHint(QPainter::Antialiasing);
  m_view->setMinimumHeight(240);
  auto* png = new QPushButton(tr("Export PNG..."));
  auto* csv = new QPushButton(tr("Export CSV..."));
  auto* buttons = new QHBoxLayout;
  buttons->addStretch();
  buttons->addWidget(png);
  buttons->addWidget(csv);
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(m_view);
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
  m_t.clear();
  m_norm.clear();
  m_kinetic.clear();
  m_strain.clear();
  m_stride = 1;
  m_skipped = 0;
  for (auto* s : m_series) s->clear();
}

void PlotPanel::setHistoryLimit(int limit) {
  m_historyLimit = std::max(4, limit + (limit & 1));  // even: thinning keeps the spacing uniform
  while (m_t.size() >= m_historyLimit) thinHistory();
}

// Drops every second sample (the first is kept) and halves the rate of new ones.
void PlotPanel::thinHistory() {
  for (QVector<double>* v : {&m_t, &m_norm, &m_kinetic, &m_strain}) {
    int k = 0;
    for (int i = 0; i < v->size(); i += 2) (*v)[k++] = (*v)[i];
    v->resize(k);
    v->squeeze();
  }
  m_stride *= 2;
  m_skipped = 0;
}

void PlotPanel::setSurface(SoBSplineDeformSurface* surface, const QString& name) {
  m_surface = surface;
  m_view->chart()->setTitle(surface ? name : QString());
  clearHistory();
  sample();
}

void PlotPanel::sample() {
  if (!m_surface) return;
  const Simulation& sim = m_surface->simulation();
  const double t = sim.time();
  if (!m_t.isEmpty() && t < m_t.back()) clearHistory();  // reset
  if (!m_t.isEmpty() && t == m_t.back()) return;
  const bsdeform::Diagnostics d = sim.diagnostics();  // one pass over the nets (issue 11)
  const double values[3] = {d.norm, d.kinetic, d.strain.total};
  if (m_t.isEmpty() || ++m_skipped >= m_stride) {
    if (m_t.size() >= m_historyLimit) thinHistory();
    m_t << t;
    m_norm << values[0];
    m_kinetic << values[1];
    m_strain << values[2];
    m_skipped = 0;
  }
  for (int i = 0; i < 3; ++i) {
    if (m_series[i]->count() >= kMaxSamples) m_series[i]->removePoints(0, m_series[i]->count() - kMaxSamples + 1);
    m_series[i]->append(t, values[i]);
  }
  // the axes follow what the series show (the latest kMaxSamples samples)
  double lo = 0.0, hi = 1e-12;
  for (const auto* series : m_series)
    for (int i = 0; i < series->count(); ++i) {
      lo = std::min(lo, series->at(i).y());
      hi = std::max(hi, series->at(i).y());
    }
  const double t0 = m_series[0]->at(0).x();
  m_axisX->setRange(t0, std::max(t, t0 + 1e-9));
  m_axisY->setRange(lo, hi * 1.05);
}

bool PlotPanel::exportCsv(const QString& path, QString& error) const {
  QByteArray text = "time,norm,kinetic,strain\n";
  for (int i = 0; i < m_t.size(); ++i)
    text += QByteArray::number(m_t[i], 'g', 17) + ',' + QByteArray::number(m_norm[i], 'g', 17) + ',' +
            QByteArray::number(m_kinetic[i], 'g', 17) + ',' + QByteArray::number(m_strain[i], 'g', 17) + '\n';
  return saveFileAtomically(path, text, error);
}

bool PlotPanel::exportPng(const QString& path, QString& error) {
  return savePngAtomically(path, m_view->grab().toImage(), error);
}

}  // namespace bsdeform
