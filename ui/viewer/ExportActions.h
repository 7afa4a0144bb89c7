// SPDX-License-Identifier: MIT
#pragma once
/// @file ExportActions.h
/// File > Export Mesh, Export Control Net and Save Screenshot: the selected surface as a mesh
/// (.obj, .stl) or its control net (.xyz, .obj) through SceneDocument, and pictures of the 3D
/// view or the whole window through Screenshot; each with its dialog.

#include <QImage>
#include <QObject>
#include <QSize>
#include <functional>

class QMainWindow;
class SoBSplineDeformSurface;
class SoQtExaminerViewer;

namespace bsdeform {

class Feedback;
class SceneDocument;

class ExportActions : public QObject {
  Q_OBJECT
 public:
  /// `selected`: the surface the exports are of (nullptr: the scene has none).
  ExportActions(SceneDocument& doc, SoQtExaminerViewer* viewer, std::function<SoBSplineDeformSurface*()> selected,
                Feedback& feedback, QMainWindow& window);

  bool exportMesh(const QString& path) { return exportSurface(path, false); }
  bool exportControlNet(const QString& path) { return exportSurface(path, true); }
  void exportMeshDialog() { exportDialog(false); }
  void exportControlNetDialog() { exportDialog(true); }

  /// The 3D view at `size` (invalid: the view's size, from the frame buffer; otherwise
  /// rendered offscreen with the same camera). A null image and a reported error on failure.
  QImage screenshot(const QSize& size = QSize());
  bool saveScreenshot(const QString& path, const QSize& size = QSize());
  /// The whole window including the 3D view.
  QImage windowScreenshot();
  void screenshotDialog();

 private:
  bool exportSurface(const QString& path, bool controlNet);
  void exportDialog(bool controlNet);

  SceneDocument& m_doc;
  SoQtExaminerViewer* m_viewer;
  std::function<SoBSplineDeformSurface*()> m_selected;
  Feedback& m_feedback;
  QMainWindow& m_window;
};

}  // namespace bsdeform
