// SPDX-License-Identifier: MIT
// bsdeform-viewer's window driven like a user would, under xvfb-run (see tests/CMakeLists.txt).
#include <Inventor/Qt/SoQt.h>
#include <Inventor/Qt/viewers/SoQtExaminerViewer.h>
#include <Inventor/SbViewVolume.h>
#include <Inventor/nodes/SoCamera.h>

#include <QApplication>
#include <QDir>
#include <QDockWidget>
#include <QAction>
#include <QFile>
#include <QKeySequence>
#include <QGLWidget>
#include <QMouseEvent>
#include <QProcess>
#include <QSettings>
#include <QTemporaryDir>
#include <QTest>
#include <catch2/catch.hpp>
#include <cstdio>
#include <cstdlib>

#include "DragTool.h"
#include "FieldEditor.h"
#include "MainWindow.h"
#include "ViewerTestSupport.h"
#include "PlotPanel.h"
#include "ViewerTestSupport.h"
#include "bsdeform/NodesInit.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/SoBSplineDeformSurface.h"
#include "bsdeform/SoForceField.h"

using bsdeform::MainWindow;

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define BSDEFORM_TEST_HAS_ASAN 1
#endif
#endif
#ifndef BSDEFORM_TEST_HAS_ASAN
#define BSDEFORM_TEST_HAS_ASAN 0
#endif

namespace {

using viewer_test::passTime;
using viewer_test::processEvents;
using viewer_test::ensureApp;
using viewer_test::firstSurface;
using viewer_test::makeWindow;
using viewer_test::nonBackgroundFraction;
using viewer_test::scenePath;
using viewer_test::writeFile;

// Pixel position of a world point in the 3D view.
QPoint toScreen(MainWindow& w, const SbVec3f& world) {
  SoQtExaminerViewer* v = w.viewer();
  const SbViewportRegion vp = v->getViewportRegion();
  const SbViewVolume vv = v->getCamera()->getViewVolume(vp.getViewportAspectRatio());
  SbVec3f s;
  vv.projectToScreen(world, s);
  const QSize size = v->getGLWidget()->size();
  return QPoint(int(s[0] * size.width()), int((1.0f - s[1]) * size.height()));
}

}  // namespace

TEST_CASE("Viewer: plays a scene, time advances and the frame buffer shows the surface", "[ui]") {
  auto w = makeWindow("region_load.iv");
  SoBSplineDeformSurface* s = firstSurface(*w);
  w->setPlaying(true);
  passTime(*w, 1.5);
  const double dt = s->simulation().parameters().timeStep;
  CHECK(s->simulation().time() == Approx(1.5).margin(dt));  // 1.5 s of the clock at speed 1
  CHECK(w->framesDrawn() > 5);
  const QImage shot = w->screenshot();
  REQUIRE(!shot.isNull());
  CHECK(nonBackgroundFraction(shot) > 0.05);
  // the orange surface is there (not a black or empty view)
  long orange = 0;
  for (int y = 0; y < shot.height(); y += 2)
    for (int x = 0; x < shot.width(); x += 2) {
      const QColor c = shot.pixelColor(x, y);
      orange += c.red() > 120 && c.red() > c.blue() + 60;
    }
  CHECK(orange > 500);
  shot.save(QStringLiteral("viewer_screenshot.png"));
  const QImage window = w->windowScreenshot();
  CHECK(window.size() == w->size());
  window.save(QStringLiteral("viewer_window.png"));  // the README picture
  // a screenshot at another size goes through the offscreen renderer with the same camera
  const QImage big = w->screenshot(QSize(320, 200));
  REQUIRE(big.size() == QSize(320, 200));
  CHECK(nonBackgroundFraction(big) > 0.05);
  CHECK(w->plotPanel().sampleCount() > 3);
}

TEST_CASE("Viewer: step advances by one time step and reset returns to t = 0", "[ui]") {
  auto w = makeWindow("paper_fig7_sinusoidal.iv");
  SoBSplineDeformSurface* s = firstSurface(*w);
  w->pause();
  const double t0 = s->simulation().time();
  const long n0 = s->simulation().stepCount();
  w->step();
  CHECK(s->simulation().time() == Approx(t0 + 0.1));
  CHECK(s->simulation().stepCount() == n0 + 1);
  w->step();
  w->step();
  CHECK(s->simulation().stepCount() == n0 + 3);
  CHECK(!w->isPlaying());
  passTime(*w, 0.3);
  CHECK(s->simulation().stepCount() == n0 + 3);  // paused
  w->reset();
  CHECK(s->simulation().time() == 0.0);
  CHECK(s->simulation().deformationNorm() == 0.0);
}

