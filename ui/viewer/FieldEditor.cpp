// SPDX-License-Identifier: MIT
#include "FieldEditor.h"

#include <Inventor/SbString.h>
#include <Inventor/fields/SoFieldContainer.h>
#include <Inventor/fields/SoMFEngine.h>
#include <Inventor/fields/SoMFNode.h>
#include <Inventor/fields/SoMFVec3d.h>
#include <Inventor/fields/SoSFBool.h>
#include <Inventor/fields/SoSFDouble.h>
#include <Inventor/fields/SoSFBitMask.h>
#include <Inventor/fields/SoSFEnum.h>
#include <Inventor/fields/SoSFFloat.h>
#include <Inventor/fields/SoSFInt32.h>
#include <Inventor/fields/SoSFTrigger.h>
#include <Inventor/fields/SoSFVec2d.h>
#include <Inventor/fields/SoSFVec3d.h>
#include <Inventor/lists/SoFieldList.h>

#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QKeyEvent>
#include <QLabel>
#include <QLineEdit>
#include <QPointer>
#include <QPushButton>
#include <QRegularExpression>
#include <QStringList>
#include <QTimer>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>
#include <memory>

#include "FieldWidgets.h"
#include "bsdeform/FieldInfo.h"
#include "bsdeform/SoBSplineDeformSurface.h"
#include "bsdeform/SoForceField.h"

