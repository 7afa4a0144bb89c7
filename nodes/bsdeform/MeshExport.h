// SPDX-License-Identifier: MIT
#pragma once
/// @file MeshExport.h
/// The triangles a surface draws, exported as Wavefront OBJ or binary STL (the viewer's Export
/// Mesh, `bsdeform-run --export-mesh`, `bsdeform.export_mesh`). No Qt: paths are std::string,
/// errors are sentences naming the file and the problem.

#include <Inventor/SbVec2f.h>
#include <Inventor/SbVec3f.h>

#include <string>
#include <vector>

class SoNode;
class SoPath;
class SoBSplineDeformSurface;

namespace bsdeform {

/// One surface's triangles in world coordinates, with shared vertices: generatePrimitives gives
/// each grid point to every triangle around it with bit-identical position, normal and (u, v),
/// so equal vertices are one (a periodic seam keeps two vertices with different (u, v), as a UV
/// seam should).
struct SurfaceMesh {
  std::string name;               ///< the OBJ object name (blanks become '_')
  std::vector<SbVec3f> points;    ///< #vertices positions
  std::vector<SbVec3f> normals;   ///< #vertices unit normals
  std::vector<SbVec2f> uv;        ///< #vertices surface parameters
  std::vector<int> triangles;     ///< 3 vertex indices per triangle, counter-clockwise
};

/// The mesh of the surface at the tail of `path` (an SoBSplineDeformSurface), with the transforms
/// along the path applied, as SoCallbackAction sees it.
SurfaceMesh surfaceMesh(SoPath* path, const std::string& name);

/// The mesh of `surface` at its first place under `root`. False with `error` when it is not there.
bool surfaceMesh(SoNode* root, SoBSplineDeformSurface* surface, const std::string& name, SurfaceMesh& mesh,
                 std::string& error);

/// Writes `meshes` to `path`, by its extension (case-insensitive): `.obj` (one object `o NAME` per
/// mesh, with `v`, `vt`, `vn` and `f v/vt/vn` lines) or `.stl` (binary; the triangles of all
/// meshes in one solid, facet normals from the vertex order). A first line or the STL header
/// says which program (`producer`) wrote it. The write is atomic (AtomicWrite.h): on failure an
/// existing file is kept and `error` names the file and the reason; an unknown extension or no
/// meshes are refused before anything is written.
bool writeMesh(const std::vector<SurfaceMesh>& meshes, const std::string& path, const std::string& producer,
               std::string& error);

/// The meshes of `surfaces` (each at its first place under `root`, named by `names`, one per
/// surface) written to `path` by writeMesh: several surfaces are objects of one OBJ, or the
/// triangles of one STL.
bool exportMesh(SoNode* root, const std::vector<SoBSplineDeformSurface*>& surfaces, const std::vector<std::string>& names,
                const std::string& path, const std::string& producer, std::string& error);

}  // namespace bsdeform
