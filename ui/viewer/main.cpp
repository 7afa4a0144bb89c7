// SPDX-License-Identifier: MIT
// bsdeform-viewer [scene.iv] [--speed X] [--measure-fps SECONDS [--grid N]] [--autosave-interval SECONDS]
//                 [--restore-recovery | --discard-recovery]
#include <Inventor/Qt/SoQt.h>

#include <QApplication>
#include <QCommandLineParser>
#include <QStringList>
#include <QTimer>
#include <malloc.h>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "MainWindow.h"
#include "bsdeform/NodesInit.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/SoBSplineDeformSurface.h"

namespace {
// Without a usable GL canvas SoQt's default handler opens a modal dialog and waits forever.
void fatal(const SbString msg, SoQt::FatalErrors, void*) {
  std::fprintf(stderr, "bsdeform-viewer: %s\n", msg.getString());
  std::exit(1);
}
}  // namespace

int main(int argc, char** argv) {
  // Mesa's software rasteriser (llvmpipe) bins each frame's triangles into 64 KB blocks (about
  // 17 MB a frame at 128^2) and frees them when the frame is done; glibc then hands the top of
  // the heap back to the system and the next frame faults the same pages in again: a third of
  // the viewer's time went to page faults (docs/benchmarks.md, "Viewer"). Those allocations are
  // Mesa's, not ours to keep (ours are: buffer objects, an allocation-free tessellation), so the
  // viewer keeps up to 256 MB of freed heap instead of trimming it. The library does not.
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
  // The command line is read before the QApplication exists: --help and a bad option need no
  // display (Qt's platform plugin aborts without one, with a message about xcb).
  QStringList arguments;
  for (int i = 0; i < argc; ++i) arguments << QString::fromLocal8Bit(argv[i]);
  QCoreApplication::setOrganizationName(QStringLiteral("bsdeform"));
  QCoreApplication::setApplicationName(QStringLiteral("bsdeform-viewer"));
  QCommandLineParser parser;
  parser.setApplicationDescription(QStringLiteral("Opens, animates and lets you pull B-spline finite-element surfaces."));
  parser.addHelpOption();
  parser.addPositionalArgument(QStringLiteral("scene"), QStringLiteral("an .iv scene (default: the built-in scene)"), QStringLiteral("[scene.iv]"));
  const QCommandLineOption measure(QStringLiteral("measure-fps"),
                                   QStringLiteral("play for SECONDS, print frames/s and steps/s, quit"), QStringLiteral("SECONDS"));
  const QCommandLineOption grid(QStringLiteral("grid"), QStringLiteral("with --measure-fps: set every surface to N x N control points"),
                                QStringLiteral("N"));
  const QCommandLineOption speed(QStringLiteral("speed"), QStringLiteral("simulated seconds per real second (default 1)"),
                                 QStringLiteral("X"));
  const QCommandLineOption autosave(QStringLiteral("autosave-interval"),
                                    QStringLiteral("seconds between autosaves of unsaved changes for crash recovery "
                                                   "(default 60, 0: off)"),
                                    QStringLiteral("SECONDS"));
  const QCommandLineOption restore(QStringLiteral("restore-recovery"),
                                   QStringLiteral("restore the newest autosave left by a viewer that did not quit cleanly"));
  const QCommandLineOption discard(QStringLiteral("discard-recovery"),
                                   QStringLiteral("delete the autosaves left by viewers that did not quit cleanly"));
  const QCommandLineOption states(QStringLiteral("states"),
                                  QStringLiteral("open the states a bsdeform-run --keep-states run of the scene wrote, "
                                                 "to scrub through (paused at the last)"),
                                  QStringLiteral("FILE"));
  parser.addOptions({measure, grid, speed, autosave, restore, discard, states});
  if (!parser.parse(arguments)) {
    std::fprintf(stderr, "bsdeform-viewer: %s (--help lists the options)\n", parser.errorText().toLocal8Bit().constData());
    return 2;
  }
  if (parser.isSet(QStringLiteral("help"))) {
    const QCoreApplication plain(argc, argv);  // the help names the program from its arguments; no display
    std::fputs(parser.helpText().toLocal8Bit().constData(), stdout);
    return 0;
  }
  // Without a display the window cannot open: say so, and what to use instead.
  const bool display = !qEnvironmentVariableIsEmpty("DISPLAY") || !qEnvironmentVariableIsEmpty("WAYLAND_DISPLAY") ||
                       !qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM");
  if (!display) {
    std::fprintf(stderr, "bsdeform-viewer: no display to open a window on (DISPLAY is not set). Run it under a desktop "
                         "or xvfb-run, or use bsdeform-run for headless runs, pictures and videos.\n");
    return 1;
  }
  QApplication app(argc, argv);
  Q_INIT_RESOURCE(viewer);  // the default scene lives in the static viewer library's resources
  bool ok = true;
  const double autosaveSeconds = parser.isSet(autosave) ? parser.value(autosave).toDouble(&ok) : 60.0;
  if (!ok || !(autosaveSeconds >= 0.0) || autosaveSeconds > 24 * 3600.0) {
    std::fprintf(stderr, "bsdeform-viewer: --autosave-interval '%s' is not a number of seconds in 0..86400\n",
                 parser.value(autosave).toUtf8().constData());
    return 2;
  }
  if (parser.isSet(restore) && parser.isSet(discard)) {
    std::fprintf(stderr, "bsdeform-viewer: give --restore-recovery or --discard-recovery, not both\n");
    return 2;
  }

  bsdeform::disableDynamicNodeLoading();  // an untrusted .iv must not make Coin load libraries
  SoQt::setFatalErrorHandler(fatal, nullptr);
  SoQt::init(argc, argv, "bsdeform-viewer");
  bsdeform::initNodes();

  bsdeform::MainWindow window;
  if (parser.isSet(measure)) window.setInteractive(false);
  const QStringList args = parser.positionalArguments();
  if (!args.isEmpty()) {
    if (!window.openScene(args.first())) window.openDefaultScene();
  } else {
    window.openDefaultScene();
  }
  if (parser.isSet(states)) window.openStates(parser.value(states));  // a refusal is reported, the scene stays
  window.autosave().setInterval(int(std::lround(autosaveSeconds * 1000.0)));
  // A viewer that died left its autosave: restore it, delete it, or ask (never in CI, where no
  // one answers: the file is kept and a line on stderr says how to choose).
  const QByteArray ci = qgetenv("CI");
  const bool unattended = !ci.isEmpty() && ci != "0" && ci.toLower() != "false";
  bsdeform::RecoveryChoice choice = bsdeform::RecoveryChoice::Ask;
  if (parser.isSet(restore))
    choice = bsdeform::RecoveryChoice::Restore;
  else if (parser.isSet(discard))
    choice = bsdeform::RecoveryChoice::Discard;
  else if (unattended)
    choice = bsdeform::RecoveryChoice::Keep;
  window.offerRecovery(choice);
  if (parser.isSet(speed)) window.setSpeed(parser.value(speed).toDouble());
  if (parser.isSet(measure)) {
    if (parser.isSet(grid))
      for (SoBSplineDeformSurface* s : window.document().surfaces()) {
        s->numUControlPoints = parser.value(grid).toInt();
        s->numVControlPoints = parser.value(grid).toInt();
      }
    window.show();
    window.setPlaying(true);
    const int ms = int(parser.value(measure).toDouble() * 1000);
    long frames0 = 0, steps0 = 0;
    QTimer::singleShot(1000, [&] {  // after a warm-up second
      frames0 = window.framesDrawn();
      steps0 = window.document().surfaces().isEmpty() ? 0 : window.document().surfaces()[0]->simulation().stepCount();
    });
    QTimer::singleShot(1000 + ms, [&] {
      const double s = ms / 1000.0;
      auto* surf = window.document().surfaces().isEmpty() ? nullptr : window.document().surfaces()[0];
      std::printf("frames/s %.1f  steps/s %.1f  (%s)\n", (window.framesDrawn() - frames0) / s,
                  surf ? (surf->simulation().stepCount() - steps0) / s : 0.0,
                  surf ? QStringLiteral("%1x%2 control points, %3 sub-steps")
                             .arg(surf->simulation().parameters().numU)
                             .arg(surf->simulation().parameters().numV)
                             .arg(surf->simulation().subSteps())
                             .toUtf8()
                             .constData()
                       : "no surface");
      QApplication::quit();
    });
    return app.exec();
  }
  window.show();
  return app.exec();
}
