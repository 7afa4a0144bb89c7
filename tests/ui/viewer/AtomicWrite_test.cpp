// SPDX-License-Identifier: MIT
// The viewer's writers on a full disk (SceneDocument's Save As and mesh export, PlotPanel's and
// writePlotPng's exports): the previous file stays byte for byte, the temporary file is gone and
// the message names the file and the system's reason; and PlotPanel's bounded history, which
// needs no window either. Runs with tests/support/enospc_shim.c preloaded (tests/CMakeLists.txt);
// each case switches the full disk on for its own directory with setenv(). The atomic writer
// itself: common/AtomicFile_test.cpp.
#include <QApplication>
#include <QFile>
#include <QTemporaryDir>
#include <catch2/catch.hpp>

#include "../common/FullDiskFiles.h"
#include "PlotPanel.h"
#include "Plot.h"
#include "SceneDocument.h"
#include "bsdeform/NodesInit.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/SoBSplineDeformSurface.h"

using testsupport::checkKept;
using testsupport::entries;
using testsupport::slurp;
using FullDisk = testsupport::QtFullDisk;

namespace {

void ensureApp() {
  static QApplication* app = nullptr;
  if (app) return;
  if (qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM")) qputenv("QT_QPA_PLATFORM", "offscreen");
  static int argc = 1;
  static char name[] = "bsdeform_io_tests";
  static char* argv[] = {name, nullptr};
  app = new QApplication(argc, argv);
  bsdeform::disableDynamicNodeLoading();
  bsdeform::initNodes();
}

}  // namespace

TEST_CASE("SceneDocument: Save As and mesh export on a full disk keep the user's file", "[ui]") {
  ensureApp();
  QTemporaryDir dir;
  bsdeform::SceneDocument doc;
  QString error;
  REQUIRE(doc.load(QStringLiteral(BSDEFORM_SCENES_DIR "/paper_fig7_sinusoidal.iv"), error));
  REQUIRE(!doc.surfaces().isEmpty());
  SoBSplineDeformSurface* s = doc.surfaces().first();
  s->stepSimulation(3);
  const QString scene = dir.filePath(QStringLiteral("scene.iv"));
  REQUIRE(doc.save(scene, error));
  const QByteArray saved = slurp(scene);
  REQUIRE(saved.contains("simulationTime"));
  s->stepSimulation(5);  // new state, not yet saved
  {
    FullDisk full(dir.path());
    error.clear();
    CHECK(!doc.save(scene, error));
    checkKept(scene, saved, error);
  }
  {
    FullDisk full(dir.path(), 3000);  // room for a part of the file only
    error.clear();
    CHECK(!doc.save(scene, error));
    checkKept(scene, saved, error);
  }
  // the kept file still loads, with the state of the first save
  bsdeform::SceneDocument again;
  REQUIRE(again.load(scene, error));
  CHECK(again.surfaces().first()->simulation().time() == Approx(0.3));

  for (const char* name : {"mesh.obj", "mesh.stl"}) {
    const QString mesh = dir.filePath(QString::fromLatin1(name));
    REQUIRE(doc.exportMesh(s, mesh, error));
    const QByteArray before = slurp(mesh);
    s->stepSimulation(1);
    FullDisk full(dir.path());
    error.clear();
    CHECK(!doc.exportMesh(s, mesh, error));
    INFO(error.toStdString());
    CHECK(error.contains(QStringLiteral("No space left on device")));
    CHECK(error.contains(QString::fromLatin1(name)));
    CHECK(slurp(mesh) == before);
  }
}

TEST_CASE("Plot exports on a full disk keep the previous files", "[ui]") {
  ensureApp();
  QTemporaryDir dir;
  bsdeform::SceneDocument doc;
  QString error;
  REQUIRE(doc.load(QStringLiteral(BSDEFORM_SCENES_DIR "/paper_fig7_sinusoidal.iv"), error));
  SoBSplineDeformSurface* s = doc.surfaces().first();
  bsdeform::PlotPanel panel;
  panel.resize(400, 300);
  panel.setSurface(s, QStringLiteral("Surface"));
  for (int i = 0; i < 5; ++i) {
    s->stepSimulation(1);
    panel.sample();
  }
  const QString csv = dir.filePath(QStringLiteral("history.csv")), png = dir.filePath(QStringLiteral("plot.png")),
                sweep = dir.filePath(QStringLiteral("sweep.png"));
  REQUIRE(panel.exportCsv(csv, error));
  REQUIRE(panel.exportPng(png, error));
  REQUIRE(bsdeform::writePlotPng(sweep, QStringLiteral("t"), QStringLiteral("x"), QStringLiteral("y"),
                                 {{QStringLiteral("a"), {0, 1, 2}, {1, 2, 3}}}, 300, 200, error));
  const QByteArray csvBefore = slurp(csv), pngBefore = slurp(png), sweepBefore = slurp(sweep);
  s->stepSimulation(1);
  panel.sample();
  FullDisk full(dir.path());
  error.clear();
  CHECK(!panel.exportCsv(csv, error));
  CHECK(error.contains(QStringLiteral("No space left on device")));
  CHECK(slurp(csv) == csvBefore);
  error.clear();
  CHECK(!panel.exportPng(png, error));
  CHECK(error.contains(QStringLiteral("No space left on device")));
  CHECK(slurp(png) == pngBefore);
  error.clear();
  CHECK(!bsdeform::writePlotPng(sweep, QStringLiteral("t"), QStringLiteral("x"), QStringLiteral("y"),
                                {{QStringLiteral("a"), {0, 1, 2}, {1, 2, 4}}}, 300, 200, error));
  CHECK(error.contains(QStringLiteral("No space left on device")));
  CHECK(error.contains(QStringLiteral("sweep.png")));
  CHECK(slurp(sweep) == sweepBefore);
  CHECK(entries(dir.path()) == QStringList({QStringLiteral("history.csv"), QStringLiteral("plot.png"), QStringLiteral("sweep.png")}));
}

TEST_CASE("PlotPanel: the history is bounded, keeps its whole time span and stays uniform", "[ui]") {
  ensureApp();
  bsdeform::SceneDocument doc;
  QString error;
  REQUIRE(doc.load(QStringLiteral(BSDEFORM_SCENES_DIR "/paper_fig7_sinusoidal.iv"), error));
  SoBSplineDeformSurface* s = doc.surfaces().first();
  bsdeform::PlotPanel panel;
  panel.setHistoryLimit(100);
  panel.setSurface(s, QStringLiteral("Surface"));  // the sample at t = 0
  const double dt = s->simulation().parameters().timeStep;
  for (int i = 0; i < 1000; ++i) {
    s->stepSimulation(1);
    panel.sample();
    REQUIRE(panel.sampleCount() <= 100);
  }
  // 1001 samples seen: thinned four times (stride 16), the first sample and the whole span kept
  CHECK(panel.historyStride() == 16);
  CHECK(panel.sampleCount() >= 50);
  QTemporaryDir dir;
  const QString csv = dir.filePath(QStringLiteral("history.csv"));
  REQUIRE(panel.exportCsv(csv, error));
  QFile f(csv);
  REQUIRE(f.open(QIODevice::ReadOnly));
  f.readLine();
  QVector<double> t;
  while (!f.atEnd()) t << f.readLine().split(',').first().toDouble();
  REQUIRE(t.size() == panel.sampleCount());
  CHECK(t.first() == 0.0);
  CHECK(t.last() >= 1000 * dt - 16 * dt - 1e-9);
  for (int i = 1; i < t.size(); ++i) CHECK(t[i] - t[i - 1] == Approx(16 * dt));  // uniform spacing
  // a reset restarts the history at full resolution
  s->resetSimulation();
  panel.restart();  // what the window does when the surface tells of a new state
  CHECK(panel.sampleCount() == 1);
  CHECK(panel.historyStride() == 1);
}
