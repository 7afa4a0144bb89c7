// SPDX-License-Identifier: MIT
// Simulation > Record in the viewer: a video of the 3D view at a rate in simulated time, and a
// numbered PNG sequence; read back with libavformat / Qt.
#include <Inventor/Qt/viewers/SoQtExaminerViewer.h>

#include <QDir>
#include <QImage>
#include <QTemporaryDir>
#include <QTest>
#include <catch2/catch.hpp>
#include <cmath>

#include "../../support/VideoReadBack.h"
#include "ViewerTestSupport.h"
#include "bsdeform/Simulation.h"
#include "bsdeform/SoBSplineDeformSurface.h"

using namespace viewer_test;

TEST_CASE("Recording: a video of the playing simulation has a frame per 1/fps of simulated time", "[ui]") {
  QTemporaryDir dir;
  auto w = makeWindow("region_load.iv");
  SoBSplineDeformSurface* s = firstSurface(*w);
  const QString path = dir.filePath(QStringLiteral("bump.mp4"));
  const double fps = 20.0;
  REQUIRE(w->startRecording(path, fps));
  CHECK(w->isRecording());
  const double t0 = s->simulation().time();
  w->setPlaying(true);
  passTime(*w, 1.5);
  w->setPlaying(false);
  processEvents();  // the frames due up to the last step
  const double t1 = s->simulation().time();
  INFO(w->lastError().toStdString());
  REQUIRE(w->stopRecording());
  CHECK_FALSE(w->isRecording());
  const testsupport::ReadBack back = testsupport::readVideo(path.toStdString());
  const QSize view = w->viewer()->getGLWidget()->size();
  CHECK(back.codec == "h264");
  CHECK(back.width == (view.width() & ~1));
  CHECK(back.height == (view.height() & ~1));
  CHECK(back.fps == Approx(fps));
  // one frame at t0 and one at every 1/fps up to t1 (the video's clock is the simulation's)
  const int expected = int(std::floor((t1 - t0) * fps + 1e-9)) + 1;
  INFO("t0 " << t0 << ", t1 " << t1);
  CHECK(back.frames == expected);
  REQUIRE(back.rgb.size() >= 2);
  // the bump grows: the first and last pictures differ
  double differing = 0;
  for (size_t i = 0; i < back.rgb.front().size(); ++i)
    differing += std::abs(int(back.rgb.front()[i]) - int(back.rgb.back()[i])) > 24;
  CHECK(differing / back.rgb.front().size() > 0.01);
}

TEST_CASE("Recording: a numbered PNG sequence while stepping by hand", "[ui]") {
  QTemporaryDir dir;
  auto w = makeWindow("region_load.iv");
  w->setPlaying(false);
  const double dt = firstSurface(*w)->simulation().parameters().timeStep;
  REQUIRE(w->startRecording(dir.filePath(QStringLiteral("take.png")), 1.0 / dt));  // one frame per step
  for (int k = 0; k < 3; ++k) {
    w->step();
    processEvents();
  }
  REQUIRE(w->stopRecording());
  const QStringList files = QDir(dir.path()).entryList(QDir::Files, QDir::Name);
  CHECK(files == QStringList({QStringLiteral("take_00000.png"), QStringLiteral("take_00001.png"),
                              QStringLiteral("take_00002.png"), QStringLiteral("take_00003.png")}));
  const QSize view = w->viewer()->getGLWidget()->size();
  for (const QString& f : files) {
    const QImage img(dir.filePath(f));
    CHECK(img.size() == QSize(view.width() & ~1, view.height() & ~1));
  }
}

TEST_CASE("Recording: an unknown file type is refused with the reason, nothing recorded", "[ui]") {
  QTemporaryDir dir;
  auto w = makeWindow("region_load.iv");
  CHECK_FALSE(w->startRecording(dir.filePath(QStringLiteral("clip.avi")), 25.0));
  CHECK_FALSE(w->isRecording());
  CHECK(w->lastError().contains(QStringLiteral("clip.avi")));
  CHECK(QDir(dir.path()).entryList(QDir::Files | QDir::Hidden).isEmpty());
}
