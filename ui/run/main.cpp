// SPDX-License-Identifier: MIT
// bsdeform-run: step an .iv scene without a window and write results, plots and images.
// See `bsdeform-run --help` and README.md. Exit codes: 0 success, 2 bad input (usage, files,
// names, values, output paths), 3 a simulation blew up (outputs up to that point are written),
// 4 an output file could not be written (disk full, I/O error; the previous file is kept),
// 1 an internal error (including a sweep run that could not be started).
#include <Inventor/SoDB.h>
#include <Inventor/SoInput.h>
#include <Inventor/actions/SoGetBoundingBoxAction.h>
#include <Inventor/errors/SoDebugError.h>
#include <Inventor/errors/SoReadError.h>
#include <Inventor/fields/SoSFTime.h>
#include <Inventor/nodes/SoSeparator.h>
#include <unistd.h>

#include <QApplication>
#include <QCommandLineParser>
#include <QDir>
#include <QElapsedTimer>
#include <QEventLoop>
#include <QFileInfo>
#include <QProcess>
#include <QTemporaryFile>
#include <QThread>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <memory>
#include <set>

#include "AtomicFile.h"
#include "VideoWriter.h"
#include "Plot.h"
#include "bsdeform/AuthoredClock.h"
#include "bsdeform/NodeRef.h"
#include "bsdeform/NodesInit.h"
#include "bsdeform/OffscreenRenderer.h"
#include "bsdeform/SceneReader.h"
#include "bsdeform/SceneText.h"
#include "bsdeform/Simulation.h"
#include "bsdeform/SoBSplineDeformSurface.h"

