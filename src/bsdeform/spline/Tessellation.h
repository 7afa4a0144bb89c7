// SPDX-License-Identifier: MIT
#pragma once
/// @file Tessellation.h
/// The surface on a regular parameter grid for drawing, export and picking: positions and
/// normals from the basis and its first derivatives (tensor evaluation: the u-combination of
/// net rows first, then v), texture coordinates (u, v), and the closest parameter to a point.

#include <vector>

#include "bsdeform/spline/SplineSpace.h"

namespace bsdeform {

/// (segU + 1) x (segV + 1) vertices, vertex (i, j) at (u, v) = (i / segU, j / segV), row-major
/// in i; two counter-clockwise triangles per cell seen from the side du x dv points to.
struct SurfaceGrid {
  int segU = 0, segV = 0;
  std::vector<float> vertices;   ///< x, y, z per vertex
  std::vector<float> normals;    ///< unit normal per vertex
  std::vector<float> texCoords;  ///< u, v per vertex
  std::vector<unsigned> indices; ///< rebuilt only when segU or segV change
  float boundsMin[3] = {0, 0, 0};  ///< the box of `vertices`, found as they are written
  float boundsMax[3] = {0, 0, 0};
  /// Working memory of tessellate(), kept so that tessellating again at the same size (every
  /// frame of an animation) allocates nothing.
  struct Scratch {
    std::vector<LocalBasis> basesV;
    std::vector<double> rowSum, rowDerivative, rawNormal;
    std::vector<char> degenerate;
  } scratch;
};

/// Evaluates S and its unit normal du x dv on the grid. Where du x dv vanishes (a collapsed
/// pole row, an apex) the normal is the normalised mean of the normals of the nearest grid row
/// in v (for a pole: its axis). Positions and normals agree across a periodic seam (the seam's
/// vertices are evaluated from the same control points).
/// @pre segU, segV >= 1
void tessellate(const SplineSpace& space, const ControlNet& net, int segU, int segV, SurfaceGrid& grid);

/// Segments of a tessellation along a direction of `spans` knot spans at Coin's `complexity`
/// (0..1): per-vertex normals are exact, so 1.5 segments per knot span (the default complexity
/// 0.5) look smooth; small nets get at least 64 c segments, large ones at most 64 + 448 c, and
/// never fewer than 4.
int tessellationSegments(float complexity, int spans);

/// (u, v) of the point of the surface closest to `p`: the nearest grid vertex, refined by
/// Gauss-Newton on |S(u, v) - p|^2; a periodic direction wraps, the others are kept in [0,1].
Eigen::Vector2d closestParameter(const SplineSpace& space, const ControlNet& net, const SurfaceGrid& grid,
                                 const Eigen::Vector3d& p);

}  // namespace bsdeform
