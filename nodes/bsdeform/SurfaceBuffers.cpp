// SPDX-License-Identifier: MIT
#include "bsdeform/SurfaceBuffers.h"

#include <Inventor/C/glue/gl.h>
#include <Inventor/elements/SoGLCacheContextElement.h>
#include <Inventor/misc/SoContextHandler.h>
#include <Inventor/system/gl.h>

namespace bsdeform {

namespace {
/// What a scheduled deletion needs once its context is current again.
struct Doomed {
  GLuint buffers[2];
};

void deleteBuffers(void* closure, std::uint32_t context) {
  auto* d = static_cast<Doomed*>(closure);
  const cc_glglue* gl = cc_glglue_instance(int(context));
  cc_glglue_glDeleteBuffers(gl, 2, d->buffers);
  delete d;
}
}  // namespace

SurfaceBuffers::SurfaceBuffers() { SoContextHandler::addContextDestructionCallback(&contextDestroyed, this); }

SurfaceBuffers::~SurfaceBuffers() {
  SoContextHandler::removeContextDestructionCallback(&contextDestroyed, this);
  // No context is current here: Coin deletes them when the context is next made current, or
  // when it is destroyed.
  for (const auto& [context, c] : m_contexts)
    SoGLCacheContextElement::scheduleDeleteCallback(context, &deleteBuffers,
                                                    new Doomed{{c.vertexBuffer, c.indexBuffer}});
}

void SurfaceBuffers::contextDestroyed(std::uint32_t context, void* self) {
  // The context's buffers go with it.
  static_cast<SurfaceBuffers*>(self)->m_contexts.erase(context);
}

bool SurfaceBuffers::draw(SoState* state, const SurfaceGrid& grid, std::uint64_t revision) {
  const std::uint32_t context = std::uint32_t(SoGLCacheContextElement::get(state));
  const cc_glglue* gl = cc_glglue_instance(int(context));
  if (!gl || !cc_glglue_has_vertex_buffer_object(gl)) {  // a GL without buffer objects
    glEnableClientState(GL_VERTEX_ARRAY);
    glEnableClientState(GL_NORMAL_ARRAY);
    glEnableClientState(GL_TEXTURE_COORD_ARRAY);
    glVertexPointer(3, GL_FLOAT, 0, grid.vertices.data());
    glNormalPointer(GL_FLOAT, 0, grid.normals.data());
    glTexCoordPointer(2, GL_FLOAT, 0, grid.texCoords.data());
    glDrawElements(GL_TRIANGLES, GLsizei(grid.indices.size()), GL_UNSIGNED_INT, grid.indices.data());
    glDisableClientState(GL_TEXTURE_COORD_ARRAY);
    glDisableClientState(GL_NORMAL_ARRAY);
    glDisableClientState(GL_VERTEX_ARRAY);
    return false;
  }
  auto found = m_contexts.find(context);
  if (found == m_contexts.end()) {
    found = m_contexts.emplace(context, PerContext{}).first;
    GLuint ids[2];
    cc_glglue_glGenBuffers(gl, 2, ids);
    found->second.vertexBuffer = ids[0];
    found->second.indexBuffer = ids[1];
  }
  PerContext& c = found->second;
  const std::size_t positions = grid.vertices.size() * sizeof(float);
  const std::size_t normals = grid.normals.size() * sizeof(float);
  const std::size_t texCoords = grid.texCoords.size() * sizeof(float);
  cc_glglue_glBindBuffer(gl, GL_ARRAY_BUFFER, c.vertexBuffer);
  if (c.revision != revision || c.vertexBytes != positions + normals + texCoords) {
    if (c.vertexBytes != positions + normals + texCoords) {
      c.vertexBytes = positions + normals + texCoords;
      cc_glglue_glBufferData(gl, GL_ARRAY_BUFFER, intptr_t(c.vertexBytes), nullptr, GL_DYNAMIC_DRAW);
    }
    cc_glglue_glBufferSubData(gl, GL_ARRAY_BUFFER, 0, intptr_t(positions), grid.vertices.data());
    cc_glglue_glBufferSubData(gl, GL_ARRAY_BUFFER, intptr_t(positions), intptr_t(normals), grid.normals.data());
    cc_glglue_glBufferSubData(gl, GL_ARRAY_BUFFER, intptr_t(positions + normals), intptr_t(texCoords),
                              grid.texCoords.data());
    c.revision = revision;
  }
  cc_glglue_glBindBuffer(gl, GL_ELEMENT_ARRAY_BUFFER, c.indexBuffer);
  if (c.segU != grid.segU || c.segV != grid.segV || c.indexCount != grid.indices.size()) {
    cc_glglue_glBufferData(gl, GL_ELEMENT_ARRAY_BUFFER, intptr_t(grid.indices.size() * sizeof(unsigned)),
                           grid.indices.data(), GL_STATIC_DRAW);
    c.segU = grid.segU;
    c.segV = grid.segV;
    c.indexCount = grid.indices.size();
  }
  glEnableClientState(GL_VERTEX_ARRAY);
  glEnableClientState(GL_NORMAL_ARRAY);
  glEnableClientState(GL_TEXTURE_COORD_ARRAY);
  // with a buffer bound, the pointers are offsets into it
  glVertexPointer(3, GL_FLOAT, 0, reinterpret_cast<const GLvoid*>(std::uintptr_t(0)));
  glNormalPointer(GL_FLOAT, 0, reinterpret_cast<const GLvoid*>(std::uintptr_t(positions)));
  glTexCoordPointer(2, GL_FLOAT, 0, reinterpret_cast<const GLvoid*>(std::uintptr_t(positions + normals)));
  glDrawElements(GL_TRIANGLES, GLsizei(c.indexCount), GL_UNSIGNED_INT, nullptr);
  glDisableClientState(GL_TEXTURE_COORD_ARRAY);
  glDisableClientState(GL_NORMAL_ARRAY);
  glDisableClientState(GL_VERTEX_ARRAY);
  // Coin's other shapes draw from client memory: leave no buffer bound
  cc_glglue_glBindBuffer(gl, GL_ARRAY_BUFFER, 0);
  cc_glglue_glBindBuffer(gl, GL_ELEMENT_ARRAY_BUFFER, 0);
  return true;
}

}  // namespace bsdeform
