// SPDX-License-Identifier: MIT
#pragma once
/// @file SceneProblems.h
/// What the nodes of an opened scene refuse, listed for the user: every surface's problem
/// (SoBSplineDeformSurface::problem()) and every force field whose values make no force, each
/// with the node, the field, the value as the file has it and the reason. The viewer shows the
/// list in one box when a scene opens, so that a refused value is not only a word in the status
/// bar while the model runs on other values.

#include <QString>
#include <QStringList>
#include <QVector>

namespace bsdeform {

class SceneDocument;

struct SceneProblem {
  QString node;    ///< the node's name in the scene panel (SceneDocument::nameOf)
  QString field;   ///< the refused field ("" when no one field is)
  QString value;   ///< the field's value as it would be written (the file's)
  QString reason;  ///< the node's sentence
  /// One line: "Cloth: uDegree = 9: <reason>".
  QString text() const;
};

/// Every problem of the document's surfaces and force fields, surfaces first, in scene order
/// (building each surface's model now): each refused value of each node (not only the first),
/// then a surface's other problems (an obstacle, a seam).
QVector<SceneProblem> sceneProblems(const SceneDocument& doc);

/// Whether any node refuses a value (a surface's field or a force field's): the surfaces'
/// records and each force field's values tried once (not field by field). Nothing plays then.
bool sceneRefused(const SceneDocument& doc);

/// The nodes sceneProblems() names, each once, in its order.
QStringList refusedNodes(const SceneDocument& doc);

}  // namespace bsdeform
