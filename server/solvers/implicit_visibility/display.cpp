#include "solvers/implicit_visibility/display.h"

#include <algorithm>

#include "gl/buffers.h"
#include "gl/textures.h"
#include "implicit_visibility/bindings.glsl"  // shaders/: the slots its passes declare

namespace gistream {

absl::StatusOr<Display> Display::Create() {
  Display d;
  GS_ASSIGN_OR_RETURN(
      d.vertex_irradiance_,
      gl::Program::Build(
          {{GL_VERTEX_SHADER, "implicit_visibility/vertex_irradiance.vert.glsl"},
           {GL_FRAGMENT_SHADER, "implicit_visibility/vertex_irradiance.frag.glsl"}}));
  GS_ASSIGN_OR_RETURN(
      d.final_, gl::Program::Build({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"},
                                    {GL_FRAGMENT_SHADER, "implicit_visibility/final.frag.glsl"}}));
  d.vao_ = gl::VertexArray::Create();
  return d;
}

void Display::UploadTriangles(const std::vector<uint32_t>& triangles) {
  indices_ = gl::StorageBuffer(triangles);
  index_count_ = GLsizei(triangles.size());
  glVertexArrayElementBuffer(vao_.id(), indices_.id());
}

void Display::UploadTransfer(const std::vector<glm::uvec3>& leaves,
                             const std::vector<glm::vec3>& weights) {
  leaves_ = gl::StorageBuffer(leaves);
  glVertexArrayVertexBuffer(vao_.id(), 1, leaves_.id(), 0, sizeof(glm::uvec3));
  glEnableVertexArrayAttrib(vao_.id(), 1);
  glVertexArrayAttribIFormat(vao_.id(), 1, 3, GL_UNSIGNED_INT, 0);
  glVertexArrayAttribBinding(vao_.id(), 1, 1);
  weights_ = gl::StorageBuffer(weights);
  glVertexArrayVertexBuffer(vao_.id(), 2, weights_.id(), 0, sizeof(glm::vec3));
  glEnableVertexArrayAttrib(vao_.id(), 2);
  glVertexArrayAttribFormat(vao_.id(), 2, 3, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(vao_.id(), 2, 2);
}

void Display::UploadVertices(const std::vector<glm::vec3>& world) {
  positions_ = gl::StorageBuffer(world);
  glVertexArrayVertexBuffer(vao_.id(), 0, positions_.id(), 0, sizeof(glm::vec3));
  glEnableVertexArrayAttrib(vao_.id(), 0);
  glVertexArrayAttribFormat(vao_.id(), 0, 3, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(vao_.id(), 0, 0);
}

void Display::Resize(uint32_t width, uint32_t height) {
  if (width == width_ && height == height_ && fbo_) return;
  width_ = width;
  height_ = height;
  irradiance_ = gl::RenderTarget(GL_RGBA32F, int(width), int(height));
  depth_ = gl::RenderTarget(GL_DEPTH_COMPONENT32F, int(width), int(height));
  fbo_ = gl::FramebufferOf({irradiance_.id()}, depth_.id());
}

void Display::Draw(const ViewCamera& camera, const GBuffer& gbuffer, GLuint indirect_buffer,
                   const DirectLighting& lighting, float indirect_scale) {
  Resize(gbuffer.width(), gbuffer.height());
  // Indirect irradiance at the vertices, interpolated, nearest surface.
  const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  const float one = 1.0f;
  glClearNamedFramebufferfv(fbo_.id(), GL_COLOR, 0, zero);
  glClearNamedFramebufferfv(fbo_.id(), GL_DEPTH, 0, &one);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glViewport(0, 0, GLsizei(width_), GLsizei(height_));
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  vertex_irradiance_.Set("uViewProj", camera.Projection() * camera.View());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, IV_VERTEX_INDIRECT_E, indirect_buffer);
  vertex_irradiance_.Use();
  glBindVertexArray(vao_.id());
  if (index_count_ > 0) glDrawElements(GL_TRIANGLES, index_count_, GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);

  // Direct per pixel + indirect + emission.
  gbuffer.BeginShadePass();
  glBindTextureUnit(IV_UNIT_INDIRECT, irradiance_.id());
  lighting.Bind(final_);
  final_.Set("uIndirectScale", indirect_scale);
  fullscreen_.Draw(final_);
}

}  // namespace gistream
