// SPDX-License-Identifier: MIT
#pragma once
/// @file HelpDialogs.h
/// The Help menu's About box (version and the libraries the viewer was built with and runs on),
/// the list of keyboard shortcuts, read from the window's own actions so that it cannot drift
/// from them, and the field reference.

#include <QPair>
#include <QString>
#include <QVector>

class QMenuBar;
class QWidget;

namespace bsdeform {

/// One line of the shortcut list: key sequence (native text), "Menu > Action".
struct ShortcutEntry {
  QString keys;
  QString action;
};

/// Every action reachable from `bar` (sub-menus included) that has a shortcut, in menu order.
QVector<ShortcutEntry> menuShortcuts(const QMenuBar* bar);

/// The About text (rich text): version, what the program does, and for each dependency the
/// version it was built against and, where the library says so, the one it runs with.
QString aboutText();

/// The shortcut list as rich text: the menus' shortcuts followed by the mouse in the 3D view.
QString shortcutsText(const QVector<ShortcutEntry>& entries);

/// Shows the About box / the shortcut list (non-modal, owned by `parent`).
void showAbout(QWidget* parent);
void showShortcuts(QWidget* parent, const QMenuBar* bar);
/// Shows the fields of both nodes (bsdeform/FieldInfo.h): one non-modal dialog per `parent`,
/// made the first time and shown again after.
void showFieldReference(QWidget* parent);

}  // namespace bsdeform
