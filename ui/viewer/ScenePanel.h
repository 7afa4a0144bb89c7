// SPDX-License-Identifier: MIT
#pragma once
/// @file ScenePanel.h
/// The viewer's scene panel: the document's surfaces and force fields as a tree (force fields
/// with their type), and the selection in it.

#include <QTreeWidget>

class SoBase;

namespace bsdeform {

class SceneDocument;

class ScenePanel : public QTreeWidget {
  Q_OBJECT
 public:
  explicit ScenePanel(const SceneDocument& doc, QWidget* parent = nullptr);

  /// Lists the document's surfaces and force fields again and selects the first surface, if any.
  void populate();
  /// The selected surface or force field (nullptr: none).
  SoBase* selectedNode() const;
  /// Selects a surface or force field (false if it is not listed).
  bool selectNode(SoBase* node);
  /// Selects the document's surface `index` (nothing when out of range).
  void selectSurface(int index);

 signals:
  /// The selection moved to the document's surface `index` or force field `index`.
  void surfaceSelected(int index);
  void forceFieldSelected(int index);

 private:
  /// The node an item stands for (nullptr for the group items).
  SoBase* nodeOf(const QTreeWidgetItem* item) const;
  void emitSelection();
  const SceneDocument& m_doc;
};

}  // namespace bsdeform
