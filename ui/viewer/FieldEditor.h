// SPDX-License-Identifier: MIT
#pragma once
/// @file FieldEditor.h
/// An editor bound to the fields of one node or engine, built from the field table
/// (bsdeform/FieldInfo.h): a typed editor per field (number spin boxes with the field's range,
/// combo boxes for enums, check boxes for bools), values without float noise, a tooltip with
/// meaning, unit, range and paper symbol on each row, and for a force field only the fields its
/// type reads. A change is written to the field at once and checked by the node; a value the
/// node refuses is shown in red with the reason and reverted when the editor loses focus.

#include <QWidget>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

class SoFieldContainer;
class SoField;
class QFormLayout;
class QLabel;

namespace bsdeform {

class FieldEditor : public QWidget {
  Q_OBJECT
 public:
  explicit FieldEditor(QWidget* parent = nullptr);
  /// Shows the fields of `container` (nullptr: nothing). The container must outlive the editor
  /// or be replaced first.
  void setContainer(SoFieldContainer* container, const QString& title);
  SoFieldContainer* container() const { return m_container; }
  /// Re-reads every field into its editor (skipping the one being edited); live values (time,
  /// steps) follow the simulation.
  void refresh();
  /// The widget that edits (or shows) the field called `name` (nullptr if it is not shown).
  QWidget* editorOf(const QString& name) const;
  /// The reason shown under the field's editor (empty when none).
  QString messageOf(const QString& name) const;

  /// Told about every change made from the editor, after the field took the new value and the
  /// node accepted it: `before` is a copy of the old value (the window makes it an undoable
  /// command). Without one the change simply stays.
  using ChangeHandler = std::function<void(SoFieldContainer* owner, SoField* field, const SoField& before, bool beforeIsDefault)>;
  void setChangeHandler(ChangeHandler handler) { m_onChange = std::move(handler); }
  /// Asked after a change whether the node takes its new values: the reason it refuses them,
  /// empty when it takes them. Without one every parsed value is taken.
  using Checker = std::function<QString(SoFieldContainer* owner)>;
  void setChecker(Checker checker) { m_check = std::move(checker); }
  /// Every field the node refuses as its values stand (values read from a file, say), each
  /// with its reason; empty when none. Each one's row shows the field's own value, not one
  /// clamped to the editor's range, in red with the reason, until the node takes its values.
  using Refusals = std::vector<std::pair<QString, QString>>;
  using RefusedFields = std::function<Refusals(SoFieldContainer* owner)>;
  void setRefusedFields(RefusedFields refused) { m_refused = std::move(refused); }

 signals:
  /// A value was refused (message names the field, the value and the reason).
  void rejected(const QString& message);
  /// A field was changed from the editor.
  void edited();
  /// Something worth a status line (e.g. "the simulation restarted from rest").
  void notice(const QString& message);
  /// The user finished with an editor (Return, Escape, a choice made): the keyboard can go
  /// back to the 3D view.
  void done();

 protected:
  bool eventFilter(QObject* watched, QEvent* event) override;

 private:
  struct Row {
    SoField* field = nullptr;
    QString name;
    QWidget* editor = nullptr;   ///< what editorOf() returns
    QLabel* message = nullptr;   ///< the reason of a refusal, a restart notice
    std::function<void()> read;  ///< field -> editor
    std::function<QString()> problem;  ///< why the editor's text cannot be taken (number boxes)
    std::function<void()> readUnclamped;  ///< field -> editor beyond the editor's range (number boxes)
    bool invalid = false;        ///< showing a refused value
    bool refusedByNode = false;  ///< showing the value the node refuses as it stands (m_refused)
    bool restarts = false;
  };
  void clear();
  void addRow(Row row, const QString& label, const QString& tooltip);
  Row* rowOf(QObject* widget);
  /// Runs `apply` (which sets the row's field from its editor); the node then accepts or refuses.
  void commit(Row& row, const std::function<bool()>& apply);
  void showInvalid(Row& row, const QString& reason);
  void revert(Row& row);
  /// Marks the rows of the fields the node refuses as they stand, and unmarks the others.
  void markRefused();

  SoFieldContainer* m_container = nullptr;
  QFormLayout* m_form = nullptr;
  std::vector<std::unique_ptr<Row>> m_rows;
  ChangeHandler m_onChange;
  Checker m_check;
  RefusedFields m_refused;
};

}  // namespace bsdeform
