// SPDX-License-Identifier: MIT
#pragma once
/// @file DefaultView.h
/// The one default view of a scene without a camera, shared by bsdeform-viewer, bsdeform-run's
/// pictures and the README images: a perspective three-quarter view from the -y side, looking
/// down at the (u, v) plane with z up on the screen, framing the whole scene. Also the standard
/// views of the viewer's View menu and the projection of a bounding box on the view (framing
/// checks, the viewer's "Follow").

#include <Inventor/SbBox2f.h>
#include <Inventor/SbBox3f.h>
#include <Inventor/SbRotation.h>
#include <Inventor/SbVec3f.h>
#include <Inventor/SbViewVolume.h>

class SoCamera;
class SoNode;
class SbViewportRegion;

namespace bsdeform {

/// Standard view directions. Default is the three-quarter view every front end starts with.
enum class StandardView {
  Default,    ///< from the -y side and above: direction (0, 0.73, -0.68), z up
  Front,      ///< along +y, z up
  Top,        ///< along -z, y up
  Side,       ///< along -x (from the +x side), z up
  Isometric,  ///< along (-1, 1, -1) / sqrt 3 (from the +x, -y, +z octant), z up
};

/// Unit direction the camera looks along for `view` (world space).
SbVec3f viewDirection(StandardView view);

/// Camera orientation that looks along `direction` with `up` as close to the screen's up as
/// possible (`up` must not be parallel to `direction`).
SbRotation lookOrientation(const SbVec3f& direction, const SbVec3f& up);

/// Camera orientation of `view` (lookOrientation with z up, y up for Top).
SbRotation viewOrientation(StandardView view);

/// The view volume `camera` renders `viewport` with (its viewport mapping applied, as
/// SoCamera::getViewVolume(viewport, ...) does, working around Coin 4.0 reading the aspect
/// ratio from its result argument).
SbViewVolume cameraViewVolume(SoCamera* camera, const SbViewportRegion& viewport);

/// The first camera in `scene` (depth first), nullptr if none.
SoCamera* findSceneCamera(SoNode* scene);

/// World-space bounding box of the shapes of `scene`: the union of each shape's box under its
/// own transformation. Tighter than SoGetBoundingBoxAction on the root, whose one box for
/// differently transformed children can be much larger than the scene (composed_scene: 4.3 x 3.6
/// for objects within 3.7 x 2.4).
SbBox3f sceneBoundingBox(SoNode* scene, const SbViewportRegion& viewport);

/// Fraction of the view that frameScene() gives the larger side of the scene's projected
/// bounding box.
constexpr float kFramedFraction = 0.8f;

/// Frames `scene` keeping the camera's direction: the camera looks at the centre of the scene's
/// bounding box from the distance (perspective) or with the height (orthographic) at which the
/// box's projection spans kFramedFraction of the view in its larger direction, and its near and
/// far planes enclose the box. Tighter than SoCamera::viewAll, which fits the bounding sphere.
void frameScene(SoCamera* camera, SoNode* scene, const SbViewportRegion& viewport);

/// The same framing of a given world-space `box` (the union of the scene's boxes over a run:
/// one camera that holds the whole motion), starting from the camera's focal distance.
void frameBox(SoCamera* camera, const SbBox3f& box, const SbViewportRegion& viewport);

/// Turns `camera` to `view` and frames `scene` for `viewport` (frameScene).
void frameView(SoCamera* camera, SoNode* scene, const SbViewportRegion& viewport,
               StandardView view = StandardView::Default);

/// `box` (world space) projected by `camera` on `viewport` (with the camera's viewport mapping,
/// as rendering does): the bounding rectangle of its eight corners in normalized viewport
/// coordinates, (0, 0) bottom left to (1, 1) top right. Empty if `box` is empty.
SbBox2f projectedBox(SoCamera* camera, const SbBox3f& box, const SbViewportRegion& viewport);

}  // namespace bsdeform
