// SPDX-License-Identifier: MIT
// bsdeform-run: step an .iv scene without a window and write results, plots and images.
// See `bsdeform-run --help` and README.md. Exit codes: 0 success, 2 bad input (usage, files,
// names, values, output paths), 3 a simulation blew up (outputs up to that point are written),
// 4 an output file could not be written (disk full, I/O error; the previous file is kept),
// 1 an internal error (including a sweep run that could not be started).
//
// The driver: RunOptions reads the command line, RunLoop does one run, SweepPool a --sweep.
#include <QApplication>
#include <QDir>
#include <QFile>
#include <QTemporaryDir>
#include <cstdio>
#include <exception>
#include <memory>

#include "RunLoop.h"
#include "RunOptions.h"
#include "SweepPool.h"
#include "bsdeform/CoinMessageCapture.h"
#include "bsdeform/NodesInit.h"

int main(int argc, char** argv) {
  using namespace bsdeform::run;
  // No windows are ever shown: plots render on Qt's offscreen platform, images through EGL.
  if (qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM")) qputenv("QT_QPA_PLATFORM", "offscreen");
  // Qt wants a private runtime directory and warns on every run without one (a container, a
  // batch job): give it one of its own for the run, removed at the end.
  std::unique_ptr<QTemporaryDir> runtimeDir;
  if (qEnvironmentVariableIsEmpty("XDG_RUNTIME_DIR")) {
    runtimeDir = std::make_unique<QTemporaryDir>(QDir::tempPath() + QStringLiteral("/bsdeform-run-XXXXXX"));
    if (runtimeDir->isValid()) qputenv("XDG_RUNTIME_DIR", QFile::encodeName(runtimeDir->path()));
  }
  QApplication app(argc, argv);
  QApplication::setApplicationName(QStringLiteral("bsdeform-run"));
  auto fail = [](const Failure& f) {
    if (!f.message.isEmpty()) std::fprintf(stderr, "bsdeform-run: %s\n", f.message.toUtf8().constData());
    return int(f.code);
  };
  RunOptions options;
  const Failure parsed = RunOptions::parse(QApplication::arguments(), options);
  if (!parsed.ok()) return fail(parsed);

  bsdeform::disableDynamicNodeLoading();
  bsdeform::initNodes();
  // Coin's messages are never printed: the ones that matter become a Failure (RunLoop).
  const bsdeform::CoinMessageCapture coinMessages;
  try {
    if (!options.sweep.isEmpty()) return fail(SweepPool(options).run());
    return fail(RunLoop(options).run());
  } catch (const std::exception& e) {
    return fail({kInternal, QStringLiteral("internal error: %1").arg(QString::fromUtf8(e.what()))});
  }
}
