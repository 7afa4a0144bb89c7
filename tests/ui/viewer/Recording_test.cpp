// SPDX-License-Identifier: MIT
// Simulation > Record in the viewer: a video of the 3D view at a rate in simulated time, and a
// numbered PNG sequence; read back with libavformat / Qt.
#include <Inventor/Qt/viewers/SoQtExaminerViewer.h>

#include <QDir>
#include <QImage>
#include <QTemporaryDir>
#include <QTest>
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "../../support/VideoReadBack.h"
#include "ViewerTestSupport.h"
#include "bsdeform/dynamics/Simulation.h"
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

TEST_CASE("Recording: a recorded frame is the picture the view shows, at two window sizes, with and without a scene camera",
          "[ui]") {
  // Issue 37, item 1: Record wrote grey frames with fine vertical stripes, stretched about 4/3
  // sideways (3-byte pixels read as 4-byte ones), while Save Screenshot was right.
  const char* scenes[] = {"region_load.iv" /* no camera of its own */, "flag.iv" /* its own camera */};
  const QSize sizes[] = {QSize(1000, 700), QSize(760, 620)};
  for (const char* scene : scenes) {
    for (const QSize& windowSize : sizes) {
      INFO(scene << " in a window of " << windowSize.width() << " x " << windowSize.height());
      QTemporaryDir dir;
      auto w = makeWindow(scene);
      w->setPlaying(false);
      w->resize(windowSize);
      processEvents();
      const QImage shot = w->screenshot().convertToFormat(QImage::Format_RGB888);
      REQUIRE(!shot.isNull());
      const QString path = dir.filePath(QStringLiteral("still.mp4"));
      REQUIRE(w->startRecording(path, 10.0));
      processEvents();
      for (int k = 0; k < 2; ++k) {
        w->step();
        processEvents();
      }
      const QImage after = w->screenshot().convertToFormat(QImage::Format_RGB888);
      REQUIRE(w->stopRecording());
      const testsupport::ReadBack back = testsupport::readVideo(path.toStdString());
      REQUIRE(back.rgb.size() >= 1);
      REQUIRE(back.width == (shot.width() & ~1));
      REQUIRE(back.height == (shot.height() & ~1));
      // the last frame against the view after the last step: colour per 16 x 16 block (the
      // encoder's 4:2:0 and quantisation blur edges, a block mean keeps colour and geometry)
      const std::vector<unsigned char>& frame = back.rgb.back();
      const int bw = back.width / 16, bh = back.height / 16;
      double worst = 0.0, total = 0.0;
      int different = 0;
      for (int by = 0; by < bh; ++by)
        for (int bx = 0; bx < bw; ++bx)
          for (int c = 0; c < 3; ++c) {
            double a = 0.0, b = 0.0;
            for (int y = by * 16; y < by * 16 + 16; ++y)
              for (int x = bx * 16; x < bx * 16 + 16; ++x) {
                a += frame[(size_t(y) * back.width + x) * 3 + c];
                b += after.constScanLine(y)[x * 3 + c];
              }
            const double d = std::abs(a - b) / 256.0;
            worst = std::max(worst, d);
            total += d;
            different += d > 12.0;
          }
      const double mean = total / (3.0 * bw * bh);
      if (std::getenv("BSDEFORM_TEST_KEEP_FRAMES")) {  // to look at
        const QString stem = QStringLiteral("recorded_%1_%2x%3").arg(QLatin1String(scene)).arg(back.width).arg(back.height);
        QImage(frame.data(), back.width, back.height, 3 * back.width, QImage::Format_RGB888).save(stem + QStringLiteral("_video.png"));
        after.save(stem + QStringLiteral("_view.png"));
      }
      INFO("mean block difference " << mean << ", worst " << worst << ", blocks off by > 12: " << different);
      CHECK(mean < 2.0);
      CHECK(different <= bw * bh / 50);
      // and the picture is not uniform (a grey frame would match a grey view)
      double lo = 255, hi = 0;
      for (size_t i = 0; i < frame.size(); i += 3) {
        const double luma = 0.3 * frame[i] + 0.59 * frame[i + 1] + 0.11 * frame[i + 2];
        lo = std::min(lo, luma);
        hi = std::max(hi, luma);
      }
      CHECK(hi - lo > 60.0);
    }
  }
}
