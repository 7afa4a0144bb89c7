// SPDX-License-Identifier: MIT
#include "bsdeform/DefaultView.h"

#include <Inventor/SbMatrix.h>
#include <Inventor/SbViewVolume.h>
#include <Inventor/SbViewportRegion.h>
#include <Inventor/actions/SoGetBoundingBoxAction.h>
#include <Inventor/actions/SoSearchAction.h>
#include <Inventor/lists/SoPathList.h>
#include <Inventor/nodes/SoCamera.h>
#include <Inventor/nodes/SoShape.h>
#include <Inventor/nodes/SoOrthographicCamera.h>
#include <Inventor/nodes/SoPerspectiveCamera.h>

#include <algorithm>
#include <cmath>

namespace bsdeform {

SbVec3f viewDirection(StandardView view) {
  SbVec3f d;
  switch (view) {
    case StandardView::Default:
      d.setValue(0.0f, 0.73f, -0.68f);
      break;
    case StandardView::Front:
      d.setValue(0.0f, 1.0f, 0.0f);
      break;
    case StandardView::Top:
      d.setValue(0.0f, 0.0f, -1.0f);
      break;
    case StandardView::Side:
      d.setValue(-1.0f, 0.0f, 0.0f);
      break;
    case StandardView::Isometric:
      d.setValue(-1.0f, 1.0f, -1.0f);
      break;
  }
  d.normalize();
  return d;
}

SbRotation lookOrientation(const SbVec3f& direction, const SbVec3f& up) {
  SbVec3f dir = direction;
  dir.normalize();
  // first the view direction (the camera looks along its -z), then a turn about it that
  // brings the camera's +y to `up` projected on the image plane
  const SbRotation toDirection(SbVec3f(0.0f, 0.0f, -1.0f), dir);
  SbVec3f cameraUp;
  toDirection.multVec(SbVec3f(0.0f, 1.0f, 0.0f), cameraUp);
  SbVec3f wanted = up - dir * up.dot(dir);
  wanted.normalize();
  const float angle = std::atan2(cameraUp.cross(wanted).dot(dir), cameraUp.dot(wanted));
  return toDirection * SbRotation(dir, angle);
}

SbRotation viewOrientation(StandardView view) {
  const SbVec3f up = view == StandardView::Top ? SbVec3f(0.0f, 1.0f, 0.0f) : SbVec3f(0.0f, 0.0f, 1.0f);
  return lookOrientation(viewDirection(view), up);
}

SoCamera* findSceneCamera(SoNode* scene) {
  if (!scene) return nullptr;
  SoSearchAction sa;
  sa.setType(SoCamera::getClassTypeId());
  sa.setInterest(SoSearchAction::FIRST);
  sa.apply(scene);
  return sa.getPath() ? static_cast<SoCamera*>(sa.getPath()->getTail()) : nullptr;
}

SbViewVolume cameraViewVolume(SoCamera* camera, const SbViewportRegion& viewport) {
  // Coin 4.0 reads the aspect ratio from the result argument before setting it: give it a copy
  SbViewportRegion used = viewport;
  return camera->getViewVolume(viewport, used, SbMatrix::identity());
}

SbBox3f sceneBoundingBox(SoNode* scene, const SbViewportRegion& viewport) {
  SbBox3f box;
  if (!scene) return box;
  SoSearchAction search;
  search.setType(SoShape::getClassTypeId());
  search.setInterest(SoSearchAction::ALL);
  search.apply(scene);
  SoGetBoundingBoxAction bba(viewport);
  const SoPathList& paths = search.getPaths();
  for (int i = 0; i < paths.getLength(); ++i) {
    bba.apply(paths[i]);
    box.extendBy(bba.getBoundingBox());
  }
  return box;
}

void frameScene(SoCamera* camera, SoNode* scene, const SbViewportRegion& viewport) {
  camera->viewAll(scene, viewport);  // a start that sees the whole scene
  frameBox(camera, sceneBoundingBox(scene, viewport), viewport);
}

void frameBox(SoCamera* camera, const SbBox3f& box, const SbViewportRegion& viewport) {
  auto* ortho = camera->isOfType(SoOrthographicCamera::getClassTypeId()) ? static_cast<SoOrthographicCamera*>(camera) : nullptr;
  if (box.isEmpty() || (!ortho && !camera->isOfType(SoPerspectiveCamera::getClassTypeId())))
    return;  // nothing to frame, or another camera type: viewAll's framing
  const float radius = 0.5f * (box.getMax() - box.getMin()).length();
  SbVec3f dir;
  camera->orientation.getValue().multVec(SbVec3f(0.0f, 0.0f, -1.0f), dir);
  SbVec3f target = box.getCenter();
  float distance = std::max(camera->focalDistance.getValue(), 1e-6f);
  // outside the box's sphere (a viewAll start already is: the iterations below keep it there)
  if (!ortho) distance = std::max(distance, 2.0f * radius);
  // The projected size is about inversely proportional to the distance (the height), and the
  // projection of the box is not centred on the projection of its centre (perspective): a few
  // corrections of both converge.
  for (int iteration = 0; iteration < 8; ++iteration) {
    camera->position = target - dir * distance;
    camera->focalDistance = distance;
    const SbBox2f p = projectedBox(camera, box, viewport);
    float w, h, cx, cy;
    p.getSize(w, h);
    p.getCenter().getValue(cx, cy);
    const float size = std::max(w, h);
    if (!(size > 0.0f)) break;
    // assumes the view volume covers the viewport (ADJUST_CAMERA, the default)
    const SbViewVolume volume = cameraViewVolume(camera, viewport);
    target += volume.getPlanePoint(distance, SbVec2f(cx, cy)) - volume.getPlanePoint(distance, SbVec2f(0.5f, 0.5f));
    const float scale = size / kFramedFraction;
    if (ortho)
      ortho->height = ortho->height.getValue() * scale;
    else
      distance *= scale;
    if (std::abs(scale - 1.0f) < 0.005f && std::abs(cx - 0.5f) < 0.005f && std::abs(cy - 0.5f) < 0.005f) break;
  }
  if (ortho) distance = std::max(distance, 2.0f * radius);  // in front of the box
  camera->position = target - dir * distance;
  camera->focalDistance = distance;
  camera->nearDistance = std::max(distance - 1.1f * radius - (target - box.getCenter()).length(), 0.01f * distance);
  camera->farDistance = distance + 1.1f * radius + (target - box.getCenter()).length();
}

void frameView(SoCamera* camera, SoNode* scene, const SbViewportRegion& viewport, StandardView view) {
  camera->orientation.setValue(viewOrientation(view));
  frameScene(camera, scene, viewport);
}

SbBox2f projectedBox(SoCamera* camera, const SbBox3f& box, const SbViewportRegion& viewport) {
  SbBox2f out;
  if (box.isEmpty()) return out;
  SbViewportRegion used = viewport;  // see cameraViewVolume
  const SbViewVolume volume = camera->getViewVolume(viewport, used, SbMatrix::identity());
  // the view volume covers `used`, which ADJUST_CAMERA makes the whole viewport; other
  // mappings may leave a border, mapped here to viewport coordinates
  const SbVec2f origin = used.getViewportOrigin(), size = used.getViewportSize();
  const SbVec2f vpOrigin = viewport.getViewportOrigin(), vpSize = viewport.getViewportSize();
  const SbVec3f& lo = box.getMin();
  const SbVec3f& hi = box.getMax();
  for (int corner = 0; corner < 8; ++corner) {
    const SbVec3f p((corner & 1) ? hi[0] : lo[0], (corner & 2) ? hi[1] : lo[1], (corner & 4) ? hi[2] : lo[2]);
    SbVec3f s;
    volume.projectToScreen(p, s);
    out.extendBy(SbVec2f((origin[0] + s[0] * size[0] - vpOrigin[0]) / vpSize[0],
                         (origin[1] + s[1] * size[1] - vpOrigin[1]) / vpSize[1]));
  }
  return out;
}

}  // namespace bsdeform
