// A full-screen triangle (shaders/render/fullscreen.vert.glsl makes the
// positions from gl_VertexID): the final shading pass of every solver and
// the tone map. Owns the empty vertex array core GL requires for it.
#pragma once

#include "gl/handle.h"
#include "gl/program.h"

namespace gistream::gl {

class FullscreenPass {
 public:
  // Draws with `program` into the bound framebuffer; creates the vertex
  // array on first use (on the thread that owns the context).
  void Draw(const Program& program) {
    if (!vao_) vao_ = VertexArray::Create();
    program.Use();
    glBindVertexArray(vao_.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
  }

 private:
  VertexArray vao_;
};

}  // namespace gistream::gl
