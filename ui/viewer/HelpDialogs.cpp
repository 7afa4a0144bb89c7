// SPDX-License-Identifier: MIT
#include "HelpDialogs.h"

#include <Inventor/Qt/SoQt.h>
#include <Inventor/SoDB.h>
#include <embree3/rtcore_config.h>
#include <suitesparse/cholmod.h>

#include <Eigen/Core>
#include <QAction>
#include <QDialog>
#include <QDialogButtonBox>
#include <QMenu>
#include <QMenuBar>
#include <QMessageBox>
#include <QTextBrowser>
#include <QVBoxLayout>

#include "bsdeform/FieldInfo.h"

#ifndef BSDEFORM_VERSION
#error "BSDEFORM_VERSION is set by ui/CMakeLists.txt"
#endif

namespace bsdeform {

namespace {
void collect(const QMenu* menu, const QString& prefix, QVector<ShortcutEntry>& out) {
  for (QAction* a : menu->actions()) {
    const QString text = prefix + a->text().remove(QLatin1Char('&'));
    if (a->menu())
      collect(a->menu(), text + QStringLiteral(" > "), out);
    else if (!a->shortcut().isEmpty())
      out.push_back({a->shortcut().toString(QKeySequence::NativeText), text});
  }
}

QString row(const QString& a, const QString& b) {
  return QStringLiteral("<tr><td><b>%1</b></td><td>&nbsp;&nbsp;%2</td></tr>").arg(a.toHtmlEscaped(), b.toHtmlEscaped());
}

void showRichText(QWidget* parent, const QString& title, const QString& html) {
  auto* dialog = new QDialog(parent);
  dialog->setAttribute(Qt::WA_DeleteOnClose);
  dialog->setWindowTitle(title);
  auto* text = new QTextBrowser;
  text->setOpenExternalLinks(true);
  text->setHtml(html);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Close);
  QObject::connect(buttons, &QDialogButtonBox::rejected, dialog, &QDialog::close);
  auto* layout = new QVBoxLayout(dialog);
  layout->addWidget(text);
  layout->addWidget(buttons);
  dialog->resize(560, 520);
  dialog->show();
}
}  // namespace

QVector<ShortcutEntry> menuShortcuts(const QMenuBar* bar) {
  QVector<ShortcutEntry> out;
  for (QAction* a : bar->actions())
    if (a->menu()) collect(a->menu(), a->text().remove(QLatin1Char('&')) + QStringLiteral(" > "), out);
  return out;
}

QString aboutText() {
  const QString built = QStringLiteral("%1.%2.%3");
  QString html = QObject::tr("<h3>bsdeform-viewer %1</h3>"
                             "<p>Opens, animates and lets you pull B-spline finite-element surfaces "
                             "(Coin3D nodes <tt>SoBSplineDeformSurface</tt> and <tt>SoForceField</tt>). "
                             "MIT licence.</p>")
                     .arg(QStringLiteral(BSDEFORM_VERSION));
  html += QObject::tr("<p>Libraries (built with / running with):</p><table>");
  html += row(QStringLiteral("Coin"), QStringLiteral("%1 / %2").arg(QStringLiteral(COIN_VERSION), QString::fromLatin1(SoDB::getVersion())));
  html += row(QStringLiteral("SoQt"), QStringLiteral("%1 / %2").arg(QStringLiteral(SOQT_VERSION), QString::fromLatin1(SoQt::getVersionString())));
  html += row(QStringLiteral("Qt"), QStringLiteral("%1 / %2").arg(QStringLiteral(QT_VERSION_STR), QString::fromLatin1(qVersion())));
  html += row(QStringLiteral("Eigen"), built.arg(EIGEN_WORLD_VERSION).arg(EIGEN_MAJOR_VERSION).arg(EIGEN_MINOR_VERSION));
  html += row(QStringLiteral("CHOLMOD (SuiteSparse)"),
              built.arg(CHOLMOD_MAIN_VERSION).arg(CHOLMOD_SUB_VERSION).arg(CHOLMOD_SUBSUB_VERSION));
  html += row(QStringLiteral("Embree"), QStringLiteral(RTC_VERSION_STRING));
  html += QStringLiteral("</table>");
  return html;
}

QString shortcutsText(const QVector<ShortcutEntry>& entries) {
  QString html = QObject::tr("<h3>Keyboard</h3><table>");
  for (const ShortcutEntry& e : entries) html += row(e.keys, e.action);
  html += QStringLiteral("</table>");
  html += QObject::tr("<h3>Mouse in the 3D view</h3><table>");
  html += row(QObject::tr("Left drag"), QObject::tr("rotate the camera (in Drag mode: pull the surface)"));
  html += row(QObject::tr("Middle drag"), QObject::tr("pan"));
  html += row(QObject::tr("Wheel"), QObject::tr("zoom"));
  html += row(QObject::tr("Esc"), QObject::tr("switch between camera and selection mode"));
  html += row(QObject::tr("Right click"), QObject::tr("the viewer's own menu (draw style, stereo, ...)"));
  html += QStringLiteral("</table>");
  return html;
}

void showAbout(QWidget* parent) { showRichText(parent, QObject::tr("About bsdeform-viewer"), aboutText()); }

void showShortcuts(QWidget* parent, const QMenuBar* bar) {
  showRichText(parent, QObject::tr("Keyboard shortcuts"), shortcutsText(menuShortcuts(bar)));
}

void showFieldReference(QWidget* parent) {
  const QString name = QStringLiteral("fieldReference");
  auto* dialog = parent->findChild<QDialog*>(name, Qt::FindDirectChildrenOnly);
  if (!dialog) {
    dialog = new QDialog(parent);
    dialog->setObjectName(name);
    dialog->setWindowTitle(QObject::tr("Field reference"));
    auto* text = new QTextBrowser;
    text->setMarkdown(QString::fromStdString(fieldReferenceMarkdown()));
    auto* layout = new QVBoxLayout(dialog);
    layout->addWidget(text);
    dialog->resize(1000, 700);
  }
  dialog->show();
  dialog->raise();
}

}  // namespace bsdeform
