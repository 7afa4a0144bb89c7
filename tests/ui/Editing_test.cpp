// SPDX-License-Identifier: MIT
// bsdeform-viewer as an editor (issue 10, items 2, 3, 7): undo/redo, insert/delete, save,
// the unsaved-changes prompt, the field editor, export. Under xvfb-run (tests/CMakeLists.txt).
#include <QAbstractSpinBox>
#include <QApplication>
#include <QCheckBox>
#include <QDir>
#include <QFile>
#include <QLineEdit>
#include <QMessageBox>
#include <QProcess>
#include <QPushButton>
#include <QRegularExpression>
#include <QSettings>
#include <QTemporaryDir>
#include <QTest>
#include <QTimer>
#include <QUndoStack>
#include <catch2/catch.hpp>

#include "FieldEditor.h"
#include "MainWindow.h"
#include "ViewerTestSupport.h"
#include "bsdeform/Simulation.h"
#include "bsdeform/SoBSplineDeformSurface.h"
#include "bsdeform/SoForceField.h"

using bsdeform::MainWindow;
using namespace bsdeform::test;

namespace {

// Types `text` into a field's editor (a line edit or a spin box, or the first of a row of
// them) and presses Return, as a user would.
void typeInto(QWidget* editor, const QString& text) {
  REQUIRE(editor);
  QWidget* target = editor;
  if (!qobject_cast<QLineEdit*>(editor) && !qobject_cast<QAbstractSpinBox*>(editor)) {
    if (auto* spin = editor->findChild<QAbstractSpinBox*>())
      target = spin;
    else
      target = editor->findChild<QLineEdit*>();
  }
  REQUIRE(target);
  target->setFocus();
  if (auto* spin = qobject_cast<QAbstractSpinBox*>(target))
    spin->selectAll();
  else
    qobject_cast<QLineEdit*>(target)->selectAll();
  QTest::keyClicks(target, text);
  QTest::keyClick(target, Qt::Key_Return);
}

// Whether the scene text gives `field` a value (a line starting with its name; the `fields [...]`
// declaration of our nodes names every field).
bool setsField(const QByteArray& text, const char* field) {
  return QString::fromUtf8(text).contains(QRegularExpression(QStringLiteral("^\\s*%1 ").arg(QLatin1String(field)),
                                                             QRegularExpression::MultilineOption));
}

QByteArray readAll(const QString& path) {
  QFile f(path);
  REQUIRE(f.open(QIODevice::ReadOnly));
  return f.readAll();
}

// Answers the next modal message box with `button` (from a timer: the box runs its own event
// loop); `seen` gets its text.
void answerNextMessageBox(QMessageBox::StandardButton button, QString& seen) {
  auto* poll = new QTimer;
  QObject::connect(poll, &QTimer::timeout, poll, [poll, button, &seen] {
    auto* box = qobject_cast<QMessageBox*>(QApplication::activeModalWidget());
    if (!box) return;
    seen = box->text();
    QAbstractButton* b = box->button(button);
    if (b) QTest::mouseClick(b, Qt::LeftButton);
    poll->deleteLater();
  });
  poll->start(50);
}

}  // namespace

TEST_CASE("Editing: undo and redo restore a field value, an inserted and a deleted force field and surface", "[ui]") {
  auto w = makeWindow("region_load.iv");
  w->pause();
  SoBSplineDeformSurface* s = firstSurface(*w);
  QUndoStack& undo = w->undoStack();
  CHECK(undo.isClean());
  // a field through the editor
  REQUIRE(w->selectNode(s));
  const double w10 = s->w10.getValue();
  typeInto(w->fieldEditor().editorOf(QStringLiteral("w10")), QStringLiteral("0.25"));
  CHECK(s->w10.getValue() == 0.25);
  CHECK(undo.count() == 1);
  CHECK(!undo.isClean());
  CHECK(w->isWindowModified());
  undo.undo();
  CHECK(s->w10.getValue() == w10);
  CHECK(s->simulation().parameters().weights.w10 == w10);
  undo.redo();
  CHECK(s->w10.getValue() == 0.25);
  CHECK(s->simulation().parameters().weights.w10 == 0.25);

  // a force field of another type on the selected surface
  REQUIRE(w->selectNode(s));
  REQUIRE(w->insertForceField(SoForceField::GRAVITY));
  REQUIRE(s->forces.getNum() == 2);
  auto* gravity = static_cast<SoForceField*>(s->forces[1]);
  CHECK(gravity->type.getValue() == SoForceField::GRAVITY);
  CHECK(w->document().forceFields().size() == 2);
  CHECK(w->selectedNode() == gravity);  // the new node is selected
  CHECK(w->fieldEditor().container() == gravity);
  undo.undo();
  CHECK(s->forces.getNum() == 1);
  CHECK(w->document().forceFields().size() == 1);
  undo.redo();
  CHECK(s->forces.getNum() == 2);
  CHECK(s->forces[1] == gravity);

  // delete the original force field (selected), undo puts the same node back at its place
  SoEngine* region = s->forces[0];
  REQUIRE(w->selectNode(region));
  REQUIRE(w->deleteSelected());
  CHECK(s->forces.getNum() == 1);
  CHECK(s->forces[0] == gravity);
  undo.undo();
  REQUIRE(s->forces.getNum() == 2);
  CHECK(s->forces[0] == region);
  CHECK(s->forces[1] == gravity);

  // a surface added, deleted and brought back
  w->insertSurface();
  REQUIRE(w->document().surfaces().size() == 2);
  SoBSplineDeformSurface* added = w->document().surfaces()[1];
  CHECK(w->selectedNode() == added);
  CHECK(!added->on.getValue());  // paused like the rest of the scene
  REQUIRE(w->deleteSelected());
  CHECK(w->document().surfaces().size() == 1);
  undo.undo();
  REQUIRE(w->document().surfaces().size() == 2);
  CHECK(w->document().surfaces()[1] == added);
  undo.undo();  // the insertion
  CHECK(w->document().surfaces().size() == 1);
  // back to the file's contents: clean again
  while (undo.canUndo()) undo.undo();
  CHECK(undo.isClean());
  CHECK(s->w10.getValue() == w10);
  CHECK(s->forces.getNum() == 1);
}

