// SPDX-License-Identifier: MIT
#pragma once
/// @file EditActions.h
/// The Edit and Insert menus' changes to the scene, each an undoable command (EditCommands.h):
/// a force field into the selected surface, a surface beside the scene, the selected surface
/// or force field deleted.

#include <QCoreApplication>
#include <functional>

class QUndoStack;
class SoBSplineDeformSurface;

namespace bsdeform {

class Feedback;
struct MaterialPreset;
class ScenePanel;
struct EditContext;

class EditActions {
  Q_DECLARE_TR_FUNCTIONS(EditActions)

 public:
  /// `panel`: the selection; `selectedSurface`: the surface a force field goes to when no
  /// surface is selected in the panel (nullptr: the scene has none).
  EditActions(EditContext& edit, QUndoStack& undo, const ScenePanel& panel,
              std::function<SoBSplineDeformSurface*()> selectedSurface, Feedback& feedback);

  /// Adds a force field of `type` (SoForceField::Type) to the selected surface. False (and a
  /// reported error) when the scene has no surface.
  bool insertForceField(int type);
  /// Adds a surface (default fields) beside the scene.
  void insertSurface();
  /// Adds a SHELL surface of `preset`'s material (MaterialPresets.h), its other fields the
  /// defaults, beside the scene.
  void insertSurface(const MaterialPreset& preset);
  /// Deletes the selected surface or force field. False when nothing is selected.
  bool deleteSelected();

 private:
  EditContext& m_edit;
  QUndoStack& m_undo;
  const ScenePanel& m_panel;
  std::function<SoBSplineDeformSurface*()> m_selectedSurface;
  Feedback& m_feedback;
};

}  // namespace bsdeform
