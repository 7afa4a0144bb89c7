// SPDX-License-Identifier: MIT
#pragma once
/// @file RunOptions.h
/// bsdeform-run's command line: the options, their help text and the checks of their values.

#include <QString>
#include <QStringList>
#include <QVector>

#include "Metrics.h"
#include "RunFailure.h"

namespace bsdeform::run {

/// --probe NAME=u,v: the surface point S(u, v) and its displacement from rest, six CSV columns
/// NAME_x NAME_y NAME_z NAME_dx NAME_dy NAME_dz in every history row (bsdeform/dynamics/Probe.h).
struct ProbeOption {
  QString name;  ///< a C identifier
  double u = 0.0, v = 0.0;  ///< in [0, 1]
  /// Reads `NAME=u,v`; false with `why` naming the option and the value.
  static bool parse(const QString& text, ProbeOption& probe, QString& why);
};

struct RunOptions {
  QString scene;
  long steps = 100;
  double until = -1.0;     ///< --until T (< 0: run --steps)
  QString outDir;          ///< default: <scene name>.out
  bool overwrite = false;
  int pngEvery = 0;
  QVector<double> pngAt;
  bool frameNamesTime = false;  ///< --frame-names time: frame_t<time>.png instead of frame_<frame>.png
  int width = 640, height = 480;
  QStringList sets;        ///< --set NAME.field=value, in order
  QString sweep;           ///< --sweep NAME.field=v1,v2,...
  QVector<Metric> metrics;  ///< --metric (repeatable): sweep.csv's columns beside the norm (Metrics.h)
  bool plot = false;
  long recordEvery = 1;
  QString keepStates;      ///< --keep-states FILE: the states for bsdeform-viewer --states (StateFile.h)
  QString video;           ///< --video FILE (.mp4, .webm)
  double videoFps = 25.0;  ///< --video-fps: frames per simulated second
  QString exportMesh;      ///< --export-mesh FILE (.obj, .stl): the surfaces' triangles at the end
  bool quiet = false;
  bool staticSolve = false;  ///< --static: solve for the equilibrium at t = 0 instead of stepping
  int loadSteps = 1;         ///< --load-steps K: the static load in K increments, a CSV row each
  /// --arc-length: with --static (SHELL), the equilibrium path by arc-length continuation, through
  /// limit points and snap-backs: --load-steps K points at most (default 50), until the load
  /// factor passes --max-load F (default 1)
  bool arcLength = false;
  double maxLoad = 1.0;      ///< --max-load F
  QVector<ProbeOption> probes;  ///< --probe NAME=u,v (repeatable), in order
  bool resultOnly = false;  ///< internal: a sweep child prints RESULT lines and writes nothing
  bool resultLines = false;  ///< internal (bsdeform.sweep): print RESULT lines after writing the outputs
  QString sweepProgram;     ///< internal: the program started per sweep value (default: this one)
  /// internal (bsdeform.sweep): a sweep.csv whose rows sweep.csv and sweep.png are written from,
  /// instead of running the values
  QString sweepRows;
  /// The arguments a sweep child gets: the scene and the run options, without the output and
  /// sweep ones.
  QStringList sweepChildArguments;

  /// Reads the command line (`arguments[0]` is the program). --help, and a line Qt's parser
  /// cannot read (an unknown option, a missing value), print and exit as
  /// QCommandLineParser::process does; a bad value is a kBadInput Failure naming the option and
  /// the value.
  static Failure parse(const QStringList& arguments, RunOptions& options);
};

}  // namespace bsdeform::run
