// SPDX-License-Identifier: MIT
#pragma once
/// @file SceneObstacles.h
/// Coin plumbing of contact: gathers the triangles of the obstacles a COLLISION force field
/// lists (any subgraph: shapes, nurbs, meshes, another SoBSplineDeformSurface) in world
/// coordinates with SoCallbackAction, keeps a bsdeform::ContactWorld current, and re-gathers
/// only when Coin says something changed (the force field's `obstacles` field, or an
/// SoPathSensor on the obstacle's path in the scene). The contact law is in the core
/// (bsdeform/contact/Contact.h).
///
/// Frames: an obstacle's world transform is the one above its first occurrence (depth-first)
/// under the surface's scene root: the head of the path of a traversal that reached the
/// surface (a render, a bounding box, a callback or pick action), kept when a later traversal
/// comes from a graph around it (an offscreen renderer's camera and light); one that is not in the scene graph is taken as it is, with no
/// transform above it. The surface's own frame is that of its first occurrence likewise.

#include <memory>
#include <string>
#include <vector>

#include "bsdeform/contact/Contact.h"

class SoNode;
class SoPath;
class SoPathSensor;
class SoSensor;
class SoMFNode;
class SoMFString;

namespace bsdeform {

/// The world transform of `surface` (x_world = linear x_local + offset): the one above its first
/// occurrence (depth first) under `sceneRoot`. False, with the identity, when it is not found
/// there (no scene given, or the node is not in it).
bool surfaceFrame(SoNode* sceneRoot, SoNode* surface, Eigen::Matrix3d& linear, Eigen::Vector3d& offset);

class SceneObstacles {
 public:
  SceneObstacles();
  ~SceneObstacles();
  SceneObstacles(const SceneObstacles&) = delete;
  SceneObstacles& operator=(const SceneObstacles&) = delete;

  /// The world the CollisionForce reads (updated in place by update()).
  std::shared_ptr<const ContactWorld> world() const { return m_world; }

  /// Brings the world up to date before a step: the surface's frame every time (cheap), the
  /// obstacles' triangles when `obstaclesChanged` or a path sensor fired since the last call.
  /// The obstacles are the nodes of `obstacles`, then those `names` name (the first node of
  /// that DEF name under `sceneRoot`, depth first). `self` is never gathered (self-collision is
  /// not supported). Problems (a NULL entry, a name not in the scene, the surface itself, an
  /// empty subgraph, dropped triangles) are appended to `warnings`, naming the field entry; the
  /// valid obstacles are used. Another SoBSplineDeformSurface among them is its shape's
  /// triangles, or with `surfaceProxies` (barrier contact) its collision proxy
  /// (SoBSplineDeformSurface::collisionProxyMesh()).
  void update(SoNode* sceneRoot, SoNode* self, const SoMFNode& obstacles, const SoMFString& names,
              bool obstaclesChanged, std::vector<std::string>& warnings, bool surfaceProxies = false);

  /// How often obstacle trees were built from scratch and refitted (moved vertices).
  int builds() const { return m_builds; }
  int refits() const { return m_refits; }

 private:
  struct Entry;
  static void sensorFired(void* data, SoSensor*);
  void gather(SoNode* sceneRoot, SoNode* self, const SoMFNode& obstacles, const SoMFString& names,
              std::vector<std::string>& warnings);

  std::shared_ptr<ContactWorld> m_world;
  std::vector<std::unique_ptr<Entry>> m_entries;
  SoNode* m_root = nullptr;
  bool m_dirty = true;
  bool m_surfaceProxies = false;
  int m_builds = 0, m_refits = 0;
};

}  // namespace bsdeform