TEST_CASE("Viewer: a mouse drag on the surface pulls it toward the cursor", "[ui]") {
  auto w = makeWindow("paper_fig2_point_force.iv");
  SoBSplineDeformSurface* s = firstSurface(*w);
  w->reset();
  w->setPlaying(true);
  w->setDragMode(true);
  QWidget* gl = w->viewer()->getGLWidget();
  const Eigen::Vector3d start = s->simulation().evaluate(0.5, 0.5, 0).position;
  const QPoint p0 = toScreen(*w, SbVec3f(float(start.x()), float(start.y()), float(start.z())));
  QTest::mousePress(gl, Qt::LeftButton, Qt::NoModifier, p0);
  processEvents();
  REQUIRE(w->dragTool().isDragging());
  const SbVec2f uv = w->dragTool().pickedParameter();
  CHECK(uv[0] == Approx(0.5).margin(0.03));
  CHECK(uv[1] == Approx(0.5).margin(0.03));
  // move the cursor up-right in steps with the button held
  for (int i = 1; i <= 10; ++i) {
    const QPoint p = p0 + QPoint(6 * i, -8 * i);
    QMouseEvent move(QEvent::MouseMove, p, gl->mapToGlobal(p), Qt::NoButton, Qt::LeftButton, Qt::NoModifier);
    QApplication::sendEvent(gl, &move);
    passTime(*w, 1.0 / 60.0);
  }
  const SbVec3f anchor = w->dragTool().anchorWorld();
  passTime(*w, 1.5);
  const Eigen::Vector3d now = s->simulation().evaluate(uv[0], uv[1], 0).position;
  const Eigen::Vector3d a(anchor[0], anchor[1], anchor[2]);
  INFO("start " << start.transpose() << " now " << now.transpose() << " anchor " << a.transpose());
  CHECK((now - start).norm() > 0.05);
  CHECK((now - start).dot(a - start) > 0.0);             // toward the cursor
  CHECK((a - now).norm() < (a - start).norm());           // closer than before
  CHECK(s->simulation().forces().size() == size_t(s->forces.getNum()) + 1);  // the scene's and the spring
  QTest::mouseRelease(gl, Qt::LeftButton, Qt::NoModifier, p0 + QPoint(60, -80));
  processEvents();
  CHECK(!w->dragTool().isDragging());
  CHECK(s->simulation().forces().size() == size_t(s->forces.getNum()));
}

TEST_CASE("Viewer: a bad file shows the error and keeps the current scene", "[ui]") {
  auto w = makeWindow("region_load.iv");
  SoBSplineDeformSurface* before = firstSurface(*w);
  QTemporaryDir dir;
  const QString bad = dir.filePath(QStringLiteral("broken.iv"));
  writeFile(bad, "#Inventor V2.1 ascii\nSeparator {\n  SoBSplineDeformSurface { integrator SIDEWAYS }\n}\n");
  CHECK(!w->openScene(bad));
  CHECK(w->lastError().contains(QStringLiteral("broken.iv")));
  CHECK(w->lastError().contains(QStringLiteral("line")));
  CHECK(w->lastError().contains(QStringLiteral("SIDEWAYS")));
  CHECK(w->document().path() == scenePath("region_load.iv"));
  CHECK(firstSurface(*w) == before);
  CHECK(!w->openScene(dir.filePath(QStringLiteral("missing.iv"))));
  CHECK(w->lastError().contains(QStringLiteral("missing.iv")));
  CHECK(firstSurface(*w) == before);
}

