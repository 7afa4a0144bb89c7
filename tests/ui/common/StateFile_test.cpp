// SPDX-License-Identifier: MIT
#include <QFile>
#include <QTemporaryDir>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "AtomicFile.h"
#include "StateFile.h"

using namespace bsdeform;

namespace {
SimulationState randomState(int points, std::mt19937& rng, double time) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  SimulationState s;
  s.current = ControlNet::NullaryExpr(points, 3, [&] { return u(rng); });
  s.previous = ControlNet::NullaryExpr(points, 3, [&] { return u(rng); });
  s.time = time;
  s.steps = 7;
  s.subStepSize = 0.1 / 3.0;
  s.startPending = false;
  return s;
}

const std::vector<StateFileSurface> kSurfaces = {{QStringLiteral("Cloth"), 121}, {QString(), 64}};

StateHistory sample() {
  std::mt19937 rng(5);
  StateHistory h;
  for (int f = 0; f < 4; ++f) h.append(frameOf({randomState(121, rng, f * 0.1), randomState(64, rng, f * 0.1 + 0.05)}));
  return h;
}

QByteArray contentsOf(const QString& path) {
  QFile f(path);
  REQUIRE(f.open(QIODevice::ReadOnly));
  return f.readAll();
}
}  // namespace

TEST_CASE("StateFile: written and read back, the same names, sizes and bits", "[ui]") {
  QTemporaryDir dir;
  const QString path = dir.filePath(QStringLiteral("run.states"));
  const StateHistory h = sample();
  QString error;
  REQUIRE(writeStateFile(path, kSurfaces, h, error));
  CHECK(contentsOf(path).startsWith("bsdeform-states 1\n"));
  StateFileContents read;
  REQUIRE(readStateFile(path, read, error));
  CHECK(read.surfaces == kSurfaces);
  REQUIRE(read.frames.size() == 4);
  for (int f = 0; f < 4; ++f) {
    CHECK(read.frames[f].time == h[f].time);
    for (int k = 0; k < 2; ++k) CHECK(sameBits(read.frames[f].surfaces[k], h[f].surfaces[k]));
  }
  CHECK(stateFileMismatch(path, read.surfaces, kSurfaces).isEmpty());
}

TEST_CASE("StateFile: a damaged or foreign file is refused naming the file, the entry and the value", "[ui]") {
  QTemporaryDir dir;
  const QString path = dir.filePath(QStringLiteral("run.states"));
  QString error;
  REQUIRE(writeStateFile(path, kSurfaces, sample(), error));
  const QByteArray good = contentsOf(path);
  StateFileContents read;
  auto refusal = [&](const QByteArray& bytes) {
    QString e;
    REQUIRE(saveFileAtomically(path, bytes, e));
    read.frames.clear();
    CHECK_FALSE(readStateFile(path, read, e));
    CHECK(e.contains(path));
    CHECK(read.frames.empty());  // nothing half-read is handed out
    return e;
  };
  CHECK(refusal(good.left(good.size() - 9)).contains(QStringLiteral("frame 4, surface 2 (no DEF name): the file ends early")));
  CHECK(refusal(QByteArray(good).replace("bsdeform-states 1", "bsdeform-states 7")).contains(QStringLiteral("version 7")));
  CHECK(refusal("#Inventor V2.1 ascii\n").contains(QStringLiteral("does not start with")));
  CHECK(refusal(good + "x").contains(QStringLiteral("1 bytes after the last frame")));

  // against a scene: the count, a name, a net size
  std::vector<StateFileSurface> scene = kSurfaces;
  scene[1].netPoints = 81;
  CHECK(stateFileMismatch(path, kSurfaces, scene) ==
        QStringLiteral("'%1': surface 2 (no DEF name) has 64 control points in the file, 81 in the scene").arg(path));
  scene[0].name = QStringLiteral("Sheet");
  CHECK(stateFileMismatch(path, kSurfaces, scene) ==
        QStringLiteral("'%1': surface 1 is named 'Cloth' in the file, 'Sheet' in the scene").arg(path));
  scene.pop_back();
  CHECK(stateFileMismatch(path, kSurfaces, scene) ==
        QStringLiteral("'%1' holds states of 2 surfaces, the scene has 1").arg(path));
}
