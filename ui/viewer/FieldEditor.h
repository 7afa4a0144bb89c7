// SPDX-License-Identifier: MIT
#pragma once
/// @file FieldEditor.h
/// An editor bound to the fields of one node or engine: every change is written to the field
/// at once (the simulation takes it on its next step), and the editor follows field changes.

#include <QWidget>
#include <functional>

class SoFieldContainer;
class SoField;
class QFormLayout;

namespace bsdeform {

class FieldEditor : public QWidget {
  Q_OBJECT
 public:
  explicit FieldEditor(QWidget* parent = nullptr);
  /// Shows the fields of `container` (nullptr: nothing). The container must outlive the editor
  /// or be replaced first.
  void setContainer(SoFieldContainer* container, const QString& title);
  SoFieldContainer* container() const { return m_container; }
  /// Re-reads every field into its editor (skipping the one being edited).
  void refresh();
  /// The widget that edits the field called `name` (nullptr if it is not shown).
  QWidget* editorOf(const QString& name) const;
  /// Told about every change made from the editor, after the field took the new value:
  /// `before` is a copy of the old value (the window makes it an undoable command). Without
  /// one the change simply stays.
  using ChangeHandler = std::function<void(SoFieldContainer* owner, SoField* field, const SoField& before, bool beforeIsDefault)>;
  void setChangeHandler(ChangeHandler handler) { m_onChange = std::move(handler); }

 signals:
  /// A value was rejected by the field's parser (message names the field and the value).
  void rejected(const QString& message);
  /// A field was changed from the editor.
  void edited();

 private:
  struct Binding {
    SoField* field;
    QWidget* widget;
    std::function<void()> read;
  };
  void clear();
  /// Runs `apply` (which sets `field` from its widget) and reports a change.
  void commit(SoField* field, const std::function<void()>& apply);
  ChangeHandler m_onChange;
  SoFieldContainer* m_container = nullptr;
  QFormLayout* m_form = nullptr;
  QVector<Binding> m_bindings;
};

}  // namespace bsdeform
