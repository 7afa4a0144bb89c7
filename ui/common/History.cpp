// SPDX-License-Identifier: MIT
#include "History.h"

#include <algorithm>

#include <QStringList>

#include "bsdeform/dynamics/Diagnostics.h"

namespace bsdeform {

void History::append(double time, const Diagnostics& d) {
  m_time << time;
  m_norm << d.norm;
  m_kinetic << d.kinetic;
  m_strain << d.strain.total;
}

void History::clear() {
  for (QVector<double>* v : {&m_time, &m_norm, &m_kinetic, &m_strain}) v->clear();
}

void History::thin() {
  for (QVector<double>* v : {&m_time, &m_norm, &m_kinetic, &m_strain}) {
    int k = 0;
    for (int i = 0; i < v->size(); i += 2) (*v)[k++] = (*v)[i];
    v->resize(k);
    v->squeeze();
  }
}

void History::dropFrom(double time) {
  const int keep = int(std::lower_bound(m_time.begin(), m_time.end(), time) - m_time.begin());
  for (QVector<double>* v : {&m_time, &m_norm, &m_kinetic, &m_strain}) v->resize(keep);
}

QVector<PlotSeries> History::plotSeries() const {
  return {{QStringLiteral("norm (eq. 15)"), m_time, m_norm},
          {QStringLiteral("kinetic energy"), m_time, m_kinetic, true},
          {QStringLiteral("strain energy"), m_time, m_strain, true}};
}

QByteArray History::csv() const {
  QByteArray text = "time,norm,kinetic,strain\n";
  for (int i = 0; i < m_time.size(); ++i)
    text += QStringList{decimalNumber(m_time[i]), historyNumber(m_norm[i]), historyNumber(m_kinetic[i]),
                        historyNumber(m_strain[i])}
                .join(QLatin1Char(','))
                .toUtf8() +
            '\n';
  return text;
}

QString History::detailedCsvHeader(bool shell) {
  // the paper's five weight terms are always 0 for a SHELL surface: not written for one
  return shell ? QStringLiteral("time,step,norm,kinetic,strain,substeps,strain_membrane,strain_bending\n")
               : QStringLiteral(
                     "time,step,norm,kinetic,strain,strain_w10,strain_w01,strain_w11,strain_w20,strain_w02,substeps,"
                     "strain_membrane,strain_bending\n");
}

QString History::detailedCsvRow(double time, long steps, int subSteps, const Diagnostics& d, bool shell) {
  const StrainEnergy& e = d.strain;
  QStringList cells{decimalNumber(time), QString::number(steps), historyNumber(d.norm), historyNumber(d.kinetic),
                    historyNumber(e.total)};
  if (!shell)
    cells << historyNumber(e.w10) << historyNumber(e.w01) << historyNumber(e.w11) << historyNumber(e.w20)
          << historyNumber(e.w02);
  cells << QString::number(subSteps) << historyNumber(d.membrane) << historyNumber(d.bending);
  return cells.join(QLatin1Char(',')) + QLatin1Char('\n');
}

}  // namespace bsdeform
