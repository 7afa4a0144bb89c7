// SPDX-License-Identifier: MIT
#include "RecordingControls.h"

#include <Inventor/Qt/viewers/SoQtViewer.h>

#include <QAction>
#include <QDir>
#include <QFileDialog>
#include <QFileInfo>
#include <QInputDialog>
#include <QSignalBlocker>
#include <QWidget>

#include "DocumentActions.h"
#include "Feedback.h"
#include "Recorder.h"
#include "SceneDocument.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/SoBSplineDeformSurface.h"

namespace bsdeform {

RecordingControls::RecordingControls(const SceneDocument& doc, SoQtViewer* viewer, std::function<QImage()> grab, Feedback& feedback,
                                     QWidget* dialogParent)
    : QObject(dialogParent),
      m_doc(doc),
      m_viewer(viewer),
      m_grab(std::move(grab)),
      m_feedback(feedback),
      m_dialogParent(dialogParent),
      m_recorder(std::make_unique<Recorder>()) {
  m_action = new QAction(tr("Record"), this);
  m_action->setCheckable(true);
  m_action->setToolTip(tr("Record the 3D view into a video (MP4, WebM) or PNG images, at a rate in simulated time"));
  connect(m_action, &QAction::toggled, this, &RecordingControls::toggled);
}

RecordingControls::~RecordingControls() = default;

bool RecordingControls::isRecording() const { return m_recorder->active(); }

void RecordingControls::setChecked(bool on) {
  const QSignalBlocker block(m_action);
  m_action->setChecked(on);
}

bool RecordingControls::start(const QString& path, double fps) {
  if (m_doc.surfaces().isEmpty()) {
    m_feedback.error(tr("Record"), tr("the scene has no surface: recording follows a surface's simulated time"));
    return false;
  }
  QString error;
  const double t = m_doc.surfaces().first()->simulation().time();
  if (!m_recorder->start(path, fps, m_viewer->getGLWidget()->size(), t, error)) {
    m_feedback.error(tr("Record"), error);
    return false;
  }
  setChecked(true);
  recordFrames();  // the first frame: the state when the recording starts
  return true;
}

bool RecordingControls::stop() {
  setChecked(false);
  if (!m_recorder->active()) return true;
  const long long frames = m_recorder->frames();
  QString error;
  if (!m_recorder->stop(error)) {
    m_feedback.error(tr("Record"), error);
    return false;
  }
  m_feedback.show(tr("Recorded %1 frames to %2").arg(frames).arg(m_recorder->path()), 8000);
  return true;
}

void RecordingControls::recordFrames() {
  if (!m_recorder->active() || m_doc.surfaces().isEmpty()) return;
  QString error;
  const double t = m_doc.surfaces().first()->simulation().time();
  if (!m_recorder->capture(t, m_grab, error)) {
    setChecked(false);
    m_feedback.error(tr("Record"), error);
    return;
  }
  m_feedback.show(tr("Recording %1: %2 frames, t = %3 s").arg(QFileInfo(m_recorder->path()).fileName())
                      .arg(m_recorder->frames()).arg(t, 0, 'f', 2));
}

void RecordingControls::toggled(bool on) {
  if (!on) {
    stop();
    return;
  }
  QString path = QFileDialog::getSaveFileName(m_dialogParent, tr("Record the 3D view"),
                                              QDir(DocumentActions::userFolder()).filePath(QStringLiteral("recording.mp4")),
                                              tr("Videos (*.mp4 *.webm);;PNG images, numbered (*.png)"));
  bool ok = !path.isEmpty();
  if (ok && QFileInfo(path).suffix().isEmpty()) path += QStringLiteral(".mp4");
  const double fps = ok ? QInputDialog::getDouble(m_dialogParent, tr("Record"), tr("Frames per simulated second:"), 25.0, 1.0,
                                                  240.0, 1, &ok)
                        : 0.0;
  if (!ok || !start(path, fps)) setChecked(false);
}

}  // namespace bsdeform
