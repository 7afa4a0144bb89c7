// SPDX-License-Identifier: MIT
// bsdeform-viewer as an editor (issue 10, items 2, 3, 7): undo/redo, insert/delete, save,
// the unsaved-changes prompt, the field editor, export. Under xvfb-run (tests/CMakeLists.txt).
#include <QAbstractSpinBox>
#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QLabel>
#include <QTextBrowser>
#include <QToolBar>
#include <QDir>
#include <QFile>
#include <QLineEdit>
#include <QMenu>
#include <QMenuBar>
#include <QMessageBox>
#include <QProcess>
#include <QPushButton>
#include <QStatusBar>
#include <QRegularExpression>
#include <QScrollArea>
#include <QSettings>
#include <QTemporaryDir>
#include <QTest>
#include <QTimer>
#include <QUndoStack>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <utility>

#include "DocumentActions.h"
#include "EditCommands.h"
#include "FieldEditor.h"
#include "MainWindow.h"
#include "MaterialPresets.h"
#include "PlotPanel.h"
#include "SceneDocument.h"
#include "ViewerClock.h"
#include "ViewerTestSupport.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/SoBSplineDeformSurface.h"
#include "bsdeform/SoForceField.h"

#include <Inventor/Qt/viewers/SoQtExaminerViewer.h>

using bsdeform::MainWindow;
using namespace viewer_test;

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

