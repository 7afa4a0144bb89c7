// SPDX-License-Identifier: MIT
// bsdeform-viewer's habits of desktop 3D programs (issue 26, item 7): the wheel zooms in
// forward, towards the cursor; undersides of open surfaces are lit; a ground grid and an axes
// gizmo; a click in the view selects in the scene panel.
#include <Inventor/Qt/viewers/SoQtExaminerViewer.h>
#include <Inventor/SoPickedPoint.h>
#include <Inventor/SoSceneManager.h>
#include <Inventor/actions/SoRayPickAction.h>
#include <Inventor/actions/SoSearchAction.h>
#include <Inventor/nodes/SoCamera.h>
#include <Inventor/nodes/SoDirectionalLight.h>
#include <Inventor/nodes/SoOrthographicCamera.h>
#include <Inventor/nodes/SoSeparator.h>
#include <Inventor/nodes/SoSwitch.h>

#include <QAction>
#include <QFile>
#include <QMenuBar>
#include <QSettings>
#include <QTemporaryDir>
#include <QTest>
#include <QWheelEvent>
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>

#include "AxesGizmo.h"
#include "Backlight.h"
#include "ClickSelect.h"
#include "ControlNetDisplay.h"
#include "DragTool.h"
#include "FieldEditor.h"
#include "GroundGrid.h"
#include "MainWindow.h"
#include "ViewDecorations.h"
#include "ViewFraming.h"
#include "ViewerTestSupport.h"
#include "WheelZoom.h"
#include "bsdeform/DefaultView.h"
#include "bsdeform/SoBSplineDeformSurface.h"
#include "bsdeform/SoForceField.h"

using namespace viewer_test;
using bsdeform::MainWindow;
using bsdeform::StandardView;
using bsdeform::ViewDecorations;
using bsdeform::WheelZoom;

