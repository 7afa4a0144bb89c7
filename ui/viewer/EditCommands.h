// SPDX-License-Identifier: MIT
#pragma once
/// @file EditCommands.h
/// The viewer's edits as QUndoCommands: a field change, a force field or a surface inserted,
/// a node deleted. Each command holds a reference to the nodes it touches, so an undo brings
/// back the very node that was removed (with its DEF name, state and connections).

#include <QString>
#include <QVector>
#include <QUndoCommand>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

class SoBase;
class SoField;
class SoFieldContainer;
class SoGroup;
class SoNode;
class SoBSplineDeformSurface;
class SoForceField;

namespace bsdeform {

class SceneDocument;
struct MaterialPreset;

/// Why `owner` (a surface or a force field) refuses its current field values: the node's
/// message, empty when it takes them. A surface rebuilds its model to find out (and keeps its
/// last valid one when refused); a force field builds its core force (COLLISION, which needs
/// the scene's obstacles, is taken as it is).
QString refusalOf(SoFieldContainer* owner);
/// A field a node refuses as its values stand, and the reason.
struct RefusedField {
  QString field;   ///< "" when no one field is at fault
  QString reason;
};
/// Every field of `owner` (a surface or a force field) refused as its values stand, each once:
/// a surface's FIELD refusals (SoBSplineDeformSurface::refusals()), a force field's fields that
/// make no force (SoForceField::refusedFields(); COLLISION is taken as it is). Empty when the
/// node takes its values.
QVector<RefusedField> refusedFieldsOf(SoFieldContainer* owner);

/// What the commands change and whom they tell.
struct EditContext {
  SceneDocument& doc;
  /// After a field of `owner` changed (from a command's redo or undo).
  std::function<void(SoFieldContainer* owner, SoField* field)> fieldChanged;
  /// After nodes were inserted or removed; the document is already rescanned. `focus`: the
  /// node to select (may no longer be in the scene).
  std::function<void(SoBase* focus)> structureChanged;
};

/// A field of a node or engine from one value to another.
class SetFieldCommand : public QUndoCommand {
 public:
  /// `field` (of `owner`) goes from `before` to `after`. `alreadySet`: the field holds `after`
  /// already (the editor applied and checked it), so the first redo() only reports it.
  SetFieldCommand(EditContext& context, SoFieldContainer* owner, SoField* field, const SoField& before, bool beforeIsDefault,
                  const SoField& after, bool alreadySet);
  ~SetFieldCommand() override;
  void undo() override;
  void redo() override;

 private:
  void set(const SoField& value, bool isDefault);
  EditContext& m_context;
  SoFieldContainer* m_owner;
  SoField* m_field;
  SoField* m_before;
  SoField* m_after;
  bool m_beforeIsDefault;
  bool m_skipRedo;
};

/// A new SoForceField of `type` appended to a surface's `forces`, with values that act at once
/// and look like the force (insertedForceDefaults()).
class InsertForceCommand : public QUndoCommand {
 public:
  InsertForceCommand(EditContext& context, SoBSplineDeformSurface* surface, int type);
  ~InsertForceCommand() override;
  void undo() override;
  void redo() override;
  SoForceField* force() const { return m_force; }

 private:
  EditContext& m_context;
  SoBSplineDeformSurface* m_surface;
  SoForceField* m_force;
};

/// Sets the fields of a force field of `type` that is inserted on `surface` to what a user
/// expects of that force (the node's own defaults are the file format's and stay):
/// GRAVITY (0, 0, -9.81) m/s² down, UNIFORM / POINT / REGION a unit load along +z at the centre,
/// EXPRESSION a bump sin(pi u) sin(pi v) along +z, SPRING at the surface's centre anchored where
/// that point is now (it holds it), PLANE_COLLISION a floor a tenth of the surface's size below
/// its lowest point, SPHERE_COLLISION a sphere of a quarter of its size just below its centre,
/// DRAG, PRESSURE and COLLISION the node's defaults (a unit coefficient, a unit pressure, no
/// obstacle yet). Positions are in the surface's own coordinates.
void insertedForceDefaults(SoForceField* force, int type, SoBSplineDeformSurface* surface);

/// A new surface (default fields, the plane (u, v, 0)) in its own Separator, moved along x
/// beside what the scene already shows; with a `preset`, a SHELL of that material
/// (applyMaterialPreset, MaterialPresets.h), its other fields the defaults.
class InsertSurfaceCommand : public QUndoCommand {
 public:
  InsertSurfaceCommand(EditContext& context, SoGroup* root, const MaterialPreset* preset = nullptr);
  ~InsertSurfaceCommand() override;
  void undo() override;
  void redo() override;
  SoBSplineDeformSurface* surface() const { return m_surface; }

 private:
  EditContext& m_context;
  SoGroup* m_root;
  SoNode* m_group;
  SoBSplineDeformSurface* m_surface;
};

/// Removes a surface from every group that holds it, or a force field from every surface that
/// lists it.
class DeleteCommand : public QUndoCommand {
 public:
  DeleteCommand(EditContext& context, SoBSplineDeformSurface* surface);
  DeleteCommand(EditContext& context, SoForceField* force);
  ~DeleteCommand() override;
  void undo() override;
  void redo() override;

 private:
  struct Place {
    SoBase* holder;  ///< an SoGroup holding a surface, or a surface listing a force
    int index;
  };
  EditContext& m_context;
  SoBase* m_target;
  bool m_isSurface;
  std::vector<Place> m_places;  ///< in increasing index order per holder
};

/// Simulation > Solve Static: every surface goes to the equilibrium of its loads at t = 0
/// (SoBSplineDeformSurface::solveStatic); undo puts back the states they had (nets, time,
/// steps), redo the equilibria.
class SolveStaticCommand : public QUndoCommand {
 public:
  /// Solves at once. If a surface cannot be solved, every surface is left as it was, error()
  /// says why and the command must not be pushed.
  SolveStaticCommand(EditContext& context, const std::vector<SoBSplineDeformSurface*>& surfaces);
  ~SolveStaticCommand() override;
  void undo() override;
  void redo() override;
  const QString& error() const { return m_error; }
  /// Per surface, "; "-separated: its method and residual.
  const QString& report() const { return m_report; }

 private:
  struct State {
    SoBSplineDeformSurface* node;
    std::unique_ptr<SoField> control, previous;
    double time;
    int steps;
  };
  static State capture(SoBSplineDeformSurface* node);
  void restore(const std::vector<State>& states);
  EditContext& m_context;
  std::vector<State> m_before, m_after;
  QString m_error, m_report;
  bool m_skipRedo = true;
};

}  // namespace bsdeform
