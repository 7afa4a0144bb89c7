// SPDX-License-Identifier: MIT
// bsdeform-viewer's view: framing, display toggles, plots and help (issue 10, items 1, 4, 5, 8).
#include <Inventor/Qt/viewers/SoQtExaminerViewer.h>
#include <Inventor/nodes/SoCamera.h>
#include <Inventor/nodes/SoSeparator.h>
#include <Inventor/nodes/SoTranslation.h>

#include <QApplication>
#include <QDir>
#include <QElapsedTimer>
#include <QFile>
#include <QFileDialog>
#include <QLineEdit>
#include <QInputDialog>
#include <QTemporaryDir>
#include <QTest>
#include <QTimer>
#include <QtCharts/QChart>
#include <QtCharts/QLogValueAxis>
#include <QtCharts/QValueAxis>
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <vector>

#include "ControlNetDisplay.h"
#include "HelpDialogs.h"
#include "MainWindow.h"
#include "Plot.h"
#include "PlotPanel.h"
#include "ViewFraming.h"
#include "ViewerTestSupport.h"
#include "bsdeform/dynamics/Diagnostics.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/SoBSplineDeformSurface.h"

using namespace viewer_test;
using bsdeform::MainWindow;
using bsdeform::StandardView;
using bsdeform::ViewFraming;

namespace {
void checkFramed(const SbBox2f& box, float minFraction, float margin = ViewFraming::kEdgeMargin) {
  float x0, y0, x1, y1;
  box.getBounds(x0, y0, x1, y1);
  INFO("projected box " << x0 << " " << y0 << " - " << x1 << " " << y1);
  CHECK(x0 >= margin);
  CHECK(y0 >= margin);
  CHECK(x1 <= 1.0f - margin);
  CHECK(y1 <= 1.0f - margin);
  CHECK(std::max(x1 - x0, y1 - y0) > minFraction);
}
}  // namespace

TEST_CASE("Viewer view: a scene without a camera opens in the default oblique view that frames it", "[ui]") {
  auto w = makeWindow("paper_fig3_opposite_point_forces.iv");
  ViewFraming& f = w->framing();
  CHECK(f.isFollowing());
  // the scene was framed when it was opened, before the window had its final size: Follow
  // fits the view as shown once the window has refreshed
  processEvents();
  // the runner's three-quarter view, not SoQt's view straight down
  SbVec3f look;
  w->viewer()->getCamera()->orientation.getValue().multVec(SbVec3f(0, 0, -1), look);
  CHECK((look - bsdeform::viewDirection(StandardView::Default)).length() < 1e-4f);
  checkFramed(f.projectedSceneBox(), 0.4f);
  // every standard view frames it too
  for (StandardView v : {StandardView::Front, StandardView::Top, StandardView::Side, StandardView::Isometric}) {
    f.setView(v);
    checkFramed(f.projectedSceneBox(), 0.4f);
  }
}

TEST_CASE("Viewer view: Follow re-frames a scene that leaves the view, and only when on", "[ui]") {
  auto w = makeWindow("paper_fig3_opposite_point_forces.iv");
  ViewFraming& f = w->framing();
  // the scene moves away (as a deforming surface can): two units along +x
  auto* move = new SoTranslation;
  move->translation.setValue(2.0f, 0.0f, 0.0f);
  w->document().root()->insertChild(move, 0);
  f.setFollowing(false);
  move->translation.setValue(2.5f, 0.0f, 0.0f);
  CHECK_FALSE(f.follow());
  CHECK(f.projectedSceneBox().getMax()[0] > 1.0f);  // out of the view
  f.setFollowing(true);  // framing as it is now: outside, so Follow starts from here
  f.viewAll();
  checkFramed(f.projectedSceneBox(), 0.4f);
  CHECK_FALSE(f.follow());  // nothing moved: no re-framing
  const int reframes = f.followReframes();  // the window's timer also follows (its first show)
  move->translation.setValue(4.0f, 0.0f, 0.0f);
  CHECK(f.follow());
  CHECK(f.followReframes() == reframes + 1);
  checkFramed(f.projectedSceneBox(), 0.4f);
  // the user zooms in on a detail: Follow does not fight the user's camera, it turns off
  SoCamera* cam = w->viewer()->getCamera();
  cam->position = cam->position.getValue() + (SbVec3f(4.5f, 0.5f, 0.0f) - cam->position.getValue()) * 0.8f;
  const SbVec3f userPlaced = cam->position.getValue();
  CHECK_FALSE(f.follow());
  CHECK_FALSE(f.isFollowing());
  move->translation.setValue(9.0f, 0.0f, 0.0f);  // the scene leaves the user's view: still theirs
  CHECK_FALSE(f.follow());
  CHECK(cam->position.getValue() == userPlaced);
  CHECK(f.followReframes() == reframes + 1);
}

