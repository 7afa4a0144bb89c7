// SPDX-License-Identifier: MIT
#include "EditActions.h"

#include <Inventor/nodes/SoSeparator.h>

#include <QUndoStack>

#include "EditCommands.h"
#include "Feedback.h"
#include "SceneDocument.h"
#include "ScenePanel.h"
#include "bsdeform/SoBSplineDeformSurface.h"
#include "bsdeform/SoForceField.h"

namespace bsdeform {

EditActions::EditActions(EditContext& edit, QUndoStack& undo, const ScenePanel& panel,
                         std::function<SoBSplineDeformSurface*()> selectedSurface, Feedback& feedback)
    : m_edit(edit), m_undo(undo), m_panel(panel), m_selectedSurface(std::move(selectedSurface)), m_feedback(feedback) {}

bool EditActions::insertForceField(int type) {
  SoBase* sel = m_panel.selectedNode();
  SoBSplineDeformSurface* surface = nullptr;
  if (sel && sel->isOfType(SoBSplineDeformSurface::getClassTypeId()))
    surface = static_cast<SoBSplineDeformSurface*>(sel);
  else
    surface = m_selectedSurface();
  if (!surface) {
    m_feedback.error(tr("Insert force field"), tr("the scene has no surface to add a force field to"));
    return false;
  }
  m_undo.push(new InsertForceCommand(m_edit, surface, type));
  return true;
}

void EditActions::insertSurface() {
  if (!m_edit.doc.root()) return;
  m_undo.push(new InsertSurfaceCommand(m_edit, m_edit.doc.root()));
}

void EditActions::insertSurface(const MaterialPreset& preset) {
  if (!m_edit.doc.root()) return;
  m_undo.push(new InsertSurfaceCommand(m_edit, m_edit.doc.root(), &preset));
}

bool EditActions::deleteSelected() {
  SoBase* sel = m_panel.selectedNode();
  if (!sel) return false;
  if (sel->isOfType(SoBSplineDeformSurface::getClassTypeId()))
    m_undo.push(new DeleteCommand(m_edit, static_cast<SoBSplineDeformSurface*>(sel)));
  else
    m_undo.push(new DeleteCommand(m_edit, static_cast<SoForceField*>(sel)));
  return true;
}

}  // namespace bsdeform
