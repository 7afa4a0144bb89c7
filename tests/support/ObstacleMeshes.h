// SPDX-License-Identifier: MIT
#pragma once
/// @file ObstacleMeshes.h
/// Obstacles for the contact tests: a box as 12 outward-wound triangles and a ContactWorld of
/// one mesh.
#include <Eigen/Core>
#include <memory>

#include "bsdeform/contact/Contact.h"
#include "bsdeform/contact/TriangleTree.h"

namespace bsdeform::test {

/// A box [lo, hi] (turned by R about the origin) as 12 triangles, counter-clockwise seen from outside.
inline TriangleMesh box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                        const Eigen::Matrix3d& R = Eigen::Matrix3d::Identity()) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i)
    m.vertices.push_back(R * Eigen::Vector3d(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z()));
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    m.triangles.emplace_back(f[0], f[1], f[2]);
    m.triangles.emplace_back(f[0], f[2], f[3]);
  }
  return m;
}

inline std::shared_ptr<ContactWorld> worldOf(const TriangleMesh& mesh) {
  auto w = std::make_shared<ContactWorld>();
  w->obstacles.push_back({std::make_shared<TriangleTree>(mesh), isClosedMesh(mesh)});
  return w;
}

}  // namespace bsdeform::test