TEST_CASE("Viewer view: Follow glides to its new framing, and a drag or a recording holds the camera", "[ui]") {
  auto w = makeWindow("paper_fig3_opposite_point_forces.iv");
  ViewFraming& f = w->framing();
  processEvents();
  f.setGlideSeconds(0.3);
  REQUIRE(f.isFollowing());
  auto* move = new SoTranslation;
  w->document().root()->insertChild(move, 0);
  SoCamera* cam = w->viewer()->getCamera();
  const SbVec3f start = cam->position.getValue();
  move->translation.setValue(3.0f, 0.0f, 0.0f);
  REQUIRE(f.follow());
  CHECK(f.isGliding());
  CHECK(cam->position.getValue() == start);  // not a jump
  // a glide is wall-clock animation, not simulated time: it is waited for
  std::vector<float> along;
  QElapsedTimer t;
  t.start();
  while (f.isGliding() && t.elapsed() < 5000) {
    QTest::qWait(20);
    along.push_back(cam->position.getValue()[0]);
  }
  CHECK_FALSE(f.isGliding());
  CHECK(along.size() >= 3);  // several frames on the way
  CHECK(std::is_sorted(along.begin(), along.end()));  // towards the scene, never back
  checkFramed(f.projectedSceneBox(), 0.4f);
  CHECK(f.isFollowing());
  // a hold (a drag, a recording) ends a glide where it was going and is not a user move
  move->translation.setValue(6.0f, 0.0f, 0.0f);
  REQUIRE(f.follow());
  f.hold();
  CHECK_FALSE(f.isGliding());
  checkFramed(f.projectedSceneBox(), 0.4f);
  CHECK_FALSE(f.follow());
  CHECK(f.isFollowing());
}

TEST_CASE("Viewer view: the camera stays put through a recording while the scene leaves the view", "[ui]") {
  auto w = makeWindow("paper_fig3_opposite_point_forces.iv");
  processEvents();
  REQUIRE(w->framing().isFollowing());
  auto* move = new SoTranslation;
  w->document().root()->insertChild(move, 0);
  QTemporaryDir dir;
  REQUIRE(w->startRecording(dir.filePath(QStringLiteral("held.webm")), 25.0));
  SoCamera* cam = w->viewer()->getCamera();
  const SbVec3f position = cam->position.getValue();
  const SbRotation orientation = cam->orientation.getValue();
  const float focal = cam->focalDistance.getValue();
  w->setPlaying(true);
  for (int i = 1; i <= 6; ++i) {
    move->translation.setValue(0.5f * float(i), 0.0f, 0.0f);  // out of the view by the end
    passTime(*w, 0.2);
    CHECK(cam->position.getValue() == position);
    CHECK(cam->orientation.getValue() == orientation);
    CHECK(cam->focalDistance.getValue() == focal);
  }
  w->stopRecording();
  CHECK(w->framing().isFollowing());  // Follow is back after the recording
  passTime(*w, 0.1);
  checkFramed(w->framing().projectedSceneBox(), 0.4f);
}

TEST_CASE("Viewer view: the default scene stays framed while it plays", "[ui]") {
  auto w = makeWindow("region_load.iv");
  w->setPlaying(true);
  // until the bump has passed its peak (t = 0.9) and settled (t = 3)
  for (int i = 0; i < 6; ++i) {
    passTime(*w, 0.5);
    // in view: Follow re-frames at the window's refresh once the growing bump passes its margin
    checkFramed(w->framing().projectedSceneBox(), 0.3f, 0.0f);
  }
  CHECK(firstSurface(*w)->simulation().time() == Approx(3.0).margin(firstSurface(*w)->simulation().parameters().timeStep));
}

