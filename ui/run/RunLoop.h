// SPDX-License-Identifier: MIT
#pragma once
/// @file RunLoop.h
/// One run of a scene (bsdeform-run without --sweep, or one sweep child): steps every surface in
/// simulated time, records the history (--record-every), writes images (--png-every,
/// --png-at) and the video (--video) as their frames fall due, then the CSV files, plots and
/// final.iv, and prints the summary (or a sweep child's RESULT lines).

#include <QDir>
#include <QStringList>
#include <QVector>
#include <memory>

#include "FrameClock.h"
#include "History.h"
#include "KeptStates.h"
#include "Metrics.h"
#include "Plot.h"
#include "RunFailure.h"
#include "RunOptions.h"
#include "RunSetup.h"
#include "bsdeform/NodeRef.h"
#include "bsdeform/dynamics/DiagnosticsBeside.h"
#include "bsdeform/OffscreenRenderer.h"
#include "bsdeform/SceneRunner.h"
#include "bsdeform/dynamics/Simulation.h"

class SoSeparator;
class SoBSplineDeformSurface;

namespace bsdeform {
class VideoWriter;
}  // namespace bsdeform

namespace bsdeform::run {

class RunLoop {
 public:
  explicit RunLoop(const RunOptions& options);
  ~RunLoop();
  /// The whole run; exit code kBlowUp when a simulation blew up (its outputs up to then are
  /// written), kBadInput for a scene that cannot run or a step that was refused.
  Failure run();

 private:
  struct Surface {
    QString name;  ///< DEF name, or "surfaceN": the output files are named after it
    SoBSplineDeformSurface* node = nullptr;
    QString csv;   ///< the history CSV (History::detailedCsvHeader and rows)
    History history;
    long lastRecorded = -1;  ///< step count of the last history row
    int callback = -1;       ///< the surface's step callback (records the rows)
    std::shared_ptr<MetricTracker> metrics;  ///< --metric: measured after every step (null without)
    PlotSeries path;  ///< --static with --probe: the first probe's displacement (x) and load factor (y)
    /// Computes the rows beside the steps (shared: Surface lives in a QVector). Its destructor
    /// finishes the row being computed, whose values `pending` keeps.
    std::shared_ptr<DiagnosticsBeside> beside = std::make_shared<DiagnosticsBeside>();
    /// The last row begun: its values are computed beside the next step (DiagnosticsBeside)
    /// and written by flushRow().
    struct PendingRow {
      double time = 0.0;
      long steps = 0;
      int subSteps = 0;
      PendingDiagnostics values;
      QString probes;  ///< the --probe cells of the state, each after a comma (taken at once: cheap)
    } pending;
  };

  Failure prepare();
  /// --static: every surface solved for its equilibrium (SoBSplineDeformSurface::solveStatic),
  /// one history row, one image on request, final.iv.
  Failure runStatic();
  Failure checkOutputNames() const;
  /// Begins the history row of the current state (after writing the one before).
  void record(Surface& s);
  /// Writes the row begun last, if it is not written yet.
  void flushRow(Surface& s);
  /// A surface took a step: its history row, when one is due.
  void stepped(Surface& s);
  /// Images and video of a scene without a camera: one camera for the whole output (m_view).
  Failure frameMotion();
  Failure render(long frame);
  Failure writeImage(long frame);
  Failure writeVideoFrames(long frame);
  Failure writeOutputs();
  void printSummary(double seconds) const;
  void printCosts(const bsdeform::Simulation& sim) const;
  void printResults() const;
  Failure outcome() const;
  QStringList m_staticLines;  ///< --static: what each surface's solve reports

  const RunOptions& m_options;
  NodeRef<SoSeparator> m_root;
  /// What images show: m_root under the one camera frameMotion() made, or null (m_root itself,
  /// with its own camera).
  NodeRef<SoSeparator> m_view;
  QVector<Surface> m_surfaces;
  std::unique_ptr<SceneRunner> m_runner;  ///< drives the surfaces and realTime
  double m_dtMin = 0.0, m_t0 = 0.0;
  double m_framingSeconds = 0.0;  ///< wall time of frameMotion()'s pass (0: none was needed)
  long m_frames = 0;
  bool m_blewUp = false;
  QDir m_out;
  QStringList m_written;
  ProgressBar m_progress;
  // One renderer (GL context, Coin's shaders and caches) and one image buffer for every frame.
  OffscreenRenderer m_renderer;
  Image m_image;
  long m_renderedFrame = -1;  ///< the frame m_image holds
  long m_imagesWritten = 0;
  QVector<long> m_imageFrames;  ///< --png-at as frames
  std::unique_ptr<VideoWriter> m_video;
  std::unique_ptr<KeptStates> m_kept;  ///< --keep-states
  FrameClock m_videoClock;
};

}  // namespace bsdeform::run
