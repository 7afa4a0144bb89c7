// SPDX-License-Identifier: MIT
#pragma once
/// @file ExaminerViewer.h
/// SoQt's examiner viewer with what the window's view decorations need from it: its
/// superimpositions (protected in SoQt 1.6) for the axes gizmo, and a View All of its own
/// (SoQt's decoration button and pop-up menu) that leaves the viewer's decorations out: the
/// switches given to excludeFromViewAll() are off while SoQt frames the scene.

#include <Inventor/Qt/viewers/SoQtExaminerViewer.h>
#include <vector>

class SoSwitch;

namespace bsdeform {

class ExaminerViewer : public SoQtExaminerViewer {
 public:
  explicit ExaminerViewer(QWidget* parent);
  ~ExaminerViewer() override;

  using SoQtViewer::addSuperimposition;
  using SoQtViewer::getSuperimpositionEnabled;
  using SoQtViewer::removeSuperimposition;
  using SoQtViewer::setSuperimpositionEnabled;

  /// `node` (referenced until the viewer goes) takes no part in viewAll().
  void excludeFromViewAll(SoSwitch* node);
  void viewAll() override;

 private:
  std::vector<SoSwitch*> m_excluded;
};

}  // namespace bsdeform
