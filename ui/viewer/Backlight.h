// SPDX-License-Identifier: MIT
#pragma once
/// @file Backlight.h
/// A second light opposite SoQt's headlight, for what the headlight cannot reach. The node lights
/// an open surface on both sides (two-sided lighting: the side you see gets the normal that
/// faces you), but SoQt's headlight is a directional light along the view axis (from the upper
/// left, direction (1, -1, -10) in camera space), not along the ray to each point. A sheet seen
/// from just below while the camera looks slightly down (curtain.iv, pinned_cloth.iv at rest),
/// or a fold near its silhouette, shows a side whose normal turns away from that direction: it
/// got only the ambient light and drew black. The backlight shines along the opposite
/// direction, so it adds light exactly where the headlight adds none (where the headlight
/// lights a face, the backlight's N.L is negative and it adds nothing): the view of a lit face
/// is unchanged, and a side turned away is shaded instead of black. FreeCAD's viewer has the
/// same light ("backlight"). It sits in the viewer's graph beside the scene, not in the scene,
/// before the scene's root: after SoQt's own camera (world space) or, for a scene with a camera
/// of its own, before that camera (camera space); it reads which from the viewing matrix.

class SoAction;
class SoDirectionalLight;
class SoRotation;
class SoTransformSeparator;

namespace bsdeform {

class Backlight {
 public:
  /// The backlight's intensity: the headlight's, so that a side turned away from the headlight by an
  /// angle is lit as the side turned towards it by that angle would be.
  static constexpr float kIntensity = 1.0f;

  Backlight();
  ~Backlight();
  Backlight(const Backlight&) = delete;
  Backlight& operator=(const Backlight&) = delete;

  /// The light: put it in the viewer's graph before the scene, after SoQt's camera.
  SoTransformSeparator* node() const { return m_root; }
  SoDirectionalLight* light() const { return m_light; }

 private:
  /// Before the light is drawn: turns camera space into the space the light is in.
  static void beforeDrawing(void* self, SoAction* action);

  SoTransformSeparator* m_root = nullptr;
  SoRotation* m_turn = nullptr;
  SoDirectionalLight* m_light = nullptr;
};

}  // namespace bsdeform
