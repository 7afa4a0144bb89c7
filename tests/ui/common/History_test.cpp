// SPDX-License-Identifier: MIT
// The diagnostics history shared by bsdeform-run and the viewer's plots (ui/common/History).
#include <QList>
#include <QStringList>
#include <memory>
#include <catch2/catch.hpp>

#include "History.h"
#include "bsdeform/dynamics/Diagnostics.h"
#include "bsdeform/dynamics/Simulation.h"

using bsdeform::History;

namespace {
bsdeform::Diagnostics diagnostics(double norm, double kinetic, double strain) {
  bsdeform::Diagnostics d;
  d.norm = norm;
  d.kinetic = kinetic;
  d.strain.total = strain;
  return d;
}
}  // namespace

TEST_CASE("History: series, CSV in the shortest text that reads back, thinning", "[ui]") {
  History h;
  for (int i = 0; i < 5; ++i) h.append(0.1 * i, diagnostics(1.0 / 3.0 * i, 2.0 * i, 0.25 * i));
  REQUIRE(h.size() == 5);
  CHECK(h.time()[4] == 0.1 * 4);
  CHECK(h.norm()[3] == 1.0 / 3.0 * 3);
  CHECK(h.kinetic()[2] == 4.0);
  CHECK(h.strain()[1] == 0.25);
  const QList<QByteArray> lines = h.csv().split('\n');
  REQUIRE(lines.size() == 7);  // header, 5 rows, the empty text after the last newline
  CHECK(lines[0] == "time,norm,kinetic,strain");
  CHECK(lines[1] == "0,0,0,0");
  CHECK(lines[2] == "0.1,0.3333333333333333,2,0.25");  // reads back exactly
  CHECK(lines[6].isEmpty());
  const QVector<bsdeform::PlotSeries> series = h.plotSeries();
  REQUIRE(series.size() == 3);
  CHECK(!series[0].rightAxis);  // the norm on the left, the energies on the right
  CHECK(series[1].rightAxis);
  CHECK(series[2].rightAxis);
  CHECK(series[2].y == h.strain());
  h.thin();  // the first sample stays, every second one goes
  REQUIRE(h.size() == 3);
  CHECK(h.time() == QVector<double>({0.0, 0.1 * 2, 0.1 * 4}));
  CHECK(h.kinetic() == QVector<double>({0.0, 4.0, 8.0}));
  h.clear();
  CHECK(h.isEmpty());
  CHECK(h.csv() == "time,norm,kinetic,strain\n");
}

TEST_CASE("History: bsdeform-run's CSV rows have a value under every header column, read back exactly", "[ui]") {
  bsdeform::ModelParameters p;
  p.numU = p.numV = 6;
  bsdeform::Simulation sim(p);
  sim.addForce(std::make_shared<bsdeform::DistributedForce>(Eigen::Vector3d(0, 0, 3)));
  sim.advance(5);
  const bsdeform::Diagnostics d = sim.diagnostics();
  const QStringList header = History::detailedCsvHeader().trimmed().split(QLatin1Char(','));
  const QStringList row = History::detailedCsvRow(sim.time(), sim.stepCount(), sim.subSteps(), d).trimmed().split(QLatin1Char(','));
  REQUIRE(row.size() == header.size());
  auto value = [&](const char* column) { return row[header.indexOf(QLatin1String(column))].toDouble(); };
  CHECK(value("time") == sim.time());
  CHECK(value("step") == double(sim.stepCount()));
  CHECK(value("norm") == d.norm);  // 17 significant digits read back to the same double
  CHECK(value("kinetic") == d.kinetic);
  CHECK(value("strain") == d.strain.total);
  CHECK(value("strain_w10") == d.strain.w10);
  CHECK(value("strain_w02") == d.strain.w02);
  CHECK(value("substeps") == double(sim.subSteps()));
  CHECK(d.strain.total > 0.0);  // a deformed state, not all zeros
}

TEST_CASE("History: the time column is the time as a person reads it, not a sum's last bits", "[ui]") {
  // Issue 37, item 4: 0.1 added ten times is 0.9999999999999999, and the CSV said so.
  History h;
  double t = 0.0;
  for (int i = 0; i < 10; ++i) t += 0.1;
  REQUIRE(t != 1.0);
  h.append(t, diagnostics(1.0 / 3.0, 0.0, 0.0));
  const QList<QByteArray> lines = h.csv().split('\n');
  CHECK(lines[1] == "1,0.3333333333333333,0,0");
  CHECK(History::detailedCsvRow(t, 10, 1, diagnostics(0, 0, 0)).startsWith(QStringLiteral("1,10,")));
  CHECK(bsdeform::decimalNumber(0.1 + 0.2) == QStringLiteral("0.3"));
  CHECK(bsdeform::historyNumber(0.1 + 0.2) == QStringLiteral("0.30000000000000004"));  // other values: exact
  CHECK(bsdeform::decimalNumber(1e-300) == QStringLiteral("1e-300"));
}
