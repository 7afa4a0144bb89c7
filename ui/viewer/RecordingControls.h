// SPDX-License-Identifier: MIT
#pragma once
/// @file RecordingControls.h
/// Simulation > Record: asks for the file and the rate, records the 3D view through Recorder
/// while the simulation runs (one call of recordFrames() after the surfaces moved), and
/// finishes the file when pressed again or when the scene goes.

#include <QImage>
#include <QObject>
#include <functional>
#include <memory>

class QAction;
class QWidget;
class SoQtViewer;

namespace bsdeform {

class Feedback;
class Recorder;
class SceneDocument;

class RecordingControls : public QObject {
  Q_OBJECT
 public:
  /// `viewer`: the 3D view (its size is the video's); `grab`: its picture; `dialogParent`: the
  /// window the dialogs belong to.
  RecordingControls(const SceneDocument& doc, SoQtViewer* viewer, std::function<QImage()> grab, Feedback& feedback,
                    QWidget* dialogParent);
  ~RecordingControls() override;

  /// Record: checked while recording.
  QAction* action() const { return m_action; }

  /// Records the 3D view at `fps` frames per simulated second into `path` (.mp4, .webm, or
  /// .png for a numbered sequence) until stop(); see Recorder.h.
  bool start(const QString& path, double fps);
  /// Finishes the recording; false (and a reported error) when the file could not be completed.
  bool stop();
  bool isRecording() const;
  /// Adds the frames that fell due since the last call (the simulated time moved).
  void recordFrames();
  /// The action pressed: asks for the file and the rate, or stops the recording.
  void toggled(bool on);

 private:
  /// The action's check without triggering it again.
  void setChecked(bool on);

  const SceneDocument& m_doc;
  SoQtViewer* m_viewer;
  std::function<QImage()> m_grab;
  Feedback& m_feedback;
  QWidget* m_dialogParent;
  std::unique_ptr<Recorder> m_recorder;
  QAction* m_action;
};

}  // namespace bsdeform
