// SPDX-License-Identifier: MIT
#pragma once
/// @file Recorder.h
/// The viewer's Record: pictures of the 3D view at a chosen rate in simulated time, into a
/// video (MP4 or WebM through VideoWriter) or a numbered PNG sequence. The frames fall due as
/// FrameClock says: at every multiple of 1/fps of simulated time since the recording began;
/// when the simulation passes several at once (a high speed) the current picture is repeated,
/// so that the video's clock is the simulation's. A reset (time going back) continues the video
/// from the new time.

#include <QCoreApplication>
#include <QImage>
#include <QSize>
#include <QString>
#include <functional>
#include <memory>

#include "FrameClock.h"

namespace bsdeform {

class VideoWriter;

class Recorder {
  Q_DECLARE_TR_FUNCTIONS(Recorder)

 public:
  Recorder();
  ~Recorder();  ///< an unfinished video is discarded (the previous file, if any, is kept)

  /// Starts recording into `path`: ".mp4" or ".webm" make a video of `size` (made even),
  /// ".png" a sequence path_00000.png, path_00001.png, ... (each written atomically).
  bool start(const QString& path, double fps, const QSize& size, double simulatedTime, QString& error);
  /// Adds the frames due by `simulatedTime`; `grab` gives the view's picture (called at most
  /// once). On an error the recording stops and `error` says why (the file and the reason).
  bool capture(double simulatedTime, const std::function<QImage()>& grab, QString& error);
  /// Finishes the file. Returns false with the reason when it could not be completed.
  bool stop(QString& error);

  bool active() const { return m_active; }
  long long frames() const { return m_frames; }
  const QString& path() const { return m_path; }

 private:
  bool addFrame(const QImage& picture, QString& error);
  bool m_active = false;
  QString m_path;
  bool m_pngSequence = false;
  FrameClock m_clock;
  QSize m_size;
  long long m_frames = 0;
  std::unique_ptr<VideoWriter> m_video;
};

}  // namespace bsdeform