namespace {

enum ExitCode { kOk = 0, kInternal = 1, kBadInput = 2, kBlowUp = 3, kWriteFailed = 4 };

struct Failure {
  ExitCode code;
  QString message;
};

QStringList g_coinMessages;

void collectCoinMessage(const SoError* e, void*) { g_coinMessages << QString::fromUtf8(e->getDebugString().getString()); }

QString num(double x) { return QString::number(x, 'g', 17); }

struct Surface {
  QString name;
  SoBSplineDeformSurface* node = nullptr;
  QString csv;
  QVector<double> t, norm, kinetic, strain;
  long lastRecorded = -1;  ///< step count of the last history row
  bool failed = false;
};

struct Options {
  QString scene;
  long steps = 100;
  double until = -1.0;
  QString outDir;
  bool overwrite = false;
  int pngEvery = 0;
  QVector<double> pngAt;
  int width = 640, height = 480;
  QStringList sets;
  QString sweep;
  bool plot = false;
  long recordEvery = 1;
  QString video;          // --video FILE (.mp4, .webm)
  double videoFps = 25.0; // --video-fps: frames per simulated second
  bool quiet = false;
  bool resultOnly = false;  // internal: a sweep child prints RESULT lines and writes nothing
  QString sweepProgram;     // internal: the program started per sweep value (default: this one)
};

// ------------------------------------------------------------------------------------------

Failure loadScene(const QString& path, bsdeform::NodeRef<SoSeparator>& root) {
  const QFileInfo info(path);
  if (info.isDir()) return {kBadInput, QStringLiteral("cannot open scene '%1': it is a directory").arg(path)};
  if (!info.exists()) return {kBadInput, QStringLiteral("cannot open scene '%1': no such file").arg(path)};
  if (!info.isFile()) return {kBadInput, QStringLiteral("cannot open scene '%1': not a regular file").arg(path)};
  {
    QFile probe(path);  // Coin does not say why a file cannot be opened; the system does
    if (!probe.open(QIODevice::ReadOnly))
      return {kBadInput, QStringLiteral("cannot open scene '%1': %2").arg(path, probe.errorString())};
  }
  std::string error;  // the guarded reader (docs/reliability.md): FILE:LINE: reason, or Coin's errors
  root.reset(bsdeform::readSceneFile(QFile::encodeName(path).toStdString(), error));
  if (!root)
    return {kBadInput, QStringLiteral("cannot read scene: %1").arg(QString::fromStdString(error).replace(QLatin1Char('\n'), QStringLiteral("; ")))};
  return {kOk, {}};
}

// NAME.field=value -> sets the field of the object DEF'ed as NAME.
Failure applySet(const QString& spec) {
  const int eq = spec.indexOf(QLatin1Char('='));
  const int dot = eq > 0 ? spec.lastIndexOf(QLatin1Char('.'), eq) : -1;
  if (eq <= 0 || dot <= 0 || dot + 1 >= eq)
    return {kBadInput, QStringLiteral("--set '%1': expected NAME.field=value").arg(spec)};
  const QString name = spec.left(dot), field = spec.mid(dot + 1, eq - dot - 1), value = spec.mid(eq + 1);
  SoBase* base = SoBase::getNamedBase(SbName(name.toUtf8().constData()), SoFieldContainer::getClassTypeId());
  if (!base) return {kBadInput, QStringLiteral("--set '%1': no node or engine is DEF'ed as '%2' in the scene").arg(spec, name)};
  auto* fc = static_cast<SoFieldContainer*>(base);
  SoField* f = fc->getField(SbName(field.toUtf8().constData()));
  if (!f) return {kBadInput, QStringLiteral("--set '%1': '%2' has no field '%3'").arg(spec, name, field)};
  g_coinMessages.clear();
  if (!f->set(value.toUtf8().constData()))
    return {kBadInput, QStringLiteral("--set '%1': '%2' is not a valid value for field %3.%4 (%5)")
                           .arg(spec, value, name, field, QString::fromLatin1(f->getTypeId().getName().getString()))};
  return {kOk, {}};
}

// The scene's distinct surfaces (bsdeform::sceneSurfaces), each named by its DEF name or, when
// it has none, "surfaceN" after its place among them: the output files are named after it.
QVector<Surface> findSurfaces(SoNode* root) {
  QVector<Surface> out;
  for (SoBSplineDeformSurface* node : bsdeform::sceneSurfaces(root)) {
    Surface s;
    s.node = node;
    const SbName n = node->getName();
    s.name = n.getLength() ? QString::fromUtf8(n.getString()) : QStringLiteral("surface%1").arg(out.size());
    out.push_back(s);
  }
  return out;
}

// One history row: the diagnostics of the current state, computed once, in one pass over the
// nets (bsdeform::Simulation::diagnostics()).
void record(Surface& s) {
  const bsdeform::Simulation& sim = s.node->simulation();
  const bsdeform::Diagnostics d = sim.diagnostics();
  const bsdeform::StrainEnergy& e = d.strain;
  if (s.csv.isEmpty())
    s.csv = QStringLiteral("time,step,norm,kinetic,strain,strain_w10,strain_w01,strain_w11,strain_w20,strain_w02,substeps\n");
  s.csv += QStringList{num(sim.time()), QString::number(sim.stepCount()), num(d.norm), num(d.kinetic),
                       num(e.total), num(e.w10), num(e.w01), num(e.w11), num(e.w20), num(e.w02),
                       QString::number(sim.subSteps())}
               .join(QLatin1Char(',')) +
           QLatin1Char('\n');
  s.t << sim.time();
  s.norm << d.norm;
  s.kinetic << d.kinetic;
  s.strain << e.total;
  s.lastRecorded = sim.stepCount();
}

// Streams the scene text into the temporary file: it is never held in memory.
bool writeScene(SoNode* root, const bsdeform::AuthoredClock& authored, const QString& path, QString& error) {
  return bsdeform::saveFileAtomically(
      path,
      [root, &authored](QIODevice& device) {
        const bsdeform::AuthoredClock::Scope fileValues(authored);
        return bsdeform::writeSceneText(root, [&device](const char* data, std::size_t size) {
          return device.write(data, qint64(size)) == qint64(size);
        });
      },
      error);
}

// Every output file is named after a surface: a DEF name that is not a plain file name, or two
// surfaces with the same name, would fail or overwrite each other only after the whole run.
Failure checkOutputNames(const QVector<Surface>& surfaces) {
  std::set<QString> seen;
  for (const Surface& s : surfaces) {
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

Failure prepareOutDir(const Options& o) {
  QDir dir(o.outDir);
  const QFileInfo info(o.outDir);
  if (info.exists() && !info.isDir()) return {kBadInput, QStringLiteral("output path '%1' is not a directory").arg(o.outDir)};
  // hidden files count: a directory holding only dot files is not empty
  const QDir::Filters everything = QDir::AllEntries | QDir::NoDotAndDotDot | QDir::Hidden | QDir::System;
  if (dir.exists() && !dir.isEmpty(everything) && !o.overwrite)
    return {kBadInput, QStringLiteral("output directory '%1' is not empty; nothing was written (use --overwrite to replace "
                                      "its files)").arg(o.outDir)};
  errno = 0;
  if (!QDir().mkpath(o.outDir)) {
    const QString why = errno ? QString::fromLocal8Bit(std::strerror(errno)) : QStringLiteral("unknown error");
    return {kBadInput, QStringLiteral("cannot create output directory '%1': %2").arg(o.outDir, why)};
  }
  // a uniquely named probe, removed again: never a name a user's file could have
  QTemporaryFile probe(dir.filePath(QStringLiteral(".bsdeform-write-test-XXXXXX")));
  if (!probe.open())
    return {kBadInput, QStringLiteral("output directory '%1' is not writable: %2").arg(o.outDir, probe.errorString())};
  return {kOk, {}};
}

// A write failure after the run: which file, why, and which files were already replaced.
Failure writeFailure(const QString& error, const QStringList& written) {
  if (written.isEmpty()) return {kWriteFailed, error};
  return {kWriteFailed, QStringLiteral("%1 (already written: %2)").arg(error, written.join(QStringLiteral(", ")))};
}

void progress(const Options& o, long frame, long frames, double t) {
  static bool tty = isatty(STDERR_FILENO);
  if (!tty || o.quiet || o.resultOnly || frames <= 0) return;
  static int last = -1;
  const int pct = int(100.0 * frame / frames);
  if (pct == last && frame != frames) return;
  last = pct;
  const int filled = pct / 4;
  std::fprintf(stderr, "\r[%s%s] %3d%%  t = %.4g", std::string(filled, '#').c_str(), std::string(25 - filled, '.').c_str(),
               pct, t);
  if (frame == frames) std::fprintf(stderr, "\n");
}

// ------------------------------------------------------------------------------------------
// One run of the scene (possibly a sweep child).

// Coin's real-time clock follows simulated time in the runner: engines driven by realTime
// (ElapsedTime, TimeCounter, ...) then animate deterministically, in step with the surfaces.
SoSFTime* realTimeField() { return static_cast<SoSFTime*>(SoDB::getGlobalField(SbName("realTime"))); }

Failure runScene(const Options& o) {
  SoDB::enableRealTimeSensor(FALSE);
  realTimeField()->setValue(SbTime(0.0));  // before reading: engines start their clocks at 0
  bsdeform::NodeRef<SoSeparator> root;  // given back on every return
  Failure f = loadScene(o.scene, root);
  if (f.code != kOk) return f;
  for (const QString& s : o.sets) {
    f = applySet(s);
    if (f.code != kOk) return f;
  }
  QVector<Surface> surfaces = findSurfaces(root.get());
  if (surfaces.isEmpty()) return {kBadInput, QStringLiteral("scene '%1' has no SoBSplineDeformSurface").arg(o.scene)};
  // Build every model and force now: bad values show up as warnings before anything runs.
  // A traversal first tells each surface its scene (the frames of COLLISION obstacles).
  g_coinMessages.clear();
  {
    SoGetBoundingBoxAction bb(SbViewportRegion(o.width, o.height));
    bb.apply(root.get());
  }
  double dtMin = INFINITY, t0 = INFINITY;
  const bsdeform::AuthoredClock authored(root.get());  // final.iv keeps the scene's own `on` and `speed`
  for (Surface& s : surfaces) {
    s.node->on = FALSE;  // the runner drives time itself
    s.node->stepSimulation(0);
    dtMin = std::min(dtMin, s.node->simulation().parameters().timeStep);
    t0 = std::min(t0, s.node->simulation().time());  // a resumed scene continues from its time
  }
  if (!g_coinMessages.isEmpty())
    return {kBadInput, QStringLiteral("scene '%1': %2").arg(o.scene, g_coinMessages.join(QStringLiteral("; ")))};
  // A step that cannot be taken (too many sub-steps, a clock that no longer advances) is bad input.
  for (const Surface& s : surfaces) {
    const std::string why = s.node->simulation().refusal();
    if (!why.empty())
      return {kBadInput, QStringLiteral("scene '%1', surface %2: %3").arg(o.scene, s.name, QString::fromStdString(why))};
  }
  if (!o.resultOnly) {
    f = checkOutputNames(surfaces);
    if (f.code != kOk) return f;
  }

  const long frames = o.until >= 0 ? std::max(0L, long(std::llround((o.until - t0) / dtMin))) : o.steps;
  if (!o.resultOnly) {
    f = prepareOutDir(o);
    if (f.code != kOk) return f;
  }
  QDir out(o.outDir);
  QStringList written;
  QString error;
  // One renderer (GL context, Coin's shaders and caches) and one image buffer for every frame.
  bsdeform::OffscreenRenderer renderer;
  bsdeform::Image img;
  long imagesWritten = 0;
  long renderedFrame = -1;  // the frame img holds
  auto render = [&](long frame) -> Failure {
    std::string err;
    if (renderedFrame != frame && !renderer.render(root.get(), o.width, o.height, img, err))
      return {kInternal, QStringLiteral("rendering failed: %1").arg(QString::fromStdString(err))};
    renderedFrame = frame;
    return {kOk, {}};
  };
  auto image = [&](long frame) -> Failure {
    std::string err;
    const Failure rendered = render(frame);
    if (rendered.code != kOk) return rendered;
    const QString path = out.filePath(QStringLiteral("frame_%1.png").arg(frame, 6, 10, QLatin1Char('0')));
    // not synced one by one (a frame's fsync cost about as much as its PNG): once at the end
    if (!bsdeform::writePng(img, QFile::encodeName(path).toStdString(), err, false))
      return writeFailure(QString::fromStdString(err), written);
    written << path;
    ++imagesWritten;
    return {kOk, {}};
  };
  QVector<long> imageFrames;
  for (double t : o.pngAt) imageFrames << long(std::llround((t - t0) / dtMin));
  // --video: a frame at t0 and at every 1/fps of simulated time after it, each the picture of
  // the last state reached by then (a frame repeats when the time step is longer than 1/fps)
  std::unique_ptr<bsdeform::VideoWriter> video;
  double nextVideoTime = t0;
  if (!o.video.isEmpty() && !o.resultOnly) {
    std::string err;
    video = bsdeform::VideoWriter::open(QFile::encodeName(o.video).toStdString(), o.width, o.height, o.videoFps, err);
    if (!video) return {kBadInput, QString::fromStdString(err)};
  }
  auto videoFrames = [&](long frame) -> Failure {
    const double now = t0 + frame * dtMin;
    while (video && nextVideoTime <= now + 1e-9 * std::max(1.0, std::abs(now))) {
      const Failure rendered = render(frame);
      if (rendered.code != kOk) return rendered;
      std::string err;
      if (!video->addFrame(img.rgb.data(), err)) return writeFailure(QString::fromStdString(err), written);
      nextVideoTime = t0 + double(video->frames()) / o.videoFps;
    }
    return {kOk, {}};
  };

  QElapsedTimer timer;
  timer.start();
  bool blewUp = false;
  realTimeField()->setValue(SbTime(t0));
  // History rows (not in a sweep child, which writes nothing): the first state, every state whose
  // step count is a multiple of --record-every, and the last state.
  const bool recording = !o.resultOnly;
  if (recording)
    for (Surface& s : surfaces) record(s);
  for (long frame = 0; frame <= frames; ++frame) {
    if (frame > 0) {
      const double globalTime = t0 + frame * dtMin;
      realTimeField()->setValue(SbTime(globalTime));
      for (Surface& s : surfaces) {
        if (s.failed) continue;
        const double dt = s.node->simulation().parameters().timeStep;
        while (!s.failed && s.node->simulation().time() + 0.5 * dt <= globalTime) {
          if (!s.node->stepSimulation(1)) {
            s.failed = blewUp = true;
          }
          const long step = s.node->simulation().stepCount();  // a failed step does not count
          if (recording && (s.failed || step % o.recordEvery == 0) && s.lastRecorded != step) record(s);
        }
      }
    }
    if (!o.resultOnly && ((o.pngEvery > 0 && frame % o.pngEvery == 0) || imageFrames.contains(frame))) {
      f = image(frame);
      if (f.code != kOk) return f;
    }
    f = videoFrames(frame);
    if (f.code != kOk) return f;
    progress(o, frame, frames, t0 + frame * dtMin);
    if (blewUp) break;
  }
  if (recording)
    for (Surface& s : surfaces)
      if (s.lastRecorded != s.node->simulation().stepCount()) record(s);
  const double seconds = timer.elapsed() / 1000.0;

  if (o.resultOnly) {
    for (const Surface& s : surfaces) {
      const bsdeform::Simulation& sim = s.node->simulation();
      const bsdeform::Diagnostics d = sim.diagnostics();
      std::printf("RESULT\t%s\t%s\t%s\t%s\t%s\n", s.name.toUtf8().constData(), num(d.norm).toUtf8().constData(),
                  num(d.kinetic).toUtf8().constData(), num(d.strain.total).toUtf8().constData(),
                  sim.status() == bsdeform::Status::Ok ? "ok" : "blew-up");
    }
    root.reset();
    return {blewUp ? kBlowUp : kOk, {}};
  }

  for (const Surface& s : surfaces) {
    const QString path = out.filePath(s.name + QStringLiteral(".csv"));
    if (!bsdeform::saveFileAtomically(path, s.csv.toUtf8(), error)) return writeFailure(error, written);
    written << path;
    if (o.plot) {
      const QString plotPath = out.filePath(s.name + QStringLiteral("_history.png"));
      QString perr;
      if (!bsdeform::writePlotPng(plotPath, s.name + QStringLiteral(": deformation over time"), QStringLiteral("time"),
                                  QStringLiteral("norm"),
                                  {{QStringLiteral("norm (eq. 15)"), s.t, s.norm},
                                   {QStringLiteral("kinetic energy"), s.t, s.kinetic, true},
                                   {QStringLiteral("strain energy"), s.t, s.strain, true}},
                                  800, 500, perr, {QStringLiteral("energy"), true, false, false}))
        return writeFailure(perr, written);
      written << plotPath;
    }
  }
  if (video) {
    std::string err;
    if (!video->finish(err)) return writeFailure(QString::fromStdString(err), written);
    written << o.video + QStringLiteral(" (%1 frames)").arg(video->frames());
  }
  if (imagesWritten > 0) {
    std::string err;
    if (!bsdeform::syncFileSystem(QFile::encodeName(o.outDir).toStdString(), err))
      return writeFailure(QString::fromStdString(err), written);
  }
  const QString ivPath = out.filePath(QStringLiteral("final.iv"));
  if (!writeScene(root.get(), authored, ivPath, error)) return writeFailure(error, written);
  written << ivPath;

  if (!o.quiet) {
    std::printf("bsdeform-run: %s, %ld frame(s) of %.4g s in %.2f s wall\n", o.scene.toUtf8().constData(), frames, dtMin, seconds);
    for (const Surface& s : surfaces) {
      const bsdeform::Simulation& sim = s.node->simulation();
      const bsdeform::ModelParameters& p = sim.parameters();
      const bsdeform::Diagnostics d = sim.diagnostics();
      std::printf("  %-14s %dx%d deg (%d,%d) dt %.4g: t = %.6g, steps %ld, norm %.6g, kinetic %.6g, strain %.6g, "
                  "limit %.4g, sub-steps %d, %s\n",
                  s.name.toUtf8().constData(), p.numU, p.numV, p.degreeU, p.degreeV, p.timeStep, sim.time(), sim.stepCount(),
                  d.norm, d.kinetic, d.strain.total, sim.stabilityLimit(), sim.subSteps(),
                  sim.status() == bsdeform::Status::Ok ? "ok" : sim.statusMessage().c_str());
    }
    for (const QString& w : written) std::printf("  wrote %s\n", w.toUtf8().constData());
  }
  QStringList blowUps;
  bool refused = false;
  for (const Surface& s : surfaces) {
    if (!s.failed) continue;
    blowUps << s.name + QStringLiteral(": ") + QString::fromStdString(s.node->simulation().statusMessage());
    refused |= s.node->simulation().status() == bsdeform::Status::Refused;
  }
  root.reset();  // the surfaces are gone after this
  if (blewUp) return {refused ? kBadInput : kBlowUp, blowUps.join(QStringLiteral("; "))};
  return {kOk, {}};
}

}  // namespace

namespace {

// --sweep NAME.field=v1,v2,...: one child process per value, in parallel over the cores.
Failure runSweep(const Options& o, const QStringList& passThrough) {
  const int eq = o.sweep.indexOf(QLatin1Char('='));
  if (eq <= 0) return {kBadInput, QStringLiteral("--sweep '%1': expected NAME.field=v1,v2,...").arg(o.sweep)};
  const QString target = o.sweep.left(eq);
  const QStringList values = o.sweep.mid(eq + 1).split(QLatin1Char(','), Qt::SkipEmptyParts);
  if (values.isEmpty()) return {kBadInput, QStringLiteral("--sweep '%1': no values").arg(o.sweep)};
  // Validate names and every value in this process first: bad input is reported before any run.
  {
    bsdeform::NodeRef<SoSeparator> root;
    Failure f = loadScene(o.scene, root);
    if (f.code != kOk) return f;
    for (const QString& s : o.sets)
      if ((f = applySet(s)).code != kOk) return f;
    for (const QString& v : values)
      if ((f = applySet(target + QLatin1Char('=') + v)).code != kOk) return f;
  }
  Failure f = prepareOutDir(o);
  if (f.code != kOk) return f;

  struct Row {
    QString value, surface, norm, kinetic, strain, status;
  };
  QVector<QVector<Row>> rows(values.size());
  QVector<QString> errors(values.size());
  const int parallel = std::max(1, QThread::idealThreadCount());
  const QString program = o.sweepProgram.isEmpty() ? QCoreApplication::applicationFilePath() : o.sweepProgram;
  QObject owner;  // parent of the child processes: all are gone when this function returns
  QEventLoop loop;
  QString startError;  // set when a child could not be started: the sweep stops
  int next = 0, running = 0, done = 0;
  std::function<void()> startMore;
  auto start = [&](int i) {
    auto* p = new QProcess(&owner);
    p->setProcessChannelMode(QProcess::SeparateChannels);
    QStringList args = passThrough;
    args << QStringLiteral("--set") << target + QLatin1Char('=') + values[i] << QStringLiteral("--result-only");
    QObject::connect(p, QOverload<int, QProcess::ExitStatus>::of(&QProcess::finished), &owner,
                     [&, i, p](int code, QProcess::ExitStatus status) {
                       const QStringList lines =
                           QString::fromUtf8(p->readAllStandardOutput()).split(QLatin1Char('\n'), Qt::SkipEmptyParts);
                       for (const QString& line : lines) {
                         const QStringList c = line.split(QLatin1Char('\t'));
                         if (c.size() == 6 && c[0] == QLatin1String("RESULT"))
                           rows[i].push_back({values[i], c[1], c[2], c[3], c[4], c[5]});
                       }
                       const QString err = QString::fromUtf8(p->readAllStandardError()).trimmed();
                       if (status == QProcess::CrashExit)
                         errors[i] = QStringLiteral("run with %1=%2 crashed: %3").arg(target, values[i], err);
                       else if (code != kOk && code != kBlowUp)
                         errors[i] = QStringLiteral("run with %1=%2 failed: %3").arg(target, values[i], err);
                       --running;
                       ++done;
                       progress(o, done, values.size(), done);
                       startMore();
                     });
    // A child that cannot start never finishes: without this the sweep would wait forever.
    QObject::connect(p, &QProcess::errorOccurred, &owner, [&, i, p](QProcess::ProcessError e) {
      if (e != QProcess::FailedToStart) return;  // crashes and exit codes arrive through finished()
      if (startError.isEmpty())
        startError = QStringLiteral("cannot start the run with %1=%2 ('%3'): %4").arg(target, values[i], program, p->errorString());
      --running;
      ++done;
      for (QProcess* other : owner.findChildren<QProcess*>())
        if (other->state() != QProcess::NotRunning) other->kill();
      startMore();
    });
    ++running;
    p->start(program, args);
  };
  startMore = [&] {
    while (startError.isEmpty() && running < parallel && next < values.size()) start(next++);
    if (running == 0) loop.quit();
  };
  startMore();
  if (running > 0) loop.exec();
  if (!startError.isEmpty()) return {kInternal, startError};
  QStringList errs;
  for (const QString& e : errors)
    if (!e.isEmpty()) errs << e;
  if (!errs.isEmpty()) return {kInternal, errs.join(QStringLiteral("; "))};

  QString csv = QStringLiteral("value,surface,norm,kinetic,strain,status\n");
  std::map<QString, bsdeform::PlotSeries> bySurface;
  bool numeric = true;
  for (const auto& rs : rows)
    for (const Row& r : rs) {
      csv += QStringList{r.value, r.surface, r.norm, r.kinetic, r.strain, r.status}.join(QLatin1Char(',')) + QLatin1Char('\n');
      bool ok = false;
      const double x = r.value.toDouble(&ok);
      numeric &= ok;
      auto& s = bySurface[r.surface];
      s.name = r.surface;
      s.x << x;
      s.y << r.norm.toDouble();
    }
  QDir out(o.outDir);
  QString error;
  if (!bsdeform::saveFileAtomically(out.filePath(QStringLiteral("sweep.csv")), csv.toUtf8(), error))
    return writeFailure(error, {});
  QStringList written{out.filePath(QStringLiteral("sweep.csv"))};
  if (numeric) {
    QVector<bsdeform::PlotSeries> series;
    for (auto& kv : bySurface) series << kv.second;
    if (!bsdeform::writePlotPng(out.filePath(QStringLiteral("sweep.png")),
                                QStringLiteral("Deformation norm (eq. 15) against %1").arg(target), target,
                                QStringLiteral("final norm ||P - P0||"), series, 800, 500, error, {QString(), true, true, true}))
      return writeFailure(error, written);
    written << out.filePath(QStringLiteral("sweep.png"));
  }
  if (!o.quiet) {
    std::printf("bsdeform-run: sweep of %s over %d value(s), %d in parallel\n", target.toUtf8().constData(), int(values.size()),
                parallel);
    std::printf("%s", csv.toUtf8().constData());
    for (const QString& w : written) std::printf("  wrote %s\n", w.toUtf8().constData());
  }
  return {kOk, {}};
}

QVector<double> parseList(const QString& text, bool& ok) {
  QVector<double> v;
  ok = true;
  for (const QString& s : text.split(QLatin1Char(','), Qt::SkipEmptyParts)) {
    bool good = false;
    v << s.toDouble(&good);
    ok &= good && std::isfinite(v.back()) && v.back() >= 0.0;
  }
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  // No windows are ever shown: plots render on Qt's offscreen platform, images through EGL.
  if (qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM")) qputenv("QT_QPA_PLATFORM", "offscreen");
  QApplication app(argc, argv);
  QApplication::setApplicationName(QStringLiteral("bsdeform-run"));
  QCommandLineParser parser;
  parser.setApplicationDescription(QStringLiteral(
      "Steps the SoBSplineDeformSurface nodes of an .iv scene without a window and writes, into the output\n"
      "directory: one CSV history per surface (time, step, norm eq. 15, kinetic energy, strain energy and its\n"
      "terms, sub-steps), the final scene with its state (final.iv, reloadable and resumable), PNG images and\n"
      "plots on request. Steps count on the surface with the smallest time step.\n"
      "Exit codes: 0 success, 2 bad input, 3 a simulation blew up, 4 an output file could not be written (the\n"
      "previous file is kept), 1 internal error."));
  parser.addHelpOption();
  parser.addPositionalArgument(QStringLiteral("scene"), QStringLiteral("the .iv scene"));
  const QCommandLineOption steps({QStringLiteral("n"), QStringLiteral("steps")}, QStringLiteral("number of steps (default 100)"),
                                 QStringLiteral("N"));
  const QCommandLineOption until({QStringLiteral("t"), QStringLiteral("until")}, QStringLiteral("run until simulated time T (a resumed scene starts at its own time)"),
                                 QStringLiteral("T"));
  const QCommandLineOption outDir({QStringLiteral("o"), QStringLiteral("out")},
                                  QStringLiteral("output directory (default: <scene name>.out); must be empty or new"),
                                  QStringLiteral("DIR"));
  const QCommandLineOption overwrite(QStringLiteral("overwrite"), QStringLiteral("allow replacing files in a non-empty output directory"));
  const QCommandLineOption pngEvery(QStringLiteral("png-every"), QStringLiteral("write an image every K steps (0: none)"),
                                    QStringLiteral("K"));
  const QCommandLineOption pngAt(QStringLiteral("png-at"), QStringLiteral("write images at these simulated times"),
                                 QStringLiteral("t1,t2,..."));
  const QCommandLineOption size(QStringLiteral("size"), QStringLiteral("image size (default 640x480)"), QStringLiteral("WxH"));
  const QCommandLineOption set(QStringLiteral("set"), QStringLiteral("override a field: NAME is a DEF name (repeatable)"),
                               QStringLiteral("NAME.field=value"));
  const QCommandLineOption sweep(QStringLiteral("sweep"),
                                 QStringLiteral("run once per value (in parallel) and write sweep.csv and sweep.png"),
                                 QStringLiteral("NAME.field=v1,v2,..."));
  const QCommandLineOption plot(QStringLiteral("plot"), QStringLiteral("also write a history plot PNG per surface"));
  const QCommandLineOption recordEvery(QStringLiteral("record-every"),
                                       QStringLiteral("history rows (CSV, plot): the first state, every state whose step "
                                                      "count is a multiple of K, and the last state (default 1: every step)"),
                                       QStringLiteral("K"));
  const QCommandLineOption video(QStringLiteral("video"),
                                  QStringLiteral("also write a video of the run: .mp4 (H.264) or .webm (VP9), at --size"),
                                  QStringLiteral("FILE"));
  const QCommandLineOption videoFps(QStringLiteral("video-fps"),
                                     QStringLiteral("video frames per simulated second (default 25)"), QStringLiteral("F"));
  const QCommandLineOption quiet({QStringLiteral("q"), QStringLiteral("quiet")}, QStringLiteral("no summary, no progress"));
  QCommandLineOption resultOnly(QStringLiteral("result-only"), QStringLiteral("internal: print RESULT lines, write nothing"));
  resultOnly.setFlags(QCommandLineOption::HiddenFromHelp);
  QCommandLineOption sweepProgram(QStringLiteral("sweep-program"),
                                  QStringLiteral("internal (tests): the program started for each sweep value"),
                                  QStringLiteral("PATH"));
  sweepProgram.setFlags(QCommandLineOption::HiddenFromHelp);
  parser.addOptions(
      {steps, until, outDir, overwrite, pngEvery, pngAt, size, video, videoFps, set, sweep, plot, recordEvery, quiet, resultOnly,
       sweepProgram});
  parser.process(app);

  auto fail = [](const Failure& f) {
    if (!f.message.isEmpty()) std::fprintf(stderr, "bsdeform-run: %s\n", f.message.toUtf8().constData());
    return int(f.code);
  };
  if (parser.positionalArguments().size() != 1)
    return fail({kBadInput, QStringLiteral("expected exactly one scene file (see --help)")});
  Options o;
  o.scene = parser.positionalArguments().first();
  bool ok = true;
  if (parser.isSet(steps)) {
    o.steps = parser.value(steps).toLong(&ok);
    if (!ok || o.steps < 0) return fail({kBadInput, QStringLiteral("--steps '%1' is not a count >= 0").arg(parser.value(steps))});
  }
  if (parser.isSet(until)) {
    o.until = parser.value(until).toDouble(&ok);
    if (!ok || !(o.until >= 0) || !std::isfinite(o.until))
      return fail({kBadInput, QStringLiteral("--until '%1' is not a time >= 0").arg(parser.value(until))});
    if (parser.isSet(steps)) return fail({kBadInput, QStringLiteral("give --steps or --until, not both")});
  }
  o.outDir = parser.isSet(outDir) ? parser.value(outDir) : QFileInfo(o.scene).completeBaseName() + QStringLiteral(".out");
  o.overwrite = parser.isSet(overwrite);
  if (parser.isSet(pngEvery)) {
    o.pngEvery = parser.value(pngEvery).toInt(&ok);
    if (!ok || o.pngEvery < 0) return fail({kBadInput, QStringLiteral("--png-every '%1' is not a count >= 0").arg(parser.value(pngEvery))});
  }
  if (parser.isSet(pngAt)) {
    o.pngAt = parseList(parser.value(pngAt), ok);
    if (!ok) return fail({kBadInput, QStringLiteral("--png-at '%1' is not a list of times >= 0").arg(parser.value(pngAt))});
  }
  if (parser.isSet(size)) {
    const QStringList wh = parser.value(size).split(QLatin1Char('x'));
    bool okW = false, okH = false;
    if (wh.size() == 2) o.width = wh[0].toInt(&okW), o.height = wh[1].toInt(&okH);
    if (!okW || !okH || o.width < 1 || o.height < 1 || o.width > 8192 || o.height > 8192)
      return fail({kBadInput, QStringLiteral("--size '%1' is not WxH within 1..8192").arg(parser.value(size))});
  }
  o.sets = parser.values(set);
  o.sweep = parser.value(sweep);
  o.plot = parser.isSet(plot);
  if (parser.isSet(recordEvery)) {
    o.recordEvery = parser.value(recordEvery).toLong(&ok);
    if (!ok || o.recordEvery < 1)
      return fail({kBadInput, QStringLiteral("--record-every '%1' is not a count >= 1").arg(parser.value(recordEvery))});
  }
  o.video = parser.value(video);
  if (parser.isSet(videoFps)) {
    o.videoFps = parser.value(videoFps).toDouble(&ok);
    if (!ok || !(o.videoFps > 0.0) || o.videoFps > 1000.0)
      return fail({kBadInput, QStringLiteral("--video-fps '%1' is not a rate in (0, 1000]").arg(parser.value(videoFps))});
  }
  if (!o.video.isEmpty() && !o.sweep.isEmpty())
    return fail({kBadInput, QStringLiteral("--video and --sweep: a sweep runs many simulations, record one with --set")});
  o.quiet = parser.isSet(quiet);
  o.resultOnly = parser.isSet(resultOnly);
  o.sweepProgram = parser.value(sweepProgram);

  bsdeform::disableDynamicNodeLoading();
  bsdeform::initNodes();
  SoDebugError::setHandlerCallback(collectCoinMessage, nullptr);
  SoReadError::setHandlerCallback(collectCoinMessage, nullptr);
  try {
    if (!o.sweep.isEmpty()) {
      // children get the same run options, without the output and sweep ones
      QStringList pass{o.scene};
      if (parser.isSet(steps)) pass << QStringLiteral("--steps") << QString::number(o.steps);
      if (parser.isSet(until)) pass << QStringLiteral("--until") << num(o.until);
      for (const QString& s : o.sets) pass << QStringLiteral("--set") << s;
      return fail(runSweep(o, pass));
    }
    return fail(runScene(o));
  } catch (const std::exception& e) {
    return fail({kInternal, QStringLiteral("internal error: %1").arg(QString::fromUtf8(e.what()))});
  }
}