TEST_CASE("Viewer: Save As then reload gives the same state, mesh export, field editor", "[ui]") {
  auto w = makeWindow("paper_fig6_sinusoidal_degree4.iv");
  SoBSplineDeformSurface* s = firstSurface(*w);
  w->pause();
  for (int i = 0; i < 7; ++i) w->step();
  const bsdeform::ControlNet net = s->simulation().current();
  const double t = s->simulation().time();
  QTemporaryDir dir;
  const QString path = dir.filePath(QStringLiteral("saved.iv"));
  w->setSpeed(3.0);
  REQUIRE(w->saveSceneAs(path));
  {
    // Pause and speed are the viewer's clock: the file animates in any Coin viewer as authored
    QFile f(path);
    REQUIRE(f.open(QIODevice::ReadOnly));
    const QByteArray text = f.readAll();
    CHECK(!text.contains("on FALSE"));
    CHECK(!text.contains("speed 3"));
    // the file's leading comment block is kept, right after the #Inventor line
    QFile original(scenePath("paper_fig6_sinusoidal_degree4.iv"));
    REQUIRE(original.open(QIODevice::ReadOnly));
    QByteArray block = original.readLine();  // #Inventor V2.1 ascii
    while (!original.atEnd()) {
      const QByteArray line = original.readLine();
      if (!line.startsWith('#')) break;
      block += line;
    }
    CHECK(block.count('\n') > 3);
    CHECK(text.startsWith(block));
  }
  // Save As is Ctrl+Shift+S
  bool saveAsKey = false;
  for (QAction* a : w->findChildren<QAction*>())
    saveAsKey |= a->text() == QStringLiteral("Save &As...") && a->shortcut() == QKeySequence(QStringLiteral("Ctrl+Shift+S"));
  CHECK(saveAsKey);
  REQUIRE(w->openScene(path));
  SoBSplineDeformSurface* r = firstSurface(*w);
  CHECK(r != s);
  CHECK(r->simulation().time() == Approx(t));
  CHECK((r->simulation().current() - net).cwiseAbs().maxCoeff() < 1e-12);
  // OBJ and STL of the surface
  REQUIRE(w->exportMesh(dir.filePath(QStringLiteral("mesh.obj"))));
  REQUIRE(w->exportMesh(dir.filePath(QStringLiteral("mesh.stl"))));
  QFile obj(dir.filePath(QStringLiteral("mesh.obj")));
  REQUIRE(obj.open(QIODevice::ReadOnly));
  int faces = 0;
  while (!obj.atEnd()) faces += obj.readLine().startsWith("f ");
  QFile stl(dir.filePath(QStringLiteral("mesh.stl")));
  REQUIRE(stl.open(QIODevice::ReadOnly));
  const QByteArray bin = stl.readAll();
  REQUIRE(bin.size() > 84);
  quint32 triangles = 0;
  std::memcpy(&triangles, bin.constData() + 80, 4);
  CHECK(faces > 100);
  CHECK(int(triangles) == faces);
  CHECK(bin.size() == 84 + 50 * faces);
  CHECK(!w->exportMesh(dir.filePath(QStringLiteral("mesh.xyz"))));
  // the field editor is bound to the selected surface
  CHECK(w->fieldEditor().container() == r);
}

// ---------------------------------------------------------------------------------------------
// Autosave and crash recovery (docs/reliability.md)

namespace {

QStringList recoveryFiles(const QString& dir) {
  return QDir(dir).entryList({QStringLiteral("recovery-*")}, QDir::Files | QDir::Hidden, QDir::Name);
}

double timeIn(const QString& path) {
  bsdeform::SceneDocument doc;
  QString error;
  const bool loaded = doc.load(path, error);
  INFO(error.toStdString());
  REQUIRE(loaded);
  REQUIRE(!doc.surfaces().isEmpty());
  return doc.surfaces().first()->simulationTime.getValue();
}

// Starts bsdeform-viewer with XDG_DATA_HOME = `home` (its recovery files go to
// home/bsdeform/bsdeform-viewer/recovery), its settings under `home` too, and CI=true.
void startViewer(QProcess& p, const QString& home, const QStringList& args) {
  QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
  env.insert(QStringLiteral("XDG_DATA_HOME"), home);
  env.insert(QStringLiteral("XDG_CONFIG_HOME"), home + QStringLiteral("/config"));  // its recent-files list
  env.insert(QStringLiteral("CI"), QStringLiteral("true"));
#if defined(__SANITIZE_ADDRESS__) || BSDEFORM_TEST_HAS_ASAN
  // Sanitizer builds: a viewer that quits destroys its QApplication, which closes the X display
  // and unloads Mesa's swrast_dri.so before LeakSanitizer's check at exit; the driver's own
  // memory then shows as leaks from "<unknown module>", which no suppression can name. The
  // viewer's code is leak-checked in this test process instead, which keeps its display open.
  const QString asan = env.value(QStringLiteral("ASAN_OPTIONS"));
  env.insert(QStringLiteral("ASAN_OPTIONS"), asan.isEmpty() ? QStringLiteral("detect_leaks=0")
                                                            : asan + QStringLiteral(":detect_leaks=0"));
#endif
  p.setProcessEnvironment(env);
  p.start(QStringLiteral(BSDEFORM_VIEWER), args);
  REQUIRE(p.waitForStarted(10000));
}

}  // namespace

