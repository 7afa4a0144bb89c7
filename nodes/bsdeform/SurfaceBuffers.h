// SPDX-License-Identifier: MIT
#pragma once
/// @file SurfaceBuffers.h
/// OpenGL vertex buffer objects for a SurfaceGrid, one set per GL context: the index buffer is
/// uploaded when the grid's size changes, positions, normals and texture coordinates when its
/// contents change; drawing then hands the driver no client memory to copy (Mesa copies client
/// arrays into fresh allocations on every draw: page faults in every frame; docs/benchmarks.md,
/// "Why the code is as it is").

#include <Inventor/SbBasic.h>

#include <cstdint>
#include <map>

#include "bsdeform/spline/Tessellation.h"

class SoState;

namespace bsdeform {

class SurfaceBuffers {
 public:
  SurfaceBuffers();
  ~SurfaceBuffers();  ///< schedules the deletion of the buffers in each context that has them
  SurfaceBuffers(const SurfaceBuffers&) = delete;
  SurfaceBuffers& operator=(const SurfaceBuffers&) = delete;

  /// Draws the grid as GL_TRIANGLES with vertex, normal and texture-coordinate arrays (the
  /// caller has sent the material). `revision` names the grid's contents: the vertex data are
  /// uploaded again when it differs from the last upload in this context. Returns false when
  /// the context has no vertex buffer objects: the grid is then drawn from client memory.
  bool draw(SoState* state, const SurfaceGrid& grid, std::uint64_t revision);

 private:
  struct PerContext {
    unsigned vertexBuffer = 0, indexBuffer = 0;
    std::size_t vertexBytes = 0;  ///< allocated size of vertexBuffer
    std::size_t indexCount = 0;
    int segU = -1, segV = -1;     ///< the grid size the index buffer holds
    std::uint64_t revision = ~std::uint64_t(0);
  };
  std::map<std::uint32_t, PerContext> m_contexts;
  static void contextDestroyed(std::uint32_t context, void* self);
};

}  // namespace bsdeform
