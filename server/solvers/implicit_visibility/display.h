// The display stage: the leaves' indirect irradiance rasterized at the mesh
// vertices into a view-sized texture (interpolated over the triangles),
// then one full-screen pass adds direct light per pixel and emission.
#pragma once

#include <vector>

#include "gl/fullscreen_pass.h"
#include "gl/handle.h"
#include "gl/program.h"
#include "render/camera.h"
#include "render/direct_lighting.h"
#include "render/gbuffer.h"

namespace gistream {

class Display {
 public:
  static absl::StatusOr<Display> Create();

  // The display mesh: world positions per leaf (mesh vertex) and triangles.
  void UploadTriangles(const std::vector<uint32_t>& triangles);
  void UploadVertices(const std::vector<glm::vec3>& world);

  // `indirect_scale` multiplies the indirect term (solvers/emission_scale.h).
  void Draw(const ViewCamera& camera, const GBuffer& gbuffer, GLuint indirect_buffer,
            const DirectLighting& lighting, float indirect_scale = 1.0f);

 private:
  void Resize(uint32_t width, uint32_t height);

  gl::Program vertex_irradiance_, final_;
  gl::VertexArray vao_;
  gl::FullscreenPass fullscreen_;
  gl::Buffer positions_, indices_;
  gl::Texture irradiance_, depth_;
  gl::Framebuffer fbo_;
  GLsizei index_count_ = 0;
  uint32_t width_ = 0, height_ = 0;
};

}  // namespace gistream
