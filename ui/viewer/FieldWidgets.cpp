// SPDX-License-Identifier: MIT
#include "FieldWidgets.h"

#include <QKeyEvent>
#include <QLineEdit>
#include <QLocale>
#include <QWheelEvent>
#include <cmath>

namespace bsdeform {

QString numberText(double value) { return QString::number(value, 'g', QLocale::FloatingPointShortest); }

QString numberText(float value) {
  // the fewest significant digits that give the float back
  for (int digits = 1; digits < 9; ++digits) {
    const QString text = QString::number(double(value), 'g', digits);
    if (text.toFloat() == value) return text;
  }
  return QString::number(double(value), 'g', 9);
}

NumberSpinBox::NumberSpinBox(double min, double max, const QString& rangeText, Kind kind, QWidget* parent)
    : QDoubleSpinBox(parent), m_rangeText(rangeText), m_kind(kind) {
  setLocale(QLocale::c());
  // no rounding of the value: the text shows what it needs (textFromValue)
  setDecimals(kind == Integer ? 0 : 323);
  setRange(std::isfinite(min) ? min : -1e300, std::isfinite(max) ? max : 1e300);
  setStepType(QAbstractSpinBox::AdaptiveDecimalStepType);
  setKeyboardTracking(false);
  setFocusPolicy(Qt::StrongFocus);
  setMinimumWidth(56);  // a narrow panel shrinks it (three side by side for a vector)
  setCorrectionMode(QAbstractSpinBox::CorrectToPreviousValue);
}

QString NumberSpinBox::textFromValue(double value) const {
  return m_kind == Single ? numberText(float(value)) : numberText(value);
}

double NumberSpinBox::valueFromText(const QString& text) const {
  bool ok = false;
  const double v = QLocale::c().toDouble(text.trimmed(), &ok);
  return ok ? v : value();
}

QValidator::State NumberSpinBox::validate(QString& text, int&) const {
  bool ok = false;
  const double v = QLocale::c().toDouble(text.trimmed(), &ok);
  if (ok && std::isfinite(v) && v >= minimum() && v <= maximum() && (m_kind != Integer || v == std::floor(v)))
    return QValidator::Acceptable;
  // anything that could become a number while typing; Return with it is explained by problem()
  for (const QChar c : text)
    if (!(c.isDigit() || c == QLatin1Char('.') || c == QLatin1Char('-') || c == QLatin1Char('+') || c == QLatin1Char('e') ||
          c == QLatin1Char('E')))
      return QValidator::Invalid;
  return QValidator::Intermediate;
}

void NumberSpinBox::showUnclamped(double value) {
  lineEdit()->setText(m_kind == Single ? numberText(float(value)) : numberText(value));
}

QString NumberSpinBox::problem() const {
  const QString text = lineEdit()->text().trimmed();
  bool ok = false;
  const double v = QLocale::c().toDouble(text, &ok);
  if (!ok || !std::isfinite(v)) return tr("'%1' is not a number").arg(text);
  if (m_kind == Integer && v != std::floor(v)) return tr("'%1' is not a whole number").arg(text);
  if (v < minimum() || v > maximum())
    return tr("%1 is outside the range %2").arg(text, m_rangeText.isEmpty() ? tr("%1..%2").arg(numberText(minimum()), numberText(maximum()))
                                                                              : m_rangeText);
  return QString();
}

void NumberSpinBox::wheelEvent(QWheelEvent* e) {
  if (hasFocus())
    QDoubleSpinBox::wheelEvent(e);
  else
    e->ignore();  // the panel scrolls instead
}

bool isSimulationKey(const QKeyEvent& e) {
  if (e.modifiers() & ~Qt::KeypadModifier) return false;
  return e.key() == Qt::Key_Space || e.key() == Qt::Key_S || e.key() == Qt::Key_R || e.key() == Qt::Key_D;
}

bool SimulationKeysPassThrough::eventFilter(QObject*, QEvent* event) {
  if (event->type() == QEvent::ShortcutOverride && isSimulationKey(*static_cast<QKeyEvent*>(event))) {
    event->ignore();  // not the widget's: the shortcut map may take it
    return true;
  }
  return false;
}

}  // namespace bsdeform
