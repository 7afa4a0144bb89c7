// SPDX-License-Identifier: MIT
#include "ExaminerViewer.h"

#include <Inventor/nodes/SoSwitch.h>

namespace bsdeform {

ExaminerViewer::ExaminerViewer(QWidget* parent) : SoQtExaminerViewer(parent) {}

ExaminerViewer::~ExaminerViewer() {
  for (SoSwitch* s : m_excluded) s->unref();
}

void ExaminerViewer::excludeFromViewAll(SoSwitch* node) {
  node->ref();
  m_excluded.push_back(node);
}

void ExaminerViewer::viewAll() {
  // off while SoQt measures the scene (notifying, so that no bounding box cache keeps it off)
  std::vector<int> shown;
  for (SoSwitch* s : m_excluded) {
    shown.push_back(s->whichChild.getValue());
    s->whichChild = SO_SWITCH_NONE;
  }
  SoQtExaminerViewer::viewAll();
  for (std::size_t k = 0; k < m_excluded.size(); ++k) m_excluded[k]->whichChild = shown[k];
}

}  // namespace bsdeform
