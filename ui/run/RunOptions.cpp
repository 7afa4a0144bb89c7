// SPDX-License-Identifier: MIT
#include "RunOptions.h"

#include <QCommandLineParser>
#include <QFileInfo>
#include <QRegularExpression>
#include <cmath>

#include "History.h"
#include "ImageSize.h"

namespace bsdeform::run {

namespace {

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

bool ProbeOption::parse(const QString& text, ProbeOption& probe, QString& why) {
  static const QRegularExpression form(QStringLiteral("^([A-Za-z_][A-Za-z0-9_]*)=([^,]*),([^,]*)$"));
  const QRegularExpressionMatch m = form.match(text);
  if (!m.hasMatch()) {
    why = QStringLiteral("--probe '%1' is not NAME=u,v (NAME a C identifier: letters, digits and '_', not starting "
                         "with a digit)")
              .arg(text);
    return false;
  }
  probe.name = m.captured(1);
  // the reaction and load columns of a static CSV end alike: a probe must not shadow them
  if (probe.name == QLatin1String("applied") || probe.name.startsWith(QLatin1String("reaction_"))) {
    why = QStringLiteral("--probe '%1': the name '%2' would give the columns of the reactions or applied loads "
                         "(reaction_..., applied_...); choose another")
              .arg(text, probe.name);
    return false;
  }
  bool okU = false, okV = false;
  probe.u = m.captured(2).trimmed().toDouble(&okU);
  probe.v = m.captured(3).trimmed().toDouble(&okV);
  if (!okU || !okV || !(probe.u >= 0.0 && probe.u <= 1.0) || !(probe.v >= 0.0 && probe.v <= 1.0)) {
    why = QStringLiteral("--probe '%1': u and v must be numbers in [0, 1], got '%2' and '%3'")
              .arg(text, m.captured(2), m.captured(3));
    return false;
  }
  return true;
}

Failure RunOptions::parse(const QStringList& arguments, RunOptions& o) {
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
  const QCommandLineOption frameNames(
      QStringLiteral("frame-names"),
      QStringLiteral("image file names: 'frame' (frame_NNNNNN.png, the frame number; default) or 'time' "
                     "(frame_tTTT.TTTTTT.png, the simulated time)"),
      QStringLiteral("frame|time"));
  const QCommandLineOption size(QStringLiteral("size"), QStringLiteral("image size (default 640x480)"), QStringLiteral("WxH"));
  const QCommandLineOption set(QStringLiteral("set"), QStringLiteral("override a field: NAME is a DEF name (repeatable)"),
                               QStringLiteral("NAME.field=value"));
  const QCommandLineOption sweep(QStringLiteral("sweep"),
                                 QStringLiteral("run once per value (in parallel) and write sweep.csv and sweep.png"),
                                 QStringLiteral("NAME.field=v1,v2,..."));
  const QCommandLineOption metric(
      QStringLiteral("metric"),
      QStringLiteral("measure over the run (repeatable; a column of sweep.csv each, the first plotted in sweep.png): "
                     "z@U:V (or x, y: the point S(U,V) at the end), max-z@U:V, min-z@U:V (over the run), stretch, "
                     "max-stretch (area / rest area), kinetic (at the end), rest-time"),
      QStringLiteral("METRIC"));
  const QCommandLineOption plot(QStringLiteral("plot"), QStringLiteral("also write a history plot PNG per surface"));
  const QCommandLineOption recordEvery(QStringLiteral("record-every"),
                                       QStringLiteral("history rows (CSV, plot): the first state, every state whose step "
                                                      "count is a multiple of K, and the last state (default 1: every step)"),
                                       QStringLiteral("K"));
  const QCommandLineOption keepStates(
      QStringLiteral("keep-states"),
      QStringLiteral("also write the states of every surface at the first time, every K-th time step (--record-every) "
                     "and the last, for bsdeform-viewer --states (older states thinned beyond 256 MiB)"),
      QStringLiteral("FILE"));
  const QCommandLineOption video(QStringLiteral("video"),
                                  QStringLiteral("also write a video of the run: .mp4 (H.264) or .webm (VP9), at --size"),
                                  QStringLiteral("FILE"));
  const QCommandLineOption videoFps(QStringLiteral("video-fps"),
                                     QStringLiteral("video frames per simulated second (default 25)"), QStringLiteral("F"));
  const QCommandLineOption exportMesh(
      QStringLiteral("export-mesh"),
      QStringLiteral("at the end of the run, also write the triangles the surfaces draw (world coordinates) as "
                     ".obj (one object per surface, named as its CSV) or .stl (binary, the triangles of all "
                     "surfaces in one solid), by the extension; the file is replaced only when written completely"),
      QStringLiteral("FILE"));
  const QCommandLineOption quiet({QStringLiteral("q"), QStringLiteral("quiet")}, QStringLiteral("no summary, no progress"));
  const QCommandLineOption staticSolve(
      QStringLiteral("static"),
      QStringLiteral("solve for the equilibrium of the loads at t = 0 instead of stepping (the paper's A P = L):\n"
                     "final.iv holds it at rest, the CSV one row (with the reactions of the held sides and pins,\n"
                     "reaction_umin_x ..., reaction_pin0_x ..., and the applied loads' sum applied_x ...), --png-every/\n"
                     "--png-at one image; prints the residual and how well the reactions balance the loads"));
  const QCommandLineOption loadSteps(
      QStringLiteral("load-steps"),
      QStringLiteral("with --static: apply the loads in K equal increments (SHELL: Newton from each equilibrium to\n"
                     "the next), one CSV row per increment with its load factor: a load-displacement curve"),
      QStringLiteral("K"));
  const QCommandLineOption arcLength(
      QStringLiteral("arc-length"),
      QStringLiteral("with --static (SHELL): trace the equilibrium path by arc-length continuation (Crisfield),\n"
                     "through limit points and snap-backs, one CSV row per converged point (its load factor, the\n"
                     "probes, the energies, the reactions): --load-steps points at most (default 50), until the\n"
                     "load factor passes --max-load; --plot draws the load factor against the first probe"));
  const QCommandLineOption maxLoad(QStringLiteral("max-load"),
                                   QStringLiteral("with --arc-length: stop once the load factor passes F (default 1)"),
                                   QStringLiteral("F"));
  const QCommandLineOption probe(
      QStringLiteral("probe"),
      QStringLiteral("add the surface point S(u,v) and its displacement from rest to every CSV row, as columns\n"
                     "NAME_x NAME_y NAME_z NAME_dx NAME_dy NAME_dz (the surface's own coordinates; repeatable)"),
      QStringLiteral("NAME=u,v"));
  QCommandLineOption resultOnly(QStringLiteral("result-only"), QStringLiteral("internal: print RESULT lines, write nothing"));
  resultOnly.setFlags(QCommandLineOption::HiddenFromHelp);
  QCommandLineOption resultLines(QStringLiteral("result-lines"),
                                 QStringLiteral("internal: print RESULT lines after writing the outputs"));
  resultLines.setFlags(QCommandLineOption::HiddenFromHelp);
  QCommandLineOption sweepProgram(QStringLiteral("sweep-program"),
                                  QStringLiteral("internal (tests): the program started for each sweep value"),
                                  QStringLiteral("PATH"));
  sweepProgram.setFlags(QCommandLineOption::HiddenFromHelp);
  QCommandLineOption sweepRows(QStringLiteral("sweep-rows"),
                               QStringLiteral("internal (bsdeform.sweep): write sweep.csv and sweep.png from the rows of "
                                              "this sweep.csv instead of running the values"),
                               QStringLiteral("CSV"));
  sweepRows.setFlags(QCommandLineOption::HiddenFromHelp);
  parser.addOptions(
      {steps, until, outDir, overwrite, pngEvery, pngAt, frameNames, size, video, videoFps, exportMesh, set, sweep, metric, plot, recordEvery, keepStates, quiet,
       staticSolve, loadSteps, arcLength, maxLoad, probe, resultOnly, resultLines, sweepProgram, sweepRows});
  parser.process(arguments);

  if (parser.positionalArguments().size() != 1) return {kBadInput, QStringLiteral("expected exactly one scene file (see --help)")};
  o = RunOptions();
  o.scene = parser.positionalArguments().first();
  bool ok = true;
  if (parser.isSet(steps)) {
    o.steps = parser.value(steps).toLong(&ok);
    if (!ok || o.steps < 0) return {kBadInput, QStringLiteral("--steps '%1' is not a count >= 0").arg(parser.value(steps))};
  }
  if (parser.isSet(until)) {
    o.until = parser.value(until).toDouble(&ok);
    if (!ok || !(o.until >= 0) || !std::isfinite(o.until))
      return {kBadInput, QStringLiteral("--until '%1' is not a time >= 0").arg(parser.value(until))};
    if (parser.isSet(steps)) return {kBadInput, QStringLiteral("give --steps or --until, not both")};
  }
  o.outDir = parser.isSet(outDir) ? parser.value(outDir) : QFileInfo(o.scene).completeBaseName() + QStringLiteral(".out");
  o.overwrite = parser.isSet(overwrite);
  if (parser.isSet(pngEvery)) {
    o.pngEvery = parser.value(pngEvery).toInt(&ok);
    if (!ok || o.pngEvery < 0) return {kBadInput, QStringLiteral("--png-every '%1' is not a count >= 0").arg(parser.value(pngEvery))};
  }
  if (parser.isSet(pngAt)) {
    o.pngAt = parseList(parser.value(pngAt), ok);
    if (!ok) return {kBadInput, QStringLiteral("--png-at '%1' is not a list of times >= 0").arg(parser.value(pngAt))};
  }
  if (parser.isSet(frameNames)) {
    const QString v = parser.value(frameNames);
    if (v != QLatin1String("frame") && v != QLatin1String("time"))
      return {kBadInput, QStringLiteral("--frame-names '%1' is neither 'frame' nor 'time'").arg(v)};
    o.frameNamesTime = v == QLatin1String("time");
  }
  if (parser.isSet(size)) {
    QSize wh;
    if (!parseImageSize(parser.value(size), wh))
      return {kBadInput,
              QStringLiteral("--size '%1' is not WxH within 1..%2").arg(parser.value(size)).arg(kMaxImageSide)};
    o.width = wh.width();
    o.height = wh.height();
  }
  o.sets = parser.values(set);
  o.sweep = parser.value(sweep);
  for (const QString& text : parser.values(metric)) {
    Metric m;
    QString why;
    if (!Metric::parse(text, m, why)) return {kBadInput, why};
    o.metrics << m;
  }
  o.plot = parser.isSet(plot);
  if (parser.isSet(recordEvery)) {
    o.recordEvery = parser.value(recordEvery).toLong(&ok);
    if (!ok || o.recordEvery < 1)
      return {kBadInput, QStringLiteral("--record-every '%1' is not a count >= 1").arg(parser.value(recordEvery))};
  }
  o.keepStates = parser.value(keepStates);
  if (parser.isSet(keepStates) && !o.sweep.isEmpty())
    return {kBadInput, QStringLiteral("--keep-states and --sweep: a sweep runs many simulations, keep one's with --set")};
  o.video = parser.value(video);
  if (parser.isSet(videoFps)) {
    o.videoFps = parser.value(videoFps).toDouble(&ok);
    if (!ok || !(o.videoFps > 0.0) || o.videoFps > 1000.0)
      return {kBadInput, QStringLiteral("--video-fps '%1' is not a rate in (0, 1000]").arg(parser.value(videoFps))};
  }
  if (!o.video.isEmpty() && !o.sweep.isEmpty())
    return {kBadInput, QStringLiteral("--video and --sweep: a sweep runs many simulations, record one with --set")};
  o.exportMesh = parser.value(exportMesh);
  if (parser.isSet(exportMesh)) {
    const QString ext = QFileInfo(o.exportMesh).suffix().toLower();
    if (ext != QLatin1String("obj") && ext != QLatin1String("stl"))
      return {kBadInput, QStringLiteral("--export-mesh '%1': unknown mesh format '%2' (use .obj or .stl)").arg(o.exportMesh, ext)};
    if (!o.sweep.isEmpty())
      return {kBadInput, QStringLiteral("--export-mesh and --sweep: a sweep runs many simulations, export one with --set")};
  }
  o.quiet = parser.isSet(quiet);
  o.staticSolve = parser.isSet(staticSolve);
  if (o.staticSolve) {
    // the equilibrium is one state: nothing to step, sweep or film
    for (const auto& [isSet, name] : {std::make_pair(parser.isSet(steps), "--steps"), std::make_pair(parser.isSet(until), "--until"),
                                      std::make_pair(!o.sweep.isEmpty(), "--sweep"), std::make_pair(!o.video.isEmpty(), "--video"),
                                      std::make_pair(parser.isSet(recordEvery), "--record-every"),
                                      std::make_pair(parser.isSet(keepStates), "--keep-states"),
                                      std::make_pair(!o.metrics.isEmpty(), "--metric")})
      if (isSet)
        return {kBadInput, QStringLiteral("--static and %1: --static solves for one state, the equilibrium at t = 0")
                               .arg(QLatin1String(name))};
  }
  if (parser.isSet(loadSteps)) {
    bool ok = false;
    o.loadSteps = parser.value(loadSteps).toInt(&ok);
    if (!ok || o.loadSteps < 1 || o.loadSteps > 100000)
      return {kBadInput, QStringLiteral("--load-steps '%1' is not a whole number in 1..100000").arg(parser.value(loadSteps))};
    if (!o.staticSolve)
      return {kBadInput, QStringLiteral("--load-steps needs --static: it divides the static load into increments")};
  }
  o.arcLength = parser.isSet(arcLength);
  if (o.arcLength) {
    if (!o.staticSolve)
      return {kBadInput, QStringLiteral("--arc-length needs --static: it traces the static equilibrium path")};
    if (!parser.isSet(loadSteps)) o.loadSteps = 50;
  }
  if (parser.isSet(maxLoad)) {
    bool ok = false;
    o.maxLoad = parser.value(maxLoad).toDouble(&ok);
    if (!ok || !(o.maxLoad > 0.0) || !std::isfinite(o.maxLoad))
      return {kBadInput, QStringLiteral("--max-load '%1' is not a number > 0").arg(parser.value(maxLoad))};
    if (!o.arcLength)
      return {kBadInput, QStringLiteral("--max-load needs --arc-length: load control stops at the full load (factor 1)")};
  }
  for (const QString& text : parser.values(probe)) {
    ProbeOption p;
    QString why;
    if (!ProbeOption::parse(text, p, why)) return {kBadInput, why};
    for (const ProbeOption& q : o.probes)
      if (q.name == p.name) return {kBadInput, QStringLiteral("--probe '%1': a probe named '%2' is given twice").arg(text, p.name)};
    o.probes << p;
  }
  if (!o.probes.isEmpty() && !o.sweep.isEmpty())
    return {kBadInput, QStringLiteral("--probe and --sweep: a sweep writes no history CSV; measure a point with "
                                      "--metric z@U:V, or probe one run with --set")};
  o.resultOnly = parser.isSet(resultOnly);
  o.resultLines = parser.isSet(resultLines);
  o.sweepProgram = parser.value(sweepProgram);
  o.sweepRows = parser.value(sweepRows);
  if (!o.sweepRows.isEmpty() && o.sweep.isEmpty()) return {kBadInput, QStringLiteral("--sweep-rows needs --sweep")};

  o.sweepChildArguments = QStringList{o.scene};
  if (parser.isSet(steps)) o.sweepChildArguments << QStringLiteral("--steps") << QString::number(o.steps);
  if (parser.isSet(until)) o.sweepChildArguments << QStringLiteral("--until") << historyNumber(o.until);
  for (const QString& s : o.sets) o.sweepChildArguments << QStringLiteral("--set") << s;
  for (const Metric& m : o.metrics) o.sweepChildArguments << QStringLiteral("--metric") << m.name;
  return {kOk, {}};
}

}  // namespace bsdeform::run