TEST_CASE("Viewer view: a screenshot at another size is lit like the view (one headlight)", "[ui]") {
  auto w = makeWindow("region_load.iv");
  processEvents();  // the GL view has drawn (a grab before its first paint is black)
  const QImage view = w->screenshot();
  const QSize other(view.width() / 2, view.height() / 2);
  const QImage small = w->screenshot(other);
  REQUIRE(small.size() == other);
  view.save(QStringLiteral("viewer_view_screenshot.png"));
  small.save(QStringLiteral("viewer_view_screenshot_half.png"));
  // mean brightness of the pixels that are not background, in both pictures
  auto meanLit = [](const QImage& img) {
    const QRgb bg = img.pixel(2, 2);
    double sum = 0.0;
    long n = 0;
    for (int y = 0; y < img.height(); ++y)
      for (int x = 0; x < img.width(); ++x)
        if (img.pixel(x, y) != bg) {
          sum += qGray(img.pixel(x, y));
          ++n;
        }
    return n ? sum / n : 0.0;
  };
  const double a = meanLit(view), b = meanLit(small);
  INFO("mean grey of the surface: view " << a << ", offscreen " << b);
  CHECK(a > 20.0);
  CHECK(std::abs(a - b) < 0.15 * a);
}

namespace {
// Answers the Save Screenshot dialogs (from a timer: each dialog runs its own event loop): the
// file dialog with `path`, the size dialog with `size`. Both answers set the whole value, so a
// dialog still open on the next tick (a slow machine) is answered again, not appended to. The
// timer is a child of the application; after 20 s it closes any dialog left open, so a failing
// test fails instead of hanging.
void answerScreenshotDialogs(const QString& path, const QString& size) {
  auto* poll = new QTimer(qApp);
  QObject::connect(poll, &QTimer::timeout, poll, [poll, path, size] {
    QWidget* modal = QApplication::activeModalWidget();
    if (auto* files = qobject_cast<QFileDialog*>(modal)) {
      auto* name = files->findChild<QLineEdit*>(QStringLiteral("fileNameEdit"));  // Qt's file name field
      if (!name) return;
      name->setText(path);
      QTest::keyClick(name, Qt::Key_Return);
    } else if (auto* input = qobject_cast<QInputDialog*>(modal)) {
      input->setTextValue(size);
      input->accept();
      poll->deleteLater();
    }
  });
  QTimer::singleShot(20000, poll, [poll] {
    if (auto* dialog = qobject_cast<QDialog*>(QApplication::activeModalWidget())) dialog->reject();
    poll->deleteLater();
  });
  poll->start(50);
}
}  // namespace

TEST_CASE("Viewer view: Save Screenshot asks for the file and the size and writes the picture at that size", "[ui]") {
  auto w = makeWindow("region_load.iv");
  processEvents();  // the GL view has drawn
  QTemporaryDir dir;
  answerScreenshotDialogs(dir.filePath(QStringLiteral("shot")), QStringLiteral("320 x 200"));
  w->screenshotDialog();
  const QImage shot(dir.filePath(QStringLiteral("shot.png")));  // ".png" added to a name without one
  REQUIRE(shot.size() == QSize(320, 200));
  CHECK(nonBackgroundFraction(shot) > 0.05);  // the surface is in the picture
  // a size that is not WxH within 1..8192: the message names it and nothing is written
  answerScreenshotDialogs(dir.filePath(QStringLiteral("bad.png")), QStringLiteral("0x5"));
  w->screenshotDialog();
  CHECK(w->lastError() == QStringLiteral("'0x5' is not a size WxH within 1..8192"));
  CHECK(!QFile::exists(dir.filePath(QStringLiteral("bad.png"))));
  CHECK(QDir(dir.path()).entryList(QDir::Files) == QStringList{QStringLiteral("shot.png")});
}

// ---------------------------------------------------------------------------------------------
// Display: control net and rest ghost

namespace {
// Pixels of a colour family in a screenshot.
long countPixels(const QImage& img, bool (*test)(const QColor&)) {
  long n = 0;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) n += test(img.pixelColor(x, y));
  return n;
}
bool yellow(const QColor& c) { return c.red() > 220 && c.green() > 200 && c.blue() < 90; }
bool red(const QColor& c) { return c.red() > 200 && c.green() < 80 && c.blue() < 80; }
bool paleGrey(const QColor& c) {
  return std::abs(c.red() - 179) < 12 && std::abs(c.green() - 184) < 12 && std::abs(c.blue() - 199) < 12;
}
}  // namespace