TEST_CASE("Viewer: autosave writes the advanced state only when it changed and removes it on save and quit", "[ui]") {
  ensureApp();
  QTemporaryDir dir;
  // a paused scene: nothing changes until the test steps it
  const QString scene = dir.filePath(QStringLiteral("paused.iv"));
  writeFile(scene, "#Inventor V2.1 ascii\nSeparator { SoBSplineDeformSurface { on FALSE numUControlPoints 6 "
                   "numVControlPoints 6 forces [ SoForceField { } ] } }\n");
  auto w = std::make_unique<MainWindow>();
  w->setInteractive(false);
  const QString recovery = dir.filePath(QStringLiteral("recovery"));
  w->autosave().setDirectory(recovery);
  w->autosave().setInterval(100);
  REQUIRE(w->openScene(scene));
  w->show();
  REQUIRE(QTest::qWaitForWindowExposed(w.get()));
  const QString path = w->autosave().filePath();
  CHECK(path.startsWith(recovery));
  QTest::qWait(500);
  CHECK(!QFile::exists(path));  // nothing changed since it was opened

  for (int i = 0; i < 4; ++i) w->step();
  REQUIRE(QTest::qWaitFor([&] { return QFile::exists(path); }, 5000));
  CHECK(timeIn(path) == Approx(0.4));
  CHECK(w->lastError().isEmpty());
  // unchanged: not written again
  const QDateTime written = QFileInfo(path).lastModified();
  QTest::qWait(500);
  CHECK(QFileInfo(path).lastModified() == written);
  // advanced again: written again
  w->step();
  REQUIRE(QTest::qWaitFor([&] { return QFile::exists(path) && timeIn(path) > 0.45; }, 5000));
  CHECK(timeIn(path) == Approx(0.5));

  // a successful save removes it; the saved state is the new baseline
  REQUIRE(w->saveSceneAs(dir.filePath(QStringLiteral("saved.iv"))));
  CHECK(!QFile::exists(path));
  QTest::qWait(400);
  CHECK(!QFile::exists(path));
  CHECK(recoveryFiles(recovery).isEmpty());  // the lock file went too

  // a clean quit removes it
  w->step();
  REQUIRE(QTest::qWaitFor([&] { return QFile::exists(path); }, 5000));
  w->close();
  CHECK(!QFile::exists(path));
  CHECK(recoveryFiles(recovery).isEmpty());
}

TEST_CASE("Viewer: the autosave of a viewer that was killed is offered at the next start and restored", "[ui]") {
  ensureApp();
  QTemporaryDir home;
  const QString recovery = home.filePath(QStringLiteral("bsdeform/bsdeform-viewer/recovery"));
  QProcess viewer;
  startViewer(viewer, home.path(), {scenePath("paper_fig7_sinusoidal.iv"), QStringLiteral("--autosave-interval"), QStringLiteral("0.2")});
  auto recoveryIv = [&] { return QDir(recovery).entryList({QStringLiteral("recovery-*.iv")}, QDir::Files); };
  REQUIRE(QTest::qWaitFor([&] { return !recoveryIv().isEmpty(); }, 30000));
  QTest::qWait(600);  // a few more autosaves while the scene plays
  viewer.kill();      // SIGKILL: no chance to clean up
  REQUIRE(viewer.waitForFinished(10000));
  REQUIRE(recoveryIv().size() == 1);
  const QString left = QDir(recovery).filePath(recoveryIv().first());
  const double t = timeIn(left);
  CHECK(t > 0.0);

  auto w = makeWindow("region_load.iv");
  w->autosave().setDirectory(recovery);
  // Keep (what happens with CI=true or without a user): nothing changes
  CHECK(!w->offerRecovery(bsdeform::RecoveryChoice::Keep));
  CHECK(QFile::exists(left));
  CHECK(w->document().path() == scenePath("region_load.iv"));
  // Restore: the scene and its state are back, under the original file name
  w->pause();
  REQUIRE(w->offerRecovery(bsdeform::RecoveryChoice::Restore));
  w->pause();
  CHECK(w->document().path() == scenePath("paper_fig7_sinusoidal.iv"));
  CHECK(w->isWindowModified());  // the restored work is not in that file: quitting asks
  REQUIRE(!w->document().surfaces().isEmpty());
  CHECK(w->document().surfaces().first()->simulation().time() >= t - 1e-9);
  CHECK(w->document().surfaces().first()->simulation().time() < t + 0.25);
  // the restored work is this viewer's recovery file now; the old one is gone
  CHECK(!QFile::exists(left));
  REQUIRE(QFile::exists(w->autosave().filePath()));
  CHECK(timeIn(w->autosave().filePath()) >= t - 1e-9);
  CHECK(!w->offerRecovery(bsdeform::RecoveryChoice::Restore));  // nothing left to offer
}