TEST_CASE("Editing: a save after pausing keeps on TRUE and the file's speed, Save clears the modified state", "[ui]") {
  auto w = makeWindow("region_load.iv");
  SoBSplineDeformSurface* s = firstSurface(*w);
  w->setSpeed(3.0);
  w->pause();
  w->step();
  CHECK(!s->on.getValue());
  CHECK(s->speed.getValue() == 3.0f);
  QTemporaryDir dir;
  const QString path = dir.filePath(QStringLiteral("paused.iv"));
  REQUIRE(w->saveSceneAs(path));
  QByteArray text = readAll(path);
  CHECK(!text.contains("on FALSE"));
  CHECK(!setsField(text, "speed"));
  CHECK(text.contains("stepCount 1"));
  // the viewer's own values are back after the write
  CHECK(!s->on.getValue());
  CHECK(s->speed.getValue() == 3.0f);
  // what the author sets in the field editor is written
  REQUIRE(w->selectNode(s));
  QWidget* on = w->fieldEditor().editorOf(QStringLiteral("on"));
  REQUIRE(on);
  auto* box = qobject_cast<QCheckBox*>(on);
  REQUIRE(box);
  CHECK(!box->isChecked());  // it shows the paused state
  box->click();              // plays
  CHECK(s->on.getValue());
  CHECK(w->isPlaying());
  box->click();  // and pauses: `on FALSE` as the author's choice
  CHECK(!s->on.getValue());
  CHECK(w->undoStack().count() == 2);
  REQUIRE(w->saveScene());  // Ctrl+S: to the same file
  CHECK(w->undoStack().isClean());
  CHECK(!w->isWindowModified());
  text = readAll(path);
  CHECK(text.contains("on FALSE"));
  CHECK(!setsField(text, "speed"));
}

TEST_CASE("Editing: bsdeform-run's final.iv keeps the scene's on and speed", "[ui]") {
  QTemporaryDir dir;
  QProcess run;
  run.start(QStringLiteral(BSDEFORM_RUN), {scenePath("region_load.iv"), QStringLiteral("-n"), QStringLiteral("3"),
                                           QStringLiteral("-o"), dir.path(), QStringLiteral("--overwrite"), QStringLiteral("--quiet")});
  REQUIRE(run.waitForFinished(60000));
  INFO(run.readAllStandardError().toStdString());
  REQUIRE(run.exitCode() == 0);
  const QByteArray text = readAll(dir.filePath(QStringLiteral("final.iv")));
  CHECK(text.contains("stepCount 3"));
  CHECK(!text.contains("on FALSE"));
}

TEST_CASE("Editing: the unsaved-changes prompt on quit and reload, Cancel keeps the window and the edit", "[ui]") {
  auto w = makeWindow("region_load.iv");
  w->pause();
  SoBSplineDeformSurface* s = firstSurface(*w);
  w->setInteractive(true);
  // no edit: no question
  QString seen;
  REQUIRE(w->maybeSave());
  REQUIRE(w->selectNode(s));
  typeInto(w->fieldEditor().editorOf(QStringLiteral("w10")), QStringLiteral("0.3"));
  REQUIRE(!w->undoStack().isClean());
  // quit: Cancel keeps the window open with the edit
  answerNextMessageBox(QMessageBox::Cancel, seen);
  CHECK(!w->close());
  CHECK(seen.contains(QStringLiteral("region_load.iv")));
  CHECK(w->isVisible());
  CHECK(s->w10.getValue() == Approx(0.3));
  // reload: Discard reads the file again
  seen.clear();
  answerNextMessageBox(QMessageBox::Discard, seen);
  w->reload();
  CHECK(!seen.isEmpty());
  SoBSplineDeformSurface* r = firstSurface(*w);
  CHECK(r != s);
  CHECK(r->w10.getValue() == Approx(0.1));
  CHECK(w->undoStack().isClean());
  w->setInteractive(false);
}

TEST_CASE("Editing: the Open dialog starts in scenes/ the first time, then in the last folder used", "[ui]") {
  ensureApp();
  QSettings().remove(QStringLiteral("lastFolder"));
  MainWindow w;
  w.setInteractive(false);
  CHECK(QDir(w.openFolder()) == QDir(QStringLiteral(BSDEFORM_SCENES_DIR)));
  QTemporaryDir dir;
  const QString copy = dir.filePath(QStringLiteral("copy.iv"));
  REQUIRE(QFile::copy(scenePath("region_load.iv"), copy));
  REQUIRE(w.openScene(copy));
  CHECK(QDir(w.openFolder()) == QDir(dir.path()));
}
