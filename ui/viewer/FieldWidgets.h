// SPDX-License-Identifier: MIT
#pragma once
/// @file FieldWidgets.h
/// Editors for the field editor: number text without float noise, a number spin box that
/// explains a refused value, and the filter that keeps the simulation's one-key shortcuts out
/// of editors.

#include <QDoubleSpinBox>
#include <QObject>
#include <QString>

class QKeyEvent;

namespace bsdeform {

/// The shortest decimal text that reads back to `value` ("0.3", not "0.30000000000000004").
QString numberText(double value);
/// The same for a single-precision value ("0.3", not "0.30000001").
QString numberText(float value);

/// A spin box for one number of a field: the field's range, as many digits as the value needs,
/// the "C" locale (as in .iv files); the mouse wheel changes it only while it has focus. Text
/// that is not a number in range stays as typed (problem() says why) until the box loses focus.
class NumberSpinBox : public QDoubleSpinBox {
  Q_OBJECT
 public:
  enum Kind { Double, Single, Integer };
  /// `rangeText`: the range as the field table words it, for the reason of a refusal.
  NumberSpinBox(double min, double max, const QString& rangeText, Kind kind, QWidget* parent = nullptr);
  /// Why the text now in the box cannot be taken (not a number, outside the range); empty when
  /// it can.
  QString problem() const;
  /// Shows `value` as it is, outside the range too (a value read from a file that the node
  /// refuses): the text stays until the user edits it or it is read again.
  void showUnclamped(double value);
  QString textFromValue(double value) const override;
  double valueFromText(const QString& text) const override;
  QValidator::State validate(QString& text, int& pos) const override;

 protected:
  void wheelEvent(QWheelEvent* e) override;

 private:
  QString m_rangeText;
  Kind m_kind;
};

/// The simulation's shortcuts without modifiers: Space (play/pause), S (step), R (reset),
/// D (drag mode).
bool isSimulationKey(const QKeyEvent& e);

/// Installed on a widget that would otherwise take those keys as text (a number editor, the
/// toolbar's speed box): they reach the shortcuts instead, since no number contains them.
class SimulationKeysPassThrough : public QObject {
 public:
  using QObject::QObject;
  bool eventFilter(QObject* watched, QEvent* event) override;
};

}  // namespace bsdeform
