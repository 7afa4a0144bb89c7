// SPDX-License-Identifier: MIT
#include "RunLoop.h"

#include <Inventor/SoDB.h>
#include <Inventor/fields/SoSFTime.h>
#include <Inventor/nodes/SoPerspectiveCamera.h>
#include <Inventor/nodes/SoSeparator.h>

#include <QElapsedTimer>
#include <QFile>
#include <QStringList>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include "AtomicFile.h"
#include "Plot.h"
#include "VideoWriter.h"
#include "bsdeform/CoinMessageCapture.h"
#include "bsdeform/DefaultView.h"
#include "bsdeform/MeshExport.h"
#include "bsdeform/SceneReader.h"
#include "bsdeform/SceneText.h"
#include "bsdeform/contact/BarrierContact.h"
#include "bsdeform/dynamics/Probe.h"
#include "bsdeform/dynamics/Reactions.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/SoBSplineDeformSurface.h"
#include "bsdeform/SoForceField.h"

namespace bsdeform::run {

namespace {

// Streams the scene text into the temporary file: it is never held in memory.
bool writeScene(SoNode* root, const QString& path, QString& error) {
  return saveFileAtomically(
      path,
      [root](QIODevice& device) {
        return writeSceneText(root, [&device](const char* data, std::size_t size) {
          return device.write(data, qint64(size)) == qint64(size);
        });
      },
      error);
}

QByteArray utf8(const QString& s) { return s.toUtf8(); }

// The history CSV's extra columns: each cell or name after a comma, so that they follow the
// usual columns (History::detailedCsvHeader / Row, whose line end is cut off first).
QString withoutLineEnd(QString line) {
  if (line.endsWith(QLatin1Char('\n'))) line.chop(1);
  return line;
}

void appendVector(QString& cells, const Eigen::Vector3d& x) {
  for (int c = 0; c < 3; ++c) cells += QLatin1Char(',') + historyNumber(x[c]);
}

QString probeHeader(const QVector<ProbeOption>& probes) {
  QString h;
  for (const ProbeOption& p : probes)
    for (const char* suffix : {"_x", "_y", "_z", "_dx", "_dy", "_dz"}) h += QLatin1Char(',') + p.name + QLatin1String(suffix);
  return h;
}

// S(u, v) and S - S_rest of every probe, at the simulation's current state (core math:
// bsdeform::probe)
QString probeCells(const Simulation& sim, const QVector<ProbeOption>& probes) {
  QString cells;
  for (const ProbeOption& p : probes) {
    const ProbeSample sample = probe(sim, p.u, p.v);
    appendVector(cells, sample.point);
    appendVector(cells, sample.displacement);
  }
  return cells;
}

QString reactionHeader(const SupportReactions& r) {
  QString h;
  auto add = [&h](const QString& name) {
    for (const char* c : {"_x", "_y", "_z"}) h += QLatin1Char(',') + name + QLatin1String(c);
  };
  for (const SupportReactions::Side& side : r.sides) add(QStringLiteral("reaction_") + QString::fromStdString(side.name));
  for (int k = 0; k < int(r.pins.size()); ++k) add(QStringLiteral("reaction_pin%1").arg(k));
  add(QStringLiteral("applied"));
  return h;
}

QString reactionCells(const SupportReactions& r) {
  QString cells;
  for (const SupportReactions::Side& side : r.sides) appendVector(cells, side.force);
  for (const Eigen::Vector3d& pin : r.pins) appendVector(cells, pin);
  appendVector(cells, r.applied);
  return cells;
}

}  // namespace

RunLoop::RunLoop(const RunOptions& options) : m_options(options), m_out(options.outDir), m_progress(options) {}

// Members go in reverse order: the runner (it refers to the surfaces), the surfaces, then the
// scene that owns them.
RunLoop::~RunLoop() {
  for (Surface& s : m_surfaces)
    if (s.callback >= 0) s.node->removeCallback(s.callback);
}

// Reads the scene, builds every model and force (bad values show up as Coin warnings before
// anything runs) and finds the time step and start time of the run.
Failure RunLoop::prepare() {
  const RunOptions& o = m_options;
  // Coin's realTime follows simulated time in the runner (SceneRunner): engines driven by it
  // (ElapsedTime, TimeCounter, ...) animate deterministically, in step with the surfaces. Set
  // before reading: engines start their clocks at 0.
  SoDB::enableRealTimeSensor(FALSE);
  realTimeField()->setValue(SbTime(0.0));
  Failure f = loadSceneWithSets(o, m_root);
  if (!f.ok()) return f;
  // The scene's distinct surfaces, each named by its DEF name or, when it has none, "surfaceN"
  // after its place among them. The runner tells each its scene (the frames of COLLISION
  // obstacles) and drives them from here on.
  CoinMessageCapture warnings;
  m_runner = std::make_unique<SceneRunner>(m_root.get());
  for (SoBSplineDeformSurface* node : m_runner->surfaces()) {
    Surface s;
    s.node = node;
    const SbName n = node->getName();
    s.name = n.getLength() ? QString::fromUtf8(n.getString()) : QStringLiteral("surface%1").arg(m_surfaces.size());
    m_surfaces.push_back(s);
  }
  if (m_surfaces.isEmpty()) return {kBadInput, QStringLiteral("scene '%1' has no SoBSplineDeformSurface").arg(o.scene)};
  for (Surface& s : m_surfaces) s.node->stepSimulation(0);  // every model and force built
  m_dtMin = m_runner->timeStep();
  m_t0 = m_runner->startTime();  // a resumed scene continues from its time
  // What a surface refuses (a field's value, a force field's, an obstacle) is bad input: the
  // run would not be the scene's. Other nodes' warnings (Coin's) likewise.
  // Every refused value of every node is named, not only the first: a user fixes them all at once.
  QStringList refused;
  std::vector<SoForceField*> forceFields;
  for (const Surface& s : m_surfaces) {
    for (const SoBSplineDeformSurface::Problem& r : s.node->refusals())
      refused << QStringLiteral("surface %1: %2").arg(s.name, QString::fromStdString(r.message));
    for (int i = 0; i < s.node->forces.getNum(); ++i) {
      SoEngine* e = s.node->forces[i];
      if (e && e->isOfType(SoForceField::getClassTypeId())) {
        auto* f = static_cast<SoForceField*>(e);
        if (std::find(forceFields.begin(), forceFields.end(), f) == forceFields.end()) forceFields.push_back(f);
      }
    }
    const SoBSplineDeformSurface::Problem& p = s.node->problem();
    // a problem other than a refused field (an obstacle, a COLLISION force's values, a seam)
    if (p.kind != SoBSplineDeformSurface::Problem::NONE && p.kind != SoBSplineDeformSurface::Problem::FIELD &&
        !(p.kind == SoBSplineDeformSurface::Problem::FORCE_FIELD && p.field.empty() &&
          p.message.find("type COLLISION") == std::string::npos))
      refused << QStringLiteral("surface %1: %2").arg(s.name, QString::fromStdString(p.message));
  }
  for (SoForceField* f : forceFields) {
    if (f->type.getValue() == SoForceField::COLLISION) continue;  // its surface reports it, with its obstacles
    const SbName n = f->getName();
    const QString name = n.getLength() ? QString::fromUtf8(n.getString()) : QStringLiteral("<unnamed>");
    for (const SoForceField::Refusal& r : f->refusedFields()) {
      SbString value;
      if (SoField* field = r.field.empty() ? nullptr : f->getField(SbName(r.field.c_str()))) field->get(value);
      refused << (r.field.empty() ? QStringLiteral("force field %1: %2").arg(name, QString::fromStdString(r.message))
                                  : QStringLiteral("force field %1: %2 = %3: %4")
                                        .arg(name, QString::fromStdString(r.field),
                                             QString::fromUtf8(value.getString()).simplified(),
                                             QString::fromStdString(r.message)));
    }
  }
  if (!refused.isEmpty())
    // one line (a sweep's row keeps the first line of a run's message)
    return {kBadInput, QStringLiteral("scene '%1' has %2 refused value(s): %3")
                           .arg(o.scene)
                           .arg(refused.size())
                           .arg(refused.join(QStringLiteral("; ")))};
  if (!warnings.messages.empty())
    return {kBadInput, QStringLiteral("scene '%1': %2").arg(o.scene, QString::fromStdString(warnings.joined("; ")))};
  // A step that cannot be taken (too many sub-steps, a clock that no longer advances) is bad
  // input; --static takes no step.
  for (const Surface& s : m_surfaces) {
    if (o.staticSolve) break;
    const std::string why = s.node->simulation().refusal();
    if (!why.empty())
      return {kBadInput, QStringLiteral("scene '%1', surface %2: %3").arg(o.scene, s.name, QString::fromStdString(why))};
  }
  if (!o.resultOnly) {
    f = checkOutputNames();
    if (!f.ok()) return f;
  }
  m_frames = o.until >= 0 ? std::max(0L, long(std::llround((o.until - m_t0) / m_dtMin))) : o.steps;
  for (double t : o.pngAt) {
    // a time the run does not reach is refused before anything runs (not skipped in silence)
    const long frame = long(std::llround((t - m_t0) / m_dtMin));
    if (!o.staticSolve && (frame < 0 || frame > m_frames))
      return {kBadInput, QStringLiteral("--png-at %1 is outside the run, which goes from t = %2 to t = %3: give "
                                        "--until %1 (or more), or leave that time out")
                             .arg(t)
                             .arg(m_t0)
                             .arg(m_t0 + m_frames * m_dtMin)};
    m_imageFrames << frame;
  }
  if (!o.resultOnly) {
    f = prepareOutDir(o);
    if (!f.ok()) return f;
  }
  // --video: a frame at t0 and at every 1/fps of simulated time after it, each the picture of
  // the last state reached by then (a frame repeats when the time step is longer than 1/fps)
  if (!o.video.isEmpty() && !o.resultOnly) {
    std::string err;
    m_video = VideoWriter::open(QFile::encodeName(o.video).toStdString(), o.width, o.height, o.videoFps, err);
    if (!m_video) return {kBadInput, QString::fromStdString(err)};
    m_videoClock = FrameClock(o.videoFps, m_t0);
  }
  const bool pictures = o.pngEvery > 0 || !m_imageFrames.isEmpty() || m_video;
  if (pictures && !o.resultOnly && !o.staticSolve && !findSceneCamera(m_root.get())) return frameMotion();
  return {kOk, {}};
}

// A scene without a camera: every image and video frame is taken with one camera, in the
// default view, that holds the whole motion. A copy of the scene is stepped through the run
// first (the steps are taken twice) and the union of its bounding boxes at every step framed
// once; a camera re-framed per picture would zoom with the motion (a clamped edge that seems to
// shrink, a balloon that never seems to grow). A scene's own camera is used as it is.
Failure RunLoop::frameMotion() {
  NodeRef<SoSeparator> copy;
  const Failure f = loadSceneWithSets(m_options, copy);
  if (!f.ok()) return f;
  const SbViewportRegion viewport(short(m_options.width), short(m_options.height));
  QElapsedTimer timer;
  timer.start();
  SbBox3f motion;
  {
    SceneRunner runner(copy.get());
    runner.advanceTo(m_t0);
    motion.extendBy(sceneBoundingBox(copy.get(), viewport));
    for (long frame = 1; frame <= m_frames; ++frame) {
      const bool ok = runner.advanceTo(m_t0 + frame * m_dtMin);
      motion.extendBy(sceneBoundingBox(copy.get(), viewport));
      if (!ok) break;  // the run itself reports the blow-up
    }
  }
  auto* view = new SoSeparator;
  auto* camera = new SoPerspectiveCamera;
  camera->orientation = viewOrientation(StandardView::Default);
  frameBox(camera, motion, viewport);
  view->addChild(camera);
  view->addChild(m_root.get());
  m_view.reset(view);
  m_framingSeconds = timer.nsecsElapsed() * 1e-9;
  return {kOk, {}};
}

// Every output file is named after a surface: a DEF name that is not a plain file name, or two
// surfaces with the same name, would fail or overwrite each other only after the whole run.
Failure RunLoop::checkOutputNames() const {
  std::set<QString> seen;
  for (const Surface& s : m_surfaces) {
    if (s.name.contains(QLatin1Char('/')) || s.name.contains(QChar(0)) || s.name == QLatin1String(".") ||
        s.name == QLatin1String(".."))
      return {kBadInput, QStringLiteral("surface DEF name '%1' cannot name the output file '%1.csv' (it contains '/' or is "
                                        "'.' or '..'); rename it in the scene")
                             .arg(s.name)};
    if (!seen.insert(s.name).second)
      return {kBadInput, QStringLiteral("two surfaces are named '%1': both would write '%1.csv'; give them different DEF "
                                        "names")
                             .arg(s.name)};
  }
  return {kOk, {}};
}

// One history row: the diagnostics of the current state, computed once, in one pass over the
// nets, on the background thread while the next step is taken
// (bsdeform::DiagnosticsBeside); written when the next row begins or the run ends.
void RunLoop::record(Surface& s) {
  flushRow(s);
  const Simulation& sim = s.node->simulation();
  s.pending.time = sim.time();
  s.pending.steps = sim.stepCount();
  s.pending.subSteps = sim.subSteps();
  s.pending.values = s.beside->begin(sim);
  s.pending.probes = probeCells(sim, m_options.probes);
  s.lastRecorded = sim.stepCount();
}

void RunLoop::flushRow(Surface& s) {
  Surface::PendingRow& row = s.pending;
  if (!row.values.valid()) return;
  const Diagnostics d = row.values.get();
  row.values = PendingDiagnostics();
  const bool shell = s.node->simulation().parameters().energy == EnergyModel::Shell;
  if (s.csv.isEmpty()) s.csv = withoutLineEnd(History::detailedCsvHeader(shell)) + probeHeader(m_options.probes) + QLatin1Char('\n');
  s.csv += withoutLineEnd(History::detailedCsvRow(row.time, row.steps, row.subSteps, d, shell)) + row.probes + QLatin1Char('\n');
  s.history.append(row.time, d);
}

// History rows (not in a sweep child, which writes nothing): the first state, every state whose
// step count is a multiple of --record-every, and the last state (the surface's step callback).
void RunLoop::stepped(Surface& s) {
  const Simulation& sim = s.node->simulation();
  const bool failed = sim.status() != Status::Ok;
  m_blewUp |= failed;
  const long step = sim.stepCount();  // a failed step does not count
  if (s.metrics) s.metrics->update(sim);
  if (!m_options.resultOnly && (failed || step % m_options.recordEvery == 0) && s.lastRecorded != step) record(s);
}

Failure RunLoop::render(long frame) {
  std::string err;
  if (m_renderedFrame != frame && !m_renderer.render(m_view.get() ? m_view.get() : m_root.get(), m_options.width, m_options.height, m_image, err))
    return {kInternal, QStringLiteral("rendering failed: %1").arg(QString::fromStdString(err))};
  m_renderedFrame = frame;
  return {kOk, {}};
}

Failure RunLoop::writeImage(long frame) {
  const Failure rendered = render(frame);
  if (!rendered.ok()) return rendered;
  const QString name = m_options.frameNamesTime
                           ? QStringLiteral("frame_t%1.png").arg(m_t0 + frame * m_dtMin, 13, 'f', 6, QLatin1Char('0'))
                           : QStringLiteral("frame_%1.png").arg(frame, 6, 10, QLatin1Char('0'));
  const QString path = m_out.filePath(name);
  // not synced one by one (a frame's fsync cost about as much as its PNG): once at the end
  std::string err;
  if (!writePng(m_image, QFile::encodeName(path).toStdString(), err, false))
    return writeFailure(QString::fromStdString(err), m_written);
  m_written << path;
  ++m_imagesWritten;
  return {kOk, {}};
}

Failure RunLoop::writeVideoFrames(long frame) {
  if (!m_video) return {kOk, {}};
  const long due = m_videoClock.due(m_t0 + frame * m_dtMin);
  if (due == 0) return {kOk, {}};
  const Failure rendered = render(frame);
  if (!rendered.ok()) return rendered;
  for (long k = 0; k < due; ++k) {
    std::string err;
    if (!m_video->addFrame(m_image.rgb.data(), err)) return writeFailure(QString::fromStdString(err), m_written);
  }
  return {kOk, {}};
}

Failure RunLoop::runStatic() {
  const RunOptions& o = m_options;
  QElapsedTimer timer;
  timer.start();
  for (Surface& s : m_surfaces) {
    QElapsedTimer one;
    one.start();
    StaticResult r;
    std::string error;
    // one row per load increment: the load factor, the usual columns, the probes, then the
    // reactions of the held sides and pins and the applied loads' sum (bsdeform/dynamics/Reactions.h)
    const bool shell = s.node->simulation().parameters().energy == EnergyModel::Shell;
    s.csv.clear();
    double imbalance = 0.0;  // the largest |applied + reactions| / |applied| over the increments
    ArcLengthOptions arc;
    arc.maxSteps = o.loadSteps;
    arc.maxLoad = o.maxLoad;
    arc.tolerance = s.node->simulation().parameters().newtonTolerance;
    s.path = PlotSeries();
    const bool solved = s.node->solveStatic(
        &r, &error, o.loadSteps, [&s, shell, &o, &imbalance](const StaticResult& all, size_t k, const Diagnostics& d) {
          // the simulation holds increment k now (its net at rest)
          const Simulation& sim = s.node->simulation();
          const StaticResult::Increment& inc = all.increments[k];
          const SupportReactions reactions = supportReactions(sim, inc.net, inc.loadFactor);
          if (s.csv.isEmpty())
            s.csv = QStringLiteral("load_factor,") + withoutLineEnd(History::detailedCsvHeader(shell)) +
                    probeHeader(o.probes) + reactionHeader(reactions) + QLatin1Char('\n');
          s.csv += decimalNumber(inc.loadFactor) + QLatin1Char(',') +
                   withoutLineEnd(History::detailedCsvRow(0.0, 0, 1, d, shell)) + probeCells(sim, o.probes) +
                   reactionCells(reactions) + QLatin1Char('\n');
          s.history.append(0.0, d);
          if (!o.probes.isEmpty()) {  // the load path against the first probe's displacement (--plot)
            const ProbeSample p = probe(sim, o.probes.first().u, o.probes.first().v);
            s.path.x << p.displacement.norm();
            s.path.y << inc.loadFactor;
          }
          if (reactions.applied.norm() > 0.0)
            imbalance = std::max(imbalance, reactions.imbalance().norm() / reactions.applied.norm());
        },
        o.arcLength ? &arc : nullptr);
    if (!solved)
      return {kBadInput, QStringLiteral("scene '%1', surface %2: %3").arg(o.scene, s.name, QString::fromStdString(error))};
    m_staticLines << QStringLiteral("%1: equilibrium by %2 in %3 s, relative residual %4%5")
                         .arg(s.name, QString::fromStdString(r.method))
                         .arg(one.elapsed() / 1000.0, 0, 'f', 2)
                         .arg(r.residual, 0, 'g', 3)
                         .arg(s.node->simulation().parameters().energy == EnergyModel::Shell  // solved by Newton
                                  ? (o.arcLength ? QStringLiteral(", %1 Newton iterations in %2 arc-length step(s), load factor %3 at the end")
                                                       .arg(r.loadIterations).arg(r.increments.size()).arg(r.increments.back().loadFactor, 0, 'g', 6)
                                                 : QStringLiteral(", %1 Newton iterations in %2 load step(s)").arg(r.loadIterations).arg(o.loadSteps))
                              : r.loadIterations > 1
                                  ? QStringLiteral(", %1 fixed-point iterations of the position-dependent loads").arg(r.loadIterations)
                                  : QString())
                  + QStringLiteral("; the reactions balance the applied loads to %1 of them").arg(imbalance, 0, 'g', 3);
    // a path that ran out of steps before the largest load factor: the answer is partial, say so
    if (o.arcLength && shell && !r.increments.empty() && r.increments.back().loadFactor < o.maxLoad)
      std::fprintf(stderr,
                   "bsdeform-run: warning: surface %s: the arc-length path stopped after %d points at load factor "
                   "%g, below --max-load %g; raise --load-steps to go on\n",
                   utf8(s.name).constData(), o.loadSteps, r.increments.back().loadFactor, o.maxLoad);
  }
  const double seconds = timer.elapsed() / 1000.0;
  if (o.pngEvery > 0 || !o.pngAt.isEmpty()) {
    const Failure f = writeImage(0);
    if (!f.ok()) return f;
  }
  const Failure f = writeOutputs();
  if (!f.ok()) return f;
  // the residual is printed even with --quiet: it is the answer
  for (const QString& line : m_staticLines) std::printf("bsdeform-run: %s\n", utf8(line).constData());
  if (!o.quiet) printSummary(seconds);
  return {kOk, {}};
}

Failure RunLoop::run() {
  const RunOptions& o = m_options;
  Failure f = prepare();
  if (!f.ok()) return f;
  if (o.staticSolve) return runStatic();

  QElapsedTimer timer;
  timer.start();
  m_runner->advanceTo(m_t0);
  if (!o.metrics.isEmpty())
    for (Surface& s : m_surfaces) {
      s.metrics = std::make_shared<MetricTracker>(o.metrics);
      s.metrics->update(s.node->simulation());  // the start counts (a maximum that is the start)
    }
  const bool recording = !o.resultOnly;
  if (recording)
    for (Surface& s : m_surfaces) record(s);
  for (int i = 0; i < m_surfaces.size(); ++i)  // by index: m_surfaces does not change from here on
    m_surfaces[i].callback = m_surfaces[i].node->addCallback([this, i](SoBSplineDeformSurface*, SoBSplineDeformSurface::Event e) {
      if (e == SoBSplineDeformSurface::STEPPED) stepped(m_surfaces[i]);
    });
  if (!o.keepStates.isEmpty()) m_kept = std::make_unique<KeptStates>(m_runner->surfaces(), o.recordEvery);
  for (long frame = 0; frame <= m_frames; ++frame) {
    if (frame > 0) m_runner->advanceTo(m_t0 + frame * m_dtMin);
    if (m_kept) m_kept->frameReached(frame, frame == m_frames || m_blewUp);
    if (!o.resultOnly && ((o.pngEvery > 0 && frame % o.pngEvery == 0) || m_imageFrames.contains(frame))) {
      f = writeImage(frame);
      if (!f.ok()) return f;
    }
    f = writeVideoFrames(frame);
    if (!f.ok()) return f;
    m_progress.show(frame, m_frames, m_t0 + frame * m_dtMin);
    if (m_blewUp) break;
  }
  if (recording)
    for (Surface& s : m_surfaces) {
      if (s.lastRecorded != s.node->simulation().stepCount()) record(s);
      flushRow(s);
    }
  const double seconds = timer.elapsed() / 1000.0;

  if (o.resultOnly) {
    printResults();
    // the reason goes to stderr (a sweep reads the status from the RESULT lines)
    return {m_blewUp ? kBlowUp : kOk, m_blewUp ? outcome().message : QString()};
  }
  f = writeOutputs();
  if (!f.ok()) return f;
  if (!o.quiet) printSummary(seconds);
  if (o.resultLines) printResults();
  return outcome();
}

// The history CSV (and plot) per surface, the video, the images' sync, final.iv, the mesh.
Failure RunLoop::writeOutputs() {
  const RunOptions& o = m_options;
  QString error;
  for (const Surface& s : m_surfaces) {
    const QString path = m_out.filePath(s.name + QStringLiteral(".csv"));
    if (!saveFileAtomically(path, s.csv.toUtf8(), error)) return writeFailure(error, m_written);
    m_written << path;
    if (o.plot && o.staticSolve && !o.probes.isEmpty()) {
      // the load path: load factor against the first probe's displacement
      const QString plotPath = m_out.filePath(s.name + QStringLiteral("_load_path.png"));
      QString perr;
      PlotSeries series = s.path;
      series.name = QStringLiteral("load factor");
      if (!writePlotPng(plotPath, s.name + QStringLiteral(": load factor against the displacement at %1").arg(o.probes.first().name),
                        QStringLiteral("|%1 displacement|").arg(o.probes.first().name), QStringLiteral("load factor"),
                        {series}, 800, 500, perr))
        return writeFailure(perr, m_written);
      m_written << plotPath;
    } else if (o.plot) {
      const QString plotPath = m_out.filePath(s.name + QStringLiteral("_history.png"));
      QString perr;
      if (!writePlotPng(plotPath, s.name + QStringLiteral(": deformation over time"), QStringLiteral("time"),
                        QStringLiteral("norm"), s.history.plotSeries(), 800, 500, perr,
                        {QStringLiteral("energy"), true, false, false}))
        return writeFailure(perr, m_written);
      m_written << plotPath;
    }
  }
  if (m_video) {
    std::string err;
    if (!m_video->finish(err)) return writeFailure(QString::fromStdString(err), m_written);
    m_written << o.video + QStringLiteral(" (%1 frames)").arg(m_video->frames());
  }
  if (m_imagesWritten > 0) {
    std::string err;
    if (!syncFileSystem(QFile::encodeName(o.outDir).toStdString(), err))
      return writeFailure(QString::fromStdString(err), m_written);
  }
  if (m_kept) {
    if (!m_kept->write(o.keepStates, error)) return writeFailure(error, m_written);
    m_written << o.keepStates;
  }
  const QString ivPath = m_out.filePath(QStringLiteral("final.iv"));
  if (!writeScene(m_root.get(), ivPath, error)) return writeFailure(error, m_written);
  m_written << ivPath;
  if (!o.exportMesh.isEmpty()) {
    std::vector<SoBSplineDeformSurface*> nodes;
    std::vector<std::string> names;
    for (const Surface& s : m_surfaces) nodes.push_back(s.node), names.push_back(s.name.toStdString());
    std::string err;
    if (!bsdeform::exportMesh(m_root.get(), nodes, names, QFile::encodeName(o.exportMesh).toStdString(), "bsdeform-run", err))
      return writeFailure(QString::fromStdString(err), m_written);
    m_written << o.exportMesh;
  }
  return {kOk, {}};
}

void RunLoop::printSummary(double seconds) const {
  if (m_options.staticSolve)
    std::printf("bsdeform-run: %s, the equilibrium at t = 0 in %.2f s wall\n", utf8(m_options.scene).constData(), seconds);
  else
    std::printf("bsdeform-run: %s, %ld frame(s) of %.4g s in %.2f s wall\n", utf8(m_options.scene).constData(), m_frames,
                m_dtMin, seconds);
  if (m_framingSeconds > 0.0)  // the scene has no camera: its motion was run once more, first
    std::printf("  plus %.2f s before it, running the motion once more to frame the pictures (the scene has no camera): %.2f s in all\n",
                m_framingSeconds, m_framingSeconds + seconds);
  for (const Surface& s : m_surfaces) {
    const Simulation& sim = s.node->simulation();
    const ModelParameters& p = sim.parameters();
    const Diagnostics d = sim.diagnostics();
    std::printf("  %-14s %dx%d deg (%d,%d) dt %.4g: t = %.6g, steps %ld, norm %.6g, kinetic %.6g, strain %.6g, "
                "limit %.4g, sub-steps %d, %s\n",
                utf8(s.name).constData(), p.numU, p.numV, p.degreeU, p.degreeV, p.timeStep, sim.time(), sim.stepCount(),
                d.norm, d.kinetic, d.strain.total, sim.stabilityLimit(), sim.subSteps(),
                sim.status() == Status::Ok ? "ok" : sim.statusMessage().c_str());
    printCosts(sim);
    if (s.metrics) {
      const QStringList values = s.metrics->values(sim);
      QStringList pairs;
      for (int i = 0; i < values.size(); ++i) pairs << m_options.metrics[i].name + QStringLiteral(" = ") + values[i];
      std::printf("  %-14s %s\n", "", utf8(pairs.join(QStringLiteral(", "))).constData());
    }
  }
  for (const QString& w : m_written) std::printf("  wrote %s\n", utf8(w).constData());
}

// Where a surface's steps spent their time (Simulation::stepCosts()): the implicit steps' phases
// and, with barrier contact, the contact's own parts, as shares of the steps' wall time.
void RunLoop::printCosts(const Simulation& sim) const {
  const StepCosts& c = sim.stepCosts();
  if (c.steps == 0 || c.total <= 0.0) return;
  const double T = c.total;
  auto share = [T](double seconds) { return 100.0 * seconds / T; };
  if (c.iterations == 0) {
    std::printf("  %-14s steps %.3g s (%.3g ms a step)\n", "", T, 1e3 * T / double(c.steps));
    return;
  }
  std::printf("  %-14s steps %.3g s (%.3g ms a step, %.3g Newton iterations a step, %ld factorisations): elastic %.0f %%, "
              "loads %.0f %%, collision checks %.0f %%, factorisation %.0f %%, solve %.0f %%, other %.0f %%\n",
              "", T, 1e3 * T / double(c.steps), double(c.iterations) / double(c.steps), c.factorisations,
              share(c.elastic), share(c.loads), share(c.collisionChecks), share(c.factorisation), share(c.solve),
              share(c.other()));
  for (const auto& f : sim.forces())
    if (const auto* barrier = dynamic_cast<const BarrierContactForce*>(f.get())) {
      const BarrierContactForce::Costs& b = barrier->costs();
      std::printf("  %-14s barrier contact (in loads and collision checks): proxy %.0f %%, broad phase %.0f %%, "
                  "pair terms %.0f %%, Jacobian push %.0f %%, CCD %.0f %%\n",
                  "", share(b.proxy), share(b.broadPhase), share(b.pairs), share(b.push), share(b.ccd));
    }
}

// A sweep child's answer: one RESULT line per surface (SweepPool reads them).
void RunLoop::printResults() const {
  for (const Surface& s : m_surfaces) {
    const Simulation& sim = s.node->simulation();
    const Diagnostics d = sim.diagnostics();
    // the metrics (--metric), if any, after the status: SweepPool's columns beyond the six
    const QString metrics = s.metrics ? QLatin1Char('\t') + s.metrics->values(sim).join(QLatin1Char('\t')) : QString();
    std::printf("RESULT\t%s\t%s\t%s\t%s\t%s%s\n", utf8(s.name).constData(), utf8(historyNumber(d.norm)).constData(),
                utf8(historyNumber(d.kinetic)).constData(), utf8(historyNumber(d.strain.total)).constData(),
                sim.status() == Status::Ok ? "ok" : "blew-up", utf8(metrics).constData());
  }
}

// A blow-up after the outputs were written: which surfaces, and why.
Failure RunLoop::outcome() const {
  if (!m_blewUp) return {kOk, {}};
  QStringList blowUps;
  bool refused = false;
  for (const Surface& s : m_surfaces) {
    if (s.node->simulation().status() == Status::Ok) continue;
    blowUps << s.name + QStringLiteral(": ") + QString::fromStdString(s.node->simulation().statusMessage());
    refused |= s.node->simulation().status() == Status::Refused;
  }
  return {refused ? kBadInput : kBlowUp, blowUps.join(QStringLiteral("; "))};
}

}  // namespace bsdeform::run
