// SPDX-License-Identifier: MIT
// The diagnostics history shared by bsdeform-run and the viewer's plots (ui/common/History).
#include <QList>
#include <catch2/catch.hpp>

#include "History.h"
#include "bsdeform/Diagnostics.h"

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

TEST_CASE("History: series, CSV with 17 significant digits, thinning", "[ui]") {
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
  CHECK(lines[2] == "0.10000000000000001,0.33333333333333331,2,0.25");  // reads back exactly
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

TEST_CASE("History: bsdeform-run's CSV header lists every column", "[ui]") {
  CHECK(History::detailedCsvHeader() ==
        QStringLiteral("time,step,norm,kinetic,strain,strain_w10,strain_w01,strain_w11,strain_w20,strain_w02,substeps\n"));
}
