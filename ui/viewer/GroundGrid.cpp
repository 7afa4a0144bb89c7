// SPDX-License-Identifier: MIT
#include "GroundGrid.h"

#include <Inventor/nodes/SoBaseColor.h>
#include <Inventor/nodes/SoCoordinate3.h>
#include <Inventor/nodes/SoDrawStyle.h>
#include <Inventor/nodes/SoLightModel.h>
#include <Inventor/nodes/SoLineSet.h>
#include <Inventor/nodes/SoMaterialBinding.h>
#include <Inventor/nodes/SoPickStyle.h>
#include <Inventor/nodes/SoSeparator.h>

#include <algorithm>
#include <cmath>

namespace bsdeform {

namespace {
const SbColor kLineColor(0.34f, 0.36f, 0.41f);  // a little lighter than the view's background
const SbColor kXAxisColor(0.62f, 0.26f, 0.26f);
const SbColor kYAxisColor(0.30f, 0.55f, 0.30f);
}  // namespace

GroundGrid::GroundGrid() {
  m_root = new SoSeparator;
  m_root->ref();
  auto* pick = new SoPickStyle;
  pick->style = SoPickStyle::UNPICKABLE;  // clicks, drags and the wheel's target pass through it
  auto* light = new SoLightModel;
  light->model = SoLightModel::BASE_COLOR;
  auto* style = new SoDrawStyle;
  style->lineWidth = 1.0f;
  auto* binding = new SoMaterialBinding;
  binding->value = SoMaterialBinding::PER_PART;  // one colour per line
  m_colors = new SoBaseColor;
  m_coords = new SoCoordinate3;
  m_lines = new SoLineSet;
  for (SoNode* n : {static_cast<SoNode*>(pick), static_cast<SoNode*>(light), static_cast<SoNode*>(style),
                    static_cast<SoNode*>(binding), static_cast<SoNode*>(m_colors), static_cast<SoNode*>(m_coords),
                    static_cast<SoNode*>(m_lines)})
    m_root->addChild(n);
  fit(SbBox3f());
}

GroundGrid::~GroundGrid() { m_root->unref(); }

float GroundGrid::roundStep(float length) {
  if (!(length > 0.0f) || !std::isfinite(length)) return 1.0f;
  const float decade = std::pow(10.0f, std::floor(std::log10(length)));
  float best = decade;
  for (float m : {2.0f, 5.0f, 10.0f})
    if (std::abs(std::log(m * decade / length)) < std::abs(std::log(best / length))) best = m * decade;
  return best;
}

void GroundGrid::fit(const SbBox3f& sceneBox) {
  float x0 = -5, y0 = -5, x1 = 5, y1 = 5, z = 0;
  m_spacing = 1.0f;
  if (!sceneBox.isEmpty()) {
    float dx, dy, dz;
    sceneBox.getSize(dx, dy, dz);
    const float size = std::max({dx, dy, dz, 1e-6f});
    m_spacing = roundStep(size / 5.0f);
    const SbVec3f lo = sceneBox.getMin(), hi = sceneBox.getMax();
    // whole cells, lines on multiples of the spacing (a world grid, not one around the scene)
    x0 = std::floor((lo[0] - size / 2) / m_spacing) * m_spacing;
    y0 = std::floor((lo[1] - size / 2) / m_spacing) * m_spacing;
    x1 = std::ceil((hi[0] + size / 2) / m_spacing) * m_spacing;
    y1 = std::ceil((hi[1] + size / 2) / m_spacing) * m_spacing;
    z = lo[2] - size / 20;
    m_margin = size / 20;
  }
  m_extent = SbBox3f(x0, y0, z, x1, y1, z);
  const int nx = int(std::lround((x1 - x0) / m_spacing)), ny = int(std::lround((y1 - y0) / m_spacing));
  m_coords->point.setNum(2 * (nx + ny + 2));
  m_colors->rgb.setNum(nx + ny + 2);
  SbVec3f* p = m_coords->point.startEditing();
  SbColor* c = m_colors->rgb.startEditing();
  int line = 0;
  for (int i = 0; i <= nx; ++i, ++line) {  // lines along y
    const float x = x0 + i * m_spacing;
    p[2 * line] = SbVec3f(x, y0, z);
    p[2 * line + 1] = SbVec3f(x, y1, z);
    c[line] = std::abs(x) < m_spacing / 2 ? kYAxisColor : kLineColor;
  }
  for (int j = 0; j <= ny; ++j, ++line) {  // lines along x
    const float y = y0 + j * m_spacing;
    p[2 * line] = SbVec3f(x0, y, z);
    p[2 * line + 1] = SbVec3f(x1, y, z);
    c[line] = std::abs(y) < m_spacing / 2 ? kXAxisColor : kLineColor;
  }
  m_coords->point.finishEditing();
  m_colors->rgb.finishEditing();
  m_lines->numVertices.setNum(line);
  int32_t* n = m_lines->numVertices.startEditing();
  std::fill(n, n + line, 2);
  m_lines->numVertices.finishEditing();
}

bool GroundGrid::lowerUnder(const SbBox3f& sceneBox) {
  if (sceneBox.isEmpty()) return false;
  const float z = sceneBox.getMin()[2] - m_margin;
  if (!(z < m_extent.getMin()[2])) return false;
  SbVec3f* p = m_coords->point.startEditing();
  for (int i = 0; i < m_coords->point.getNum(); ++i) p[i][2] = z;
  m_coords->point.finishEditing();
  SbVec3f lo = m_extent.getMin(), hi = m_extent.getMax();
  lo[2] = hi[2] = z;
  m_extent.setBounds(lo, hi);
  return true;
}

}  // namespace bsdeform
