// SPDX-License-Identifier: MIT
#pragma once
/// @file GroundGrid.h
/// The viewer's ground grid: lines of a horizontal (z = const) grid under the scene, the lines
/// x = 0 and y = 0 in the colours of the X (red) and Y (green) axes. It is unpickable, drawn
/// without lighting, and sized to the scene when the scene is shown: the grid cell is a round
/// number (1, 2 or 5 times a power of ten) about a fifth of the scene's size, the grid reaches
/// half the scene's size beyond its footprint, and it lies a twentieth of that size under the
/// scene's lowest point (a flat plate at z = 0 is not cut by it).

#include <Inventor/SbBox3f.h>

class SoCoordinate3;
class SoBaseColor;
class SoLineSet;
class SoSeparator;

namespace bsdeform {

class GroundGrid {
 public:
  GroundGrid();
  ~GroundGrid();
  GroundGrid(const GroundGrid&) = delete;
  GroundGrid& operator=(const GroundGrid&) = delete;

  /// The grid's graph (referenced by this object).
  SoSeparator* node() const { return m_root; }
  /// Places and sizes the grid under `sceneBox` (world space; empty: a 10 x 10 grid of unit
  /// cells at z = 0).
  void fit(const SbBox3f& sceneBox);
  /// Lowers the grid to lie under `sceneBox` too (a cloth that falls below where the scene
  /// started), by the same margin fit() leaves; the cells and extent stay. Never raises it.
  /// Returns whether it moved.
  bool lowerUnder(const SbBox3f& sceneBox);
  /// The grid's cell size, its extent and its height, as fit() chose them.
  float spacing() const { return m_spacing; }
  const SbBox3f& extent() const { return m_extent; }

  /// A round cell size near `length`: 1, 2 or 5 times a power of ten, the nearest on a log scale.
  static float roundStep(float length);

 private:
  SoSeparator* m_root = nullptr;
  SoCoordinate3* m_coords = nullptr;
  SoBaseColor* m_colors = nullptr;
  SoLineSet* m_lines = nullptr;
  float m_spacing = 1.0f;
  float m_margin = 0.0f;  ///< how far under the scene's lowest point fit() put it
  SbBox3f m_extent;
};

}  // namespace bsdeform