namespace {

QWidget* glWidget(MainWindow& w) { return w.viewer()->getGLWidget(); }

// The first shape of the view's graph under `pixel` (widget coordinates), independent of the
// viewer's classes: nullptr for the background.
const SoPickedPoint* pickAt(MainWindow& w, SoRayPickAction& pick, const QPoint& pixel) {
  const QWidget* gl = glWidget(w);
  pick.setNormalizedPoint(SbVec2f((pixel.x() + 0.5f) / gl->width(), 1.0f - (pixel.y() + 0.5f) / gl->height()));
  pick.apply(w.viewer()->getSceneManager()->getSceneGraph());
  return pick.getPickedPoint();
}

// A pixel of the view (on a grid of 6 px, from the centre out) whose nearest shape `accept`s.
QPoint findPixel(MainWindow& w, const std::function<bool(const SoPickedPoint&)>& accept, double minFromCentre = 0) {
  const QWidget* gl = glWidget(w);
  const QPoint centre(gl->width() / 2, gl->height() / 2);
  for (int r = 0; r < std::max(gl->width(), gl->height()) / 2; r += 6)
    for (int dx = -r; dx <= r; dx += 6)
      for (int dy : {-r, r}) {
        for (const QPoint p : {centre + QPoint(dx, dy), centre + QPoint(dy, dx)}) {
          if (!gl->rect().contains(p) || std::hypot(p.x() - centre.x(), p.y() - centre.y()) < minFromCentre) continue;
          SoRayPickAction pick(w.viewer()->getViewportRegion());
          const SoPickedPoint* pp = pickAt(w, pick, p);
          if (pp && accept(*pp)) return p;
        }
      }
  FAIL("no pixel of the view shows the shape looked for");
  return QPoint();
}

bool isTail(const SoPickedPoint& pp, SoNode* node) { return pp.getPath()->getTail() == node; }

// `world` on the view, in widget pixels (y down), through the camera as it is now.
QPointF pixelOf(MainWindow& w, const SbVec3f& world) {
  const QWidget* gl = glWidget(w);
  SbVec3f ndc;
  bsdeform::cameraViewVolume(w.viewer()->getCamera(), w.viewer()->getViewportRegion()).projectToScreen(world, ndc);
  return QPointF(ndc[0] * gl->width(), (1.0f - ndc[1]) * gl->height());
}

void turnWheel(MainWindow& w, const QPoint& at, int eighthsOfDegree) {
  QWidget* gl = glWidget(w);
  QWheelEvent e(QPointF(at), QPointF(gl->mapToGlobal(at)), QPoint(), QPoint(0, eighthsOfDegree), Qt::NoButton, Qt::NoModifier,
                Qt::NoScrollPhase, false);
  QCoreApplication::sendEvent(gl, &e);
}

double distance(const QPointF& a, const QPointF& b) { return std::hypot(a.x() - b.x(), a.y() - b.y()); }

// A move with the left button held, delivered now. QTest::mouseMove on a QWidget moves the X
// cursor and waits for the server's event, which under load can arrive after the release.
void moveHeld(QWidget* gl, const QPoint& p) {
  QMouseEvent move(QEvent::MouseMove, p, gl->mapToGlobal(p), Qt::NoButton, Qt::LeftButton, Qt::NoModifier);
  QCoreApplication::sendEvent(gl, &move);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// The wheel

TEST_CASE("Viewer habits: the wheel turned forward zooms in towards the point under the cursor, which stays there", "[ui]") {
  auto w = makeWindow("paper_fig3_opposite_point_forces.iv");
  w->framing().setFollowing(false);
  processEvents();
  WheelZoom& wheel = w->wheelZoom();
  REQUIRE_FALSE(wheel.isInverted());
  // a point of the surface well away from the view's centre: zooming to the centre would move it
  SoBSplineDeformSurface* surface = firstSurface(*w);
  const QPoint cursor = findPixel(*w, [surface](const SoPickedPoint& pp) { return isTail(pp, surface); }, 120.0);
  SoRayPickAction pick(w->viewer()->getViewportRegion());
  const SbVec3f target = pickAt(*w, pick, cursor)->getPoint();
  SoCamera* camera = w->viewer()->getCamera();
  const float before = (camera->position.getValue() - target).length();
  turnWheel(*w, cursor, 120);  // one notch forward (away from the user)
  const float after = (camera->position.getValue() - target).length();
  CHECK(after == Approx(before * WheelZoom::kNotchFactor).epsilon(1e-4));
  const QPointF centreOfCursorPixel(cursor.x() + 0.5, cursor.y() + 0.5);
  CHECK(distance(pixelOf(*w, target), centreOfCursorPixel) < 1.0);
  // backwards: out again, the point still under the cursor
  turnWheel(*w, cursor, -240);
  CHECK((camera->position.getValue() - target).length() > before);
  CHECK(distance(pixelOf(*w, target), centreOfCursorPixel) < 1.0);
}

TEST_CASE("Viewer habits: Invert Wheel Zoom flips the direction and is kept as a preference", "[ui]") {
  auto w = makeWindow("paper_fig3_opposite_point_forces.iv");
  w->framing().setFollowing(false);
  processEvents();
  SoBSplineDeformSurface* surface = firstSurface(*w);
  const QPoint cursor = findPixel(*w, [surface](const SoPickedPoint& pp) { return isTail(pp, surface); }, 80.0);
  SoRayPickAction pick(w->viewer()->getViewportRegion());
  const SbVec3f target = pickAt(*w, pick, cursor)->getPoint();
  SoCamera* camera = w->viewer()->getCamera();
  QAction* invert = nullptr;
  for (QAction* a : w->menuBar()->findChildren<QAction*>())
    if (a->text() == QStringLiteral("&Invert Wheel Zoom")) invert = a;
  REQUIRE(invert);
  invert->trigger();  // as the user does it
  CHECK(w->wheelZoom().isInverted());
  CHECK(QSettings().value(WheelZoom::kInvertKey).toBool());
  const float before = (camera->position.getValue() - target).length();
  turnWheel(*w, cursor, 120);
  CHECK((camera->position.getValue() - target).length() == Approx(before / WheelZoom::kNotchFactor).epsilon(1e-4));
  CHECK(distance(pixelOf(*w, target), QPointF(cursor.x() + 0.5, cursor.y() + 0.5)) < 1.0);
  // the next window starts with the preference
  auto next = makeWindow("paper_fig3_opposite_point_forces.iv");
  CHECK(next->wheelZoom().isInverted());
  next->wheelZoom().setInverted(false);
  CHECK_FALSE(QSettings().value(WheelZoom::kInvertKey).toBool());
}

TEST_CASE("Viewer habits: with an orthographic camera the wheel narrows the view about the cursor", "[ui]") {
  auto w = makeWindow("paper_fig2_point_force.iv");  // the paper's orthographic view
  processEvents();
  auto* camera = dynamic_cast<SoOrthographicCamera*>(w->viewer()->getCamera());
  REQUIRE(camera);
  SoBSplineDeformSurface* surface = firstSurface(*w);
  const QPoint cursor = findPixel(*w, [surface](const SoPickedPoint& pp) { return isTail(pp, surface); }, 80.0);
  SoRayPickAction pick(w->viewer()->getViewportRegion());
  const SbVec3f target = pickAt(*w, pick, cursor)->getPoint();
  const float height = camera->height.getValue();
  turnWheel(*w, cursor, 120);
  CHECK(camera->height.getValue() == Approx(height * WheelZoom::kNotchFactor).epsilon(1e-4));
  CHECK(distance(pixelOf(*w, target), QPointF(cursor.x() + 0.5, cursor.y() + 0.5)) < 1.0);
}

// ---------------------------------------------------------------------------------------------
// Ground grid and axes

namespace {
bool gridGrey(const QColor& c) {  // GroundGrid's line colour over the background
  return std::abs(c.red() - 87) < 10 && std::abs(c.green() - 92) < 10 && std::abs(c.blue() - 105) < 10;
}
bool gizmoRed(const QColor& c) { return c.red() > 200 && c.green() < 110 && c.blue() < 110; }
bool netPoint(const QColor& c) {  // ControlNetDisplay's moving (yellow) and held (red) points
  return c.red() > 200 && c.blue() < 90 && (c.green() > 200 || c.green() < 80);
}
bool gizmoBlue(const QColor& c) { return c.blue() > 200 && c.red() < 140 && c.green() < 170; }
// Pixels passing `test` in the rectangle `r` of `img`, and their mean position.
long count(const QImage& img, const QRect& r, bool (*test)(const QColor&), QPointF* mean = nullptr) {
  long n = 0;
  double sx = 0, sy = 0;
  for (int y = r.top(); y <= r.bottom(); ++y)
    for (int x = r.left(); x <= r.right(); ++x)
      if (test(img.pixelColor(x, y))) {
        ++n;
        sx += x;
        sy += y;
      }
  if (mean && n) *mean = QPointF(sx / n, sy / n);
  return n;
}
bool contains(SoNode* graph, SoNode* node) {
  SoSearchAction search;
  search.setNode(node);
  search.setSearchingAll(TRUE);
  search.apply(graph);
  return search.getPath() != nullptr;
}
}  // namespace

TEST_CASE("Viewer habits: the ground grid stays under a cloth that falls below where it started", "[ui][slow]") {
  // Issue 37, item 7: the grid sat under the rest plane, and pinned_cloth hung through it.
  auto w = makeWindow("pinned_cloth.iv");
  ViewDecorations& deco = w->decorations();
  REQUIRE(deco.isGridVisible());
  const float spacing = deco.grid().spacing();
  const float startZ = deco.grid().extent().getMin()[2];
  w->setPlaying(true);
  passTime(*w, 2.0);
  processEvents();
  const SbBox3f scene = bsdeform::sceneBoundingBox(w->document().root(), w->viewer()->getViewportRegion());
  INFO("cloth's lowest z " << scene.getMin()[2] << ", grid at " << deco.grid().extent().getMin()[2]);
  REQUIRE(scene.getMin()[2] < startZ);  // it did fall below where the grid began
  CHECK(deco.grid().extent().getMin()[2] < scene.getMin()[2]);
  CHECK(deco.grid().spacing() == spacing);  // lowered, not refitted: the cells stay
  w->screenshot().save(QStringLiteral("viewer_grid_under_fallen_cloth.png"));  // looked at
}

TEST_CASE("Viewer habits: a scene without its own environment gets the ground grid and the axes, neither saved", "[ui]") {
  auto w = makeWindow("paper_fig3_opposite_point_forces.iv");
  ViewDecorations& deco = w->decorations();
  CHECK_FALSE(ViewDecorations::hasOwnEnvironment(w->document().root()));
  CHECK(deco.isGridVisible());
  CHECK(deco.isAxesVisible());
  // drawn with the scene, but not a part of it: never saved, never found as an obstacle there
  CHECK(contains(w->viewer()->getSceneManager()->getSceneGraph(), deco.gridNode()));
  CHECK_FALSE(contains(w->document().root(), deco.gridNode()));
  // under the scene, around it
  const SbBox3f scene = bsdeform::sceneBoundingBox(w->document().root(), w->viewer()->getViewportRegion());
  const SbBox3f& grid = deco.grid().extent();
  CHECK(grid.getMin()[2] < scene.getMin()[2]);
  CHECK(grid.getMin()[0] < scene.getMin()[0]);
  CHECK(grid.getMax()[1] > scene.getMax()[1]);
  processEvents();
  const QImage with = w->screenshot();
  with.save(QStringLiteral("viewer_grid_axes.png"));
  QTemporaryDir dir;
  REQUIRE(w->saveSceneAs(dir.filePath(QStringLiteral("with.iv"))));
  deco.setGridVisible(false);
  deco.setAxesVisible(false);
  processEvents();
  const QImage without = w->screenshot();
  REQUIRE(w->saveSceneAs(dir.filePath(QStringLiteral("without.iv"))));
  QFile a(dir.filePath(QStringLiteral("with.iv"))), b(dir.filePath(QStringLiteral("without.iv")));
  REQUIRE(a.open(QIODevice::ReadOnly));
  REQUIRE(b.open(QIODevice::ReadOnly));
  const QByteArray text = a.readAll();
  CHECK(text == b.readAll());
  CHECK_FALSE(text.contains("LineSet"));
  CHECK_FALSE(text.contains("PickStyle"));
  // in the picture: grid lines, and the triad's colours in the bottom-left corner
  const QRect all = with.rect();
  const QRect corner(0, with.height() - bsdeform::AxesGizmo::kSidePixels - 8, bsdeform::AxesGizmo::kSidePixels + 8,
                     bsdeform::AxesGizmo::kSidePixels + 8);
  CHECK(count(with, all, gridGrey) > count(without, all, gridGrey) + 500);
  CHECK(count(with, corner, gizmoRed) > 20);
  CHECK(count(with, corner, gizmoBlue) > 20);
  CHECK(count(without, corner, gizmoRed) == 0);
}

TEST_CASE("Viewer habits: the grid is not in the framing, the axes turn with the camera", "[ui]") {
  auto w = makeWindow("paper_fig3_opposite_point_forces.iv");
  REQUIRE(w->decorations().isGridVisible());
  w->framing().setFollowing(false);
  // View All frames the surface as without the grid (the grid is larger than the scene)
  w->framing().viewAll();
  float x0, y0, x1, y1;
  w->framing().projectedSceneBox().getBounds(x0, y0, x1, y1);
  CHECK(std::max(x1 - x0, y1 - y0) == Approx(bsdeform::kFramedFraction).epsilon(0.05));
  // and SoQt's own View All (its eye button, its menu) frames it as without the grid too
  w->viewer()->viewAll();
  const SbBox2f withGrid = w->framing().projectedSceneBox();
  CHECK(w->decorations().isGridVisible());  // back on after SoQt measured the scene
  w->decorations().setGridVisible(false);
  w->viewer()->viewAll();
  const SbBox2f withoutGrid = w->framing().projectedSceneBox();
  w->decorations().setGridVisible(true);
  CHECK((withGrid.getMin() - withoutGrid.getMin()).length() < 1e-4f);
  CHECK((withGrid.getMax() - withoutGrid.getMax()).length() < 1e-4f);
  // from the top (y up on the screen) X points right; from the front (z up) Z points up
  const QRect corner(0, 0, bsdeform::AxesGizmo::kSidePixels + 8, bsdeform::AxesGizmo::kSidePixels + 8);
  auto centreOf = [&](bool (*test)(const QColor&)) {
    processEvents();
    const QImage img = w->screenshot();
    QPointF mean;
    const QRect r = corner.translated(0, img.height() - corner.height());
    REQUIRE(count(img, r, test, &mean) > 10);
    return mean - QPointF(r.left() + bsdeform::AxesGizmo::kMarginPixels + bsdeform::AxesGizmo::kSidePixels / 2.0,
                          r.bottom() - bsdeform::AxesGizmo::kMarginPixels - bsdeform::AxesGizmo::kSidePixels / 2.0);
  };
  w->framing().setView(StandardView::Top);
  const QPointF xTop = centreOf(gizmoRed);
  CHECK(xTop.x() > 15);
  CHECK(std::abs(xTop.y()) < 8);
  const SbRotation camera = w->viewer()->getCamera()->orientation.getValue();
  CHECK(w->decorations().axes().rotation().equals(camera.inverse(), 1e-5f));
  w->framing().setView(StandardView::Front);
  const QPointF zFront = centreOf(gizmoBlue);
  CHECK(zFront.y() < -15);  // up on the screen
  CHECK(std::abs(zFront.x()) < 8);
}

TEST_CASE("Viewer habits: the grid of a scene with a camera of its own is drawn through that camera", "[ui]") {
  // the scene's camera sits under the scene's root, and the grid comes after that root
  auto w = makeWindow("pressure_bulge.iv");
  REQUIRE(bsdeform::findSceneCamera(w->document().root()) == w->viewer()->getCamera());
  REQUIRE(w->decorations().isGridVisible());
  w->setPlaying(false);
  processEvents();
  const QImage img = w->screenshot();
  img.save(QStringLiteral("viewer_grid_scene_camera.png"));
  // the grid's X axis line (y = 0, red) where the camera puts it
  const SbBox3f& grid = w->decorations().grid().extent();
  int inView = 0, onLine = 0;
  for (int k = 1; k < 20; ++k) {
    const float x = grid.getMin()[0] + (grid.getMax()[0] - grid.getMin()[0]) * k / 20.0f;
    const QPointF at = pixelOf(*w, SbVec3f(x, 0.0f, grid.getMin()[2]));
    const QPoint p(int(at.x()), int(at.y()));
    if (!QRect(2, 2, img.width() - 4, img.height() - 4).contains(p)) continue;
    ++inView;
    bool red = false;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const QColor c = img.pixelColor(p + QPoint(dx, dy));
        red |= c.red() > c.green() + 40 && c.red() > c.blue() + 40;
      }
    onLine += red;
  }
  INFO(onLine << " of " << inView << " points of the line in view are red");
  CHECK(inView >= 5);
  CHECK(onLine >= inView / 2);
}

TEST_CASE("Viewer view: the control net of a scene with a camera of its own is drawn over its surface", "[ui]") {
  // like the grid, the net comes after the scene's root, where the scene's camera is over
  auto w = makeWindow("pressure_bulge.iv");
  REQUIRE(bsdeform::findSceneCamera(w->document().root()) == w->viewer()->getCamera());
  w->setPlaying(false);
  w->decorations().setGridVisible(false);
  w->decorations().setAxesVisible(false);  // its red X is not a net point
  w->netDisplay().setNetVisible(true);
  processEvents();
  const QImage img = w->screenshot();
  img.save(QStringLiteral("viewer_net_scene_camera.png"));
  float x0, y0, x1, y1;
  w->framing().projectedSceneBox().getBounds(x0, y0, x1, y1);  // (0, 0) bottom left
  const QRect surface(QPoint(int(x0 * img.width()) - 10, int((1 - y1) * img.height()) - 10),
                      QPoint(int(x1 * img.width()) + 10, int((1 - y0) * img.height()) + 10));
  const long all = count(img, img.rect(), netPoint);
  INFO(all << " net points' pixels, " << count(img, surface, netPoint) << " over the surface");
  CHECK(all > 200);
  CHECK(count(img, surface, netPoint) > 0.95 * all);
}

TEST_CASE("Viewer habits: a scene with shapes of its own has no grid unless asked, and the user's choice is kept", "[ui]") {
  auto w = makeWindow("cloth_on_cube.iv");
  CHECK(ViewDecorations::hasOwnEnvironment(w->document().root()));
  CHECK_FALSE(w->decorations().isGridVisible());
  CHECK(w->decorations().isAxesVisible());
  QAction* grid = nullptr;
  for (QAction* a : w->menuBar()->findChildren<QAction*>())
    if (a->text() == QStringLiteral("Ground &Grid")) grid = a;
  REQUIRE(grid);
  grid->trigger();  // on for this scene
  CHECK(w->decorations().isGridVisible());
  REQUIRE(w->openScene(scenePath("paper_fig3_opposite_point_forces.iv")));
  CHECK(w->decorations().isGridVisible());
  grid->trigger();  // off: kept off for every scene
  CHECK_FALSE(w->decorations().isGridVisible());
  REQUIRE(w->openScene(scenePath("region_load.iv")));
  CHECK_FALSE(w->decorations().isGridVisible());
  grid->trigger();  // on again: the default again
  REQUIRE(w->openScene(scenePath("paper_fig3_opposite_point_forces.iv")));
  CHECK(w->decorations().isGridVisible());
  CHECK(QSettings().value(ViewDecorations::kGridKey).toBool());
}

TEST_CASE("GroundGrid: round cell sizes", "[ui]") {
  CHECK(bsdeform::GroundGrid::roundStep(0.19f) == Approx(0.2f));
  CHECK(bsdeform::GroundGrid::roundStep(0.4f) == Approx(0.5f));
  CHECK(bsdeform::GroundGrid::roundStep(0.8f) == Approx(1.0f));
  CHECK(bsdeform::GroundGrid::roundStep(30.0f) == Approx(20.0f));
  CHECK(bsdeform::GroundGrid::roundStep(0.0f) == 1.0f);
}

// ---------------------------------------------------------------------------------------------
// Two-sided lighting

TEST_CASE("Viewer habits: an open surface seen from below is lit, not black", "[ui]") {
  // the node lights an open surface on both sides (tests/nodes/DefaultView_test.cpp checks it
  // offscreen); here in the window, with the viewer's headlight and the scene's own light
  auto w = makeWindow("region_load.iv");
  w->decorations().setGridVisible(false);
  w->decorations().setAxesVisible(false);
  w->framing().setFollowing(false);
  SoCamera* camera = w->viewer()->getCamera();
  auto meanGrey = [&](const SbVec3f& direction, const char* file) {
    camera->orientation = bsdeform::lookOrientation(direction, SbVec3f(0, 1, 0));
    w->framing().viewAll();
    processEvents();
    const QImage img = w->screenshot();
    img.save(QLatin1String(file));
    const QRgb background = img.pixel(2, 2);
    double sum = 0;
    long n = 0;
    for (int y = 0; y < img.height(); ++y)
      for (int x = 0; x < img.width(); ++x)
        if (img.pixel(x, y) != background) {
          sum += qGray(img.pixel(x, y));
          ++n;
        }
    REQUIRE(n > img.width() * img.height() / 4);  // the surface fills a good part of the view
    return sum / n;
  };
  const double above = meanGrey(SbVec3f(0.1f, 0.2f, -1.0f), "viewer_surface_from_above.png");
  const double below = meanGrey(SbVec3f(0.1f, 0.2f, 1.0f), "viewer_surface_from_below.png");
  INFO("mean grey of the surface from above " << above << ", from below " << below);
  CHECK(above > 100.0);
  CHECK(below > 0.7 * above);  // lit from one side only, the underside is at the ambient level
}

TEST_CASE("Viewer habits: a sheet seen from just below while the camera looks down is shaded, not black", "[ui]") {
  // curtain.iv at rest: the camera is 0.15 below the cloth and looks 8.6 degrees down, so the
  // side it sees faces away from SoQt's headlight direction; the backlight lights it
  auto w = makeWindow("curtain.iv");
  w->decorations().setGridVisible(false);
  w->setPlaying(false);
  auto surfaceGrey = [&](const char* file, long& dark) {
    processEvents();
    const QImage img = w->screenshot();
    img.save(QLatin1String(file));
    double sum = 0;
    long n = 0;
    dark = 0;
    for (int y = 0; y < img.height(); y += 4)
      for (int x = 0; x < img.width(); x += 4) {
        SoRayPickAction pick(w->viewer()->getViewportRegion());
        const SoPickedPoint* pp = pickAt(*w, pick, QPoint(x, y));
        if (!pp || !pp->getPath()->getTail()->isOfType(SoBSplineDeformSurface::getClassTypeId())) continue;
        const int grey = qGray(img.pixel(x, y));
        sum += grey;
        dark += grey < 25;
        ++n;
      }
    REQUIRE(n > 100);
    return sum / n;
  };
  long dark = 0;
  const double lit = surfaceGrey("viewer_curtain_from_below.png", dark);
  INFO("mean grey of the cloth " << lit << ", " << dark << " near-black samples");
  CHECK(lit > 30.0);  // a sheet seen at 4 degrees: shaded dimly, as the same angle from above
  CHECK(dark == 0);
  w->backlight().light()->on = FALSE;  // the headlight alone: black
  long darkWithout = 0;
  const double unlit = surfaceGrey("viewer_curtain_headlight_only.png", darkWithout);
  INFO("with the headlight alone " << unlit << ", " << darkWithout << " near-black samples");
  CHECK(unlit < 15.0);
}

// ---------------------------------------------------------------------------------------------
// Click to select

TEST_CASE("Viewer habits: a click on a surface selects it in the scene panel, a drag does not", "[ui]") {
  auto w = makeWindow("composed_scene.iv");
  w->framing().setFollowing(false);
  processEvents();
  REQUIRE(w->document().surfaces().size() == 2);
  SoBSplineDeformSurface* left = w->document().surfaces()[0];
  SoBSplineDeformSurface* right = w->document().surfaces()[1];
  REQUIRE(w->selectedNode() == left);  // the panel starts at the first
  QWidget* gl = glWidget(*w);
  const QPoint onRight = findPixel(*w, [right](const SoPickedPoint& pp) { return isTail(pp, right); });
  const QPoint onLeft = findPixel(*w, [left](const SoPickedPoint& pp) { return isTail(pp, left); });
  const QPoint onCone = findPixel(*w, [&](const SoPickedPoint& pp) { return !isTail(pp, left) && !isTail(pp, right); });
  QTest::mouseClick(gl, Qt::LeftButton, Qt::NoModifier, onRight);
  processEvents();
  CHECK(w->selectedNode() == right);
  CHECK(w->fieldEditor().container() == right);
  // a shape the panel does not list, and the background: the selection stays
  QTest::mouseClick(gl, Qt::LeftButton, Qt::NoModifier, onCone);
  QTest::mouseClick(gl, Qt::LeftButton, Qt::NoModifier, QPoint(3, 3));
  processEvents();
  CHECK(w->selectedNode() == right);
  // a camera turn that starts on the left surface is not a click
  const SbRotation before = w->viewer()->getCamera()->orientation.getValue();
  QTest::mousePress(gl, Qt::LeftButton, Qt::NoModifier, onLeft);
  for (int k = 1; k <= 8; ++k) moveHeld(gl, onLeft + QPoint(6 * k, 3 * k));
  QTest::mouseRelease(gl, Qt::LeftButton, Qt::NoModifier, onLeft + QPoint(48, 24));
  processEvents();
  CHECK(w->selectedNode() == right);
  CHECK_FALSE(w->viewer()->getCamera()->orientation.getValue().equals(before, 1e-6f));  // SoQt turned the camera
}

TEST_CASE("Viewer habits: in drag mode a click selects and a pull pulls without selecting", "[ui]") {
  auto w = makeWindow("composed_scene.iv");
  w->framing().setFollowing(false);
  w->setPlaying(false);
  processEvents();
  SoBSplineDeformSurface* left = w->document().surfaces()[0];
  SoBSplineDeformSurface* right = w->document().surfaces()[1];
  QWidget* gl = glWidget(*w);
  const QPoint onRight = findPixel(*w, [right](const SoPickedPoint& pp) { return isTail(pp, right); });
  w->setDragMode(true);
  QTest::mouseClick(gl, Qt::LeftButton, Qt::NoModifier, onRight);
  processEvents();
  CHECK(w->selectedNode() == right);
  CHECK_FALSE(w->dragTool().isDragging());  // let go on release
  const QPoint onLeft = findPixel(*w, [left](const SoPickedPoint& pp) { return isTail(pp, left); });
  QTest::mousePress(gl, Qt::LeftButton, Qt::NoModifier, onLeft);
  processEvents();
  CHECK(w->dragTool().surface() == left);  // the drag tool has it
  for (int k = 1; k <= 6; ++k) moveHeld(gl, onLeft + QPoint(0, -6 * k));
  QTest::mouseRelease(gl, Qt::LeftButton, Qt::NoModifier, onLeft + QPoint(0, -36));
  processEvents();
  CHECK_FALSE(w->dragTool().isDragging());
  CHECK(w->selectedNode() == right);
}

TEST_CASE("Viewer habits: a click on a collision obstacle selects its force field", "[ui]") {
  auto w = makeWindow("cloth_on_cube.iv");
  w->framing().setFollowing(false);
  processEvents();
  SoForceField* collision = nullptr;
  for (SoForceField* f : w->document().forceFields())
    if (f->type.getValue() == SoForceField::COLLISION) collision = f;
  REQUIRE(collision);
  REQUIRE(collision->obstacles.getNum() > 0);
  SoNode* box = collision->obstacles[0];
  const QPoint onBox = findPixel(*w, [box](const SoPickedPoint& pp) { return pp.getPath()->containsNode(box); });
  CHECK(w->clickSelect().nodeAt(onBox) == collision);
  QTest::mouseClick(glWidget(*w), Qt::LeftButton, Qt::NoModifier, onBox);
  processEvents();
  CHECK(w->selectedNode() == collision);
}
TEST_CASE("Viewer habits: the drag line of a scene with a camera of its own ends at the cursor", "[ui]") {
  auto w = makeWindow("pressure_bulge.iv");
  REQUIRE(bsdeform::findSceneCamera(w->document().root()) == w->viewer()->getCamera());
  w->setPlaying(false);
  w->decorations().setGridVisible(false);
  w->decorations().setAxesVisible(false);
  processEvents();
  SoBSplineDeformSurface* s = firstSurface(*w);
  const QPoint on = findPixel(*w, [s](const SoPickedPoint& pp) { return isTail(pp, s); });
  w->setDragMode(true);
  QWidget* gl = glWidget(*w);
  const QPoint to = on + QPoint(0, -60);
  QTest::mousePress(gl, Qt::LeftButton, Qt::NoModifier, on);
  for (int k = 1; k <= 6; ++k) moveHeld(gl, on + QPoint(0, -10 * k));
  processEvents();
  REQUIRE(w->dragTool().isDragging());
  const QImage img = w->screenshot();
  img.save(QStringLiteral("viewer_drag_line_scene_camera.png"));
  QTest::mouseRelease(gl, Qt::LeftButton, Qt::NoModifier, to);
  // the line's yellow marker at the anchor, under the cursor
  bool yellowAtCursor = false;
  for (int dy = -4; dy <= 4; ++dy)
    for (int dx = -4; dx <= 4; ++dx) {
      const QColor c = img.pixelColor(to + QPoint(dx, dy));
      yellowAtCursor |= c.red() > 220 && c.green() > 200 && c.blue() < 90;
    }
  CHECK(yellowAtCursor);
}