namespace bsdeform {

namespace {
const char* const kInvalidStyle = "background-color: #ffd0d0;";

QString tooltipOf(const FieldInfo* info, const QString& name) {
  if (!info) return name;
  QString t = QStringLiteral("<b>%1</b>").arg(name);
  if (*info->symbol) t += QStringLiteral(" &nbsp;(paper: %1)").arg(QString::fromUtf8(info->symbol).toHtmlEscaped());
  t += QStringLiteral("<br>") + QString::fromUtf8(info->meaning).toHtmlEscaped();
  if (*info->unit) t += QStringLiteral("<br>Unit: ") + QString::fromUtf8(info->unit).toHtmlEscaped();
  if (*info->range) t += QStringLiteral("<br>Range: ") + QString::fromUtf8(info->range).toHtmlEscaped();
  if (info->restarts) t += QStringLiteral("<br><i>Changing it restarts the simulation from rest.</i>");
  if (info->live) t += QStringLiteral("<br><i>Kept current by the simulation.</i>");
  return t;
}

SoField* copyOf(const SoField& f) {
  auto* copy = static_cast<SoField*>(f.getTypeId().createInstance());
  copy->copyFrom(f);
  return copy;
}

QString coinText(SoField* f) {
  SbString s;
  f->get(s);
  return QString::fromUtf8(s.getString());
}

// A list of nodes (COLLISION's obstacles) as a person names them: "Box, Ball"; a node without a
// DEF name as its type in angle brackets, "<Cube>" (kept at its place when the text is edited).
QString nodeListText(const SoMFNode& f) {
  QStringList names;
  for (int i = 0; i < f.getNum(); ++i) {
    SoNode* n = f[i];
    if (!n)
      names << QStringLiteral("NULL");
    else if (n->getName().getLength())
      names << QString::fromUtf8(n->getName().getString());
    else
      names << QStringLiteral("<%1>").arg(QString::fromLatin1(n->getTypeId().getName().getString()));
  }
  return names.join(QStringLiteral(", "));
}

// Sets the list from names separated by commas or spaces: each a DEF name (the node last given
// it), NULL, or the "<Type>" of the unnamed node already at that place. False (the field left
// alone) when a name names nothing.
bool setNodeList(SoMFNode& f, const QString& text) {
  const QStringList words = text.split(QRegularExpression(QStringLiteral("[,\\s]+")), Qt::SkipEmptyParts);
  std::vector<SoNode*> nodes;
  for (int i = 0; i < words.size(); ++i) {
    const QString& w = words[i];
    if (w == QLatin1String("NULL")) {
      nodes.push_back(nullptr);
    } else if (w.startsWith(QLatin1Char('<')) && w.endsWith(QLatin1Char('>'))) {
      SoNode* here = i < f.getNum() ? f[i] : nullptr;
      if (!here || here->getName().getLength() ||
          QString::fromLatin1(here->getTypeId().getName().getString()) != w.mid(1, w.size() - 2))
        return false;
      nodes.push_back(here);
    } else {
      SoNode* n = SoNode::getByName(SbName(w.toUtf8().constData()));
      if (!n) return false;
      nodes.push_back(n);
    }
  }
  f.setNum(int(nodes.size()));
  for (int i = 0; i < int(nodes.size()); ++i) f.set1Value(i, nodes[size_t(i)]);
  return true;
}
}  // namespace

FieldEditor::FieldEditor(QWidget* parent) : QWidget(parent) {
  m_form = new QFormLayout(this);
  m_form->setFieldGrowthPolicy(QFormLayout::AllNonFixedFieldsGrow);
}

void FieldEditor::clear() {
  // deleteLater: a row's widget may be the sender of the signal that led here (a type change)
  while (m_form->rowCount() > 0) {
    const QFormLayout::TakeRowResult r = m_form->takeRow(0);
    for (QLayoutItem* item : {r.labelItem, r.fieldItem}) {
      if (!item) continue;
      if (QWidget* w = item->widget()) {
        w->hide();
        w->deleteLater();
      }
      delete item;
    }
  }
  m_rows.clear();
}

FieldEditor::Row* FieldEditor::rowOf(QObject* widget) {
  for (const auto& r : m_rows)
    if (widget == r->editor || (widget->isWidgetType() && r->editor->isAncestorOf(static_cast<QWidget*>(widget)))) return r.get();
  return nullptr;
}

void FieldEditor::addRow(Row row, const QString& label, const QString& tooltip) {
  auto* cell = new QWidget;
  auto* box = new QVBoxLayout(cell);
  box->setContentsMargins(0, 0, 0, 0);
  box->setSpacing(1);
  box->addWidget(row.editor);
  row.message = new QLabel;
  row.message->setWordWrap(true);
  row.message->hide();
  box->addWidget(row.message);
  row.editor->setToolTip(tooltip);
  auto* name = new QLabel(label);
  name->setToolTip(tooltip);
  name->setBuddy(row.editor);
  m_form->addRow(name, cell);
  // the filter: Return and focus changes of every input of the row
  const QList<QWidget*> inputs = row.editor->findChildren<QWidget*>() << row.editor;
  for (QWidget* w : inputs) w->installEventFilter(this);
  m_rows.push_back(std::make_unique<Row>(std::move(row)));
}

void FieldEditor::setContainer(SoFieldContainer* container, const QString& title) {
  clear();
  m_container = container;
  if (!container) return;
  const char* node = container->getTypeId().getName().getString();
  auto* heading = new QLabel(QStringLiteral("<b>%1</b> (%2)").arg(title.toHtmlEscaped(), QString::fromLatin1(node)));
  heading->setWordWrap(true);
  m_form->addRow(heading);
  const int forceType = container->isOfType(SoForceField::getClassTypeId()) ? static_cast<SoForceField*>(container)->type.getValue() : -1;
  const int energyModel = container->isOfType(SoBSplineDeformSurface::getClassTypeId())
                              ? static_cast<SoBSplineDeformSurface*>(container)->energy.getValue()
                              : -1;
  SoFieldList fields;
  container->getFields(fields);
  for (int i = 0; i < fields.getLength(); ++i) {
    SoField* f = fields[i];
    SbName fieldName;
    container->getFieldName(f, fieldName);
    const QString name = QString::fromLatin1(fieldName.getString());
    if (forceType >= 0 && !forceFieldUses(forceType, fieldName.getString())) continue;  // not read by this type
    if (energyModel >= 0 && !surfaceFieldUses(energyModel, fieldName.getString())) continue;  // not read by this energy
    const FieldInfo* info = findFieldInfo(node, fieldName.getString());
    const QString label = info && *info->symbol ? QStringLiteral("%1  %2").arg(name, QString::fromUtf8(info->symbol)) : name;
    const double lo = info ? info->min : -HUGE_VAL, hi = info ? info->max : HUGE_VAL;
    const QString rangeText = info ? QString::fromUtf8(info->range) : QString();
    Row row;
    row.field = f;
    row.name = name;
    row.restarts = info && info->restarts;
    const SoType t = f->getTypeId();
    auto number = [&](NumberSpinBox::Kind kind) {
      auto* spin = new NumberSpinBox(lo, hi, rangeText, kind);
      spin->installEventFilter(new SimulationKeysPassThrough(spin));
      return spin;
    };
    if ((info && info->live) || t.isDerivedFrom(SoMFVec3d::getClassTypeId()) || t.isDerivedFrom(SoMFEngine::getClassTypeId())) {
      // shown, not edited: the state, the nets, the force list
      auto* show = new QLabel;
      show->setTextInteractionFlags(Qt::TextSelectableByMouse);
      row.editor = show;
      if (t.isDerivedFrom(SoMFVec3d::getClassTypeId()))
        row.read = [f, show] {
          const int n = static_cast<SoMFVec3d*>(f)->getNum();
          show->setText(n ? tr("%1 points").arg(n) : tr("(empty)"));
        };
      else if (t.isDerivedFrom(SoMFEngine::getClassTypeId()))
        row.read = [f, show] { show->setText(tr("%n engine(s)", "", static_cast<SoMFEngine*>(f)->getNum())); };
      else if (t.isDerivedFrom(SoSFDouble::getClassTypeId()))
        // a running sum (0.1 + 0.1 + 0.1): 12 digits, as the status bar, not the last ulp
        row.read = [f, show] { show->setText(QString::number(static_cast<SoSFDouble*>(f)->getValue(), 'g', 12)); };
      else
        row.read = [f, show] { show->setText(coinText(f)); };
    } else if (t.isDerivedFrom(SoSFTrigger::getClassTypeId())) {
      auto* button = new QPushButton(name);
      button->setFocusPolicy(Qt::TabFocus);
      connect(button, &QPushButton::clicked, this, [this, f] {
        f->touch();
        emit edited();
      });
      row.editor = button;
    } else if (t.isDerivedFrom(SoSFBool::getClassTypeId())) {
      auto* check = new QCheckBox;
      check->setFocusPolicy(Qt::TabFocus);  // a click leaves the keyboard where it was (Space!)
      auto* bf = static_cast<SoSFBool*>(f);
      connect(check, &QCheckBox::toggled, this, [this, bf, check](bool on) {
        if (bf->getValue() == SbBool(on)) return;
        if (Row* r = rowOf(check)) commit(*r, [bf, on] {
            bf->setValue(on);
            return true;
          });
      });
      row.editor = check;
      row.read = [bf, check] {
        const QSignalBlocker block(check);
        check->setChecked(bf->getValue());
      };
    } else if (t.isDerivedFrom(SoSFBitMask::getClassTypeId())) {
      // a bit mask (holdUMin ...): one check box per bit, the value their sum
      auto* box = new QWidget;
      auto* h = new QHBoxLayout(box);
      h->setContentsMargins(0, 0, 0, 0);
      auto* bf = static_cast<SoSFBitMask*>(f);
      QVector<QPair<QCheckBox*, int>> bits;
      for (int k = 0; k < bf->getNumEnums(); ++k) {
        SbName en;
        const int value = bf->getEnum(k, en);
        auto* check = new QCheckBox(QString::fromLatin1(en.getString()));
        check->setFocusPolicy(Qt::TabFocus);
        h->addWidget(check);
        bits.append({check, value});
      }
      h->addStretch(1);
      for (const auto& [check, value] : bits)
        connect(check, &QCheckBox::toggled, this, [this, bf, box, bits] {
          int mask = 0;
          for (const auto& [c, v] : bits)
            if (c->isChecked()) mask |= v;
          if (bf->getValue() != mask)
            if (Row* r = rowOf(box)) commit(*r, [bf, mask] {
                bf->setValue(mask);
                return true;
              });
          emit done();
        });
      row.editor = box;
      row.read = [bf, bits] {
        for (const auto& [check, value] : bits) {
          const QSignalBlocker block(check);
          check->setChecked((bf->getValue() & value) != 0);
        }
      };
    } else if (t.isDerivedFrom(SoSFEnum::getClassTypeId())) {
      auto* combo = new QComboBox;
      combo->setFocusPolicy(Qt::TabFocus);
      auto* ef = static_cast<SoSFEnum*>(f);
      for (int k = 0; k < ef->getNumEnums(); ++k) {
        SbName en;
        const int value = ef->getEnum(k, en);
        combo->addItem(QString::fromLatin1(en.getString()), value);
      }
      connect(combo, QOverload<int>::of(&QComboBox::activated), this, [this, ef, combo](int index) {
        const int value = combo->itemData(index).toInt();
        if (ef->getValue() != value)
          if (Row* r = rowOf(combo)) commit(*r, [ef, value] {
              ef->setValue(value);
              return true;
            });
        emit done();
      });
      row.editor = combo;
      row.read = [ef, combo] {
        const QSignalBlocker block(combo);
        combo->setCurrentIndex(combo->findData(ef->getValue()));
      };
    } else if (t.isDerivedFrom(SoSFDouble::getClassTypeId()) || t.isDerivedFrom(SoSFFloat::getClassTypeId()) ||
               t.isDerivedFrom(SoSFInt32::getClassTypeId())) {
      const bool isFloat = t.isDerivedFrom(SoSFFloat::getClassTypeId()), isInt = t.isDerivedFrom(SoSFInt32::getClassTypeId());
      NumberSpinBox* spin = number(isInt ? NumberSpinBox::Integer : isFloat ? NumberSpinBox::Single : NumberSpinBox::Double);
      auto get = [f, isFloat, isInt]() -> double {
        return isInt ? static_cast<SoSFInt32*>(f)->getValue() : isFloat ? static_cast<SoSFFloat*>(f)->getValue() : static_cast<SoSFDouble*>(f)->getValue();
      };
      connect(spin, &QAbstractSpinBox::editingFinished, this, [this, f, spin, get, isFloat, isInt] {
        const double v = spin->value();
        if (v == get() || !spin->problem().isEmpty()) return;
        if (Row* r = rowOf(spin)) commit(*r, [f, v, isFloat, isInt] {
            if (isInt)
              static_cast<SoSFInt32*>(f)->setValue(int(v));
            else if (isFloat)
              static_cast<SoSFFloat*>(f)->setValue(float(v));
            else
              static_cast<SoSFDouble*>(f)->setValue(v);
            return true;
          });
      });
      row.editor = spin;
      row.read = [spin, get] {
        const QSignalBlocker block(spin);
        // a value beyond the box's range is shown as it is, never clamped (the box says why
        // it cannot be taken as it stands)
        const double v = get();
        if (v < spin->minimum() || v > spin->maximum()) spin->showUnclamped(v);
        else spin->setValue(v);
      };
      row.problem = [spin] { return spin->problem(); };
      row.readUnclamped = [spin, get] {
        const QSignalBlocker block(spin);
        spin->showUnclamped(get());
      };
    } else if (t.isDerivedFrom(SoSFVec2d::getClassTypeId()) || t.isDerivedFrom(SoSFVec3d::getClassTypeId())) {
      const int n = t.isDerivedFrom(SoSFVec2d::getClassTypeId()) ? 2 : 3;
      auto* rowWidget = new QWidget;
      auto* h = new QHBoxLayout(rowWidget);
      h->setContentsMargins(0, 0, 0, 0);
      QVector<NumberSpinBox*> spins;
      for (int k = 0; k < n; ++k) {
        spins << number(NumberSpinBox::Double);
        h->addWidget(spins.back());
      }
      auto get = [f, n](int k) {
        return n == 2 ? static_cast<SoSFVec2d*>(f)->getValue()[k] : static_cast<SoSFVec3d*>(f)->getValue()[k];
      };
      for (NumberSpinBox* spin : spins)
        connect(spin, &QAbstractSpinBox::editingFinished, this, [this, f, n, spins, get, rowWidget] {
          bool same = true;
          for (int k = 0; k < n; ++k) {
            if (!spins[k]->problem().isEmpty()) return;
            same &= spins[k]->value() == get(k);
          }
          if (same) return;
          if (Row* r = rowOf(rowWidget)) commit(*r, [f, n, spins] {
              if (n == 2)
                static_cast<SoSFVec2d*>(f)->setValue(spins[0]->value(), spins[1]->value());
              else
                static_cast<SoSFVec3d*>(f)->setValue(spins[0]->value(), spins[1]->value(), spins[2]->value());
              return true;
            });
        });
      row.editor = rowWidget;
      row.read = [spins, get] {
        for (int k = 0; k < spins.size(); ++k) {
          const QSignalBlocker block(spins[k]);
          const double v = get(k);
          if (v < spins[k]->minimum() || v > spins[k]->maximum()) spins[k]->showUnclamped(v);
          else spins[k]->setValue(v);
        }
      };
      row.problem = [spins] {
        for (NumberSpinBox* s : spins)
          if (!s->problem().isEmpty()) return s->problem();
        return QString();
      };
    } else if (t.isDerivedFrom(SoMFNode::getClassTypeId())) {
      // nodes by their names, not as Inventor text (which writes each node out whole)
      auto* nodes = static_cast<SoMFNode*>(f);
      auto* edit = new QLineEdit;
      edit->setToolTip(tr("DEF names, separated by commas"));
      connect(edit, &QLineEdit::editingFinished, this, [this, nodes, edit] {
        const QString text = edit->text().trimmed();
        if (text == nodeListText(*nodes)) return;
        if (Row* r = rowOf(edit)) commit(*r, [nodes, text] { return setNodeList(*nodes, text); });
      });
      row.editor = edit;
      row.read = [nodes, edit] { edit->setText(nodeListText(*nodes)); };
    } else {
      // every other field in its own text form: lists of points, strings
      auto* edit = new QLineEdit;
      connect(edit, &QLineEdit::editingFinished, this, [this, f, edit] {
        const QString text = edit->text().trimmed();
        if (text == coinText(f)) return;
        if (Row* r = rowOf(edit)) commit(*r, [f, text] { return bool(f->set(text.toUtf8().constData())); });
      });
      row.editor = edit;
      row.read = [f, edit] { edit->setText(coinText(f)); };
    }
    addRow(std::move(row), label, tooltipOf(info, name));
  }
  refresh();
}

void FieldEditor::commit(Row& row, const std::function<bool()>& apply) {
  SoField* field = row.field;
  // what the node refused before the change (a file's value of another field)
  const QString alreadyRefused = m_check ? m_check(m_container) : QString();
  const Refusals refusedBefore = m_refused ? m_refused(m_container) : Refusals();
  std::unique_ptr<SoField> before(copyOf(*field));
  const bool beforeIsDefault = field->isDefault();
  const QString name = row.name;
  if (!apply()) {
    field->copyFrom(*before);
    field->setDefault(beforeIsDefault);
    showInvalid(row, tr("not a valid value for this field"));
    emit rejected(tr("%1: not a valid value").arg(name));
    return;
  }
  if (before->isSame(*field)) return;
  QString reason = m_check ? m_check(m_container) : QString();
  // Taken unless this field is now refused, or the change makes another field refused that was
  // not (a degree that no longer fits the rest net): other fields refused as before (a file's
  // values) do not refuse this change.
  const Refusals refusedAfter = m_refused ? m_refused(m_container) : Refusals();
  auto listed = [](const Refusals& list, const QString& field) {
    return std::any_of(list.begin(), list.end(), [&field](const auto& r) { return r.first == field; });
  };
  bool refused = false;
  for (const auto& r : refusedAfter)
    if (r.first == row.name || !listed(refusedBefore, r.first)) {
      reason = r.second;
      refused = true;
      if (r.first == row.name) break;
    }
  if (refusedAfter.empty() && !reason.isEmpty() && reason != alreadyRefused) refused = true;
  if (refused) {
    field->copyFrom(*before);  // the node keeps its last valid values
    field->setDefault(beforeIsDefault);
    showInvalid(row, reason);
    emit rejected(tr("%1: %2").arg(name, reason));
    // a choice (combo, check box) keeps no focus to lose: it goes back at once, the reason stays
    QWidget* focus = QApplication::focusWidget();
    if (!focus || (focus != row.editor && !row.editor->isAncestorOf(focus))) revert(row);
    return;
  }
  row.invalid = false;
  row.editor->setStyleSheet(QString());
  row.message->setVisible(row.restarts);
  if (row.restarts) {
    row.message->setStyleSheet(QStringLiteral("color: #805000;"));
    row.message->setText(tr("The simulation restarted from rest."));
  }
  const bool restarts = row.restarts;
  // the handler may rebuild this editor (a force field's type): `row` is not used afterwards
  if (m_onChange) m_onChange(m_container, field, *before, beforeIsDefault);
  if (restarts) emit notice(tr("%1 changed: the simulation restarted from rest").arg(name));
  emit edited();
}

void FieldEditor::showInvalid(Row& row, const QString& reason) {
  row.invalid = true;
  row.editor->setStyleSheet(QString::fromLatin1(kInvalidStyle));
  row.message->setStyleSheet(QStringLiteral("color: #c00000;"));
  row.message->setText(reason);
  row.message->show();
}

void FieldEditor::revert(Row& row) {
  row.invalid = false;
  row.editor->setStyleSheet(QString());
  if (row.read) row.read();
  row.message->setText(tr("Not applied: %1").arg(row.message->text()));
  markRefused();
}

void FieldEditor::markRefused() {
  const Refusals refused = m_refused && m_container ? m_refused(m_container) : Refusals();
  QWidget* focus = QApplication::focusWidget();
  for (const auto& r : m_rows) {
    auto it = std::find_if(refused.begin(), refused.end(), [&r](const auto& x) { return !x.first.isEmpty() && x.first == r->name; });
    const bool now = it != refused.end();
    if (focus && (focus == r->editor || r->editor->isAncestorOf(focus))) continue;  // being edited
    if (now) {
      if (r->readUnclamped)
        r->readUnclamped();
      else if (r->read)
        r->read();
      r->refusedByNode = true;
      showInvalid(*r, it->second);
    } else if (r->refusedByNode) {
      r->refusedByNode = false;
      r->invalid = false;
      r->editor->setStyleSheet(QString());
      r->message->hide();
      if (r->read) r->read();
    }
  }
}

bool FieldEditor::eventFilter(QObject* watched, QEvent* event) {
  Row* row = rowOf(watched);
  if (!row) return false;
  if (event->type() == QEvent::KeyPress) {
    auto* key = static_cast<QKeyEvent*>(event);
    if (key->key() == Qt::Key_Escape) {
      if (row->invalid) revert(*row);
      else if (row->read) row->read();
      emit done();
      return true;
    }
    if (key->key() == Qt::Key_Return || key->key() == Qt::Key_Enter) {
      if (row->problem && !row->problem().isEmpty()) {
        showInvalid(*row, row->problem());
        return true;  // the text stays for the user to correct
      }
      // after the editor took the Return (and committed): back to the 3D view when accepted
      QPointer<QObject> w(watched);
      QTimer::singleShot(0, this, [this, w] {
        Row* r = w ? rowOf(w) : nullptr;
        if (r && !r->invalid) emit done();
      });
    }
  } else if (event->type() == QEvent::FocusOut) {
    if (row->problem && !row->problem().isEmpty()) showInvalid(*row, row->problem());
    // after the editor's own focus-out handling (which commits): a refused value goes back
    QPointer<QObject> w(watched);
    QTimer::singleShot(0, this, [this, w] {
      Row* r = w ? rowOf(w) : nullptr;
      if (r && r->invalid) revert(*r);
    });
  }
  return false;
}

QWidget* FieldEditor::editorOf(const QString& name) const {
  for (const auto& r : m_rows)
    if (r->name == name) return r->editor;
  return nullptr;
}

QString FieldEditor::messageOf(const QString& name) const {
  for (const auto& r : m_rows)
    if (r->name == name) return r->message->isHidden() ? QString() : r->message->text();
  return QString();
}

void FieldEditor::refresh() {
  QWidget* focus = QApplication::focusWidget();
  for (const auto& r : m_rows) {
    if (!r->read || r->invalid) continue;
    if (focus && (focus == r->editor || r->editor->isAncestorOf(focus))) continue;  // being edited
    r->read();
  }
  markRefused();
}

}  // namespace bsdeform
