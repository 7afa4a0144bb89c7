// SPDX-License-Identifier: MIT
#pragma once
/// @file Metrics.h
/// What a run measures for a sweep (`--metric`, repeatable): one number per surface from the
/// whole run, beside the final norm. The names are sweep.csv's column names:
///
/// | metric        | the number                                                              |
/// |---------------|-------------------------------------------------------------------------|
/// | `z@U:V`       | coordinate z (or x, y) of the surface point S(U, V) at the end          |
/// | `max-z@U:V`   | its largest value over the run (every step); `min-z@U:V` the smallest   |
/// | `stretch`     | area of the surface / its rest area, at the end                         |
/// | `max-stretch` | the largest of that over the run                                        |
/// | `kinetic`     | kinetic energy at the end                                               |
/// | `rest-time`   | the time after which the kinetic energy stays below 1e-3 of its largest |
/// |               | value over the run; nan when it has not come to rest by the end         |
///
/// Points are in the surface's own coordinates (those of its control net).

#include <QString>
#include <QStringList>
#include <QVector>

namespace bsdeform {
class Simulation;
}

namespace bsdeform::run {

struct Metric {
  enum Kind { Point, PointMax, PointMin, Stretch, MaxStretch, Kinetic, RestTime } kind = Kinetic;
  double u = 0.0, v = 0.0;  ///< the point's parameters (Point*)
  int axis = 2;             ///< 0 x, 1 y, 2 z (Point*)
  QString name;             ///< as given: the column's name

  /// Reads one `--metric` value; false with `error` naming it and what is allowed.
  static bool parse(const QString& text, Metric& metric, QString& error);
};

/// One surface's metrics over a run: update() after every step (and at the start), values()
/// at the end, as the shortest text that reads back (rest-time at its 15-digit value, as the
/// CSV's time column; nan when there is none).
class MetricTracker {
 public:
  explicit MetricTracker(const QVector<Metric>& metrics);
  void update(const Simulation& sim);
  QStringList values(const Simulation& sim) const;

 private:
  QVector<Metric> m_metrics;
  QVector<double> m_extreme;  ///< per metric: the largest / smallest so far (PointMax, PointMin, MaxStretch)
  bool m_any = false;
  bool m_wantsKinetic = false;
  double m_maxKinetic = 0.0;
  QVector<double> m_times, m_kinetic;  ///< rest-time: the whole series (decided at the end)
};

}  // namespace bsdeform::run