TEST_CASE("bsdeform-viewer: --restore-recovery, --discard-recovery and CI=true keeping the file", "[ui]") {
  ensureApp();
  QTemporaryDir home;
  const QString recovery = home.filePath(QStringLiteral("bsdeform/bsdeform-viewer/recovery"));
  REQUIRE(QDir().mkpath(recovery));
  const QString orphan = recovery + QStringLiteral("/recovery-1-1.iv");  // no lock: its viewer is gone
  auto makeOrphan = [&] {
    QFile::remove(orphan);
    REQUIRE(QFile::copy(scenePath("paper_fig2_point_force.iv"), orphan));
  };
  auto runViewer = [&](const QStringList& extra) {
    QProcess p;
    startViewer(p, home.path(), QStringList{QStringLiteral("--measure-fps"), QStringLiteral("0.1")} + extra);
    REQUIRE(p.waitForFinished(60000));
    CHECK(p.exitStatus() == QProcess::NormalExit);
    CHECK(p.exitCode() == 0);
    return QString::fromUtf8(p.readAllStandardError());
  };
  makeOrphan();
  QString err = runViewer({});
  INFO(err.toStdString());
  CHECK(QFile::exists(orphan));  // nobody to ask: kept, and stderr says how to choose
  CHECK(err.contains(QStringLiteral("--restore-recovery")));
  err = runViewer({QStringLiteral("--restore-recovery")});
  CHECK(err.contains(QStringLiteral("Restored")));
  CHECK(!QFile::exists(orphan));
  CHECK(recoveryFiles(recovery).isEmpty());  // the restoring viewer quit cleanly
  makeOrphan();
  err = runViewer({QStringLiteral("--discard-recovery")});
  CHECK(!QFile::exists(orphan));
  CHECK(recoveryFiles(recovery).isEmpty());
}

TEST_CASE("Viewer: a new window comes back with the size and dock layout the last one was closed with", "[ui]") {
  auto docks = [](bsdeform::MainWindow& w) {
    auto* scene = w.findChild<QDockWidget*>(QStringLiteral("sceneDock"));
    auto* plots = w.findChild<QDockWidget*>(QStringLiteral("plotDock"));
    REQUIRE(scene);
    REQUIRE(plots);
    return std::make_pair(scene, plots);
  };
  QSize closedSize;
  {
    auto w = makeWindow("region_load.iv");
    const auto [scene, plots] = docks(*w);
    REQUIRE(w->dockWidgetArea(plots) == Qt::BottomDockWidgetArea);  // the default layout
    REQUIRE(!scene->isHidden());
    w->resize(900, 640);
    w->addDockWidget(Qt::LeftDockWidgetArea, plots);
    scene->hide();
    processEvents();
    closedSize = w->size();
    REQUIRE(closedSize != QSize(1200, 800));
    REQUIRE(w->close());
  }
  {
    auto w = makeWindow("region_load.iv");
    const auto [scene, plots] = docks(*w);
    CHECK(w->size() == closedSize);
    CHECK(w->dockWidgetArea(plots) == Qt::LeftDockWidgetArea);
    CHECK(scene->isHidden());
    CHECK(!plots->isHidden());
  }
  // nothing saved (a first start): the default size and docks
  QSettings().remove(QStringLiteral("window"));
  auto w = makeWindow("region_load.iv");
  const auto [scene, plots] = docks(*w);
  CHECK(w->size() == QSize(1200, 800));
  CHECK(w->dockWidgetArea(plots) == Qt::BottomDockWidgetArea);
  CHECK(!scene->isHidden());
}

