// SPDX-License-Identifier: MIT
// The viewer's timeline (Timeline.h, TimelinePanel.h) and bsdeform-run --keep-states, driven as
// a user would: Step, Play, the slider, Edit > Undo, File > Open States.
#include <Inventor/nodes/SoSeparator.h>

#include <QFile>
#include <QLabel>
#include <QLocale>
#include <QProcess>
#include <QSlider>
#include <QStatusBar>
#include <QTemporaryDir>
#include <QTest>
#include <QUndoStack>
#include <catch2/catch.hpp>
#include <cstring>
#include <memory>
#include <vector>

#include "MainWindow.h"
#include "PlotPanel.h"
#include "Timeline.h"
#include "TimelinePanel.h"
#include "ViewerTestSupport.h"
#include "bsdeform/SceneReader.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/dynamics/SimulationState.h"
#include "bsdeform/SoBSplineDeformSurface.h"

using bsdeform::MainWindow;
using namespace viewer_test;

namespace {

// Two surfaces with different time steps (the timeline keeps both at the clock's common time).
const char* kTwoSurfaces = R"IV(#Inventor V2.1 ascii
Separator {
  DEF Sheet SoBSplineDeformSurface {
    numUControlPoints 6 numVControlPoints 6 damping 0.3 timeStep 0.05
    forces [ SoForceField { type UNIFORM force 0 0 1 magnitude 20 } ]
  }
  Translation { translation 1.5 0 0 }
  DEF Plate SoBSplineDeformSurface {
    numUControlPoints 5 numVControlPoints 4 damping 0.6 timeStep 0.1 integrator IMPLICIT
    forces [ SoForceField { type POINT point 0.4 0.6 force 0 0 -3 } ]
  }
}
)IV";

bool sameBits(const void* a, const void* b, std::size_t n) { return std::memcmp(a, b, n) == 0; }

// What a surface's state fields say (the nets written as a save would write them) and its
// simulation's state.
struct Shown {
  std::vector<std::vector<SbVec3d>> controlNet, previousNet;
  std::vector<double> time;
  std::vector<int> steps;
  std::vector<bsdeform::SimulationState> states;
};

Shown shownNow(MainWindow& w) {
  Shown s;
  for (SoBSplineDeformSurface* surface : w.document().surfaces()) {
    surface->syncStateFields();
    s.controlNet.emplace_back(surface->controlNet.getValues(0), surface->controlNet.getValues(0) + surface->controlNet.getNum());
    s.previousNet.emplace_back(surface->previousNet.getValues(0), surface->previousNet.getValues(0) + surface->previousNet.getNum());
    s.time.push_back(surface->simulationTime.getValue());
    s.steps.push_back(surface->stepCount.getValue());
    s.states.push_back(surface->state());
  }
  return s;
}

// Bitwise: controlNet, previousNet (the velocity), simulationTime, stepCount, and the
// simulation's own state.
bool same(const Shown& a, const Shown& b) {
  if (a.states.size() != b.states.size()) return false;
  for (std::size_t k = 0; k < a.states.size(); ++k) {
    if (a.controlNet[k].size() != b.controlNet[k].size() || a.previousNet[k].size() != b.previousNet[k].size()) return false;
    if (!sameBits(a.controlNet[k].data(), b.controlNet[k].data(), a.controlNet[k].size() * sizeof(SbVec3d)) ||
        !sameBits(a.previousNet[k].data(), b.previousNet[k].data(), a.previousNet[k].size() * sizeof(SbVec3d)) ||
        !sameBits(&a.time[k], &b.time[k], sizeof(double)) || a.steps[k] != b.steps[k] ||
        !bsdeform::sameBits(a.states[k], b.states[k]))
      return false;
  }
  return true;
}

std::unique_ptr<MainWindow> twoSurfaceWindow(const QTemporaryDir& dir) {
  const QString path = dir.filePath(QStringLiteral("two_surfaces.iv"));
  writeFile(path, kTwoSurfaces);
  auto w = makeWindow("region_load.iv");
  REQUIRE(w->openScene(path));
  w->pause();
  processEvents();
  return w;
}

void scrubTo(MainWindow& w, int index) {
  w.timelinePanel().slider()->setValue(index);
  processEvents();
  REQUIRE(w.timeline().position() == index);
}

}  // namespace

