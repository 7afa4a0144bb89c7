// SPDX-License-Identifier: MIT
#include "ExportActions.h"

#include <Inventor/nodes/SoSeparator.h>

#include <QFileDialog>
#include <QFileInfo>
#include <QMainWindow>

#include "AtomicFile.h"
#include "DocumentActions.h"
#include "Feedback.h"
#include "SceneDocument.h"
#include "Screenshot.h"

namespace bsdeform {

ExportActions::ExportActions(SceneDocument& doc, SoQtExaminerViewer* viewer, std::function<SoBSplineDeformSurface*()> selected,
                             Feedback& feedback, QMainWindow& window)
    : QObject(&window), m_doc(doc), m_viewer(viewer), m_selected(std::move(selected)), m_feedback(feedback), m_window(window) {}

bool ExportActions::exportSurface(const QString& path, bool controlNet) {
  SoBSplineDeformSurface* s = m_selected();
  if (!s) {
    m_feedback.error(tr("Export failed"), tr("the scene has no surface"));
    return false;
  }
  QString error;
  if (!(controlNet ? m_doc.exportControlNet(s, path, error) : m_doc.exportMesh(s, path, error))) {
    m_feedback.error(tr("Export failed"), error);
    return false;
  }
  m_feedback.show(tr("Exported %1 to %2").arg(m_doc.nameOf(s), path), 5000);
  return true;
}

void ExportActions::exportDialog(bool controlNet) {
  const QStringList filters = controlNet ? QStringList{tr("Points, x y z per line (*.xyz)"), tr("Wavefront OBJ, points and net lines (*.obj)")}
                                         : QStringList{tr("Wavefront OBJ (*.obj)"), tr("STL (*.stl)")};
  QString filter;
  QString path = QFileDialog::getSaveFileName(&m_window, controlNet ? tr("Export the control net of the selected surface")
                                                                    : tr("Export mesh of the selected surface"),
                                              m_doc.path().isEmpty() ? DocumentActions::openFolder() : QFileInfo(m_doc.path()).absolutePath(),
                                              filters.join(QStringLiteral(";;")), &filter);
  if (path.isEmpty()) return;
  if (QFileInfo(path).suffix().isEmpty()) path += QLatin1Char('.') + filter.section(QStringLiteral("(*."), 1).chopped(1);
  exportSurface(path, controlNet);
}

QImage ExportActions::screenshot(const QSize& size) {
  QString error;
  const QImage img = Screenshot(m_viewer).view(m_doc.root(), size, error);
  if (!error.isEmpty()) m_feedback.error(tr("Screenshot failed"), error);
  return img;
}

QImage ExportActions::windowScreenshot() { return Screenshot(m_viewer).window(&m_window); }

bool ExportActions::saveScreenshot(const QString& path, const QSize& size) {
  const QImage img = screenshot(size);
  if (img.isNull()) return false;
  QString error;
  if (!savePngAtomically(path, img, error)) {
    m_feedback.error(tr("Screenshot failed"), error);
    return false;
  }
  m_feedback.show(tr("Saved %1 (%2 x %3)").arg(path).arg(img.width()).arg(img.height()), 5000);
  return true;
}

void ExportActions::screenshotDialog() {
  QString path, error;
  QSize size;
  if (Screenshot(m_viewer).ask(&m_window, path, size, error))
    saveScreenshot(path, size);
  else if (!error.isEmpty())
    m_feedback.error(tr("Screenshot"), error);
}

}  // namespace bsdeform
