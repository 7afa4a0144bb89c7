// SPDX-License-Identifier: MIT
#include "SweepPool.h"

#include <Inventor/nodes/SoSeparator.h>

#include <QCoreApplication>
#include <QDir>
#include <QEventLoop>
#include <QFile>
#include <QProcess>
#include <QThread>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>

#include "AtomicFile.h"
#include "Plot.h"
#include "RunSetup.h"

namespace bsdeform::run {

SweepPool::SweepPool(const RunOptions& options) : m_options(options) {}

Failure SweepPool::parseSweep() {
  const QString& sweep = m_options.sweep;
  const int eq = sweep.indexOf(QLatin1Char('='));
  if (eq <= 0) return {kBadInput, QStringLiteral("--sweep '%1': expected NAME.field=v1,v2,...").arg(sweep)};
  m_target = sweep.left(eq);
  m_values = sweep.mid(eq + 1).split(QLatin1Char(','), Qt::SkipEmptyParts);
  if (m_values.isEmpty()) return {kBadInput, QStringLiteral("--sweep '%1': no values").arg(sweep)};
  return {kOk, {}};
}

Failure SweepPool::validate() {
  NodeRef<SoSeparator> root;
  Failure f = loadSceneWithSets(m_options, root);
  for (int i = 0; f.ok() && i < m_values.size(); ++i) f = applySet(m_target + QLatin1Char('=') + m_values[i]);
  return f;
}

void SweepPool::collect(int i, const QString& output, const QString& stderrText, int code, bool crashed) {
  for (const QString& line : output.split(QLatin1Char('\n'), Qt::SkipEmptyParts)) {
    const QStringList c = line.split(QLatin1Char('\t'));
    if (c.size() == 6 + m_options.metrics.size() && c[0] == QLatin1String("RESULT"))
      m_rows[i].push_back({m_values[i], c[1], c[2], c[3], c[4], c[5], c.mid(6)});
  }
  if (crashed)
    m_errors[i] = QStringLiteral("run with %1=%2 crashed: %3").arg(m_target, m_values[i], stderrText);
  else if (code != kOk && code != kBlowUp)
    m_errors[i] = QStringLiteral("run with %1=%2 failed: %3").arg(m_target, m_values[i], stderrText);
}

// One child process per value, at most m_parallel at once; each one's signals start the next.
Failure SweepPool::runChildren() {
  m_rows = QVector<QVector<Row>>(m_values.size());
  m_errors = QVector<QString>(m_values.size());
  m_parallel = std::max(1, QThread::idealThreadCount());
  const QString program =
      m_options.sweepProgram.isEmpty() ? QCoreApplication::applicationFilePath() : m_options.sweepProgram;
  ProgressBar progress(m_options);
  QObject owner;  // parent of the child processes: all are gone when this function returns
  QEventLoop loop;
  QString startError;  // set when a child could not be started: the sweep stops
  int next = 0, running = 0, done = 0;
  std::function<void()> startMore;
  auto start = [&](int i) {
    auto* p = new QProcess(&owner);
    p->setProcessChannelMode(QProcess::SeparateChannels);
    // the children fill the cores beside each other: one kernel thread each, unless the
    // environment says otherwise (Parallel.h: the default is every CPU)
    if (qEnvironmentVariableIsEmpty("BSDEFORM_THREADS")) {
      QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
      env.insert(QStringLiteral("BSDEFORM_THREADS"), QStringLiteral("1"));
      p->setProcessEnvironment(env);
    }
    QStringList args = m_options.sweepChildArguments;
    args << QStringLiteral("--set") << m_target + QLatin1Char('=') + m_values[i] << QStringLiteral("--result-only");
    QObject::connect(p, QOverload<int, QProcess::ExitStatus>::of(&QProcess::finished), &owner,
                     [&, i, p](int code, QProcess::ExitStatus status) {
                       collect(i, QString::fromUtf8(p->readAllStandardOutput()),
                               QString::fromUtf8(p->readAllStandardError()).trimmed(), code,
                               status == QProcess::CrashExit);
                       --running;
                       ++done;
                       progress.show(done, m_values.size(), done);
                       startMore();
                     });
    // A child that cannot start never finishes: without this the sweep would wait forever.
    QObject::connect(p, &QProcess::errorOccurred, &owner, [&, i, p](QProcess::ProcessError e) {
      if (e != QProcess::FailedToStart) return;  // crashes and exit codes arrive through finished()
      if (startError.isEmpty())
        startError =
            QStringLiteral("cannot start the run with %1=%2 ('%3'): %4").arg(m_target, m_values[i], program, p->errorString());
      --running;
      ++done;
      for (QProcess* other : owner.findChildren<QProcess*>())
        if (other->state() != QProcess::NotRunning) other->kill();
      startMore();
    });
    ++running;
    p->start(program, args);
  };
  startMore = [&] {
    while (startError.isEmpty() && running < m_parallel && next < m_values.size()) start(next++);
    if (running == 0) loop.quit();
  };
  startMore();
  if (running > 0) loop.exec();
  if (!startError.isEmpty()) return {kInternal, startError};
  QStringList errs;
  for (const QString& e : m_errors)
    if (!e.isEmpty()) errs << e;
  if (!errs.isEmpty()) return {kInternal, errs.join(QStringLiteral("; "))};
  return {kOk, {}};
}

QString SweepPool::csvHeader() const {
  QStringList header{QStringLiteral("value,surface,norm,kinetic,strain,status")};
  for (const Metric& m : m_options.metrics) header << m.name;
  return header.join(QLatin1Char(','));
}

Failure SweepPool::readRows() {
  const QString& path = m_options.sweepRows;
  QFile file(path);
  if (!file.open(QIODevice::ReadOnly))
    return {kBadInput, QStringLiteral("cannot open sweep rows '%1': %2").arg(path, file.errorString())};
  const QStringList lines = QString::fromUtf8(file.readAll()).split(QLatin1Char('\n'), Qt::SkipEmptyParts);
  if (lines.isEmpty() || lines.first() != csvHeader())
    return {kBadInput, QStringLiteral("sweep rows '%1': the first line is not sweep.csv's header").arg(path)};
  const int columns = 6 + int(m_options.metrics.size());
  QVector<Row> rows;
  for (int i = 1; i < lines.size(); ++i) {
    const QStringList c = lines[i].split(QLatin1Char(','));
    if (c.size() != columns)
      return {kBadInput,
              QStringLiteral("sweep rows '%1', line %2: expected %3 columns, got %4").arg(path).arg(i + 1).arg(columns).arg(c.size())};
    rows.push_back({c[0], c[1], c[2], c[3], c[4], c[5], c.mid(6)});
  }
  m_rows = {rows};
  return {kOk, {}};
}

// sweep.csv (every row, a column per --metric after the six), sweep.png (the final norm, or the
// first metric, against the value, when every value is a number) and the summary.
Failure SweepPool::writeResults() {
  QString csv = csvHeader() + QLatin1Char('\n');
  const bool plotMetric = !m_options.metrics.isEmpty();
  std::map<QString, PlotSeries> bySurface;
  bool numeric = true;
  for (const auto& rs : m_rows)
    for (const Row& r : rs) {
      csv += (QStringList{r.value, r.surface, r.norm, r.kinetic, r.strain, r.status} + r.metrics).join(QLatin1Char(',')) +
             QLatin1Char('\n');
      bool ok = false;
      const double x = r.value.toDouble(&ok);
      numeric &= ok;
      const QString& y = plotMetric ? (r.metrics.isEmpty() ? QString() : r.metrics.front()) : r.norm;
      bool finite = false;
      const double yValue = y.toDouble(&finite);
      if (y.isEmpty() || !finite || !std::isfinite(yValue)) continue;  // a failed run, a surface never at rest
      auto& s = bySurface[r.surface];
      s.name = r.surface;
      s.x << x;
      s.y << yValue;
    }
  const QDir out(m_options.outDir);
  QString error;
  if (!saveFileAtomically(out.filePath(QStringLiteral("sweep.csv")), csv.toUtf8(), error)) return writeFailure(error, {});
  QStringList written{out.filePath(QStringLiteral("sweep.csv"))};
  if (numeric) {
    QVector<PlotSeries> series;
    for (auto& kv : bySurface) series << kv.second;
    // a metric is plotted as it is: no least-squares line through a swing's phase
    const bool ok = plotMetric ? writePlotPng(out.filePath(QStringLiteral("sweep.png")),
                                              QStringLiteral("%1 against %2").arg(m_options.metrics.front().name, m_target),
                                              m_target, m_options.metrics.front().name, series, 800, 500, error,
                                              {QString(), false, true, false})
                               : writePlotPng(out.filePath(QStringLiteral("sweep.png")),
                                              QStringLiteral("Deformation norm (eq. 15) against %1").arg(m_target), m_target,
                                              QStringLiteral("final norm ||P - P0||"), series, 800, 500, error,
                                              {QString(), true, true, true});
    if (!ok) return writeFailure(error, written);
    written << out.filePath(QStringLiteral("sweep.png"));
  }
  if (!m_options.quiet) {
    std::printf("bsdeform-run: sweep of %s over %d value(s), %d in parallel\n", m_target.toUtf8().constData(),
                int(m_values.size()), m_parallel);
    std::printf("%s", csv.toUtf8().constData());
    for (const QString& w : written) std::printf("  wrote %s\n", w.toUtf8().constData());
  }
  return {kOk, {}};
}

Failure SweepPool::run() {
  const bool replay = !m_options.sweepRows.isEmpty();
  Failure f = parseSweep();
  if (f.ok()) f = replay ? readRows() : validate();
  if (f.ok()) f = prepareOutDir(m_options);
  if (f.ok() && !replay) f = runChildren();
  if (f.ok()) f = writeResults();
  return f;
}

}  // namespace bsdeform::run