TEST_CASE("Timeline: scrub restores the exact state, stepping on discards the later states undoably", "[ui][timeline]") {
  QTemporaryDir dir;
  auto w = twoSurfaceWindow(dir);
  const bsdeform::Timeline& tl = w->timeline();
  std::vector<Shown> stepped{shownNow(*w)};
  for (int k = 1; k <= 5; ++k) {
    w->step();
    processEvents();
    stepped.push_back(shownNow(*w));
  }
  REQUIRE(tl.history().size() == 6);
  REQUIRE(stepped[5].steps[0] == 5);
  w->play();
  passTime(*w, 1.0);
  w->pause();
  processEvents();
  const int n = tl.history().size();
  REQUIRE(n > 20);
  REQUIRE(tl.isAtEnd());
  const Shown newest = shownNow(*w);
  REQUIRE(newest.steps[0] > 20);

  // the slider, back and forth: each state comes back bit for bit, paused
  w->play();
  scrubTo(*w, 2);
  CHECK_FALSE(w->isPlaying());
  CHECK(same(shownNow(*w), stepped[2]));
  INFO(w->timelinePanel().label().toStdString());
  CHECK(w->timelinePanel().label().startsWith(QStringLiteral("t = %1 s of").arg(QLocale().toString(tl.history()[2].time, 'g', 6))));
  CHECK(w->timelinePanel().label().endsWith(QStringLiteral(" %1 states").arg(n)));
  scrubTo(*w, n - 1);
  CHECK(same(shownNow(*w), newest));
  scrubTo(*w, 2);
  CHECK(same(shownNow(*w), stepped[2]));
  CHECK(w->undoStack().count() == 0);  // scrubbing alone is not an edit

  // stepping on from there takes the same steps as the first time and drops the later states
  w->step();
  processEvents();
  CHECK(same(shownNow(*w), stepped[3]));
  CHECK(tl.history().size() == 4);
  CHECK(tl.isAtEnd());
  REQUIRE(w->undoStack().count() == 1);
  CHECK(w->undoStack().undoText().startsWith(QStringLiteral("Discard Later States")));

  // Undo brings the later states back, at the state they branched from; Redo swaps again
  w->undoStack().undo();
  processEvents();
  CHECK(tl.history().size() == n);
  CHECK(tl.position() == 2);
  CHECK(same(shownNow(*w), stepped[2]));
  scrubTo(*w, n - 1);
  CHECK(same(shownNow(*w), newest));
  w->undoStack().redo();
  processEvents();
  CHECK(tl.history().size() == 4);
  CHECK(same(shownNow(*w), stepped[3]));
}

TEST_CASE("Timeline: the plots show the history up to the position, replay plays the kept states", "[ui][timeline]") {
  auto w = makeWindow("region_load.iv");
  processEvents();
  passTime(*w, 1.0);
  w->pause();
  processEvents();
  const bsdeform::Timeline& tl = w->timeline();
  const int n = tl.history().size();
  REQUIRE(n > 10);
  const double newest = tl.history().back().time;
  CHECK(w->plotPanel().lastShownTime() == newest);
  scrubTo(*w, 5);
  const double t5 = tl.history()[5].time;
  CHECK(w->plotPanel().lastShownTime() == t5);
  CHECK(w->plotPanel().sampleCount() > 10);  // the later samples are kept for scrubbing forward
  scrubTo(*w, n - 1);
  CHECK(w->plotPanel().lastShownTime() == newest);

  // replay from state 5: forward through the kept states without stepping, to the newest
  scrubTo(*w, 5);
  REQUIRE(w->timeline().advanceReplay((newest - t5) / 2));
  CHECK(tl.position() > 5);
  CHECK(tl.position() < n - 1);
  CHECK(tl.history()[tl.position()].time <= t5 + (newest - t5) / 2);
  // the kept state itself, not steps taken from state 5
  CHECK(bsdeform::sameBits(firstSurface(*w)->state(), tl.history()[tl.position()].surfaces[0]));
  CHECK(w->plotPanel().lastShownTime() == tl.history()[tl.position()].time);
  CHECK_FALSE(w->timeline().advanceReplay(newest));
  CHECK(tl.isAtEnd());
  CHECK(w->plotPanel().lastShownTime() == newest);

  // the Replay button: the status bar says it replays, not "0.0 steps/s" (issue 37, item 7)
  scrubTo(*w, 1);
  w->timelinePanel().setReplaying(true);
  REQUIRE(QTest::qWaitFor([&] { return tl.position() > 1; }, 5000));
  processEvents();
  QString rates;
  for (QLabel* l : w->statusBar()->findChildren<QLabel*>()) rates += l->text() + QLatin1Char('\n');
  INFO(rates.toStdString());
  CHECK(rates.contains(QStringLiteral("replay 1 x")));
  CHECK_FALSE(rates.contains(QStringLiteral("steps/s")));
  w->timelinePanel().setReplaying(false);
  scrubTo(*w, n - 1);

  // stepping on from an earlier state: the plots go on from there
  const QVector<double> timesBefore = w->plotPanel().history().time(), normsBefore = w->plotPanel().history().norm();
  scrubTo(*w, 5);
  w->step();
  processEvents();
  CHECK(w->plotPanel().lastShownTime() == tl.history().back().time);
  CHECK(tl.history().back().time < newest);
  // a few more steps on the new branch, then Undo: the plots are the first branch's again
  for (int k = 0; k < 3; ++k) w->step();
  processEvents();
  w->undoStack().undo();
  processEvents();
  scrubTo(*w, tl.history().size() - 1);
  CHECK(w->plotPanel().history().time() == timesBefore);
  CHECK(w->plotPanel().history().norm() == normsBefore);
  w->undoStack().redo();  // and the new branch's after Redo
  processEvents();
  CHECK(w->plotPanel().history().time().back() == tl.history().back().time);
  CHECK(w->plotPanel().history().time().back() < newest);

  // a screenshot of the timeline, scrubbed back to its middle after a longer run
  w->play();
  passTime(*w, 2.0);
  w->pause();
  processEvents();
  scrubTo(*w, tl.history().size() / 2);
  w->windowScreenshot().save(QStringLiteral("viewer_timeline.png"));
}