// Presses Return on the next modal message box: its default button answers.
void pressReturnOnNextMessageBox(QString& seen) {
  auto* poll = new QTimer;
  QObject::connect(poll, &QTimer::timeout, poll, [poll, &seen] {
    auto* box = qobject_cast<QMessageBox*>(QApplication::activeModalWidget());
    if (!box) return;
    seen = box->text();
    QTest::keyClick(box, Qt::Key_Return);
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
  // the keys: Ctrl+Z and Ctrl+Shift+Z with the 3D view focused
  QWidget* gl = w->viewer()->getGLWidget();
  gl->activateWindow();
  gl->setFocus();
  QTRY_VERIFY(gl->hasFocus());
  QTest::keyClick(gl, Qt::Key_Z, Qt::ControlModifier);
  CHECK(s->w10.getValue() == w10);
  QTest::keyClick(gl, Qt::Key_Z, Qt::ControlModifier | Qt::ShiftModifier);
  CHECK(s->w10.getValue() == 0.25);

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
  CHECK(added->on.getValue());  // the author's value: it follows the clock like the rest
  CHECK(!w->isPlaying());
  passTime(*w, 0.5);
  CHECK(added->simulation().stepCount() == 0);  // and the clock is paused
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

TEST_CASE("Editing: every inserted force field type acts at once the way its name says", "[ui]") {
  auto w = makeWindow("paper_fig7_sinusoidal.iv");  // a 1 x 1 plane at z = 0, clamped all round
  w->pause();
  SoBSplineDeformSurface* s = firstSurface(*w);
  s->forces.setNum(0);  // only the inserted force acts
  auto inserted = [&](int type) {
    s->resetSimulation();  // inserted on the surface at rest
    REQUIRE(w->selectNode(s));
    REQUIRE(w->insertForceField(type));
    return static_cast<SoForceField*>(s->forces[s->forces.getNum() - 1]);
  };
  auto centreAfter = [&](int steps) {
    s->resetSimulation();
    for (int k = 0; k < steps; ++k) w->step();
    return s->simulation().evaluate(0.5, 0.5, 0).position;
  };
  {
    SoForceField* g = inserted(SoForceField::GRAVITY);
    CHECK(g->force.getValue() == SbVec3d(0.0, 0.0, -9.81));  // down, one g
    CHECK(g->magnitude.getValue() == 1.0);
    CHECK(centreAfter(3).z() < 0.0);
    w->undoStack().undo();
  }
  for (int type : {int(SoForceField::UNIFORM), int(SoForceField::POINT), int(SoForceField::REGION), int(SoForceField::EXPRESSION),
                   int(SoForceField::PRESSURE)}) {
    INFO("type " << type);
    inserted(type);
    CHECK(centreAfter(3).z() > 1e-4);  // a load along +z lifts the centre at once
    w->undoStack().undo();
  }
  {
    SoForceField* spring = inserted(SoForceField::SPRING);
    const Eigen::Vector3d centre = s->simulation().evaluate(0.5, 0.5, 0).position;
    CHECK(spring->point.getValue() == SbVec2d(0.5, 0.5));
    CHECK(spring->anchor.getValue() == SbVec3d(centre.x(), centre.y(), centre.z()));  // holds the centre where it is
    CHECK((centreAfter(3) - centre).norm() < 1e-12);
    w->undoStack().undo();
  }
  {
    SoForceField* floor = inserted(SoForceField::PLANE_COLLISION);
    CHECK(floor->normal.getValue() == SbVec3d(0, 0, 1));
    CHECK(floor->center.getValue()[2] < 0.0);  // below the surface, not through it
    CHECK((centreAfter(2) - Eigen::Vector3d(0.5, 0.5, 0.0)).norm() < 1e-12);  // a floor below does not push
    CHECK(s->problem().kind == SoBSplineDeformSurface::Problem::NONE);
    w->undoStack().undo();
  }
  {
    SoForceField* ball = inserted(SoForceField::SPHERE_COLLISION);
    const SbVec3d c = ball->center.getValue();
    CHECK(c[2] + ball->radius.getValue() < 0.0);  // just below the centre, not touching it
    CHECK(std::abs(c[0] - 0.5) < 1e-9);
    CHECK(std::abs(c[1] - 0.5) < 1e-9);
    w->undoStack().undo();
  }
  for (int type : {int(SoForceField::DRAG), int(SoForceField::COLLISION)}) {
    INFO("type " << type);
    inserted(type);
    CHECK((centreAfter(2) - Eigen::Vector3d(0.5, 0.5, 0.0)).norm() < 1e-12);  // nothing moves a surface at rest
    w->undoStack().undo();
  }
}

// The menu Insert > Surface, as the user finds it.
QMenu* insertSurfaceMenu(MainWindow& w) {
  for (QAction* top : w.menuBar()->actions())
    if (top->menu() && top->text() == QStringLiteral("&Insert"))
      for (QAction* a : top->menu()->actions())
        if (a->menu() && a->text() == QStringLiteral("&Surface")) return a->menu();
  return nullptr;
}

TEST_CASE("Editing: Insert > Surface offers the named SHELL materials, inserted with the table's values, and each steps", "[ui][slow]") {
  auto w = makeWindow("region_load.iv");
  w->pause();
  QUndoStack& undo = w->undoStack();
  QMenu* menu = insertSurfaceMenu(*w);
  REQUIRE(menu);
  std::map<QString, QAction*> items;
  for (QAction* a : menu->actions())
    if (!a->isSeparator() && !a->menu()) items[a->text()] = a;
  const std::vector<bsdeform::MaterialPreset>& presets = bsdeform::materialPresets();
  CHECK(items.size() == presets.size() + 1);  // the plain surface and one per material

  // the plain insert as before: the node's defaults, the paper's energy
  REQUIRE(items.count(QStringLiteral("&Plain (default fields)")));
  items[QStringLiteral("&Plain (default fields)")]->trigger();
  REQUIRE(w->document().surfaces().size() == 2);
  SoBSplineDeformSurface* plain = w->document().surfaces()[1];
  CHECK(w->selectedNode() == plain);
  CHECK(plain->energy.getValue() == SoBSplineDeformSurface::PAPER_ENERGY);
  undo.undo();
  REQUIRE(w->document().surfaces().size() == 1);

  for (const bsdeform::MaterialPreset& preset : presets) {
    const QString name = QString::fromUtf8(preset.name);
    INFO(name.toStdString());
    REQUIRE(items.count(name));
    items[name]->trigger();  // as the user does it
    REQUIRE(w->document().surfaces().size() == 2);
    SoBSplineDeformSurface* s = w->document().surfaces()[1];
    CHECK(w->selectedNode() == s);
    CHECK(undo.undoText() == QStringLiteral("Add surface: %1").arg(name));
    CHECK(s->energy.getValue() == SoBSplineDeformSurface::SHELL);
    CHECK(s->youngsModulus.getValue() == preset.youngsModulus);
    CHECK(s->poissonRatio.getValue() == preset.poissonRatio);
    CHECK(s->thickness.getValue() == preset.thickness);
    CHECK(s->density.getValue() == preset.density);
    CHECK(bsdeform::refusalOf(s).isEmpty());
    // the model the surface runs is that material, and it steps under gravity
    const bsdeform::ModelParameters& p = s->simulation().parameters();
    CHECK(p.energy == bsdeform::EnergyModel::Shell);
    CHECK(p.material.youngsModulus == preset.youngsModulus);
    CHECK(p.material.poissonRatio == preset.poissonRatio);
    CHECK(p.material.thickness == preset.thickness);
    CHECK(p.material.density == preset.density);
    REQUIRE(w->insertForceField(SoForceField::GRAVITY));
    REQUIRE(s->stepSimulation(3));
    CHECK(s->simulation().stepCount() == 3);
    CHECK(s->simulation().status() == bsdeform::Status::Ok);
    CHECK(s->simulation().deformationNorm() > 0.0);  // it moved
    undo.undo();  // the gravity
    undo.undo();  // the surface
    CHECK(w->document().surfaces().size() == 1);
  }
}

TEST_CASE("Editing: docs/nodes.md's table of named materials is the presets' table", "[ui]") {
  // Each preset has a row "| name | E | ν | t | ρ | source |" with the same numbers.
  QFile doc(QStringLiteral(BSDEFORM_SCENES_DIR "/../docs/nodes.md"));
  REQUIRE(doc.open(QIODevice::ReadOnly | QIODevice::Text));
  const QStringList lines = QString::fromUtf8(doc.readAll()).split(QLatin1Char('\n'));
  for (const bsdeform::MaterialPreset& preset : bsdeform::materialPresets()) {
    const QString name = QString::fromUtf8(preset.name);
    INFO(name.toStdString());
    QStringList cells;
    for (const QString& line : lines)
      if (line.startsWith(QStringLiteral("| %1 |").arg(name))) cells = line.split(QLatin1Char('|'));
    REQUIRE(cells.size() >= 7);  // "", name, E, ν, t, ρ, source..., ""
    bool ok[4] = {};
    CHECK(cells[2].trimmed().toDouble(&ok[0]) == preset.youngsModulus);
    CHECK(cells[3].trimmed().toDouble(&ok[1]) == preset.poissonRatio);
    CHECK(cells[4].trimmed().toDouble(&ok[2]) == preset.thickness);
    CHECK(cells[5].trimmed().toDouble(&ok[3]) == preset.density);
    CHECK((ok[0] && ok[1] && ok[2] && ok[3]));
  }
}

TEST_CASE("Editing: deleting the only surface leaves a scene that steps, saves and comes back with undo", "[ui]") {
  auto w = makeWindow("region_load.iv");
  w->pause();
  SoBSplineDeformSurface* s = firstSurface(*w);
  REQUIRE(w->selectNode(s));
  REQUIRE(w->deleteSelected());
  CHECK(w->document().surfaces().isEmpty());
  CHECK(w->document().forceFields().isEmpty());
  CHECK(w->fieldEditor().container() == nullptr);
  CHECK(!w->deleteSelected());  // nothing selected
  CHECK(!w->insertForceField(SoForceField::UNIFORM));  // no surface to add it to
  w->step();
  w->reset();
  passTime(*w, 0.25);  // a window with no surface lets time pass
  QTemporaryDir dir;
  REQUIRE(w->saveSceneAs(dir.filePath(QStringLiteral("empty.iv"))));
  CHECK(!readAll(dir.filePath(QStringLiteral("empty.iv"))).contains("SoBSplineDeformSurface"));
  w->undoStack().undo();
  REQUIRE(w->document().surfaces().size() == 1);
  CHECK(w->document().surfaces().first() == s);
  CHECK(w->fieldEditor().container() == s);
  w->step();
  CHECK(s->simulation().stepCount() == 1);
}

TEST_CASE("Editing: a save after pausing keeps on TRUE and the file's speed, Save clears the modified state", "[ui]") {
  auto w = makeWindow("region_load.iv");
  SoBSplineDeformSurface* s = firstSurface(*w);
  w->setSpeed(3.0);
  w->play();
  passTime(*w, 0.1);  // at 3x: 0.3 s of simulated time
  CHECK(s->simulation().time() == Approx(0.3).margin(1e-9));
  w->pause();
  w->step();
  // Play / Pause and the speed are the viewer's clock: the fields stay as the file has them
  CHECK(s->on.getValue());
  CHECK(s->on.isDefault());
  CHECK(s->speed.getValue() == 1.0f);
  QTemporaryDir dir;
  const QString path = dir.filePath(QStringLiteral("paused.iv"));
  REQUIRE(w->saveSceneAs(path));
  QByteArray text = readAll(path);
  CHECK(!text.contains("on FALSE"));
  CHECK(!setsField(text, "speed"));
  CHECK(text.contains("stepCount 4"));
  // what the author sets in the field editor is written, and is not the viewer's Play
  REQUIRE(w->selectNode(s));
  QWidget* on = w->fieldEditor().editorOf(QStringLiteral("on"));
  REQUIRE(on);
  auto* box = qobject_cast<QCheckBox*>(on);
  REQUIRE(box);
  CHECK(box->isChecked());  // the file's value
  box->click();             // `on FALSE`: the author's choice
  CHECK(!s->on.getValue());
  CHECK(!w->isPlaying());
  w->play();
  passTime(*w, 0.5);
  CHECK(s->simulation().stepCount() == 4);  // a surface that does not follow the clock stands still
  w->pause();
  box->click();
  CHECK(s->on.getValue());
  box->click();
  CHECK(!s->on.getValue());
  CHECK(w->undoStack().count() == 3);
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
  // Return on the question is Cancel, not Save: the file stays as it is, the edit too
  seen.clear();
  const QByteArray file = readAll(scenePath("region_load.iv"));
  pressReturnOnNextMessageBox(seen);
  CHECK(!w->close());
  CHECK(!seen.isEmpty());
  CHECK(w->isVisible());
  CHECK(readAll(scenePath("region_load.iv")) == file);
  CHECK(!w->undoStack().isClean());
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

TEST_CASE("Editing: Save As of a template, Record and Save Screenshot start in the user's folder, never the working one",
          "[ui]") {
  // Issue 37, item 7: without ~/Documents the Save dialog of a template proposed the folder the
  // viewer was started in (the repository), and Record's dialog opened there even with one.
  ensureApp();
  QTemporaryDir home;
  const QByteArray oldHome = qgetenv("HOME");
  qputenv("HOME", QFile::encodeName(home.path()));
  QSettings().remove(QStringLiteral("lastFolder"));
  CHECK(QDir(bsdeform::DocumentActions::userFolder()) == QDir(home.path()));  // no ~/Documents
  REQUIRE(QDir(home.path()).mkdir(QStringLiteral("Documents")));
  CHECK(QDir(bsdeform::DocumentActions::userFolder()) == QDir(home.filePath(QStringLiteral("Documents"))));
  // a shipped scene's folder is never proposed; a folder of the user's is, once used
  QSettings().setValue(QStringLiteral("lastFolder"), QStringLiteral(BSDEFORM_SCENES_DIR));
  CHECK(QDir(bsdeform::DocumentActions::userFolder()) == QDir(home.filePath(QStringLiteral("Documents"))));
  QTemporaryDir mine;
  QSettings().setValue(QStringLiteral("lastFolder"), mine.path());
  CHECK(QDir(bsdeform::DocumentActions::userFolder()) == QDir(mine.path()));
  QSettings().remove(QStringLiteral("lastFolder"));
  qputenv("HOME", oldHome);
}

// ---------------------------------------------------------------------------------------------
// The field editor (item 3)

namespace {

QString textOf(QWidget* editor) {
  REQUIRE(editor);
  if (auto* spin = qobject_cast<QAbstractSpinBox*>(editor)) return spin->text();
  if (auto* label = qobject_cast<QLabel*>(editor)) return label->text();
  if (auto* line = qobject_cast<QLineEdit*>(editor)) return line->text();
  if (auto* spin = editor->findChild<QAbstractSpinBox*>()) return spin->text();
  FAIL("no text in this editor");
  return QString();
}

QWidget* glWidget(MainWindow& w) { return w.viewer()->getGLWidget(); }

// A window with `scene`, paused, its first surface selected in the scene panel (and editor).
std::unique_ptr<MainWindow> pausedWithSurfaceSelected(const char* scene) {
  auto w = makeWindow(scene);
  w->pause();
  REQUIRE(w->selectNode(firstSurface(*w)));
  return w;
}

// Gives the keyboard focus to `widget` and waits until it has it.
void focus(QWidget* widget) {
  widget->activateWindow();
  widget->setFocus(Qt::OtherFocusReason);
  QTRY_VERIFY(widget->hasFocus());
}

}  // namespace

TEST_CASE("Field editor: typed editors with the field's range, values without float noise, tooltips from the field table", "[ui]") {
  auto w = pausedWithSurfaceSelected("region_load.iv");
  SoBSplineDeformSurface* s = firstSurface(*w);
  bsdeform::FieldEditor& ed = w->fieldEditor();
  auto* w10 = qobject_cast<QDoubleSpinBox*>(ed.editorOf(QStringLiteral("w10")));
  REQUIRE(w10);
  CHECK(w10->minimum() == 0.0);
  CHECK(w10->text() == QStringLiteral("0.1"));
  auto* degree = qobject_cast<QAbstractSpinBox*>(ed.editorOf(QStringLiteral("uDegree")));
  REQUIRE(degree);
  CHECK(qobject_cast<QDoubleSpinBox*>(degree)->maximum() == 7.0);
  CHECK(qobject_cast<QComboBox*>(ed.editorOf(QStringLiteral("integrator"))));
  CHECK(qobject_cast<QCheckBox*>(ed.editorOf(QStringLiteral("on"))));
  CHECK(ed.editorOf(QStringLiteral("radii"))->findChildren<QDoubleSpinBox*>().size() == 3);
  // a float field: 0.3f is shown as 0.3
  s->speed = 0.3f;
  ed.refresh();
  CHECK(textOf(ed.editorOf(QStringLiteral("speed"))) == QStringLiteral("0.3"));
  s->damping = 0.1 + 0.2;  // 0.30000000000000004: shown as the double it is, no more digits
  ed.refresh();
  CHECK(textOf(ed.editorOf(QStringLiteral("damping"))) == QStringLiteral("0.30000000000000004"));
  // the tooltip: meaning, unit, range, paper symbol
  const QString tip = ed.editorOf(QStringLiteral("w10"))->toolTip();
  CHECK(tip.contains(QStringLiteral("stretching along u")));
  CHECK(tip.contains(QStringLiteral("ω10")));
  CHECK(tip.contains(QStringLiteral("Range: &gt;= 0")));
  CHECK(tip.contains(QStringLiteral("Unit:")));

  // a force field shows the fields its type reads, and follows a type change
  REQUIRE(w->insertForceField(SoForceField::POINT));
  CHECK(ed.editorOf(QStringLiteral("point")));
  CHECK(ed.editorOf(QStringLiteral("force")));
  CHECK(!ed.editorOf(QStringLiteral("regionMin")));
  CHECK(!ed.editorOf(QStringLiteral("coefficient")));
  auto* type = qobject_cast<QComboBox*>(ed.editorOf(QStringLiteral("type")));
  REQUIRE(type);
  type->setCurrentIndex(type->findText(QStringLiteral("DRAG")));
  emit type->activated(type->currentIndex());
  processEvents();  // the rows are rebuilt
  CHECK(ed.editorOf(QStringLiteral("coefficient")));
  CHECK(!ed.editorOf(QStringLiteral("point")));
  CHECK(!ed.editorOf(QStringLiteral("force")));
  w->undoStack().undo();  // back to POINT
  processEvents();
  CHECK(ed.editorOf(QStringLiteral("point")));
  CHECK(!ed.editorOf(QStringLiteral("coefficient")));

  // Help > Field Reference shows the same table
  w->showFieldReference();
  auto* browser = w->findChild<QTextBrowser*>();
  REQUIRE(browser);
  CHECK(browser->toPlainText().contains(QStringLiteral("regionMin")));
  CHECK(browser->toPlainText().contains(QStringLiteral("stretching along u")));
}

TEST_CASE("Field editor: an invalid value is shown in red with the reason and reverted when the editor loses focus", "[ui]") {
  auto w = pausedWithSurfaceSelected("region_load.iv");
  SoBSplineDeformSurface* s = firstSurface(*w);
  bsdeform::FieldEditor& ed = w->fieldEditor();
  // outside the field's range: the text stays, in red, with the reason; the field keeps 0.1
  QWidget* w10 = ed.editorOf(QStringLiteral("w10"));
  typeInto(w10, QStringLiteral("-1"));
  CHECK(textOf(w10) == QStringLiteral("-1"));
  CHECK(ed.messageOf(QStringLiteral("w10")).contains(QStringLiteral("outside the range >= 0")));
  CHECK(w10->styleSheet().contains(QStringLiteral("background")));
  CHECK(s->w10.getValue() == 0.1);
  CHECK(w->undoStack().count() == 0);
  focus(glWidget(*w));
  QTRY_COMPARE(textOf(w10), QStringLiteral("0.1"));
  CHECK(w10->styleSheet().isEmpty());
  CHECK(ed.messageOf(QStringLiteral("w10")).startsWith(QStringLiteral("Not applied")));

  // values the node refuses: a rectangle with u0 > u1 (the core's message), and PERIODIC on one side
  SoEngine* region = s->forces[0];
  REQUIRE(w->selectNode(region));
  QWidget* regionMin = ed.editorOf(QStringLiteral("regionMin"));
  typeInto(regionMin, QStringLiteral("0.8"));
  CHECK(ed.messageOf(QStringLiteral("regionMin")).contains(QStringLiteral("u0 <= u1")));
  CHECK(static_cast<SoForceField*>(region)->regionMin.getValue()[0] == 0.3);
  focus(glWidget(*w));
  QTRY_COMPARE(textOf(regionMin), QStringLiteral("0.3"));
  CHECK(w->undoStack().count() == 0);

  REQUIRE(w->selectNode(s));
  auto* side = qobject_cast<QComboBox*>(ed.editorOf(QStringLiteral("boundaryUMin")));
  REQUIRE(side);
  emit side->activated(side->findText(QStringLiteral("PERIODIC")));
  CHECK(ed.messageOf(QStringLiteral("boundaryUMin")).contains(QStringLiteral("PERIODIC")));
  CHECK(s->boundaryUMin.getValue() == SoBSplineDeformSurface::CLAMPED);
  CHECK(side->currentText() == QStringLiteral("CLAMPED"));  // a choice goes back at once
  w->step();
  CHECK(s->simulation().status() == bsdeform::Status::Ok);
  CHECK(w->undoStack().count() == 0);
}

TEST_CASE("Field editor: live time and steps, and a net-size change says that it restarts", "[ui]") {
  auto w = pausedWithSurfaceSelected("region_load.iv");
  SoBSplineDeformSurface* s = firstSurface(*w);
  bsdeform::FieldEditor& ed = w->fieldEditor();
  for (int i = 0; i < 3; ++i) w->step();
  processEvents();  // the window refreshes once after the steps it was told of
  CHECK(textOf(ed.editorOf(QStringLiteral("stepCount"))) == QStringLiteral("3"));
  CHECK(textOf(ed.editorOf(QStringLiteral("simulationTime"))) == QStringLiteral("0.3"));
  CHECK(ed.editorOf(QStringLiteral("numUControlPoints"))->toolTip().contains(QStringLiteral("restarts")));
  typeInto(ed.editorOf(QStringLiteral("numUControlPoints")), QStringLiteral("12"));
  CHECK(s->numUControlPoints.getValue() == 12);
  CHECK(ed.messageOf(QStringLiteral("numUControlPoints")).contains(QStringLiteral("restarted")));
  CHECK(s->simulation().time() == 0.0);
  CHECK(s->simulation().parameters().numU == 12);
}

TEST_CASE("Field editor: Space, S, R and D act on the simulation from the 3D view and the toolbar, never typed into an editor", "[ui]") {
  auto w = pausedWithSurfaceSelected("region_load.iv");
  SoBSplineDeformSurface* s = firstSurface(*w);
  QWidget* gl = glWidget(*w);
  focus(gl);
  QTest::keyClick(gl, Qt::Key_S);
  CHECK(s->simulation().stepCount() == 1);
  QTest::keyClick(gl, Qt::Key_Space);
  CHECK(w->isPlaying());
  QTest::keyClick(gl, Qt::Key_Space);
  CHECK(!w->isPlaying());
  // the toolbar's speed box lets them through
  auto* speed = w->findChild<QToolBar*>(QStringLiteral("simulationToolBar"))->findChild<QDoubleSpinBox*>();
  REQUIRE(speed);
  focus(speed);
  QTest::keyClick(speed, Qt::Key_S);
  CHECK(s->simulation().stepCount() == 2);
  QTest::keyClick(speed, Qt::Key_R);
  CHECK(s->simulation().stepCount() == 0);
  CHECK(speed->value() == 1.0);
  // after an edit confirmed with Return the keyboard is back in the 3D view
  QWidget* w10 = w->fieldEditor().editorOf(QStringLiteral("w10"));
  typeInto(w10, QStringLiteral("0.2"));
  CHECK(s->w10.getValue() == 0.2);
  QTRY_VERIFY(gl->hasFocus());
  QTest::keyClick(QApplication::focusWidget(), Qt::Key_S);
  CHECK(s->simulation().stepCount() == 1);
  CHECK(textOf(w10) == QStringLiteral("0.2"));
  // a number editor with focus does not take S as text either
  focus(w10);
  QTest::keyClick(w10, Qt::Key_S);
  CHECK(s->simulation().stepCount() == 2);
  CHECK(textOf(w10) == QStringLiteral("0.2"));
}

// ---------------------------------------------------------------------------------------------
// Export (item 7)

namespace {

// A scene file in `dir`: a 5 x 5 bicubic surface moved by (2, 0, 0), paused, pushed up.
QString translatedScene(const QTemporaryDir& dir) {
  const QString path = dir.filePath(QStringLiteral("moved.iv"));
  writeFile(path, "#Inventor V2.1 ascii\nSeparator { Translation { translation 2 0 0 }\n"
                  "  SoBSplineDeformSurface { on FALSE numUControlPoints 5 numVControlPoints 5\n"
                  "    forces [ SoForceField { type UNIFORM force 0 0 5 } ] } }\n");
  return path;
}

// A window with that scene, five steps on.
std::unique_ptr<MainWindow> pushedForExport(const QTemporaryDir& dir) {
  ensureApp();
  auto w = std::make_unique<MainWindow>();
  w->setInteractive(false);
  REQUIRE(w->openScene(translatedScene(dir)));
  for (int i = 0; i < 5; ++i) w->step();
  return w;
}

QList<QByteArray> linesStartingWith(const QByteArray& text, const char* prefix) {
  QList<QByteArray> out;
  for (const QByteArray& line : text.split('\n'))
    if (line.startsWith(prefix)) out << line;
  return out;
}

}  // namespace

TEST_CASE("Export: the OBJ is one connected grid, (s+1)^2 shared vertices for s^2 quads, with normals and (u, v)", "[ui]") {
  QTemporaryDir dir;
  std::unique_ptr<MainWindow> window = pushedForExport(dir);
  MainWindow& w = *window;
  const QString path = dir.filePath(QStringLiteral("mesh.obj"));
  REQUIRE(w.exportMesh(path));
  const QByteArray text = readAll(path);
  const int vertices = linesStartingWith(text, "v ").size();
  const QList<QByteArray> faces = linesStartingWith(text, "f ");
  CHECK(linesStartingWith(text, "vt ").size() == vertices);
  CHECK(linesStartingWith(text, "vn ").size() == vertices);
  // a square grid of s x s quads, two triangles each
  const int s = int(std::lround(std::sqrt(faces.size() / 2.0)));
  INFO("vertices " << vertices << ", triangles " << faces.size());
  REQUIRE(s > 4);
  CHECK(faces.size() == 2 * s * s);
  CHECK(vertices == (s + 1) * (s + 1));
  // Blender's view: faces share vertex indices; every edge lies on one face (the border) or two,
  // and the border is the 4 s edges of the square
  std::map<std::pair<int, int>, int> edges;
  for (const QByteArray& face : faces) {
    const QList<QByteArray> corners = face.mid(2).trimmed().split(' ');
    REQUIRE(corners.size() == 3);
    int idx[3];
    for (int k = 0; k < 3; ++k) {
      const QList<QByteArray> parts = corners[k].split('/');
      REQUIRE(parts.size() == 3);
      idx[k] = parts[0].toInt();
      CHECK(parts[1].toInt() == idx[k]);  // its (u, v) and normal under the same index
      CHECK(parts[2].toInt() == idx[k]);
      CHECK(idx[k] >= 1);
      CHECK(idx[k] <= vertices);
    }
    for (int k = 0; k < 3; ++k) ++edges[std::minmax(idx[k], idx[(k + 1) % 3])];
  }
  int border = 0, inner = 0, other = 0;
  for (const auto& e : edges) (e.second == 1 ? border : e.second == 2 ? inner : other)++;
  CHECK(other == 0);
  CHECK(border == 4 * s);
  // world coordinates: the translation is applied
  double minX = 1e9;
  for (const QByteArray& v : linesStartingWith(text, "v ")) minX = std::min(minX, v.split(' ')[1].toDouble());
  CHECK(minX == Approx(2.0).margin(1e-6));
  // STL as before: one record per triangle
  REQUIRE(w.exportMesh(dir.filePath(QStringLiteral("mesh.stl"))));
  CHECK(readAll(dir.filePath(QStringLiteral("mesh.stl"))).size() == 84 + 50 * faces.size());
}

TEST_CASE("Export: the control net as x y z points and as OBJ points with the net's lines, in world coordinates", "[ui]") {
  QTemporaryDir dir;
  std::unique_ptr<MainWindow> window = pushedForExport(dir);
  MainWindow& w = *window;
  SoBSplineDeformSurface* s = firstSurface(w);
  const bsdeform::ControlNet& net = s->simulation().current();
  const int rows = s->simulation().space().netRows(), cols = s->simulation().space().netCols();
  REQUIRE(rows == 11);
  REQUIRE(net.rows() == rows * cols);
  REQUIRE(w.exportControlNet(dir.filePath(QStringLiteral("net.xyz"))));
  QList<QByteArray> points;
  for (const QByteArray& line : readAll(dir.filePath(QStringLiteral("net.xyz"))).split('\n'))
    if (!line.isEmpty() && !line.startsWith('#')) points << line;
  REQUIRE(points.size() == rows * cols);
  double lifted = 0.0;
  for (int i = 0; i < points.size(); ++i) {
    const QList<QByteArray> xyz = points[i].split(' ');
    REQUIRE(xyz.size() == 3);
    CHECK(xyz[0].toDouble() == Approx(net(i, 0) + 2.0).margin(1e-6));
    CHECK(xyz[1].toDouble() == Approx(net(i, 1)).margin(1e-6));
    CHECK(xyz[2].toDouble() == Approx(net(i, 2)).margin(1e-6));
    lifted = std::max(lifted, xyz[2].toDouble());
  }
  CHECK(lifted > 0.0);  // the pushed state, not the rest net
  REQUIRE(w.exportControlNet(dir.filePath(QStringLiteral("net.obj"))));
  const QByteArray obj = readAll(dir.filePath(QStringLiteral("net.obj")));
  CHECK(linesStartingWith(obj, "v ").size() == rows * cols);
  const QList<QByteArray> lines = linesStartingWith(obj, "l ");
  REQUIRE(lines.size() == rows + cols);
  CHECK(lines[0].split(' ').size() == 1 + cols);      // a row: cols points
  CHECK(lines[rows].split(' ').size() == 1 + rows);   // a column: rows points
  CHECK(!w.exportControlNet(dir.filePath(QStringLiteral("net.stl"))));
}

TEST_CASE("Editing: Simulation > Solve Static puts the surface at its equilibrium, undo and redo, a loose surface is refused",
          "[ui]") {
  auto w = makeWindow("cantilever.iv");
  SoBSplineDeformSurface* s = firstSurface(*w);
  s->stepSimulation(3);  // a state of its own, which undo must bring back
  const bsdeform::ControlNet before = s->simulation().current();
  const double t = s->simulation().time();
  REQUIRE(w->solveStatic());
  CHECK(!w->isPlaying());
  // the plots show the equilibrium, one sample, as a mark (a line of one point is not drawn)
  processEvents();
  CHECK(w->plotPanel().sampleCount() == 1);
  CHECK(w->plotPanel().marksPoints());
  CHECK(s->simulation().evaluate(1.0, 0.5).position.z() == Approx(-0.25).epsilon(1e-9));
  CHECK(s->simulation().current() == s->simulation().previous());
  CHECK(s->simulation().time() == 0.0);
  const bsdeform::ControlNet equilibrium = s->simulation().current();
  w->undoStack().undo();
  CHECK((s->simulation().current() - before).cwiseAbs().maxCoeff() <= 1e-14);
  CHECK(s->simulation().time() == Approx(t));
  w->undoStack().redo();
  CHECK((s->simulation().current() - equilibrium).cwiseAbs().maxCoeff() <= 1e-14);
  CHECK(w->isWindowModified());
  // every side FREE: nothing holds it, the error names the free motions, nothing changes
  s->boundaryUMin = SoBSplineDeformSurface::FREE;
  s->resetSimulation();
  const int commands = w->undoStack().count();
  CHECK(!w->solveStatic());
  CHECK(w->lastError().contains(QStringLiteral("translations")));
  CHECK(w->undoStack().count() == commands);
  CHECK(s->simulation().deformationNorm() == 0.0);
}

// ---------------------------------------------------------------------------------------------
// Values a file gives that the nodes refuse (issue 26, item 6)

namespace {

QString stateOfStatusBar(MainWindow& w) {
  QString all;
  for (QLabel* l : w.statusBar()->findChildren<QLabel*>()) all += l->text() + QLatin1Char('\n');
  return all;
}

}  // namespace

TEST_CASE("Refusals: a file's refused values are listed when it opens, shown as read in red, and the status stays red until fixed",
          "[ui]") {
  QTemporaryDir dir;
  const QString path = dir.filePath(QStringLiteral("refused.iv"));
  writeFile(path, "#Inventor V2.1 ascii\nSeparator {\n"
                  "  DEF Sheet SoBSplineDeformSurface { uDegree 9\n"
                  "    forces [ DEF Bump SoForceField { type EXPRESSION expression [ \"sin(\", \"0\", \"0\" ] } ] }\n"
                  "  DEF Fine SoBSplineDeformSurface { numUControlPoints 6 }\n"
                  "}\n");
  ensureApp();
  auto window = std::make_unique<MainWindow>();
  MainWindow& w = *window;
  w.setInteractive(false);
  w.clock().setWallClock(false);
  REQUIRE(w.openScene(path));
  // one box lists every problem: node, field, the file's value, the reason
  const QString box = w.lastError();
  INFO(box.toStdString());
  CHECK(box.contains(QStringLiteral("Sheet: uDegree = 9: ")));
  CHECK(box.contains(QStringLiteral("Bump: ")));
  CHECK(box.contains(QStringLiteral("sin(")));
  CHECK_FALSE(box.contains(QStringLiteral("Fine")));  // a surface without a problem is not listed
  // the editor shows 9 (not the 7 its range would clamp to), in red, with the node's reason
  auto* sheet = static_cast<SoBSplineDeformSurface*>(SoNode::getByName("Sheet"));
  auto* fine = static_cast<SoBSplineDeformSurface*>(SoNode::getByName("Fine"));
  REQUIRE(sheet);
  REQUIRE(fine);
  REQUIRE(w.selectNode(sheet));
  bsdeform::FieldEditor& ed = w.fieldEditor();
  QWidget* degree = ed.editorOf(QStringLiteral("uDegree"));
  CHECK(textOf(degree) == QStringLiteral("9"));
  CHECK(degree->styleSheet().contains(QStringLiteral("#ffd0d0")));
  CHECK(ed.messageOf(QStringLiteral("uDegree")).contains(QStringLiteral("uDegree")));
  w.show();
  processEvents();
  w.windowScreenshot().save(QStringLiteral("viewer_refused_value.png"));  // looked at
  // another field of the same surface can still be edited: the refusal is the file's, not its
  typeInto(ed.editorOf(QStringLiteral("numUControlPoints")), QStringLiteral("8"));
  CHECK(sheet->numUControlPoints.getValue() == 8);
  processEvents();
  // the status bar names the refusal, in red, also while the other surface is selected
  CHECK(stateOfStatusBar(w).contains(QStringLiteral("refused: Sheet.uDegree")));
  REQUIRE(w.selectNode(fine));
  processEvents();
  INFO(stateOfStatusBar(w).toStdString());
  CHECK(stateOfStatusBar(w).contains(QStringLiteral("refused: Sheet.uDegree")));
  CHECK(stateOfStatusBar(w).contains(QStringLiteral("#c00")));
  // fixed from the editor: the mark and the red go
  REQUIRE(w.selectNode(sheet));
  degree = ed.editorOf(QStringLiteral("uDegree"));
  REQUIRE(qobject_cast<QAbstractSpinBox*>(degree));
  typeInto(degree, QStringLiteral("3"));
  CHECK(sheet->uDegree.getValue() == 3);
  processEvents();
  ed.refresh();
  CHECK(ed.messageOf(QStringLiteral("uDegree")).isEmpty());
  CHECK_FALSE(degree->styleSheet().contains(QStringLiteral("#ffd0d0")));
  CHECK(sheet->problem().kind != SoBSplineDeformSurface::Problem::FIELD);
  CHECK_FALSE(stateOfStatusBar(w).contains(QStringLiteral("Sheet.uDegree")));
}

TEST_CASE("Refusals: three bad values of a surface and two of a force field are all listed, shown as read, and nothing runs",
          "[ui]") {
  // Issue 37, item 3: the dialog listed only the first refused value of each surface, the editor
  // clamped the others silently (poissonRatio 0.7 as 0.4999999, thickness -0.001 as 1e-300), and
  // the default model ran under gravity behind the dialog.
  QTemporaryDir dir;
  const QString path = dir.filePath(QStringLiteral("three.iv"));
  writeFile(path, "#Inventor V2.1 ascii\nSeparator {\n"
                  "  DEF Cloth SoBSplineDeformSurface { energy SHELL uDegree 9 poissonRatio 0.7 thickness -0.001\n"
                  "    boundaryVMin FREE boundaryVMax FREE\n"
                  "    forces [ SoForceField { type GRAVITY },\n"
                  "             DEF Tether SoForceField { type SPRING point 2 0.5 stiffness -5 } ] }\n"
                  "}\n");
  ensureApp();
  auto window = std::make_unique<MainWindow>();
  MainWindow& w = *window;
  w.setInteractive(false);
  w.clock().setWallClock(false);
  REQUIRE(w.openScene(path));
  const QString box = w.lastError();
  INFO(box.toStdString());
  for (const char* row : {"Cloth: uDegree = 9: ", "Cloth: poissonRatio = 0.7: ", "Cloth: thickness = -0.001: ",
                          "Tether: point = 2 0.5: ", "Tether: stiffness = -5: "})
    CHECK(box.contains(QLatin1String(row)));
  auto* cloth = static_cast<SoBSplineDeformSurface*>(SoNode::getByName("Cloth"));
  REQUIRE(cloth);
  CHECK(cloth->refusals().size() == 3);
  // a scene opened with refusals starts paused, and Play and Step do not run it
  CHECK_FALSE(w.isPlaying());
  w.play();
  CHECK_FALSE(w.isPlaying());
  w.step();
  passTime(w, 1.0);
  CHECK(cloth->simulation().time() == 0.0);
  CHECK(cloth->stepCount.getValue() == 0);
  // every value as the file has it, red, with its reason
  REQUIRE(w.selectNode(cloth));
  bsdeform::FieldEditor& ed = w.fieldEditor();
  const std::pair<const char*, const char*> shown[] = {{"uDegree", "9"}, {"poissonRatio", "0.7"}, {"thickness", "-0.001"}};
  for (const auto& f : shown) {
    INFO(f.first);
    QWidget* editor = ed.editorOf(QLatin1String(f.first));
    CHECK(textOf(editor) == QLatin1String(f.second));
    CHECK(editor->styleSheet().contains(QStringLiteral("#ffd0d0")));
    CHECK(ed.messageOf(QLatin1String(f.first)).contains(QLatin1String(f.first)));
  }
  auto* tether = static_cast<SoForceField*>(SoBase::getNamedBase("Tether", SoForceField::getClassTypeId()));
  REQUIRE(tether);
  REQUIRE(w.selectNode(tether));
  CHECK(ed.editorOf(QStringLiteral("stiffness"))->styleSheet().contains(QStringLiteral("#ffd0d0")));
  CHECK(ed.editorOf(QStringLiteral("point"))->styleSheet().contains(QStringLiteral("#ffd0d0")));
  // the status bar names every refused value of every node
  processEvents();
  const QString status = stateOfStatusBar(w);
  INFO(status.toStdString());
  for (const char* what : {"Cloth.uDegree", "Cloth.poissonRatio", "Cloth.thickness", "Tether.point", "Tether.stiffness"})
    CHECK(status.contains(QLatin1String(what)));
  // fixed one by one: still nothing runs until the last is fixed
  cloth->uDegree = 3;
  cloth->poissonRatio = 0.3;
  cloth->thickness = 0.001;
  tether->point.setValue(0.5, 0.5);
  processEvents();
  w.play();
  CHECK_FALSE(w.isPlaying());  // the tether's stiffness is still refused
  tether->stiffness = 5;
  processEvents();
  w.play();
  CHECK(w.isPlaying());
  passTime(w, 0.2);
  CHECK(cloth->simulation().time() > 0.0);
}

TEST_CASE("Field editor: a SHELL scene's numbers as written, and the obstacles by their names", "[ui]") {
  // Issue 37, item 4: youngsModulus 821000.0000000001 and poissonRatio 0.24300000000000002 in
  // every SHELL scene; the obstacles as raw Inventor text ("height 0.60000002").
  ensureApp();
  {
    auto w = makeWindow("curtain.iv");
    auto* curtain = static_cast<SoBSplineDeformSurface*>(SoNode::getByName("Curtain"));
    REQUIRE(curtain);
    REQUIRE(w->selectNode(curtain));
    bsdeform::FieldEditor& ed = w->fieldEditor();
    CHECK(textOf(ed.editorOf(QStringLiteral("youngsModulus"))) == QStringLiteral("821000"));
    CHECK(textOf(ed.editorOf(QStringLiteral("poissonRatio"))) == QStringLiteral("0.243"));
    CHECK(textOf(ed.editorOf(QStringLiteral("thickness"))) == QStringLiteral("0.000318"));
    CHECK(textOf(ed.editorOf(QStringLiteral("density"))) == QStringLiteral("472.6"));
  }
  QTemporaryDir dir;
  const QString path = dir.filePath(QStringLiteral("two.iv"));
  writeFile(path, "#Inventor V2.1 ascii\nSeparator {\n"
                  "  Separator { Transform { translation 0.3 0.5 -0.6 } DEF Ball Sphere { radius 0.5 } }\n"
                  "  Separator { Transform { translation 0.7 0.5 -0.6 } DEF Box Cube { height 0.6 } }\n"
                  "  SoBSplineDeformSurface { on FALSE numUControlPoints 6 numVControlPoints 6\n"
                  "    forces [ DEF Contact SoForceField { type COLLISION obstacles [ USE Ball, USE Box ] } ] } }\n");
  auto window = std::make_unique<MainWindow>();
  MainWindow& w = *window;
  w.setInteractive(false);
  w.clock().setWallClock(false);
  REQUIRE(w.openScene(path));
  auto* contact = static_cast<SoForceField*>(SoBase::getNamedBase("Contact", SoForceField::getClassTypeId()));
  REQUIRE(contact);
  REQUIRE(w.selectNode(contact));
  bsdeform::FieldEditor& ed = w.fieldEditor();
  QWidget* obstacles = ed.editorOf(QStringLiteral("obstacles"));
  CHECK(textOf(obstacles) == QStringLiteral("Ball, Box"));
  typeInto(obstacles, QStringLiteral("Box"));
  REQUIRE(contact->obstacles.getNum() == 1);
  CHECK(contact->obstacles[0] == SoNode::getByName("Box"));
  // a name that names nothing is refused, the list kept
  typeInto(ed.editorOf(QStringLiteral("obstacles")), QStringLiteral("Box, Nowhere"));
  CHECK(contact->obstacles.getNum() == 1);
  CHECK(ed.messageOf(QStringLiteral("obstacles")).contains(QStringLiteral("not a valid value")));
}

TEST_CASE("Editor: at the window's default size the field editor shows its rows whole, with no sideways scrolling",
          "[ui]") {
  auto w = makeWindow("region_load.iv");
  processEvents();
  REQUIRE(w->selectNode(w->document().surfaces().front()));
  processEvents();
  auto* scroll = w->findChild<QScrollArea*>(QStringLiteral("fieldEditorScroll"));
  REQUIRE(scroll);
  const QWidget* viewport = scroll->viewport();
  // every editor lies within the width; count the rows wholly visible from the top
  int whole = 0;
  for (const char* name : {"numUControlPoints", "numVControlPoints", "uDegree", "vDegree", "w10", "w01", "w11", "w20",
                           "w02", "energy", "massModel", "mass", "damping", "timeStep"}) {
    QWidget* e = w->fieldEditor().editorOf(QLatin1String(name));
    REQUIRE(e);
    const QRect r(e->mapTo(viewport, QPoint(0, 0)), e->size());
    INFO(name << " at " << r.x() << "," << r.y() << " " << r.width() << "x" << r.height() << " in " << viewport->width() << "x"
              << viewport->height());
    CHECK(r.left() >= 0);
    CHECK(r.right() < viewport->width());
    if (r.top() >= 0 && r.bottom() < viewport->height()) ++whole;
  }
  CHECK(whole >= 12);
}

TEST_CASE("Editing: a shipped scene opens as a template, Save never writes over it, Save As makes it the user's",
          "[ui]") {
  ensureApp();
  auto window = std::make_unique<MainWindow>();
  MainWindow& w = *window;
  w.setInteractive(false);
  w.clock().setWallClock(false);
  const QString shipped = scenePath("curtain.iv");
  const QByteArray original = readAll(shipped);
  REQUIRE(w.openScene(shipped));
  CHECK(w.isTemplate());
  CHECK(w.windowTitle().contains(QStringLiteral("(template)")));
  for (int i = 0; i < 3; ++i) w.step();
  REQUIRE(w.selectNode(firstSurface(w)));
  typeInto(w.fieldEditor().editorOf(QStringLiteral("damping")), QStringLiteral("0.7"));
  REQUIRE(!w.undoStack().isClean());
  // Save: refused (interactive, it asks for a name), the shipped file untouched
  CHECK_FALSE(w.saveScene());
  CHECK(w.lastError().contains(QStringLiteral("template")));
  CHECK(readAll(shipped) == original);
  // Save As: the user's own file, no longer a template; Save writes there from now on
  QTemporaryDir dir;
  const QString mine = dir.filePath(QStringLiteral("my_curtain.iv"));
  REQUIRE(w.saveSceneAs(mine));
  CHECK_FALSE(w.isTemplate());
  CHECK_FALSE(w.windowTitle().contains(QStringLiteral("(template)")));
  CHECK(readAll(mine).startsWith("#Inventor V2.1 ascii"));
  CHECK(readAll(mine).contains("# "));  // the template's comment block came along
  typeInto(w.fieldEditor().editorOf(QStringLiteral("damping")), QStringLiteral("0.8"));
  CHECK(w.saveScene());
  CHECK(readAll(mine).contains("damping 0.8"));
  CHECK(readAll(shipped) == original);
  // a copy of a shipped scene elsewhere is the user's file: not a template
  const QString copy = dir.filePath(QStringLiteral("copy.iv"));
  REQUIRE(QFile::copy(shipped, copy));
  REQUIRE(w.openScene(copy));
  CHECK_FALSE(w.isTemplate());
}

TEST_CASE("Field editor: a bit mask (holdVMax) is one check box per component, and a click edits the field", "[ui]") {
  ensureApp();
  auto w = makeWindow("scordelis_lo_roof.iv");
  auto* roof = static_cast<SoBSplineDeformSurface*>(SoNode::getByName("Roof"));
  REQUIRE(roof);
  REQUIRE(w->selectNode(roof));
  bsdeform::FieldEditor& ed = w->fieldEditor();
  QWidget* editor = ed.editorOf(QStringLiteral("holdVMax"));
  REQUIRE(editor);
  const auto boxes = editor->findChildren<QCheckBox*>();
  REQUIRE(boxes.size() == 3);
  QCheckBox *x = nullptr, *y = nullptr, *z = nullptr;
  for (QCheckBox* b : boxes) (b->text() == QLatin1String("X") ? x : b->text() == QLatin1String("Y") ? y : z) = b;
  REQUIRE((x && y && z));
  CHECK(x->isChecked());  // the diaphragm: X | Z
  CHECK(!y->isChecked());
  CHECK(z->isChecked());
  y->click();
  CHECK(roof->holdVMax.getValue() == (SoBSplineDeformSurface::X | SoBSplineDeformSurface::Y | SoBSplineDeformSurface::Z));
  x->click();
  CHECK(roof->holdVMax.getValue() == (SoBSplineDeformSurface::Y | SoBSplineDeformSurface::Z));
}