TEST_CASE("Viewer view: the control net shows moving and held points, the ghost the rest surface, neither is saved",
          "[ui]") {
  auto w = makeWindow("paper_fig3_opposite_point_forces.iv");
  bsdeform::ControlNetDisplay& net = w->netDisplay();
  REQUIRE(net.surfaceCount() == 1);
  w->setPlaying(false);
  for (int i = 0; i < 15; ++i) w->step();
  processEvents();
  const QImage plain = w->screenshot();
  net.setNetVisible(true);
  // 5 x 5 bicubic, every side clamped: 25 moving points in a net of 11 x 11
  CHECK(net.movingPointCount(0) == 25);
  CHECK(net.heldPointCount(0) == 121 - 25);
  processEvents();
  const QImage withNet = w->screenshot();
  withNet.save(QStringLiteral("viewer_control_net.png"));
  CHECK(countPixels(withNet, yellow) > countPixels(plain, yellow) + 50);
  CHECK(countPixels(withNet, red) > countPixels(plain, red) + 100);
  net.setNetVisible(false);
  net.setGhostVisible(true);
  processEvents();
  const QImage withGhost = w->screenshot();
  withGhost.save(QStringLiteral("viewer_rest_ghost.png"));
  CHECK(countPixels(withGhost, paleGrey) > countPixels(plain, paleGrey) + 200);
  // display aids are not part of the scene: a saved file has neither
  net.setNetVisible(true);
  QTemporaryDir dir;
  const QString path = dir.filePath(QStringLiteral("saved.iv"));
  REQUIRE(w->saveSceneAs(path));
  QFile f(path);
  REQUIRE(f.open(QIODevice::ReadOnly));
  const QByteArray text = f.readAll();
  CHECK_FALSE(text.contains("IndexedLineSet"));
  CHECK_FALSE(text.contains("QuadMesh"));
  CHECK_FALSE(text.contains("PointSet"));
}

TEST_CASE("Viewer view: pins count as held points of the control net", "[ui]") {
  auto w = makeWindow("pinned_cloth.iv");
  bsdeform::ControlNetDisplay& net = w->netDisplay();
  net.setNetVisible(true);
  SoBSplineDeformSurface* s = firstSurface(*w);
  const bsdeform::Simulation& sim = s->simulation();
  REQUIRE(!sim.pinnedRows().empty());
  CHECK(net.movingPointCount(0) == int(sim.space().numMoving()) - int(sim.pinnedRows().size()));
  CHECK(net.movingPointCount(0) + net.heldPointCount(0) <= int(sim.space().netSize()));
}

// ---------------------------------------------------------------------------------------------
// Plots

