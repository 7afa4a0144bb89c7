// SPDX-License-Identifier: MIT
#include "FieldEditor.h"

#include <Inventor/SbString.h>
#include <Inventor/fields/SoFieldContainer.h>
#include <Inventor/fields/SoFieldData.h>
#include <Inventor/fields/SoMFEngine.h>
#include <Inventor/fields/SoMFVec3d.h>
#include <Inventor/fields/SoSFBool.h>
#include <Inventor/fields/SoSFEnum.h>
#include <Inventor/fields/SoSFInt32.h>
#include <Inventor/fields/SoSFTrigger.h>
#include <Inventor/lists/SoFieldList.h>

#include <QCheckBox>
#include <QComboBox>
#include <QFormLayout>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>
#include <QSpinBox>
#include <memory>

namespace bsdeform {

FieldEditor::FieldEditor(QWidget* parent) : QWidget(parent) {
  m_form = new QFormLayout(this);
  m_form->setFieldGrowthPolicy(QFormLayout::AllNonFixedFieldsGrow);
}

void FieldEditor::clear() {
  m_bindings.clear();
  while (m_form->rowCount() > 0) m_form->removeRow(0);
}

void FieldEditor::setContainer(SoFieldContainer* container, const QString& title) {
  clear();
  m_container = container;
  if (!container) return;
  auto* heading = new QLabel(QStringLiteral("<b>%1</b> (%2)").arg(title.toHtmlEscaped(),
                                                                   QString::fromLatin1(container->getTypeId().getName().getString())));
  m_form->addRow(heading);
  SoFieldList fields;
  container->getFields(fields);
  for (int i = 0; i < fields.getLength(); ++i) {
    SoField* f = fields[i];
    SbName name;
    container->getFieldName(f, name);
    const QString label = QString::fromLatin1(name.getString());
    const SoType t = f->getTypeId();
    if (t.isDerivedFrom(SoMFVec3d::getClassTypeId())) {
      auto* info = new QLabel;
      m_form->addRow(label, info);
      m_bindings.push_back({f, info, [f, info] {
                              const int n = static_cast<SoMFVec3d*>(f)->getNum();
                              info->setText(n ? QStringLiteral("%1 points").arg(n) : QStringLiteral("(derived)"));
                            }});
    } else if (t.isDerivedFrom(SoMFEngine::getClassTypeId())) {
      auto* info = new QLabel;
      m_form->addRow(label, info);
      m_bindings.push_back({f, info, [f, info] { info->setText(QStringLiteral("%1 engine(s)").arg(static_cast<SoMFEngine*>(f)->getNum())); }});
    } else if (t.isDerivedFrom(SoSFTrigger::getClassTypeId())) {
      auto* button = new QPushButton(label);
      connect(button, &QPushButton::clicked, this, [this, f] {
        f->touch();
        emit edited();
      });
      m_form->addRow(label, button);
    } else if (t.isDerivedFrom(SoSFBool::getClassTypeId())) {
      auto* box = new QCheckBox;
      auto* bf = static_cast<SoSFBool*>(f);
      connect(box, &QCheckBox::toggled, this, [this, bf](bool on) {
        if (bf->getValue() != SbBool(on)) commit(bf, [bf, on] { bf->setValue(on); });
      });
      m_form->addRow(label, box);
      m_bindings.push_back({f, box, [bf, box] {
                              const QSignalBlocker block(box);
                              box->setChecked(bf->getValue());
                            }});
    } else if (t.isDerivedFrom(SoSFEnum::getClassTypeId())) {
      auto* combo = new QComboBox;
      auto* ef = static_cast<SoSFEnum*>(f);
      for (int k = 0; k < ef->getNumEnums(); ++k) {
        SbName en;
        const int value = ef->getEnum(k, en);
        combo->addItem(QString::fromLatin1(en.getString()), value);
      }
      connect(combo, QOverload<int>::of(&QComboBox::activated), this, [this, ef, combo](int index) {
        const int value = combo->itemData(index).toInt();
        if (ef->getValue() != value) commit(ef, [ef, value] { ef->setValue(value); });
      });
      m_form->addRow(label, combo);
      m_bindings.push_back({f, combo, [ef, combo] {
                              const QSignalBlocker block(combo);
                              combo->setCurrentIndex(combo->findData(ef->getValue()));
                            }});
    } else if (t.isDerivedFrom(SoSFInt32::getClassTypeId())) {
      auto* spin = new QSpinBox;
      spin->setRange(-1000000, 1000000);
      auto* inf = static_cast<SoSFInt32*>(f);
      connect(spin, &QSpinBox::editingFinished, this, [this, inf, spin] {
        const int value = spin->value();
        if (inf->getValue() != value) commit(inf, [inf, value] { inf->setValue(value); });
      });
      m_form->addRow(label, spin);
      m_bindings.push_back({f, spin, [inf, spin] {
                              const QSignalBlocker block(spin);
                              spin->setValue(inf->getValue());
                            }});
    } else {
      // Every other field through its own text form: numbers, vectors, strings, lists.
      auto* edit = new QLineEdit;
      connect(edit, &QLineEdit::editingFinished, this, [this, f, edit, label] {
        SbString current;
        f->get(current);
        const QString text = edit->text().trimmed();
        if (text == QString::fromUtf8(current.getString())) return;
        bool parsed = true;
        commit(f, [f, &text, &parsed] { parsed = f->set(text.toUtf8().constData()); });
        if (!parsed) {
          emit rejected(QStringLiteral("%1: '%2' is not a valid value").arg(label, text));
          edit->setText(QString::fromUtf8(current.getString()));
        }
      });
      m_form->addRow(label, edit);
      m_bindings.push_back({f, edit, [f, edit] {
                              SbString s;
                              f->get(s);
                              edit->setText(QString::fromUtf8(s.getString()));
                            }});
    }
  }
  refresh();
}

void FieldEditor::commit(SoField* field, const std::function<void()>& apply) {
  std::unique_ptr<SoField> before(static_cast<SoField*>(field->getTypeId().createInstance()));
  before->copyFrom(*field);
  const bool beforeIsDefault = field->isDefault();
  apply();
  if (before->isSame(*field)) return;
  if (m_onChange) m_onChange(m_container, field, *before, beforeIsDefault);
  emit edited();
}

QWidget* FieldEditor::editorOf(const QString& name) const {
  if (!m_container) return nullptr;
  SoField* f = m_container->getField(SbName(name.toLatin1().constData()));
  for (const Binding& b : m_bindings)
    if (b.field == f) return b.widget;
  return nullptr;
}

void FieldEditor::refresh() {
  for (const Binding& b : m_bindings)
    if (!b.widget->hasFocus()) b.read();
}

}  // namespace bsdeform
