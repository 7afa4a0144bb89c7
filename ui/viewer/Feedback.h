// SPDX-License-Identifier: MIT
#pragma once
/// @file Feedback.h
/// How the viewer's parts tell the user what happened: a line in the window's status bar and,
/// for an error, a warning box, or a line on stderr instead when the window is not interactive
/// (tests, --measure-fps). The last error is kept for the tests.

#include <QString>

class QMainWindow;

namespace bsdeform {

class Feedback {
 public:
  explicit Feedback(QMainWindow& window) : m_window(window) {}

  /// Off: no dialogs (errors go to stderr and lastError()); tests and batch measurement.
  void setInteractive(bool on) { m_interactive = on; }
  bool isInteractive() const { return m_interactive; }
  const QString& lastError() const { return m_lastError; }
  void clearError() { m_lastError.clear(); }

  /// `message` becomes lastError(); its first line goes to the status bar for 10 s and the
  /// whole of it into a warning box titled `title` (stderr when not interactive).
  void error(const QString& title, const QString& message);
  /// `message` in the status bar for `ms` milliseconds (0: until the next message).
  void show(const QString& message, int ms = 0);
  /// As show(), and on stderr when not interactive: an outcome a batch run should see.
  void report(const QString& message, int ms);

 private:
  QMainWindow& m_window;
  bool m_interactive = true;
  QString m_lastError;
};

}  // namespace bsdeform
