// SPDX-License-Identifier: MIT
#include "ViewDecorations.h"

#include <Inventor/actions/SoSearchAction.h>
#include <Inventor/nodes/SoSeparator.h>
#include <Inventor/nodes/SoShape.h>
#include <Inventor/nodes/SoSwitch.h>

#include <QAction>
#include <QMenu>
#include <QSettings>

#include "AxesGizmo.h"
#include "ExaminerViewer.h"
#include "GroundGrid.h"
#include "bsdeform/DefaultView.h"
#include "bsdeform/SoBSplineDeformSurface.h"

namespace bsdeform {

const char* const ViewDecorations::kGridKey = "view/groundGrid";
const char* const ViewDecorations::kAxesKey = "view/axes";

ViewDecorations::ViewDecorations(ExaminerViewer* viewer, QObject* parent)
    : QObject(parent), m_viewer(viewer), m_grid(new GroundGrid), m_axes(new AxesGizmo(viewer)) {
  m_gridSwitch = new SoSwitch;
  m_gridSwitch->ref();
  m_gridSwitch->addChild(m_grid->node());
  m_gridSwitch->whichChild = SO_SWITCH_NONE;
  m_viewer->excludeFromViewAll(m_gridSwitch);  // SoQt's own View All frames the scene alone too
  m_axes->setVisible(QSettings().value(kAxesKey, true).toBool());
}

ViewDecorations::~ViewDecorations() { m_gridSwitch->unref(); }

void ViewDecorations::addActions(QMenu* menu) {
  m_gridAction = menu->addAction(tr("Ground &Grid"));
  m_gridAction->setCheckable(true);
  m_gridAction->setChecked(isGridVisible());
  m_gridAction->setShortcut(QKeySequence(tr("Shift+G")));
  m_gridAction->setToolTip(tr("A grid under the scene; on by default for scenes without shapes of their own besides the surfaces (Shift+G)"));
  connect(m_gridAction, &QAction::toggled, this, &ViewDecorations::setGridVisible);
  // the user's choice is kept; a scene's default (sceneShown) is not a choice
  connect(m_gridAction, &QAction::triggered, this, [](bool on) { QSettings().setValue(kGridKey, on); });
  m_axesAction = menu->addAction(tr("A&xes"));
  m_axesAction->setCheckable(true);
  m_axesAction->setChecked(isAxesVisible());
  m_axesAction->setShortcut(QKeySequence(tr("Shift+A")));
  m_axesAction->setToolTip(tr("The X, Y, Z axes in the corner of the view, turning with the camera (Shift+A)"));
  connect(m_axesAction, &QAction::toggled, this, &ViewDecorations::setAxesVisible);
  connect(m_axesAction, &QAction::triggered, this, [](bool on) { QSettings().setValue(kAxesKey, on); });
}

void ViewDecorations::sceneShown(SoNode* scene) {
  m_scene = scene;
  refit();
  setGridVisible(scene && !hasOwnEnvironment(scene) && QSettings().value(kGridKey, true).toBool());
}

void ViewDecorations::refit() {
  m_grid->fit(m_scene ? sceneBoundingBox(m_scene, m_viewer->getViewportRegion()) : SbBox3f());
}

void ViewDecorations::follow() {
  if (!m_scene || !isGridVisible()) return;
  m_grid->lowerUnder(sceneBoundingBox(m_scene, m_viewer->getViewportRegion()));
}

void ViewDecorations::setGridVisible(bool on) {
  m_gridSwitch->whichChild = on ? 0 : SO_SWITCH_NONE;
  if (m_gridAction && m_gridAction->isChecked() != on) m_gridAction->setChecked(on);
}

void ViewDecorations::setAxesVisible(bool on) {
  m_axes->setVisible(on);
  if (m_axesAction && m_axesAction->isChecked() != on) m_axesAction->setChecked(on);
}

bool ViewDecorations::isGridVisible() const { return m_gridSwitch->whichChild.getValue() == 0; }

bool ViewDecorations::isAxesVisible() const { return m_axes->isVisible(); }

bool ViewDecorations::hasOwnEnvironment(SoNode* scene) {
  SoSearchAction search;
  search.setType(SoShape::getClassTypeId());
  search.setInterest(SoSearchAction::ALL);
  search.setSearchingAll(TRUE);  // inside switches that are off too: the file has them
  search.apply(scene);
  const SoPathList& found = search.getPaths();
  for (int i = 0; i < found.getLength(); ++i)
    if (!found[i]->getTail()->isOfType(SoBSplineDeformSurface::getClassTypeId())) return true;
  return false;
}

}  // namespace bsdeform
