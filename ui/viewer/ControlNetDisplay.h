// SPDX-License-Identifier: MIT
#pragma once
/// @file ControlNetDisplay.h
/// Display aids drawn over the scene, never part of it (not saved): the control net of every
/// surface (its points, moving ones and held ones - clamped sides and pins - in two colours, and
/// the polylines of its rows and columns) and the rest surface as a wireframe ghost. Each
/// surface's overlay carries the transformation the surface has in the scene.

#include <QObject>
#include <vector>

class QMenu;
class QAction;
class SoBSplineDeformSurface;
class SoCoordinate3;
class SoIndexedLineSet;
class SoMatrixTransform;
class SoNode;
class SoPath;
class SoPointSet;
class SoQuadMesh;
class SoSeparator;
class SoSwitch;

namespace bsdeform {

class ControlNetDisplay : public QObject {
  Q_OBJECT
 public:
  /// Samples per side of the rest-surface ghost.
  static constexpr int kGhostSamples = 25;

  explicit ControlNetDisplay(QObject* parent = nullptr);
  ~ControlNetDisplay() override;

  /// The overlay's root: put it after the scene, beside it (not under it).
  SoSeparator* node() const { return m_root; }
  /// Adds the "Control Net" and "Rest Surface (Ghost)" toggles to `menu`.
  void addActions(QMenu* menu);
  /// Follows the surfaces of `scene` (rebuilds the overlay).
  void setScene(SoNode* scene);
  void setNetVisible(bool on);
  void setGhostVisible(bool on);
  bool isNetVisible() const { return m_netVisible; }
  bool isGhostVisible() const { return m_ghostVisible; }
  /// Copies the current nets (and rest surfaces) into the overlay; cheap, call periodically.
  void update();

  /// What the overlay of surface `index` holds (tests): net points drawn as moving / held.
  int movingPointCount(int index) const;
  int heldPointCount(int index) const;
  int surfaceCount() const { return int(m_items.size()); }

 private:
  struct Item {
    SoPath* path = nullptr;  // from the scene root to the surface (referenced)
    SoBSplineDeformSurface* surface = nullptr;
    SoMatrixTransform* transform = nullptr;
    SoSwitch* netSwitch = nullptr;
    SoSwitch* ghostSwitch = nullptr;
    SoCoordinate3* netCoords = nullptr;  // moving points, then held points, then periodic copies
    SoIndexedLineSet* netLines = nullptr;
    SoPointSet* movingPoints = nullptr;
    SoPointSet* heldPoints = nullptr;
    SoCoordinate3* ghostCoords = nullptr;
    std::vector<int> slot;  // net row -> index in netCoords
    int rows = 0, cols = 0, moving = 0, held = 0;
    long pinKey = -1;       // pins the slots were made for (count)
  };
  void clear();
  void updateItem(Item& item);

  SoSeparator* m_root = nullptr;
  SoNode* m_scene = nullptr;
  std::vector<Item> m_items;
  bool m_netVisible = false, m_ghostVisible = false;
  QAction* m_netAction = nullptr;
  QAction* m_ghostAction = nullptr;
};

}  // namespace bsdeform
