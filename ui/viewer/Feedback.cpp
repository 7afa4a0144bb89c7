// SPDX-License-Identifier: MIT
#include "Feedback.h"

#include <QMainWindow>
#include <QMessageBox>
#include <QStatusBar>
#include <cstdio>

namespace bsdeform {

void Feedback::error(const QString& title, const QString& message) {
  m_lastError = message;
  show(title + QStringLiteral(": ") + message.section(QLatin1Char('\n'), 0, 0), 10000);
  if (m_interactive)
    QMessageBox::warning(&m_window, title, message);
  else
    std::fprintf(stderr, "bsdeform-viewer: %s: %s\n", title.toUtf8().constData(), message.toUtf8().constData());
}

void Feedback::show(const QString& message, int ms) { m_window.statusBar()->showMessage(message, ms); }

void Feedback::report(const QString& message, int ms) {
  show(message, ms);
  if (!m_interactive) std::fprintf(stderr, "bsdeform-viewer: %s\n", message.toUtf8().constData());
}

}  // namespace bsdeform