TEST_CASE("Viewer view: norm and energies on separate axes with round ticks, y >= 0, a range after Reset", "[ui]") {
  using Axis = bsdeform::PlotPanel::Axis;
  auto w = makeWindow("region_load.iv");
  bsdeform::PlotPanel& plots = w->plotPanel();
  auto range = [&](Axis a) { return std::make_pair(plots.axis(a)->min(), plots.axis(a)->max()); };
  // one sample at t = 0, everything zero: real ranges, not a degenerate axis
  w->reset();
  CHECK(range(Axis::Time).first < range(Axis::Time).second);
  CHECK(range(Axis::Norm) == std::make_pair(0.0, 1.0));
  CHECK(range(Axis::Energy) == std::make_pair(0.0, 1.0));
  for (int i = 0; i < 20; ++i) w->step();
  processEvents();  // the axes are fitted once per refresh, the samples taken at every step
  CHECK(plots.sampleCount() == 21);
  const bsdeform::Diagnostics d = firstSurface(*w)->simulation().diagnostics();
  // the norm (about 8 at t = 2) and the energies (below 1) each get their own scale
  CHECK(plots.axis(Axis::Norm)->min() == 0.0);
  CHECK(plots.axis(Axis::Energy)->min() == 0.0);
  CHECK(plots.axis(Axis::Norm)->max() >= d.norm);
  CHECK(plots.axis(Axis::Energy)->max() >= d.strain.total);
  CHECK(plots.axis(Axis::Energy)->max() < 0.5 * plots.axis(Axis::Norm)->max());
  CHECK(plots.axis(Axis::Time)->max() >= 2.0);
  // round ticks: the range is a whole number of steps of 1, 2 or 5 times a power of ten
  for (Axis a : {Axis::Time, Axis::Norm, Axis::Energy}) {
    const auto* axis = plots.axis(a);
    const double step = (axis->max() - axis->min()) / (axis->tickCount() - 1);
    const double mantissa = step / std::pow(10.0, std::floor(std::log10(step) + 1e-9));
    INFO("axis " << int(a) << " " << axis->min() << " .. " << axis->max() << " ticks " << axis->tickCount());
    CHECK((std::abs(mantissa - 1) < 1e-6 || std::abs(mantissa - 2) < 1e-6 || std::abs(mantissa - 5) < 1e-6));
    CHECK(std::abs(axis->min() / step - std::round(axis->min() / step)) < 1e-6);
  }
  w->reset();
  CHECK(range(Axis::Norm) == std::make_pair(0.0, 1.0));
  CHECK(plots.axis(Axis::Time)->max() < 2.0);
}

TEST_CASE("Plot: a sweep over decades gets a log axis, the fitted line with its equation and r", "[ui]") {
  ensureApp();
  bsdeform::PlotSeries s;
  s.name = QStringLiteral("Surface");
  for (double x : {0.0, 0.0001, 0.001, 0.01, 0.1, 1.0, 10.0, 100.0, 200.0}) {
    s.x << x;
    s.y << 0.4 + 0.038 * x;
  }
  bsdeform::PlotOptions o;
  o.nonNegative = o.logXWhenDecades = o.fitLine = true;
  std::unique_ptr<QtCharts::QChart> chart(bsdeform::makePlotChart(QStringLiteral("sweep"), QStringLiteral("w10"), QStringLiteral("norm"), {s}, o));
  const auto horizontal = chart->axes(Qt::Horizontal);
  REQUIRE(horizontal.size() == 1);
  CHECK(qobject_cast<QtCharts::QLogValueAxis*>(horizontal.first()) != nullptr);
  CHECK(chart->title().contains(QStringLiteral("not on the log axis")));  // x = 0
  QStringList names;
  for (QtCharts::QAbstractSeries* series : chart->series()) names << series->name();
  INFO(names.join(QStringLiteral(" | ")).toStdString());
  CHECK(names.join(QStringLiteral(" | ")).contains(QStringLiteral("n = 0.4 + 0.038 w10, r = 1.0000")));
  // values within one decade: a linear axis
  bsdeform::PlotSeries t;
  t.name = QStringLiteral("Surface");
  t.x = {1, 2, 3, 5, 8};
  t.y = {1, 2, 3, 5, 8};
  std::unique_ptr<QtCharts::QChart> linear(bsdeform::makePlotChart(QStringLiteral("sweep"), QStringLiteral("w10"), QStringLiteral("norm"), {t}, o));
  CHECK(qobject_cast<QtCharts::QValueAxis*>(linear->axes(Qt::Horizontal).first()) != nullptr);
}

// ---------------------------------------------------------------------------------------------
// Help

TEST_CASE("Viewer view: Help lists every shortcut of the menus, none used twice, and About names the versions", "[ui]") {
  auto w = makeWindow("paper_fig3_opposite_point_forces.iv");
  const QVector<bsdeform::ShortcutEntry> entries = bsdeform::menuShortcuts(w->menuBar());
  QStringList keys, actions;
  for (const bsdeform::ShortcutEntry& e : entries) {
    keys << e.keys;
    actions << e.action;
  }
  INFO(actions.join(QStringLiteral(", ")).toStdString());
  CHECK(actions.contains(QStringLiteral("Simulation > Pause")) != actions.contains(QStringLiteral("Simulation > Play")));
  CHECK(actions.contains(QStringLiteral("View > Follow")));
  CHECK(actions.contains(QStringLiteral("View > Control Net")));
  CHECK(actions.contains(QStringLiteral("View > Standard Views > Top")));
  CHECK(actions.contains(QStringLiteral("File > Open...")));
  // an ambiguous shortcut triggers nothing in Qt: every key sequence belongs to one action
  QStringList sorted = keys;
  sorted.removeDuplicates();
  CHECK(sorted.size() == keys.size());
  const QString text = bsdeform::shortcutsText(entries);
  for (const bsdeform::ShortcutEntry& e : entries) CHECK(text.contains(e.keys.toHtmlEscaped()));
  const QString about = bsdeform::aboutText();
  CHECK(about.contains(QStringLiteral(BSDEFORM_VERSION)));
  for (const char* lib : {"Coin", "SoQt", "Qt", "Eigen", "CHOLMOD", "Embree"}) CHECK(about.contains(QLatin1String(lib)));
  CHECK(about.contains(QString::fromLatin1(qVersion())));
}