TEST_CASE("Viewer: Save and the autosave of a scene with two COLLISION obstacles open again", "[ui]") {
  // Issue 37, item 0: Coin writes the obstacles as `USE A,` newline `USE B ]`, which its reader
  // took as a node called "A,": the user's saved work and its autosave could not be opened.
  ensureApp();
  QTemporaryDir dir;
  const QString scene = dir.filePath(QStringLiteral("two.iv"));
  writeFile(scene, "#Inventor V2.1 ascii\nSeparator {\n"
                   "  Separator { Transform { translation 0.3 0.5 -0.6 } DEF A Sphere { radius 0.5 } }\n"
                   "  Separator { Transform { translation 0.7 0.5 -0.6 } DEF B Cube { } }\n"
                   "  SoBSplineDeformSurface { on FALSE numUControlPoints 6 numVControlPoints 6 timeStep 0.01\n"
                   "    forces [ SoForceField { type GRAVITY },\n"
                   "             SoForceField { type COLLISION obstacles [ USE A, USE B ] } ] } }\n");
  auto w = std::make_unique<MainWindow>();
  w->setInteractive(false);
  const QString recovery = dir.filePath(QStringLiteral("recovery"));
  w->autosave().setDirectory(recovery);
  w->autosave().setInterval(100);
  REQUIRE(w->openScene(scene));
  w->show();
  REQUIRE(QTest::qWaitForWindowExposed(w.get()));
  const QString autosaved = w->autosave().filePath();
  for (int i = 0; i < 3; ++i) w->step();
  REQUIRE(QTest::qWaitFor([&] { return QFile::exists(autosaved); }, 5000));
  // copied before the save removes it
  const QString autosaveCopy = dir.filePath(QStringLiteral("autosave-copy.iv"));
  REQUIRE(QFile::copy(autosaved, autosaveCopy));
  const QString saved = dir.filePath(QStringLiteral("saved.iv"));
  REQUIRE(w->saveSceneAs(saved));
  CHECK(w->lastError().isEmpty());
  for (const QString& path : {saved, autosaveCopy}) {
    INFO(path.toStdString());
    bsdeform::SceneDocument doc;
    QString error;
    const bool loaded = doc.load(path, error);
    INFO(error.toStdString());
    REQUIRE(loaded);
    int collisions = 0;
    for (SoForceField* ff : doc.forceFields()) {
      if (ff->type.getValue() != SoForceField::COLLISION) continue;
      ++collisions;
      REQUIRE(ff->obstacles.getNum() == 2);
      CHECK(std::string(ff->obstacles[0]->getName().getString()) == "A");
      CHECK(std::string(ff->obstacles[1]->getName().getString()) == "B");
    }
    CHECK(collisions == 1);
    CHECK(timeIn(path) == Approx(0.03));
  }
  // and the window opens its own file again
  CHECK(w->openScene(saved));
  CHECK(w->lastError().isEmpty());
}

TEST_CASE("Viewer: --help and a missing display are answered without a window", "[ui]") {
  // Issue 37, item 7: `bsdeform-viewer --help` without a display failed with Qt's "could not
  // connect to display".
  ensureApp();
  QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
  for (const char* name : {"DISPLAY", "WAYLAND_DISPLAY", "QT_QPA_PLATFORM"}) env.remove(QLatin1String(name));
  auto runViewer = [&env](const QStringList& args, QByteArray& out, QByteArray& err) {
    QProcess p;
    p.setProcessEnvironment(env);
    p.start(QStringLiteral(BSDEFORM_VIEWER), args);
    REQUIRE(p.waitForFinished(20000));
    out = p.readAllStandardOutput();
    err = p.readAllStandardError();
    return p.exitStatus() == QProcess::NormalExit ? p.exitCode() : -1;
  };
  QByteArray out, err;
  CHECK(runViewer({QStringLiteral("--help")}, out, err) == 0);
  CHECK(out.contains("--measure-fps"));
  CHECK(out.contains("--states"));
  CHECK(runViewer({}, out, err) == 1);
  CHECK(err.contains("no display"));
  CHECK(err.contains("bsdeform-run"));
  CHECK(runViewer({QStringLiteral("--no-such-option")}, out, err) == 2);
  CHECK(err.contains("no-such-option"));
}