TEST_CASE("Timeline: the kept states stay within the stated memory budget, older states thinned", "[ui][timeline]") {
  auto w = makeWindow("region_load.iv");
  bsdeform::Timeline& tl = w->timeline();
  CHECK(tl.history().budget() == bsdeform::StateHistory::kDefaultBudget);
  CHECK(w->timelinePanel().memoryText().contains(QStringLiteral("256")));
  const std::size_t frameBytes = tl.history().bytes();  // the first state alone
  tl.setBudget(12 * frameBytes);
  passTime(*w, 3.0);  // 30 steps of 0.1 s, a state each
  processEvents();
  CHECK(tl.history().bytes() <= 12 * frameBytes);
  CHECK(tl.history().size() >= 6);
  CHECK(tl.history().thinnings() > 0);
  CHECK(tl.history()[0].time == 0.0);
  CHECK(tl.history().back().time == firstSurface(*w)->simulation().time());
  CHECK(w->timelinePanel().memoryText().contains(QStringLiteral("thinned")));
  CHECK(w->timelinePanel().slider()->toolTip().contains(QStringLiteral("budget")));
  // the first state, thinned or not, is still the rest state
  w->pause();
  scrubTo(*w, 0);
  CHECK(firstSurface(*w)->simulation().stepCount() == 0);
  CHECK(firstSurface(*w)->simulation().current() == firstSurface(*w)->simulation().rest());
}

TEST_CASE("Timeline: Reset, a rebuilt model and another scene start it again, a live edit keeps it", "[ui][timeline]") {
  auto w = makeWindow("region_load.iv");
  bsdeform::Timeline& tl = w->timeline();
  passTime(*w, 0.5);
  const int n = tl.history().size();
  REQUIRE(n > 5);
  SoBSplineDeformSurface* s = firstSurface(*w);
  s->damping.setValue(2.0);  // the motion goes on (MODEL_CHANGED)
  passTime(*w, 0.5);
  CHECK(tl.history().size() > n);
  CHECK(tl.history()[0].time == 0.0);
  w->reset();
  processEvents();
  CHECK(tl.history().size() == 1);
  passTime(*w, 0.5);
  REQUIRE(tl.history().size() > 1);
  s->numUControlPoints.setValue(10);  // another net: the model starts from rest
  passTime(*w, 0.2);
  CHECK(tl.history()[0].time == 0.0);
  CHECK(tl.history().back().surfaces[0].current.rows() == s->simulation().current().rows());
  CHECK(tl.history().back().time <= 0.2 + 1e-9);
  REQUIRE(w->openScene(scenePath("curtain.iv")));
  processEvents();
  CHECK(tl.history().size() == 1);
  CHECK(tl.history()[0].surfaces.size() == std::size_t(w->document().surfaces().size()));
}

