// SPDX-License-Identifier: MIT
#include "ViewerTestSupport.h"

#include "ViewFraming.h"

#include <Inventor/Qt/SoQt.h>
#include <Inventor/SoDB.h>
#include <Inventor/sensors/SoSensorManager.h>

#include <QApplication>
#include <QFile>
#include <QTemporaryDir>
#include <QTest>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "AtomicFile.h"
#include "ViewFraming.h"
#include "ViewerClock.h"
#include "bsdeform/NodesInit.h"
#include "bsdeform/SoBSplineDeformSurface.h"

// Q_INIT_RESOURCE must be used outside any namespace.
static void initViewerResources() { Q_INIT_RESOURCE(viewer); }

namespace viewer_test {

namespace {
void fatal(const SbString msg, SoQt::FatalErrors, void*) {
  // A missing GL canvas must fail the test, not open a dialog and hang (coin-notes §6).
  std::fprintf(stderr, "SoQt fatal error: %s\n", msg.getString());
  std::abort();
}
}  // namespace

void ensureApp() {
  static QApplication* app = nullptr;
  if (app) return;
  static int argc = 1;
  static char name[] = "bsdeform_ui_tests";
  static char* argv[] = {name, nullptr};
  // autosaves and settings of the windows under test stay out of the user's home
  static QTemporaryDir home;
  qputenv("XDG_DATA_HOME", QFile::encodeName(home.filePath(QStringLiteral("data"))));
  qputenv("XDG_CONFIG_HOME", QFile::encodeName(home.filePath(QStringLiteral("config"))));
  app = new QApplication(argc, argv);
  QApplication::setOrganizationName(QStringLiteral("bsdeform-tests"));
  initViewerResources();
  bsdeform::disableDynamicNodeLoading();
  SoQt::setFatalErrorHandler(fatal, nullptr);
  SoQt::init(argc, argv, "bsdeform_ui_tests");
  bsdeform::initNodes();
}

QString scenePath(const char* name) { return QStringLiteral(BSDEFORM_SCENES_DIR "/") + QLatin1String(name); }

std::unique_ptr<bsdeform::MainWindow> makeWindow(const char* scene) {
  ensureApp();
  auto w = std::make_unique<bsdeform::MainWindow>();
  w->setInteractive(false);
  w->clock().setWallClock(false);
  w->framing().setGlideSeconds(0.0);  // Follow re-frames at once (a glide takes wall time)
  REQUIRE(w->openScene(scenePath(scene)));
  w->show();
  REQUIRE(QTest::qWaitForWindowExposed(w.get()));
  return w;
}

void processEvents() {
  for (int i = 0; i < 3; ++i) {  // a refresh posted by a step, the redraw it asks for
    SoDB::getSensorManager()->processDelayQueue(FALSE);
    QCoreApplication::processEvents();
  }
}

void passTime(bsdeform::MainWindow& w, double seconds) {
  const int frames = int(std::lround(seconds * 60.0));
  for (int k = 0; k < frames; ++k) {
    w.clock().advance(1.0 / 60.0);
    processEvents();
  }
}

SoBSplineDeformSurface* firstSurface(bsdeform::MainWindow& w) {
  REQUIRE(!w.document().surfaces().isEmpty());
  return w.document().surfaces().first();
}

void writeFile(const QString& path, const QByteArray& contents) {
  QString error;
  const bool written = bsdeform::saveFileAtomically(path, contents, error);
  INFO(error.toStdString());
  REQUIRE(written);
}

double nonBackgroundFraction(const QImage& img) {
  const QRgb bg = img.pixel(2, 2);
  long n = 0;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) n += img.pixel(x, y) != bg;
  return double(n) / (img.width() * img.height());
}

}  // namespace viewer_test