TEST_CASE("Viewer view: a scene's own camera is the one the view shows and the mouse moves", "[ui]") {
  auto w = makeWindow("paper_fig3_opposite_point_forces.iv");  // SoQt makes a camera of its own
  CHECK(bsdeform::findSceneCamera(w->document().root()) == nullptr);
  REQUIRE(w->openScene(scenePath("pressure_bulge.iv")));       // a scene with its camera
  SoCamera* own = bsdeform::findSceneCamera(w->document().root());
  REQUIRE(own);
  // SoQt used to keep its own camera for the same root: the scene's camera was drawn while the
  // mouse moved SoQt's, and drag mapped the cursor through the wrong one
  CHECK(w->viewer()->getCamera() == own);
  CHECK_FALSE(w->framing().isFollowing());
}

TEST_CASE("Viewer view: control net and ghost on every scene: moving points are the simulation's", "[ui][slow]") {
  auto w = makeWindow("region_load.iv");
  bsdeform::ControlNetDisplay& net = w->netDisplay();
  net.setNetVisible(true);
  net.setGhostVisible(true);
  const QStringList scenes = QDir(QStringLiteral(BSDEFORM_SCENES_DIR)).entryList({QStringLiteral("*.iv")}, QDir::Files);
  REQUIRE(scenes.size() >= 14);
  for (const QString& name : scenes) {
    INFO(name.toStdString());
    REQUIRE(w->openScene(scenePath(name.toUtf8().constData())));
    w->step();  // the window's tick updates the overlay
    REQUIRE(net.surfaceCount() == w->document().surfaces().size());
    for (int i = 0; i < net.surfaceCount(); ++i) {
      const bsdeform::Simulation& sim = w->document().surfaces()[i]->simulation();
      // the unknowns that are not pinned, and the points derived from them next to a
      // SIMPLY_SUPPORTED or BUILT_IN side (they move too)
      int derived = 0;
      for (int r = 0; r < sim.space().netRows(); ++r)
        for (int c = 0; c < sim.space().netCols(); ++c) derived += sim.space().isDerived(r, c);
      CHECK(net.movingPointCount(i) == int(sim.space().numMoving()) - int(sim.pinnedRows().size()) + derived);
      CHECK(net.movingPointCount(i) + net.heldPointCount(i) <= int(sim.space().netSize()));
    }
  }
}

TEST_CASE("Viewer view: drawing a collision scene gathers no obstacle, refits none and makes no force", "[ui]") {
  auto w = makeWindow("cloth_on_cube.iv");
  processEvents();
  SoBSplineDeformSurface* s = firstSurface(*w);
  for (int k = 0; k < 3; ++k) w->step();
  processEvents();
  const int builds = s->obstacleBuilds(), refits = s->obstacleRefits(), forces = s->forcesMade();
  const long steps = s->simulation().stepCount();
  CHECK(builds == 1);
  // frames without steps (a paused view redrawn, the camera moved)
  SoCamera* cam = w->viewer()->getCamera();
  for (int k = 0; k < 10; ++k) {
    cam->position = cam->position.getValue() + SbVec3f(0.01f, 0.0f, 0.0f);
    w->viewer()->render();
    processEvents();
  }
  CHECK(s->obstacleBuilds() == builds);
  CHECK(s->obstacleRefits() == refits);
  CHECK(s->forcesMade() == forces);
  CHECK(s->simulation().stepCount() == steps);
}
