// SPDX-License-Identifier: MIT
#include "ControlNetDisplay.h"

#include <Inventor/SbViewportRegion.h>
#include <Inventor/actions/SoGetMatrixAction.h>
#include <Inventor/actions/SoSearchAction.h>
#include <Inventor/lists/SoPathList.h>
#include <Inventor/nodes/SoBaseColor.h>
#include <Inventor/nodes/SoCoordinate3.h>
#include <Inventor/nodes/SoDepthBuffer.h>
#include <Inventor/nodes/SoDrawStyle.h>
#include <Inventor/nodes/SoIndexedLineSet.h>
#include <Inventor/nodes/SoLightModel.h>
#include <Inventor/nodes/SoMatrixTransform.h>
#include <Inventor/nodes/SoPickStyle.h>
#include <Inventor/nodes/SoPointSet.h>
#include <Inventor/nodes/SoQuadMesh.h>
#include <Inventor/nodes/SoSeparator.h>
#include <Inventor/nodes/SoSwitch.h>

#include <QAction>
#include <QMenu>
#include <algorithm>

#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/SoBSplineDeformSurface.h"

namespace bsdeform {

namespace {
SoBaseColor* color(float r, float g, float b) {
  auto* c = new SoBaseColor;
  c->rgb.setValue(r, g, b);
  return c;
}
}  // namespace

ControlNetDisplay::ControlNetDisplay(QObject* parent) : QObject(parent) {
  m_root = new SoSeparator;
  m_root->ref();
  auto* light = new SoLightModel;  // lines and points in flat colours
  light->model = SoLightModel::BASE_COLOR;
  m_root->addChild(light);
  auto* pick = new SoPickStyle;  // the mouse drags the surface, not its overlay
  pick->style = SoPickStyle::UNPICKABLE;
  m_root->addChild(pick);
}

ControlNetDisplay::~ControlNetDisplay() {
  clear();
  m_root->unref();
}

void ControlNetDisplay::addActions(QMenu* menu) {
  m_netAction = menu->addAction(tr("Control &Net"));
  m_netAction->setCheckable(true);
  m_netAction->setShortcut(QKeySequence(tr("N")));
  m_netAction->setToolTip(tr("Show the control points (moving: yellow, held by a clamped side or a pin: red) and "
                             "the polylines of the net (N)"));
  connect(m_netAction, &QAction::toggled, this, &ControlNetDisplay::setNetVisible);
  m_ghostAction = menu->addAction(tr("&Rest Surface (Ghost)"));
  m_ghostAction->setCheckable(true);
  m_ghostAction->setShortcut(QKeySequence(tr("G")));
  m_ghostAction->setToolTip(tr("Show the undeformed rest surface as a wireframe (G)"));
  connect(m_ghostAction, &QAction::toggled, this, &ControlNetDisplay::setGhostVisible);
}

void ControlNetDisplay::clear() {
  for (Item& item : m_items) item.path->unref();
  m_items.clear();
  // keep the light model and pick style
  while (m_root->getNumChildren() > 2) m_root->removeChild(m_root->getNumChildren() - 1);
}

void ControlNetDisplay::setScene(SoNode* scene) {
  clear();
  m_scene = scene;
  if (!scene) return;
  SoSearchAction search;
  search.setType(SoBSplineDeformSurface::getClassTypeId());
  search.setInterest(SoSearchAction::ALL);
  search.apply(scene);
  const SoPathList& paths = search.getPaths();
  for (int k = 0; k < paths.getLength(); ++k) {
    Item item;
    item.path = paths[k]->copy();
    item.path->ref();
    item.surface = static_cast<SoBSplineDeformSurface*>(item.path->getTail());
    auto* sep = new SoSeparator;
    item.transform = new SoMatrixTransform;
    sep->addChild(item.transform);

    item.netSwitch = new SoSwitch;
    auto* net = new SoSeparator;
    auto* onTop = new SoDepthBuffer;  // the net runs through the surface: draw all of it, as CAD tools do
    onTop->test = FALSE;
    net->addChild(onTop);
    auto* style = new SoDrawStyle;
    style->pointSize = 6.0f;
    style->lineWidth = 1.0f;
    net->addChild(style);
    item.netCoords = new SoCoordinate3;
    net->addChild(item.netCoords);
    net->addChild(color(0.55f, 0.75f, 1.0f));
    item.netLines = new SoIndexedLineSet;
    net->addChild(item.netLines);
    net->addChild(color(1.0f, 0.9f, 0.2f));
    item.movingPoints = new SoPointSet;
    net->addChild(item.movingPoints);
    net->addChild(color(0.95f, 0.15f, 0.15f));
    item.heldPoints = new SoPointSet;
    net->addChild(item.heldPoints);
    item.netSwitch->addChild(net);
    sep->addChild(item.netSwitch);

    item.ghostSwitch = new SoSwitch;
    auto* ghost = new SoSeparator;
    auto* wire = new SoDrawStyle;
    wire->style = SoDrawStyle::LINES;
    ghost->addChild(wire);
    ghost->addChild(color(0.7f, 0.72f, 0.78f));
    item.ghostCoords = new SoCoordinate3;
    ghost->addChild(item.ghostCoords);
    auto* mesh = new SoQuadMesh;
    mesh->verticesPerRow = kGhostSamples;
    mesh->verticesPerColumn = kGhostSamples;
    ghost->addChild(mesh);
    item.ghostSwitch->addChild(ghost);
    sep->addChild(item.ghostSwitch);

    m_root->addChild(sep);
    m_items.push_back(item);
  }
  setNetVisible(m_netVisible);
  setGhostVisible(m_ghostVisible);
}

void ControlNetDisplay::setNetVisible(bool on) {
  m_netVisible = on;
  if (m_netAction && m_netAction->isChecked() != on) m_netAction->setChecked(on);
  for (Item& item : m_items) item.netSwitch->whichChild = on ? 0 : SO_SWITCH_NONE;
  update();
}

void ControlNetDisplay::setGhostVisible(bool on) {
  m_ghostVisible = on;
  if (m_ghostAction && m_ghostAction->isChecked() != on) m_ghostAction->setChecked(on);
  for (Item& item : m_items) item.ghostSwitch->whichChild = on ? 0 : SO_SWITCH_NONE;
  update();
}

void ControlNetDisplay::update() {
  if (!m_netVisible && !m_ghostVisible) return;
  for (Item& item : m_items) updateItem(item);
}

void ControlNetDisplay::updateItem(Item& item) {
  SoGetMatrixAction matrix{SbViewportRegion()};
  matrix.apply(item.path);
  if (item.transform->matrix.getValue() != matrix.getMatrix()) item.transform->matrix = matrix.getMatrix();
  const Simulation& sim = item.surface->simulation();
  const SplineSpace& space = sim.space();
  if (m_netVisible) {
    const int rows = space.netRows(), cols = space.netCols();
    const std::vector<Eigen::Index>& pins = sim.pinnedRows();
    if (rows != item.rows || cols != item.cols || long(pins.size()) != item.pinKey) {
      // slots: moving points first, then held ones (clamped sides, pins), then periodic copies
      item.rows = rows;
      item.cols = cols;
      item.pinKey = long(pins.size());
      std::vector<int> kind(size_t(rows) * cols);  // 0 moving, 1 held, 2 periodic copy
      for (int i = 0; i < rows; ++i)
        for (int j = 0; j < cols; ++j) {
          const int r = i * cols + j;
          if (space.isMoving(i, j) || space.isDerived(i, j))  // a derived point (SIMPLY_SUPPORTED, BUILT_IN) moves too
            kind[r] = 0;
          else
            kind[r] = space.movingLayerU(i) >= 0 && space.movingLayerV(j) >= 0 ? 2 : 1;
        }
      for (Eigen::Index r : pins) kind[size_t(r)] = 1;
      item.slot.assign(kind.size(), 0);
      int next = 0;
      for (int k = 0; k < 3; ++k)
        for (size_t r = 0; r < kind.size(); ++r)
          if (kind[r] == k) item.slot[r] = next++;
      item.moving = int(std::count(kind.begin(), kind.end(), 0));
      item.held = int(std::count(kind.begin(), kind.end(), 1));
      std::vector<int32_t> lines;
      lines.reserve(size_t(rows) * cols * 2 + rows + cols);
      for (int i = 0; i < rows; ++i) {
        for (int j = 0; j < cols; ++j) lines.push_back(item.slot[size_t(i) * cols + j]);
        lines.push_back(SO_END_LINE_INDEX);
      }
      for (int j = 0; j < cols; ++j) {
        for (int i = 0; i < rows; ++i) lines.push_back(item.slot[size_t(i) * cols + j]);
        lines.push_back(SO_END_LINE_INDEX);
      }
      item.netLines->coordIndex.setValues(0, int(lines.size()), lines.data());
      item.netLines->coordIndex.setNum(int(lines.size()));
      item.movingPoints->startIndex = 0;
      item.movingPoints->numPoints = item.moving;
      item.heldPoints->startIndex = item.moving;
      item.heldPoints->numPoints = item.held;
    }
    const ControlNet& net = sim.current();
    if (size_t(net.rows()) != item.slot.size()) return;  // not the full net: nothing sensible to draw
    item.netCoords->point.setNum(int(net.rows()));
    SbVec3f* p = item.netCoords->point.startEditing();
    for (Eigen::Index r = 0; r < net.rows(); ++r)
      p[item.slot[size_t(r)]].setValue(float(net(r, 0)), float(net(r, 1)), float(net(r, 2)));
    item.netCoords->point.finishEditing();
  }
  if (m_ghostVisible) {
    const ControlNet& rest = sim.rest();
    item.ghostCoords->point.setNum(kGhostSamples * kGhostSamples);
    SbVec3f* p = item.ghostCoords->point.startEditing();
    for (int a = 0; a < kGhostSamples; ++a)
      for (int b = 0; b < kGhostSamples; ++b) {
        const Eigen::Vector3d x =
            space.evaluate(rest, double(a) / (kGhostSamples - 1), double(b) / (kGhostSamples - 1), 0).position;
        p[a * kGhostSamples + b].setValue(float(x[0]), float(x[1]), float(x[2]));
      }
    item.ghostCoords->point.finishEditing();
  }
}

int ControlNetDisplay::movingPointCount(int index) const { return m_items.at(size_t(index)).moving; }
int ControlNetDisplay::heldPointCount(int index) const { return m_items.at(size_t(index)).held; }

}  // namespace bsdeform