TEST_CASE("Timeline: bsdeform-run --keep-states opens in the viewer and scrubs to the runner's numbers", "[ui][timeline]") {
  QTemporaryDir dir;
  const QString states = dir.filePath(QStringLiteral("run.states"));
  QProcess run;
  run.start(QStringLiteral(BSDEFORM_RUN),
            {scenePath("region_load.iv"), QStringLiteral("-n"), QStringLiteral("20"), QStringLiteral("--record-every"),
             QStringLiteral("5"), QStringLiteral("--keep-states"), states, QStringLiteral("-o"), dir.filePath(QStringLiteral("out")),
             QStringLiteral("--quiet")});
  REQUIRE(run.waitForFinished(60000));
  INFO(run.readAllStandardError().toStdString());
  REQUIRE(run.exitCode() == 0);

  auto w = makeWindow("region_load.iv");
  w->pause();
  passTime(*w, 0.3);  // something to lose if the file were refused
  REQUIRE(w->openStates(states));
  const bsdeform::Timeline& tl = w->timeline();
  REQUIRE(tl.history().size() == 5);  // steps 0, 5, 10, 15, 20
  CHECK(tl.isAtEnd());
  SoBSplineDeformSurface* s = firstSurface(*w);
  CHECK(s->simulation().stepCount() == 20);
  // the plots show every kept state, not an empty plot at the last one (issue 37, item 7)
  const bsdeform::History& plotted = w->plotPanel().history();
  REQUIRE(plotted.size() == 5);
  CHECK(plotted.time().front() == 0.0);
  CHECK(plotted.norm().back() > plotted.norm().front());

  // the last state is final.iv's: saved from the viewer, the same state fields to the last bit
  // (final.iv's numbers are the 15-digit values a save writes, bsdeform::snap15)
  std::string error;
  SoSeparator* final = bsdeform::readSceneFile(dir.filePath(QStringLiteral("out/final.iv")).toStdString(), error);
  REQUIRE(final);
  final->ref();
  SoBSplineDeformSurface* f = nullptr;
  for (SoBSplineDeformSurface* x : bsdeform::sceneSurfaces(final)) f = x;
  REQUIRE(f);
  s->syncStateFields();
  CHECK(f->controlNet == s->controlNet);
  CHECK(f->previousNet == s->previousNet);
  CHECK(f->simulationTime.getValue() == s->simulationTime.getValue());
  CHECK(f->stepCount.getValue() == s->stepCount.getValue());
  CHECK(s->controlNet.getNum() == int(s->simulation().current().rows()));
  final->unref();

  // each kept state has the norm of the runner's CSV row of its step, to the last digit
  QFile csv(dir.filePath(QStringLiteral("out/surface0.csv")));
  REQUIRE(csv.open(QIODevice::ReadOnly));
  const QList<QByteArray> rows = csv.readAll().split('\n');
  int checked = 0;
  for (const QByteArray& row : rows.mid(1)) {
    const QList<QByteArray> cells = row.split(',');
    if (cells.size() < 3 || cells[1].toLong() % 5 != 0) continue;
    scrubTo(*w, int(cells[1].toLong() / 5));
    CHECK(s->simulation().stepCount() == cells[1].toLong());
    // the CSV's time is the 15-digit value of the sum of steps (History: decimalNumber)
    CHECK(QString::number(s->simulation().time(), 'g', 15).toDouble() == cells[0].toDouble());
    CHECK(s->simulation().diagnostics().norm == cells[2].toDouble());
    ++checked;
  }
  CHECK(checked == 5);
}

TEST_CASE("Timeline: a state file of another scene is refused naming the file, the entry and the value, losing nothing",
          "[ui][timeline]") {
  QTemporaryDir dir;
  const QString states = dir.filePath(QStringLiteral("run.states"));
  QProcess run;
  run.start(QStringLiteral(BSDEFORM_RUN), {scenePath("region_load.iv"), QStringLiteral("-n"), QStringLiteral("3"),
                                           QStringLiteral("--keep-states"), states, QStringLiteral("-o"),
                                           dir.filePath(QStringLiteral("out")), QStringLiteral("--quiet")});
  REQUIRE(run.waitForFinished(60000));
  REQUIRE(run.exitCode() == 0);

  auto w = twoSurfaceWindow(dir);
  w->step();
  processEvents();
  const Shown before = shownNow(*w);
  const int kept = w->timeline().history().size();
  CHECK_FALSE(w->openStates(states));
  CHECK(w->lastError() == QStringLiteral("'%1' holds states of 1 surfaces, the scene has 2").arg(states));
  CHECK(same(shownNow(*w), before));
  CHECK(w->timeline().history().size() == kept);

  // the same surface count, another net size
  auto r = makeWindow("region_load.iv");
  firstSurface(*r)->numUControlPoints.setValue(10);
  processEvents();
  CHECK_FALSE(r->openStates(states));
  CHECK(r->lastError() ==
        QStringLiteral("'%1': surface 1 (no DEF name) has 900 control points in the file, 480 in the scene").arg(states));
}
