// SPDX-License-Identifier: MIT
#include "ScenePanel.h"

#include "SceneDocument.h"
#include "bsdeform/SoBSplineDeformSurface.h"
#include "bsdeform/SoForceField.h"

namespace bsdeform {

// Each node's item carries its place in the document: surface i as i, force field i as -1 - i.

ScenePanel::ScenePanel(const SceneDocument& doc, QWidget* parent) : QTreeWidget(parent), m_doc(doc) {
  setHeaderHidden(true);
  connect(this, &QTreeWidget::itemSelectionChanged, this, &ScenePanel::emitSelection);
}

void ScenePanel::populate() {
  clear();
  auto* surfaces = new QTreeWidgetItem(this, {tr("Surfaces")});
  for (int i = 0; i < m_doc.surfaces().size(); ++i) {
    auto* item = new QTreeWidgetItem(surfaces, {m_doc.nameOf(m_doc.surfaces()[i])});
    item->setData(0, Qt::UserRole, i);
  }
  auto* forces = new QTreeWidgetItem(this, {tr("Force fields")});
  for (int i = 0; i < m_doc.forceFields().size(); ++i) {
    SoForceField* f = m_doc.forceFields()[i];
    SbName type;
    f->type.getEnum(f->type.getValue(), type);
    auto* item = new QTreeWidgetItem(forces, {QStringLiteral("%1 (%2)").arg(m_doc.nameOf(f), QString::fromLatin1(type.getString()))});
    item->setData(0, Qt::UserRole, -1 - i);
  }
  expandAll();
  if (!m_doc.surfaces().isEmpty()) selectSurface(0);
}

SoBase* ScenePanel::nodeOf(const QTreeWidgetItem* item) const {
  if (!item || !item->data(0, Qt::UserRole).isValid()) return nullptr;
  const int code = item->data(0, Qt::UserRole).toInt();
  if (code >= 0) return code < m_doc.surfaces().size() ? m_doc.surfaces()[code] : nullptr;
  return -1 - code < m_doc.forceFields().size() ? m_doc.forceFields()[-1 - code] : nullptr;
}

SoBase* ScenePanel::selectedNode() const {
  const QList<QTreeWidgetItem*> sel = selectedItems();
  return sel.isEmpty() ? nullptr : nodeOf(sel.first());
}

bool ScenePanel::selectNode(SoBase* node) {
  for (int top = 0; top < topLevelItemCount(); ++top) {
    QTreeWidgetItem* group = topLevelItem(top);
    for (int i = 0; i < group->childCount(); ++i)
      if (nodeOf(group->child(i)) == node) {
        setCurrentItem(group->child(i));
        return true;
      }
  }
  return false;
}

void ScenePanel::selectSurface(int index) {
  QTreeWidgetItem* surfaces = topLevelItem(0);
  if (surfaces && index >= 0 && index < surfaces->childCount()) setCurrentItem(surfaces->child(index));
}

void ScenePanel::emitSelection() {
  const QList<QTreeWidgetItem*> sel = selectedItems();
  if (sel.isEmpty() || !sel.first()->data(0, Qt::UserRole).isValid()) return;
  const int code = sel.first()->data(0, Qt::UserRole).toInt();
  if (code >= 0)
    emit surfaceSelected(code);
  else
    emit forceFieldSelected(-1 - code);
}

}  // namespace bsdeform
