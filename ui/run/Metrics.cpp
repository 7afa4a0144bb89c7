// SPDX-License-Identifier: MIT
#include "Metrics.h"

#include <QRegularExpression>
#include <algorithm>
#include <cmath>

#include "History.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/spline/SplineSpace.h"

namespace bsdeform::run {

bool Metric::parse(const QString& text, Metric& m, QString& error) {
  m = Metric();
  m.name = text.trimmed();
  if (m.name == QLatin1String("stretch")) m.kind = Stretch;
  else if (m.name == QLatin1String("max-stretch")) m.kind = MaxStretch;
  else if (m.name == QLatin1String("kinetic")) m.kind = Kinetic;
  else if (m.name == QLatin1String("rest-time")) m.kind = RestTime;
  else {
    static const QRegularExpression point(QStringLiteral("^(max-|min-)?([xyz])@([^:]+):([^:]+)$"));
    const QRegularExpressionMatch match = point.match(m.name);
    bool okU = false, okV = false;
    if (match.hasMatch()) {
      m.u = match.captured(3).toDouble(&okU);
      m.v = match.captured(4).toDouble(&okV);
    }
    if (!match.hasMatch() || !okU || !okV || !(m.u >= 0.0 && m.u <= 1.0 && m.v >= 0.0 && m.v <= 1.0)) {
      error = QStringLiteral("--metric '%1' is not one of z@U:V (or x, y; U, V in [0, 1]), max-z@U:V, min-z@U:V, "
                             "stretch, max-stretch, kinetic, rest-time")
                  .arg(text);
      return false;
    }
    m.kind = match.captured(1) == QLatin1String("max-") ? PointMax : match.captured(1) == QLatin1String("min-") ? PointMin : Point;
    m.axis = match.captured(2) == QLatin1String("x") ? 0 : match.captured(2) == QLatin1String("y") ? 1 : 2;
  }
  return true;
}

namespace {
double pointOf(const Simulation& sim, const Metric& m) { return sim.evaluate(m.u, m.v).position[m.axis]; }
double stretchOf(const Simulation& sim) {
  const double rest = sim.restArea();
  return rest > 0.0 ? surfaceArea(sim.space(), sim.current()) / rest : NAN;
}
}  // namespace

MetricTracker::MetricTracker(const QVector<Metric>& metrics) : m_metrics(metrics), m_extreme(metrics.size(), NAN) {
  for (const Metric& m : metrics) m_wantsKinetic |= m.kind == Metric::RestTime;
}

void MetricTracker::update(const Simulation& sim) {
  for (int i = 0; i < m_metrics.size(); ++i) {
    const Metric& m = m_metrics[i];
    double x = NAN;
    if (m.kind == Metric::PointMax || m.kind == Metric::PointMin) x = pointOf(sim, m);
    else if (m.kind == Metric::MaxStretch) x = stretchOf(sim);
    else continue;
    double& e = m_extreme[i];
    if (!m_any || std::isnan(e)) e = x;
    else e = m.kind == Metric::PointMin ? std::min(e, x) : std::max(e, x);
  }
  if (m_wantsKinetic) {
    const double k = sim.diagnostics().kinetic;
    m_times << sim.time();
    m_kinetic << k;
    if (std::isfinite(k)) m_maxKinetic = std::max(m_maxKinetic, k);
  }
  m_any = true;
}

QStringList MetricTracker::values(const Simulation& sim) const {
  QStringList out;
  for (int i = 0; i < m_metrics.size(); ++i) {
    const Metric& m = m_metrics[i];
    double x = NAN;
    switch (m.kind) {
      case Metric::Point: x = pointOf(sim, m); break;
      case Metric::PointMax:
      case Metric::PointMin:
      case Metric::MaxStretch: x = m_extreme[i]; break;
      case Metric::Stretch: x = stretchOf(sim); break;
      case Metric::Kinetic: x = sim.diagnostics().kinetic; break;
      case Metric::RestTime: {
        // the first time from which on the kinetic energy stays below 1e-3 of its largest value
        const double threshold = 1e-3 * m_maxKinetic;
        int last = -1;  // the last sample above it
        for (int k = 0; k < m_kinetic.size(); ++k)
          if (!(m_kinetic[k] <= threshold)) last = k;
        if (m_maxKinetic > 0.0 && last + 1 < m_kinetic.size()) x = m_times[last + 1];
        else if (m_maxKinetic == 0.0 && !m_times.isEmpty()) x = m_times.front();  // never moved
        break;
      }
    }
    // a time at its 15-digit value (as the CSV's time column), the rest exactly
    out << (std::isnan(x) ? QStringLiteral("nan") : m.kind == Metric::RestTime ? decimalNumber(x) : historyNumber(x));
  }
  return out;
}

}  // namespace bsdeform::run
