// The display stage: the leaves' indirect irradiance rasterized at the mesh
// vertices into a view-sized texture (interpolated over the triangles),
// then one full-screen pass adds direct light per pixel and emission. A
// display vertex takes a weighted sum of three leaves' irradiance: a leaf
// itself (weights 1, 0, 0), or the full mesh's vertex interpolated on the
// proxy elements' nearest triangle (hierarchy/vertex_transfer.h), so the
// texture covers what the G-buffer's full mesh covers.
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

  // The display mesh (SceneElements): triangles, each display vertex's
  // three leaves and weights, and world positions.
  void UploadTriangles(const std::vector<uint32_t>& triangles);
  void UploadTransfer(const std::vector<glm::uvec3>& leaves, const std::vector<glm::vec3>& weights);
  void UploadVertices(const std::vector<glm::vec3>& world);

  // `indirect_scale` multiplies the indirect term (solvers/emission_scale.h).
  void Draw(const ViewCamera& camera, const GBuffer& gbuffer, GLuint indirect_buffer,
            const DirectLighting& lighting, float indirect_scale = 1.0f);

 private:
  void Resize(uint32_t width, uint32_t height);

  gl::Program vertex_irradiance_, final_;
  gl::VertexArray vao_;
  gl::FullscreenPass fullscreen_;
  gl::Buffer positions_, indices_, leaves_, weights_;
  gl::Texture irradiance_, depth_;
  gl::Framebuffer fbo_;
  GLsizei index_count_ = 0;
  uint32_t width_ = 0, height_ = 0;
};

}  // namespace gistream
